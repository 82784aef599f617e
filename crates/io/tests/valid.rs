//! The tiny valid fixtures read to exactly the positions and faces they were written with.

#![allow(clippy::unwrap_used)] // helpers outside #[test] fns unwrap too

use std::path::PathBuf;

use flatcut_io::{Format, Units, color, read_mesh, read_mesh_from_bytes};

fn valid(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/valid")
        .join(name)
}

fn bits(p: &[[f64; 3]]) -> Vec<[u64; 3]> {
    p.iter().map(|v| v.map(f64::to_bits)).collect()
}

const QUADTRI_FACES: [[u32; 3]; 3] = [[0, 1, 2], [0, 2, 3], [3, 2, 4]];

#[test]
fn obj_groups_shared_vertices_negative_index() {
    let m = read_mesh(&valid("quad_groups.obj"), Units::Mm).unwrap();
    assert_eq!(
        m.mesh.positions,
        vec![
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0.5, 1.5, 0.25],
            [9., 9., 9.]
        ],
        "the unreferenced vertex 6 is kept"
    );
    assert_eq!(m.mesh.faces, QUADTRI_FACES);
    let labels = m.mesh.face_labels.as_ref().unwrap();
    assert_eq!(
        labels.names,
        vec!["left side".to_string(), "right".to_string()]
    );
    assert_eq!(labels.labels, vec![0, 0, 1]);
    // Vertices 3 and 4 (1-based) are shared by both groups and stay single vertices.
    assert_eq!(m.source.faces_read, 2);
    assert_eq!(m.source.polygons_triangulated, 1);
    assert_eq!(m.source.vertices_read, 6);
    assert_eq!(m.source.format, Format::Obj);
    assert!(m.source.warnings.is_empty(), "{:?}", m.source.warnings);
    assert_eq!(
        m.source.file_size,
        std::fs::metadata(valid("quad_groups.obj")).unwrap().len()
    );
}

#[test]
fn units_scale_positions() {
    let mm = read_mesh(&valid("quad_groups.obj"), Units::Mm)
        .unwrap()
        .mesh;
    for u in [Units::Cm, Units::Dm, Units::M, Units::In] {
        let m = read_mesh(&valid("quad_groups.obj"), u).unwrap().mesh;
        for (a, b) in m.positions.iter().zip(&mm.positions) {
            for k in 0..3 {
                assert_eq!(a[k], b[k] * u.factor_to_mm());
            }
        }
    }
}

#[test]
fn ply_ascii_le_be_with_shuffled_and_extra_properties() {
    let expect_pos: [[f64; 3]; 5] = [
        [0., 0., 0.1],
        [1., 0., 0.2],
        [1., 1., 0.30000000000000004],
        [0., 1., -0.0],
        [0.5, 1.5, 1e-300],
    ];
    let mut meshes = Vec::new();
    for name in ["shuffled_ascii.ply", "shuffled_le.ply", "shuffled_be.ply"] {
        let m = read_mesh(&valid(name), Units::Mm).unwrap();
        assert_eq!(bits(&m.mesh.positions), bits(&expect_pos), "{name}");
        assert_eq!(m.mesh.faces, QUADTRI_FACES, "{name}");
        let colors = m.mesh.attributes.colors.as_ref().unwrap();
        for (i, c) in colors.iter().enumerate() {
            let k = i as u8 + 1;
            assert_eq!(
                *c,
                [
                    color::u8_to_linear(10 * k),
                    color::u8_to_linear(20 * k),
                    color::u8_to_linear(30 * k),
                    1.0
                ]
            );
        }
        assert_eq!(m.source.faces_read, 2);
        assert_eq!(m.source.polygons_triangulated, 1);
        assert!(
            m.source.warnings.iter().any(|w| w.contains("'material'")),
            "{:?}",
            m.source.warnings
        );
        meshes.push(m.mesh);
    }
    assert_eq!(meshes[0], meshes[1]);
    assert_eq!(meshes[1], meshes[2]);
}

#[test]
fn stl_ascii_and_binary_starting_with_solid_are_welded() {
    for name in ["two_facets_ascii.stl", "solid_header_binary.stl"] {
        let m = read_mesh(&valid(name), Units::Mm).unwrap();
        assert_eq!(
            m.mesh.positions,
            vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
            "{name}"
        );
        assert_eq!(m.mesh.faces, vec![[0, 1, 2], [0, 2, 3]], "{name}");
        assert_eq!(m.source.faces_read, 2);
        assert_eq!(m.source.vertices_read, 6);
    }
}

#[test]
fn gltf_data_uri_and_external_bin() {
    let expect: Vec<[f64; 3]> = vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0.5, 1.5, 0.25],
    ];
    for name in ["datauri.gltf", "external.gltf"] {
        let m = read_mesh(&valid(name), Units::Mm).unwrap();
        assert_eq!(m.mesh.positions, expect, "{name}");
        assert_eq!(m.mesh.faces, QUADTRI_FACES, "{name}");
    }
    // From bytes there is no directory to find external.bin in: a clear error.
    let bytes = std::fs::read(valid("external.gltf")).unwrap();
    let err = read_mesh_from_bytes(&bytes, Format::Gltf, "external.gltf", Units::Mm)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("external.gltf") && err.contains("external.bin"),
        "{err}"
    );
    let bytes = std::fs::read(valid("datauri.gltf")).unwrap();
    assert!(read_mesh_from_bytes(&bytes, Format::Gltf, "x.gltf", Units::Mm).is_ok());
}

#[test]
fn glb_hierarchical_node_transform() {
    let m = read_mesh(&valid("transform.glb"), Units::Mm).unwrap();
    // world = translate(10,20,30) · rotate_z(90°) · scale(2): (x, y, z) → (10 − 2y, 20 + 2x, 30 + 2z).
    let local: [[f64; 3]; 5] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0.5, 1.5, 0.25],
    ];
    assert_eq!(m.mesh.positions.len(), 5);
    for (p, l) in m.mesh.positions.iter().zip(local) {
        let e = [10. - 2. * l[1], 20. + 2. * l[0], 30. + 2. * l[2]];
        for k in 0..3 {
            // The quaternion is stored as f32 (0.70710677), so the rotation is 90° to ~1e-7.
            assert!((p[k] - e[k]).abs() < 1e-6, "{p:?} vs {e:?}");
        }
    }
    assert_eq!(
        m.mesh.faces, QUADTRI_FACES,
        "a proper rotation keeps the winding"
    );
}

#[test]
fn unsupported_extension_lists_supported_ones() {
    let err = read_mesh(std::path::Path::new("scan.xyz"), Units::Mm)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("scan.xyz") && err.contains(".obj") && err.contains(".glb"),
        "{err}"
    );
}
