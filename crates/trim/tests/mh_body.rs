//! The wetsuit cut of the MakeHuman body (fixtures/cuts/mh_body_wetsuit.toml) on
//! $FLATCUT_DATA/mh_body.obj: ten disk pieces, head, hands and feet dropped, every seam's
//! mates equal in 3D length. Skipped (passes) only when FLATCUT_DATA is unset.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_trim::{Cuts, trim};

#[test]
fn mh_body_wetsuit_cut_gives_disks_and_equal_mates() {
    let Some(dir) = std::env::var_os("FLATCUT_DATA") else {
        eprintln!("FLATCUT_DATA unset: skipping mh_body");
        return;
    };
    let path = std::path::PathBuf::from(dir).join("mh_body.obj");
    assert!(
        path.exists(),
        "FLATCUT_DATA is set but {} is missing",
        path.display()
    );
    let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Dm)
        .unwrap()
        .mesh;
    let fixture = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/cuts/mh_body_wetsuit.toml"
    );
    let mut cuts: Cuts = toml::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
    assert_eq!(cuts.units.as_deref(), Some("dm"));
    cuts.scale(100.0);
    let t = trim(&mesh, &cuts).unwrap();
    common::check_conservation(&mesh, &t);

    assert_eq!(t.pieces.len(), 10);
    for p in &t.report.pieces {
        assert!(p.disk, "{p:?}");
    }
    // Head, two hands, two feet: unnamed, dropped, and still accounted for.
    let dropped: Vec<_> = t.report.pieces.iter().filter(|p| !p.kept).collect();
    assert_eq!(dropped.len(), 5);
    let faces: usize = t.report.pieces.iter().map(|p| p.faces).sum();
    assert_eq!(faces, t.embedded.mesh.faces.len());

    // 4 waist + 4 centre + per side (2 arm hole, 1 shoulder, 2 side, 1 underarm, 1 inseam).
    assert_eq!(t.ledger.seams.len(), 22);
    // Only the underarm seams sew a piece (the sleeve tube) to itself.
    for s in &t.ledger.seams {
        assert_eq!(
            s.a.piece == s.b.piece,
            s.line.starts_with("underarm"),
            "{}",
            s.id
        );
    }
    // Left and right mirror each other: the mirrored seams agree in length to well under a
    // millimetre (the template is symmetric up to its vertex precision).
    let len = |id: &str| {
        t.ledger
            .seams
            .iter()
            .find(|s| s.id == id)
            .unwrap()
            .length_3d_mm
    };
    for id in ["side-{}/0", "side-{}/1", "underarm-{}/0", "inseam-{}/0"] {
        let (l, r) = (
            len(&id.replace("{}", "left")),
            len(&id.replace("{}", "right")),
        );
        assert!((l - r).abs() < 1.0, "{id}: {l} vs {r}");
    }
}
