//! `flatcut trim` end to end: a sphere in centimetres cut by a loop and a T-line into three
//! named pieces written in mm, the seam ledger, and bad cut files refused with their place.

#![allow(clippy::unwrap_used)]

mod common;

use common::{flatcut, refused, succeed_json};

use flatcut_mesh::{SeamLedger, geometry, shapes};

// Sphere of radius 10 cm: an equator loop and a line over the north pole ending on it.
const CUTS: &str = r#"units = "cm"

[[cut]]
name = "equator"
points = [[9.925, 0.0, 1.219], [-1.219, 0.0, 9.925], [-9.925, 0.0, -1.219], [1.219, 0.0, -9.925]]
closed = true

[[cut]]
name = "crown"
points = [[9.925, 0.0, 1.219], [0.0, 10.0, 0.0], [-9.925, 0.0, -1.219]]

[[piece]]
name = "south"
seed = [0.0, -10.0, 0.0]

[[piece]]
name = "north-front"
seed = [0.99, 6.93, 6.93]

[[piece]]
name = "north-back"
seed = [0.99, 6.93, -6.93]
"#;

fn sphere_file(dir: &std::path::Path) -> std::path::PathBuf {
    // Written in cm: 100 mm radius divided by 10 on write.
    let mesh = shapes::icosphere(100.0, 3);
    let path = dir.join("sphere.obj");
    flatcut_io::write_mesh(
        &path,
        &mesh,
        &flatcut_io::WriteOptions {
            units: Some(flatcut_io::Units::Cm),
            ..Default::default()
        },
    )
    .unwrap();
    path
}

#[test]
fn trim_writes_pieces_in_mm_and_the_seam_ledger() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_file(dir.path());
    let cuts = dir.path().join("cuts.toml");
    std::fs::write(&cuts, CUTS).unwrap();
    let out_dir = dir.path().join("out");
    let summary = succeed_json(
        flatcut()
            .arg("trim")
            .arg(&input)
            .arg("--cuts")
            .arg(&cuts)
            .arg("--out")
            .arg(&out_dir)
            .arg("--json"),
    );
    assert_eq!(summary["pieces"].as_array().unwrap().len(), 3);
    assert_eq!(summary["seams"].as_array().unwrap().len(), 3);

    let ledger: SeamLedger =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("seams.json")).unwrap())
            .unwrap();
    ledger.check().unwrap();
    assert_eq!(ledger.pieces, ["south", "north-front", "north-back"]);
    // The pieces, read back in mm, cover the sphere (written in cm, so 100 mm radius).
    let sphere = shapes::icosphere(100.0, 3);
    let mut area = 0.0;
    for name in &ledger.pieces {
        let p = flatcut_io::read_mesh(&out_dir.join(format!("{name}.obj")), flatcut_io::Units::Mm)
            .unwrap();
        area += geometry::total_area(&p.mesh);
        // Every seam chain index is a vertex of its piece.
        for s in ledger.seams_of(name) {
            let side = if &s.a.piece == name { &s.a } else { &s.b };
            assert!(
                side.vertices
                    .iter()
                    .all(|&v| (v as usize) < p.mesh.positions.len())
            );
        }
    }
    let whole = geometry::total_area(&sphere);
    // OBJ text keeps ~1e-12 relative precision.
    assert!((area - whole).abs() < 1e-8 * whole, "{area} vs {whole}");
    // The full report lists every source face's fate.
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("trim_report.json")).unwrap())
            .unwrap();
    assert_eq!(
        report["face_fates"].as_array().unwrap().len(),
        sphere.faces.len()
    );
}

#[test]
fn trim_refuses_bad_cut_files_with_their_place() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_file(dir.path());
    let run = |text: &str| {
        let cuts = dir.path().join("bad.toml");
        std::fs::write(&cuts, text).unwrap();
        let out = flatcut()
            .arg("trim")
            .arg(&input)
            .arg("--cuts")
            .arg(&cuts)
            .arg("--out")
            .arg(dir.path().join("o"))
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1));
        String::from_utf8_lossy(&out.stderr).to_string()
    };
    // An unknown key, on line 4 column 1.
    let err = run("units = \"cm\"\n[[cut]]\nname = \"a\"\nshape = 3\n");
    assert!(err.contains("bad.toml:4:1"), "{err}");
    assert!(err.contains("shape"), "{err}");
    // Bad units.
    let err = run("units = \"furlong\"\n");
    assert!(err.contains("units") && err.contains("furlong"), "{err}");
    // A landmark 3 cm off the sphere, named.
    let err = run(&CUTS.replace("[0.0, 10.0, 0.0]", "[0.0, 13.0, 0.0]"));
    assert!(err.contains("line \"crown\" point 1"), "{err}");
    // A piece name that is no file name.
    let err = run(&CUTS.replace("name = \"south\"", "name = \"../south\""));
    assert!(err.contains("../south"), "{err}");
}

/// A piece named like the input mesh in the output folder would overwrite it: refused before
/// anything is written, the input untouched.
#[test]
fn trim_refuses_to_write_a_piece_over_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let sphere = sphere_file(dir.path());
    let input = out_dir.join("south.obj");
    std::fs::rename(&sphere, &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    let cuts = dir.path().join("cuts.toml");
    std::fs::write(&cuts, CUTS).unwrap();
    let err = refused([
        "trim".as_ref(),
        input.as_os_str(),
        "--cuts".as_ref(),
        cuts.as_os_str(),
        "--out".as_ref(),
        out_dir.as_os_str(),
    ]);
    assert!(
        err.contains("piece \"south\"") && err.contains("is the input IN"),
        "{err}"
    );
    assert_eq!(std::fs::read(&input).unwrap(), before);
    assert!(!out_dir.join("seams.json").exists());
}
