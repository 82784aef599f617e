//! Write → read round trips: OBJ and PLY (double) are bit-exact, GLB and STL exact to f32.

#![allow(clippy::unwrap_used)] // helpers outside #[test] fns unwrap too

use std::path::Path;

use flatcut_io::{Format, Units, WriteOptions, color, read_mesh, write_mesh};
use flatcut_mesh::{FaceLabels, TriMesh};

/// A grid whose coordinates are awkward for decimal round trips.
fn awkward_mesh() -> TriMesh {
    let specials = [
        0.1 + 0.2,
        1e-300,
        -0.0,
        123456.789,
        5e-324,
        -1.0 / 3.0,
        2f64.powi(60),
        0.7,
        -987.654321e-7,
    ];
    let n = 4usize;
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let s = specials[(i * n + j) % specials.len()];
            positions.push([i as f64 + s, j as f64 * std::f64::consts::PI, s]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let a = (i * n + j) as u32;
            faces.push([a, a + n as u32, a + 1]);
            faces.push([a + 1, a + n as u32, a + n as u32 + 1]);
        }
    }
    let mut m = TriMesh::new(positions, faces).unwrap();
    let f = m.faces.len();
    m.face_labels = Some(FaceLabels {
        names: vec!["front panel".into(), "back".into()],
        labels: (0..f).map(|i| u32::from(i >= f / 2)).collect(),
    });
    m
}

fn bits(p: &[[f64; 3]]) -> Vec<[u64; 3]> {
    p.iter().map(|v| v.map(f64::to_bits)).collect()
}

fn roundtrip(mesh: &TriMesh, dir: &Path, name: &str) -> TriMesh {
    let path = dir.join(name);
    write_mesh(
        &path,
        mesh,
        &WriteOptions {
            units: Some(Units::Mm),
            ..Default::default()
        },
    )
    .unwrap();
    read_mesh(&path, Units::Mm).unwrap().mesh
}

#[test]
fn obj_ply_obj_is_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    let m = awkward_mesh();
    let a = roundtrip(&m, dir.path(), "a.obj");
    assert_eq!(bits(&a.positions), bits(&m.positions));
    assert_eq!(a.faces, m.faces);
    assert_eq!(a.face_labels, m.face_labels, "OBJ keeps groups");
    let b = roundtrip(&a, dir.path(), "b.ply");
    assert_eq!(bits(&b.positions), bits(&m.positions));
    assert_eq!(b.faces, m.faces);
    let c = roundtrip(&b, dir.path(), "c.obj");
    assert_eq!(bits(&c.positions), bits(&m.positions));
    assert_eq!(c.faces, m.faces);
    // Nothing but the three files is left in the directory (temp files renamed away).
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
}

#[test]
fn glb_is_exact_to_f32_with_colors() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = awkward_mesh();
    m.positions.iter_mut().for_each(|p| p[1] = p[1].min(1e30));
    let n = m.positions.len();
    let colors: Vec<[f32; 4]> = (0..n)
        .map(|i| [i as f32 / n as f32, 0.25, 1.0 / 3.0, 0.5])
        .collect();
    m.attributes.colors = Some(colors.clone());
    let g = roundtrip(&m, dir.path(), "m.glb");
    let expect: Vec<[f64; 3]> = m
        .positions
        .iter()
        .map(|p| p.map(|x| f64::from(x as f32)))
        .collect();
    assert_eq!(bits(&g.positions), bits(&expect));
    assert_eq!(g.faces, m.faces);
    assert_eq!(g.attributes.colors.unwrap(), colors);
}

#[test]
fn glb_colors_a_scalar_with_viridis() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = awkward_mesh();
    let n = m.positions.len();
    m.attributes.scalar = Some((0..n).map(|i| i as f64 * 2.0).collect());
    // Default range = min..max: first vertex gets the ramp start, last the end.
    let g = roundtrip(&m, dir.path(), "s.glb");
    let c = g.attributes.colors.unwrap();
    assert_eq!(c[0], color::viridis(0.0, 0.0, 1.0));
    assert_eq!(c[n - 1], color::viridis(1.0, 0.0, 1.0));
    // A caller-chosen range.
    let path = dir.path().join("r.glb");
    let opts = WriteOptions {
        scalar_range: Some((0.0, 4.0)),
        ..Default::default()
    };
    write_mesh(&path, &m, &opts).unwrap();
    let c = read_mesh(&path, Units::Mm)
        .unwrap()
        .mesh
        .attributes
        .colors
        .unwrap();
    assert_eq!(c[1], color::viridis(0.5, 0.0, 1.0));
    assert_eq!(
        c[5],
        color::viridis(1.0, 0.0, 1.0),
        "values above the range clamp"
    );
}

