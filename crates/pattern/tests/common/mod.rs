//! Hand-made pieces and ledgers for the pattern tests.
#![allow(dead_code)]

use flatcut_mesh::TriMesh;
use flatcut_pattern::{PieceInput, PieceMeta};

/// A planar grid [x0, x0+w] × [0, h] with nx × ny vertices, faces counter-clockwise.
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

/// A flat piece whose 2D coordinates are its x, y.
pub fn flat_piece(name: &str, mesh: TriMesh) -> PieceInput {
    let uv = mesh.positions.iter().map(|p| [p[0], p[1]]).collect();
    PieceInput {
        name: name.into(),
        mesh,
        uv,
        meta: PieceMeta::default(),
        internal_lines: vec![],
        e_h: vec![],
        e_r: vec![],
        edge_strain: vec![],
    }
}

/// Distance from p to the polyline (open).
pub fn polyline_arc_of(p: [f64; 2], pts: &[[f64; 2]]) -> (f64, f64) {
    // (distance to the polyline, arc length of the nearest point)
    let mut best = (f64::INFINITY, 0.0);
    let mut acc = 0.0;
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let ab = [b[0] - a[0], b[1] - a[1]];
        let l2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / l2).clamp(0.0, 1.0);
        let q = [a[0] + t * ab[0], a[1] + t * ab[1]];
        let d = (p[0] - q[0]).hypot(p[1] - q[1]);
        if d < best.0 {
            best = (d, acc + t * l2.sqrt());
        }
        acc += l2.sqrt();
    }
    best
}
