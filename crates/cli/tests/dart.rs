//! `flatcut dart` end to end: a bump piece in, the darted piece and its seam ledger out;
//! suggestions; bad darts refused with exit code 1, naming the dart, writing nothing.

#![allow(clippy::unwrap_used)]

mod common;

use common::{flatcut, refused};

use std::path::Path;

use flatcut_io::{Units, WriteOptions, read_mesh, write_mesh};
use flatcut_mesh::{SeamKind, SeamLedger, TriMesh, shapes};

/// z = 30·exp(−r²/40²) over a disk of radius 100 mm, 6 rings; the top is vertex 0.
fn bump() -> TriMesh {
    let mut m = shapes::planar_disk(100.0, 6);
    for p in &mut m.positions {
        p[2] = 30.0 * (-(p[0] * p[0] + p[1] * p[1]) / 1600.0).exp();
    }
    m
}

fn write(path: &Path, m: &TriMesh, units: Units) {
    let opts = WriteOptions {
        units: Some(units),
        ..Default::default()
    };
    write_mesh(path, m, &opts).unwrap();
}

#[test]
fn dart_writes_the_piece_and_its_seam() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("back.obj");
    let m = bump();
    write(&input, &m, Units::Cm);
    let out = dir.path().join("back_darted.obj");
    // Points in cm: the rim at (10, 0, ~0) and the top (0, 0, 3).
    let rim = m.positions[1 + 3 * 6 * 5];
    let r = flatcut()
        .arg("dart")
        .arg(&input)
        .arg(&out)
        .args(["--units", "cm", "--from"])
        .arg(format!(
            "{},{},{}",
            rim[0] / 10.0,
            rim[1] / 10.0,
            rim[2] / 10.0
        ))
        .args(["--tip", "0,0,3", "--json"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let json: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let darts = json["darts"].as_array().unwrap();
    assert_eq!(darts.len(), 1);
    assert_eq!(darts[0]["tip_vertex"], 0);
    let seams_path = dir.path().join("back_darted.seams.json");
    assert_eq!(
        json["seams"].as_str().unwrap(),
        seams_path.to_str().unwrap()
    );
    let ledger: SeamLedger =
        serde_json::from_str(&std::fs::read_to_string(&seams_path).unwrap()).unwrap();
    ledger.check().unwrap();
    assert_eq!(ledger.pieces, vec!["back".to_string()]);
    assert_eq!(ledger.seams.len(), 1);
    let s = &ledger.seams[0];
    assert_eq!(s.kind, SeamKind::Dart);
    assert_eq!(s.a.vertices[0], 0);
    assert_eq!(s.b.vertices[0], 0);
    // The 3D length in mm: at least the chord from the rim to the top.
    let chord = flatcut_mesh::vec3::dist(rim, m.positions[0]);
    assert!(
        s.length_3d_mm >= chord && s.length_3d_mm < 1.1 * chord,
        "{}",
        s.length_3d_mm
    );
    // The piece came back in cm (as --units says), opened along the dart: both legs'
    // vertices after the tip are distinct copies at the same place.
    let back = read_mesh(&out, Units::Cm).unwrap().mesh;
    assert!(back.positions.len() > m.positions.len());
    for k in 1..s.a.vertices.len() {
        let (a, b) = (s.a.vertices[k] as usize, s.b.vertices[k] as usize);
        assert_ne!(a, b);
        assert!(flatcut_mesh::vec3::dist(back.positions[a], back.positions[b]) < 1e-9);
    }
}

#[test]
fn suggest_proposes_the_top() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bump.obj");
    write(&input, &bump(), Units::Mm);
    let r = flatcut()
        .arg("dart")
        .arg(&input)
        .args(["--suggest", "2", "--json"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let json: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let s = json["suggestions"].as_array().unwrap();
    assert!(!s.is_empty());
    // Tip within two rings (2 × 100/6 mm) of the top.
    let tip: Vec<f64> = s[0]["tip"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(tip[0].hypot(tip[1]) <= 2.0 * 100.0 / 6.0 + 1e-9, "{tip:?}");
    // Text mode prints commands one can paste back.
    let r = flatcut()
        .arg("dart")
        .arg(&input)
        .args(["--suggest", "1"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&r.stdout);
    assert!(text.contains("--from") && text.contains("--tip"), "{text}");
}

#[test]
fn bad_darts_fail_naming_the_dart_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bump.obj");
    write(&input, &bump(), Units::Mm);
    let out = dir.path().join("out.obj");
    let run = |extra: &[&str]| {
        flatcut()
            .arg("dart")
            .arg(&input)
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    // Start in the middle of the piece.
    let r = run(&["--from", "20,0,20", "--tip", "0,0,30"]);
    assert_eq!(r.status.code(), Some(1));
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(
        e.contains("dart 0 \"dart-1\"") && e.contains("boundary"),
        "{e}"
    );
    // Tip off the piece, second dart.
    let r = run(&[
        "--from", "100,0,0", "--tip", "0,0,30", "--from", "-100,0,0", "--tip", "0,0,90",
    ]);
    assert_eq!(r.status.code(), Some(1));
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(e.contains("dart-2") && e.contains("surface"), "{e}");
    // Unpaired --from.
    let r = run(&["--from", "100,0,0"]);
    assert_eq!(r.status.code(), Some(1));
    // Not a point.
    let r = run(&["--from", "100,0", "--tip", "0,0,30"]);
    assert_ne!(r.status.code(), Some(0));
    assert!(!out.exists());
    assert!(!dir.path().join("out.seams.json").exists());
}

#[test]
fn darts_join_an_existing_ledger() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("back.obj");
    let m = bump();
    write(&input, &m, Units::Mm);
    // A ledger in which the whole rim of "back" is sewn to a piece "front".
    let topo = flatcut_mesh::Topology::build(&m).unwrap();
    let rim: Vec<u32> = topo.boundary_loops()[0].iter().map(|v| v.0).collect();
    let mut ledger = SeamLedger::new(vec!["front".into(), "back".into()]);
    ledger.seams.push(flatcut_mesh::Seam {
        id: "rim/0".into(),
        line: "rim".into(),
        kind: SeamKind::Seam,
        a: flatcut_mesh::SeamSide {
            piece: "back".into(),
            vertices: rim.clone(),
        },
        b: flatcut_mesh::SeamSide {
            piece: "front".into(),
            vertices: (0..rim.len() as u32).collect(),
        },
        length_3d_mm: 600.0,
        start_mm: [0.0; 3],
        end_mm: [0.0; 3],
    });
    let ledger_in = dir.path().join("seams.json");
    std::fs::write(&ledger_in, serde_json::to_string(&ledger).unwrap()).unwrap();
    let start = m.positions[rim[4] as usize];
    let out = dir.path().join("back_darted.obj");
    let seams_out = dir.path().join("all_seams.json");
    let r = flatcut()
        .arg("dart")
        .arg(&input)
        .arg(&out)
        .arg("--from")
        .arg(format!("{},{},{}", start[0], start[1], start[2]))
        .args(["--tip", "0,0,30", "--ledger"])
        .arg(&ledger_in)
        .arg("--seams")
        .arg(&seams_out)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let l: SeamLedger =
        serde_json::from_str(&std::fs::read_to_string(&seams_out).unwrap()).unwrap();
    l.check().unwrap();
    let ids: Vec<&str> = l.seams.iter().map(|s| s.id.as_str()).collect();
    assert_eq!(ids, ["dart-1/0", "rim/0.1", "rim/0.2"]);
    // The input ledger is untouched; writing over it is refused.
    let again: SeamLedger =
        serde_json::from_str(&std::fs::read_to_string(&ledger_in).unwrap()).unwrap();
    assert_eq!(again, ledger);
    let r = flatcut()
        .arg("dart")
        .arg(&input)
        .arg(&out)
        .arg("--from")
        .arg(format!("{},{},{}", start[0], start[1], start[2]))
        .args(["--tip", "0,0,30", "--ledger"])
        .arg(&ledger_in)
        .arg("--seams")
        .arg(&ledger_in)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(1));
}

/// The seam ledger written over the ledger read (`--seams` = `--ledger`), or the darted piece
/// over its input: refused before anything is read or written.
#[test]
fn dart_refuses_to_overwrite_its_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bump.obj");
    write(&input, &bump(), Units::Mm);
    let before = std::fs::read(&input).unwrap();
    let ledger = dir.path().join("ledger.json");
    let out = dir.path().join("out.obj");
    let err = refused([
        "dart".as_ref(),
        input.as_os_str(),
        out.as_os_str(),
        "--suggest".as_ref(),
        "1".as_ref(),
        "--ledger".as_ref(),
        ledger.as_os_str(),
        "--seams".as_ref(),
        ledger.as_os_str(),
    ]);
    assert!(
        err.contains("--seams") && err.contains("is the input --ledger"),
        "{err}"
    );
    let err = refused([
        "dart".as_ref(),
        input.as_os_str(),
        input.as_os_str(),
        "--suggest".as_ref(),
        "1".as_ref(),
    ]);
    assert!(err.contains("is the input IN"), "{err}");
    assert_eq!(std::fs::read(&input).unwrap(), before);
    assert!(!out.exists());
}