#[test]
fn ply_colors_round_trip_through_u8() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = awkward_mesh();
    let n = m.positions.len();
    let colors: Vec<[f32; 4]> = (0..n)
        .map(|i| {
            let k = (i * 17 % 256) as u8;
            [
                color::u8_to_linear(k),
                color::u8_to_linear(255 - k),
                color::u8_to_linear(k / 2),
                1.0,
            ]
        })
        .collect();
    m.attributes.colors = Some(colors.clone());
    let p = roundtrip(&m, dir.path(), "c.ply");
    assert_eq!(p.attributes.colors.unwrap(), colors);
}

#[test]
fn stl_is_exact_to_f32_and_welded() {
    let dir = tempfile::tempdir().unwrap();
    let m = awkward_mesh();
    let path = dir.path().join("m.stl");
    write_mesh(
        &path,
        &m,
        &WriteOptions {
            units: Some(Units::Mm),
            ..Default::default()
        },
    )
    .unwrap();
    let s = read_mesh(&path, Units::Mm).unwrap();
    assert_eq!(s.source.faces_read, m.faces.len());
    assert_eq!(s.source.vertices_read, 3 * m.faces.len());
    // Welding recovers one vertex per distinct f32 position: every triangle maps onto the
    // original's corners rounded to f32.
    assert_eq!(s.mesh.faces.len(), m.faces.len());
    for (fs, fm) in s.mesh.faces.iter().zip(&m.faces) {
        for k in 0..3 {
            let a = s.mesh.positions[fs[k] as usize];
            let b = m.positions[fm[k] as usize].map(|x| f64::from(x as f32) + 0.0);
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
    }
    let distinct: std::collections::HashSet<_> = m
        .positions
        .iter()
        .map(|p| p.map(|x| (x as f32 + 0.0).to_bits()))
        .collect();
    assert_eq!(s.mesh.positions.len(), distinct.len());
}

#[test]
fn units_on_write_and_read_cancel() {
    let dir = tempfile::tempdir().unwrap();
    let m = awkward_mesh();
    let path = dir.path().join("cm.ply");
    write_mesh(
        &path,
        &m,
        &WriteOptions {
            units: Some(Units::Cm),
            ..Default::default()
        },
    )
    .unwrap();
    let back = read_mesh(&path, Units::Cm).unwrap().mesh;
    // Relative error of a division and a multiplication; 5e-324 / 10 underflows to 0.
    for (a, b) in back.positions.iter().zip(&m.positions) {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() <= 4.0 * f64::EPSILON * b[k].abs() + 10.0 * f64::MIN_POSITIVE,
                "{} vs {}",
                a[k],
                b[k]
            );
        }
    }
}

#[test]
fn failed_writes_leave_no_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.obj");
    std::fs::write(&path, b"original").unwrap();
    // A NaN position is refused before anything is written.
    let mut bad = awkward_mesh();
    bad.positions[3][1] = f64::NAN;
    let err = write_mesh(
        &path,
        &bad,
        &WriteOptions {
            units: Some(Units::Mm),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("keep.obj") && err.contains("vertex 3"),
        "{err}"
    );
    // A coordinate beyond f32 fails inside the GLB writer: the temp file is removed.
    let mut big = awkward_mesh();
    big.positions[0][0] = 1e300;
    let glb = dir.path().join("keep.glb");
    std::fs::write(&glb, b"original").unwrap();
    assert!(
        write_mesh(
            &glb,
            &big,
            &WriteOptions {
                units: Some(Units::Mm),
                ..Default::default()
            }
        )
        .is_err()
    );
    assert_eq!(std::fs::read(&path).unwrap(), b"original");
    assert_eq!(std::fs::read(&glb).unwrap(), b"original");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "no temp file left behind"
    );
    // Unknown extension and .gltf are refused with the supported list.
    for name in ["x.xyz", "x.gltf"] {
        let err = write_mesh(
            &dir.path().join(name),
            &awkward_mesh(),
            &WriteOptions {
                units: Some(Units::Mm),
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(err.to_string().contains(".glb"), "{err}");
    }
    // Explicit format overrides the extension.
    let p = dir.path().join("as_ply.dat");
    let opts = WriteOptions {
        format: Some(Format::Ply),
        ..Default::default()
    };
    write_mesh(&p, &awkward_mesh(), &opts).unwrap();
    assert!(
        std::fs::read(&p)
            .unwrap()
            .starts_with(b"ply\nformat binary_little_endian")
    );
}

#[test]
fn in_memory_encoding_matches_file_and_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let m = awkward_mesh();
    for format in [Format::Obj, Format::Ply, Format::Stl, Format::Glb] {
        let bytes = flatcut_io::write_mesh_to_vec(
            &m,
            format,
            &WriteOptions {
                units: Some(Units::Mm),
                ..Default::default()
            },
        )
        .unwrap();
        let path = dir.path().join(format!("m.{}", format.name()));
        write_mesh(
            &path,
            &m,
            &WriteOptions {
                units: Some(Units::Mm),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), bytes, "{format:?}");
        let back = flatcut_io::read_mesh_from_bytes(&bytes, format, "mem", Units::Mm).unwrap();
        assert_eq!(back.mesh.faces.len(), m.faces.len());
    }
    assert!(
        flatcut_io::write_mesh_to_vec(
            &m,
            Format::Gltf,
            &WriteOptions {
                units: Some(Units::Mm),
                ..Default::default()
            }
        )
        .is_err()
    );
}

