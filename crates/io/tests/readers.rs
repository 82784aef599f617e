//! Smaller reader behaviours: OBJ forward references, colours and warnings; PLY aliases;
//! STL multiple solids and trailing bytes; SourceInfo counts.

#![allow(clippy::unwrap_used)] // helpers outside #[test] fns unwrap too

use flatcut_io::{Format, LoadedMesh, Units, color, read_mesh_from_bytes};

fn read(bytes: &[u8], format: Format) -> LoadedMesh {
    read_mesh_from_bytes(bytes, format, "mem", Units::Mm).unwrap()
}

#[test]
fn obj_forward_reference_colours_and_unknown_keywords() {
    let m = read(
        b"f 1 2 3\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\ncurv 0 1 2\ncurv 1\nfo 3 2 1\n",
        Format::Obj,
    );
    assert_eq!(m.mesh.faces, vec![[0, 1, 2], [2, 1, 0]]);
    assert_eq!(
        m.mesh.attributes.colors.as_ref().unwrap()[1],
        [0.0, 1.0, 0.0, 1.0]
    );
    assert_eq!(
        m.source.warnings,
        vec!["2 line(s) with unknown keyword 'curv' ignored (first at line 5)".to_string()]
    );
    assert!(m.mesh.face_labels.is_none());
}

#[test]
fn obj_colours_0_255_and_partial() {
    let m = read(
        b"v 0 0 0 255 0 0\nv 1 0 0 0 128 0\nv 0 1 0 0 0 0\nf 1 2 3\n",
        Format::Obj,
    );
    let c = m.mesh.attributes.colors.unwrap();
    assert_eq!(c[1][1], color::srgb_to_linear(128.0 / 255.0));
    assert!(m.source.warnings.iter().any(|w| w.contains("0..255")));
    let m = read(b"v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Format::Obj);
    assert!(m.mesh.attributes.colors.is_none());
    assert!(m.source.warnings.iter().any(|w| w.contains("only 1 of 3")));
}

#[test]
fn obj_faces_before_first_group_get_default_label() {
    let m = read(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng a\nf 1 2 3\ng\nf 3 2 1\ng a\nf 2 3 1\n",
        Format::Obj,
    );
    let l = m.mesh.face_labels.unwrap();
    assert_eq!(l.names, vec!["default".to_string(), "a".to_string()]);
    assert_eq!(l.labels, vec![0, 1, 0, 1]);
}

#[test]
fn ply_vertex_index_name_aliases_and_list_types() {
    let mut b = b"ply\r\nformat binary_big_endian 1.0\r\nelement vertex 4\r\nproperty float64 x\r\nproperty float64 y\r\nproperty float64 z\r\n\
element face 1\r\nproperty list ushort int8 vertex_index\r\nend_header\r\n"
        .to_vec();
    for p in [[0.0f64, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
        for c in p {
            b.extend_from_slice(&c.to_be_bytes());
        }
    }
    b.extend_from_slice(&4u16.to_be_bytes());
    b.extend_from_slice(&[0, 1, 2, 3]);
    let m = read(&b, Format::Ply);
    assert_eq!(m.mesh.faces, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(m.source.polygons_triangulated, 1);
    assert!(m.mesh.attributes.colors.is_none());
}

#[test]
fn stl_multiple_solids_and_trailing_bytes() {
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    let text = format!("solid a\n{facet}endsolid a\nsolid b\n{facet}endsolid b\n");
    let m = read(text.as_bytes(), Format::Stl);
    assert_eq!(
        m.mesh.faces,
        vec![[0, 1, 2], [0, 1, 2]],
        "identical positions weld across solids"
    );
    assert_eq!(m.source.faces_read, 2);

    let mut b = vec![0u8; 80];
    b.extend_from_slice(&1u32.to_le_bytes());
    b.extend_from_slice(&[0; 12]);
    for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        b.extend_from_slice(&c.to_le_bytes());
    }
    b.extend_from_slice(&[0, 0, 9, 9, 9]);
    let m = read(&b, Format::Stl);
    assert_eq!(m.mesh.faces, vec![[0, 1, 2]]);
    assert_eq!(
        m.source.warnings,
        vec!["3 bytes after the last of 1 facets ignored".to_string()]
    );
}
