//! Exact unfolding of a developable piece: triangles are laid down one by one in
//! breadth-first order across shared edges, each new vertex placed from its two 3D edge
//! lengths on the left of the shared edge (so that counter-clockwise faces stay
//! counter-clockwise). On a perfectly developable, simply placed piece this is an isometry
//! by construction; on any other piece, vertices reached along different paths disagree,
//! and the largest disagreement is reported. Used as an independent cross-check of the
//! LSCM + refinement result.

use std::collections::VecDeque;

use flatcut_mesh::vec3::dist;

use crate::piece::Piece;

/// The result of [`unfold`].
#[derive(Clone, Debug, PartialEq)]
pub struct Unfolding {
    /// 2D position of each local vertex of the piece (mm); the first placement wins.
    pub uv: Vec<[f64; 2]>,
    /// Largest distance (mm) between a vertex's first placement and a later one reached
    /// through another face (0 for a developable piece, up to rounding).
    pub max_mismatch_mm: f64,
}

/// The point c with |c − b| = `lb`, |c − a| = `la`, on the left of the directed line b → a
/// (the height is clamped at 0 when the lengths violate the triangle inequality).
fn apex(b: [f64; 2], a: [f64; 2], lb: f64, la: f64) -> [f64; 2] {
    let e = [a[0] - b[0], a[1] - b[1]];
    let l = e[0].hypot(e[1]);
    let ex = [e[0] / l, e[1] / l];
    let s = (lb * lb - la * la + l * l) / (2.0 * l);
    let h = (lb * lb - s * s).max(0.0).sqrt();
    [b[0] + s * ex[0] - h * ex[1], b[1] + s * ex[1] + h * ex[0]]
}

/// Unfolds `piece` breadth-first from its first face (corner 0 at the origin, corner 1 on
/// +x). Vertices of faces unreachable across edges stay at (0, 0) (a piece from
/// [`crate::split_pieces`] is edge-connected, so that does not happen).
pub fn unfold(piece: &Piece) -> Unfolding {
    let n = piece.positions.len();
    let faces = &piece.local_faces;
    let mut uv = vec![[0.0; 2]; n];
    let mut placed = vec![false; n];
    let mut mismatch: f64 = 0.0;
    if faces.is_empty() {
        return Unfolding {
            uv,
            max_mismatch_mm: 0.0,
        };
    }
    // Directed edge (a, b) → face, for finding the face across an edge as (b, a).
    let mut directed: Vec<((u32, u32), u32)> = faces
        .iter()
        .enumerate()
        .flat_map(|(fi, f)| (0..3).map(move |k| ((f[k], f[(k + 1) % 3]), fi as u32)))
        .collect();
    directed.sort_unstable();
    let across = |a: u32, b: u32| {
        directed
            .binary_search_by(|probe| probe.0.cmp(&(b, a)))
            .ok()
            .map(|i| directed[i].1 as usize)
    };
    let len = |i: u32, j: u32| dist(piece.positions[i as usize], piece.positions[j as usize]);
    let f0 = faces[0];
    uv[f0[0] as usize] = [0.0, 0.0];
    uv[f0[1] as usize] = [len(f0[0], f0[1]), 0.0];
    uv[f0[2] as usize] = apex(
        uv[f0[0] as usize],
        uv[f0[1] as usize],
        len(f0[2], f0[0]),
        len(f0[2], f0[1]),
    );
    for v in f0 {
        placed[v as usize] = true;
    }
    let mut visited = vec![false; faces.len()];
    visited[0] = true;
    let mut queue = VecDeque::from([0usize]);
    while let Some(fi) = queue.pop_front() {
        let f = faces[fi];
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let Some(g) = across(a, b) else { continue };
            if visited[g] {
                continue;
            }
            visited[g] = true;
            let gf = faces[g];
            let Some(c) = gf.iter().copied().find(|&v| v != a && v != b) else {
                continue;
            };
            // Face g runs b → a, so its third vertex lies left of b → a.
            let p = apex(uv[b as usize], uv[a as usize], len(c, b), len(c, a));
            if placed[c as usize] {
                let q = uv[c as usize];
                mismatch = mismatch.max((p[0] - q[0]).hypot(p[1] - q[1]));
            } else {
                uv[c as usize] = p;
                placed[c as usize] = true;
            }
            queue.push_back(g);
        }
    }
    Unfolding {
        uv,
        max_mismatch_mm: mismatch,
    }
}