#[test]
fn obj_writes_texcoords_as_vt_and_v_slash_vt_faces() {
    let mut mesh = flatcut_mesh::TriMesh::new(
        vec![[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 20.0, 0.0]],
        vec![[0, 1, 2]],
    )
    .unwrap();
    mesh.attributes.texcoords = Some(vec![[0.0, 0.0], [10.5, 0.25], [0.1, 20.0]]);
    let bytes = flatcut_io::write_mesh_to_vec(
        &mesh,
        flatcut_io::Format::Obj,
        &flatcut_io::WriteOptions {
            units: Some(flatcut_io::Units::Mm),
            ..Default::default()
        },
    )
    .unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    let vt: Vec<&str> = text.lines().filter(|l| l.starts_with("vt ")).collect();
    assert_eq!(vt, ["vt 0.0 0.0", "vt 10.5 0.25", "vt 0.1 20.0"]);
    assert!(text.lines().any(|l| l == "f 1/1 2/2 3/3"), "{text}");
    // Our own reader takes the v/vt form back with the same positions and faces.
    let back = flatcut_io::read_mesh_from_bytes(
        &bytes,
        flatcut_io::Format::Obj,
        "vt.obj",
        flatcut_io::Units::Mm,
    )
    .unwrap();
    assert_eq!(back.mesh.positions, mesh.positions);
    assert_eq!(back.mesh.faces, mesh.faces);
    // Written in cm, texcoords are converted like positions.
    let opts = flatcut_io::WriteOptions {
        units: Some(flatcut_io::Units::Cm),
        ..Default::default()
    };
    let text = String::from_utf8(
        flatcut_io::write_mesh_to_vec(&mesh, flatcut_io::Format::Obj, &opts).unwrap(),
    )
    .unwrap();
    assert!(text.lines().any(|l| l == "vt 1.05 0.025"), "{text}");
}

#[test]
fn glb_is_written_in_metres_by_default_and_read_back_to_millimetres() {
    // glTF fixes metres: a 1680 mm dress form must be 1.68 units tall in any viewer.
    let m = TriMesh::new(
        vec![[0.0, 0.0, 0.0], [1680.0, 0.0, 0.0], [0.0, 250.5, 0.0]],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let bytes = flatcut_io::write_mesh_to_vec(&m, Format::Glb, &WriteOptions::default()).unwrap();
    let in_metres =
        flatcut_io::read_mesh_from_bytes(&bytes, Format::Glb, "m.glb", Units::Mm).unwrap();
    assert_eq!(in_metres.mesh.positions[1][0], 1.68f32 as f64);
    let back = flatcut_io::read_mesh_from_bytes(
        &bytes,
        Format::Glb,
        "m.glb",
        Units::default_for(Format::Glb),
    )
    .unwrap();
    for (a, b) in back.mesh.positions.iter().zip(&m.positions) {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() <= 1e-7 * b[k].abs().max(1.0),
                "{a:?} vs {b:?}"
            );
        }
    }
    // OBJ keeps millimetres by default, bit-exact.
    let obj = flatcut_io::write_mesh_to_vec(&m, Format::Obj, &WriteOptions::default()).unwrap();
    let back = flatcut_io::read_mesh_from_bytes(
        &obj,
        Format::Obj,
        "m.obj",
        Units::default_for(Format::Obj),
    )
    .unwrap();
    assert_eq!(back.mesh.positions, m.positions);
}
