//! A small pattern for the export tests: a rectangle cut in two along a seam (left piece cut
//! as a mirrored pair), with made-up per-face values.
#![allow(dead_code, clippy::unwrap_used)]

use flatcut_mesh::{Seam, SeamKind, SeamLedger, SeamSide, TriMesh};
use flatcut_pattern::{
    Layout, LayoutOptions, PatternOptions, PatternPiece, PieceInput, PieceMeta, build_pieces,
    layout,
};

pub fn grid(x0: f64, w: f64, h: f64, nx: usize, ny: usize) -> TriMesh {
    let mut positions = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            positions.push([
                x0 + w * i as f64 / (nx - 1) as f64,
                h * j as f64 / (ny - 1) as f64,
                0.0,
            ]);
        }
    }
    let mut faces = Vec::new();
    let id = |i: usize, j: usize| (j * nx + i) as u32;
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh {
        positions,
        faces,
        ..Default::default()
    }
}

pub fn input(name: &str, mesh: TriMesh, meta: PieceMeta) -> PieceInput {
    let uv: Vec<[f64; 2]> = mesh.positions.iter().map(|p| [p[0], p[1]]).collect();
    let nf = mesh.faces.len();
    PieceInput {
        name: name.into(),
        uv,
        meta,
        internal_lines: vec![],
        e_h: (0..nf).map(|f| 0.01 * f as f64 / nf as f64).collect(),
        e_r: (0..nf)
            .map(|f| 0.02 * (nf - f) as f64 / nf as f64)
            .collect(),
        edge_strain: vec![],
        mesh,
    }
}

/// Two pieces (front-left mirrored ×2, front-right ×1) and their sheet layout.
pub fn sample() -> (Vec<PatternPiece>, Layout) {
    let left = input(
        "front-left",
        grid(0.0, 100.0, 60.0, 6, 4),
        PieceMeta {
            size: "38".into(),
            quantity: 2,
            mirror: true,
            fabric: "neoprène 3 mm".into(),
            ..Default::default()
        },
    );
    let mut right = input(
        "front-right",
        grid(100.0, 80.0, 60.0, 5, 4),
        PieceMeta::default(),
    );
    right.internal_lines = vec![vec![1, 6, 11, 16]];
    let mut ledger = SeamLedger::new(vec!["front-left".into(), "front-right".into()]);
    ledger.seams.push(Seam {
        id: "centre/0".into(),
        line: "centre".into(),
        kind: SeamKind::Seam,
        a: SeamSide {
            piece: "front-left".into(),
            vertices: vec![5, 11, 17, 23],
        },
        b: SeamSide {
            piece: "front-right".into(),
            vertices: vec![0, 5, 10, 15],
        },
        length_3d_mm: 60.0,
        start_mm: [100.0, 0.0, 0.0],
        end_mm: [100.0, 60.0, 0.0],
    });
    let pieces = build_pieces(&[left, right], Some(&ledger), &PatternOptions::default()).unwrap();
    let lay = layout(
        &pieces,
        &LayoutOptions {
            sheet_width_mm: 400.0,
            ..Default::default()
        },
    )
    .unwrap();
    (pieces, lay)
}

/// Compares `bytes` with fixtures/golden/`name`, or rewrites it when FLATCUT_BLESS=1.
pub fn golden(name: &str, bytes: &[u8]) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/golden")
        .join(name);
    if std::env::var("FLATCUT_BLESS").as_deref() == Ok("1") {
        std::fs::write(&path, bytes).unwrap();
        return;
    }
    let want = std::fs::read(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; run with FLATCUT_BLESS=1 to create it",
            path.display()
        )
    });
    assert!(
        want == bytes,
        "{} differs from the output; if the change is intended, re-run with FLATCUT_BLESS=1 and review the diff",
        path.display()
    );
}
