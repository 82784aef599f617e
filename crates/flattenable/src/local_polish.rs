//! Local polish: the end of a robust run on a large piece solved on a small region.
//!
//! Near θ = 2π the residual of a large piece is local: on the 100k-face bench cap, once
//! θ_err is near 1.5e-8 fewer than 60 of its 49 729 interior vertices are still above the
//! 1e-9 tolerance, yet every global step factorises A G Aᵀ over all of them and moves them
//! all (the last 15 iterations of that run). Here the vertices still above the tolerance,
//! grown by [`MOVING_RINGS`] rings, move, and their neighbours one ring farther are held
//! (a weight of [`HELD_WEIGHT`]) but keep their constraint rows. Every other vertex keeps
//! its position and, since its star contains no moving vertex, its θ: the region's own
//! least-norm problem is the piece's, restricted to the region's unknowns, and its
//! factorisations are those of a small matrix.

use flatcut_mesh::{Topology, TriMesh, VertexId};

use crate::options::{ProcessOptions, Target, Update};
use crate::piece::Piece;
use crate::report::PieceReport;

/// Rings of neighbours added around the vertices above the tolerance to make the moving set:
/// the least-norm step spreads a correction over a few rings, and a held rim right next to
/// a corrected vertex would make its step longer (measured below in
/// docs/algorithms/flattenable.md, "Local polish").
pub(crate) const MOVING_RINGS: usize = 3;
/// Weight of the held rim: 1/w² = 1e-16 of a free vertex's metric, so they move by round-off
/// at most, while their rows keep their θ at 2π as the moving vertices next to them move.
const HELD_WEIGHT: f64 = 1e8;
/// A rim vertex above this fraction of the tolerance moves instead of being held.
const RIM_FRACTION: f64 = 0.25;

/// A region of a piece and the way back.
pub(crate) struct Region {
    /// The region as a piece of its own: input positions, the moving vertices at their
    /// weights, every other interior vertex held.
    pub piece: Piece,
    /// Vertex of the parent piece (local index) of each region vertex.
    pub parent_of: Vec<u32>,
}

/// The region around the parent's interior vertices `active` (interior indices), or `None`
/// when the region would hold more than `max_interior` interior vertices (a global step is
/// then as cheap) or cannot be built.
pub(crate) fn region(
    piece: &Piece,
    active: &[usize],
    theta: &[f64],
    tolerance_rad: f64,
    max_interior: usize,
    min_angle_deg: f64,
) -> Option<Region> {
    let layout = &piece.layout;
    let nv = piece.pos0.len();
    // Moving: the active vertices and MOVING_RINGS rings of interior neighbours.
    let mut moving = vec![false; nv];
    let mut front: Vec<u32> = active.iter().map(|&i| layout.interior[i]).collect();
    for &p in &front {
        moving[p as usize] = true;
    }
    for _ in 0..MOVING_RINGS {
        let mut next = Vec::new();
        for &p in &front {
            for &q in piece.topo.one_ring(VertexId(p)).unwrap_or(&[]) {
                if !moving[q as usize] && layout.index_of[q as usize] != flatcut_mesh::INVALID {
                    moving[q as usize] = true;
                    next.push(q);
                }
            }
        }
        front = next;
    }
    // The held rim must have room below the tolerance: the region's steps move its θ at
    // second order, and a rim vertex at the tolerance pushed over it cannot be brought back
    // by its few moving neighbours (measured: the region's run then stalls at 1.03 × the
    // tolerance). Rim vertices above RIM_FRACTION of it move too, until none is left.
    let rim_limit = RIM_FRACTION * tolerance_rad;
    let mut grow: Vec<u32> = (0..nv as u32).filter(|&p| moving[p as usize]).collect();
    while let Some(p) = grow.pop() {
        for &q in piece.topo.one_ring(VertexId(p)).unwrap_or(&[]) {
            let i = layout.index_of[q as usize];
            if i != flatcut_mesh::INVALID
                && !moving[q as usize]
                && (theta[i as usize] - std::f64::consts::TAU).abs() > rim_limit
            {
                moving[q as usize] = true;
                grow.push(q);
            }
        }
    }
    // Constrained: the moving vertices and their interior neighbours (whose θ the moving
    // ones change); the region's faces are their stars, so each keeps its whole star.
    let mut constrained = moving.clone();
    for p in 0..nv {
        if moving[p] {
            for &q in piece.topo.one_ring(VertexId(p as u32)).unwrap_or(&[]) {
                if layout.index_of[q as usize] != flatcut_mesh::INVALID {
                    constrained[q as usize] = true;
                }
            }
        }
    }
    if constrained.iter().filter(|&&c| c).count() > max_interior {
        return None;
    }
    let mut in_region = vec![false; piece.faces.len()];
    for p in 0..nv {
        if constrained[p] {
            for f in piece.topo.vertex_faces(VertexId(p as u32)) {
                in_region[f.idx()] = true;
            }
        }
    }
    let faces: Vec<u32> = (0..piece.faces.len() as u32)
        .filter(|&f| in_region[f as usize])
        .collect();
    let parent_input = TriMesh {
        positions: piece.pos0.clone(),
        faces: piece.faces.clone(),
        ..Default::default()
    };
    let (mesh, parent_of) = flatcut_mesh::submesh(&parent_input, &faces);
    let topo = Topology::build(&mesh).ok()?;
    let parent_interior_weight = |p: u32| {
        let i = layout.index_of[p as usize];
        if i == flatcut_mesh::INVALID {
            1.0
        } else {
            piece.weights[i as usize]
        }
    };
    let weights: Vec<f64> = parent_of
        .iter()
        .map(|&p| {
            if moving[p as usize] {
                parent_interior_weight(p)
            } else {
                HELD_WEIGHT
            }
        })
        .collect();
    let vertex_map = parent_of
        .iter()
        .map(|&p| piece.vertex_map[p as usize])
        .collect();
    let sub = Piece::new(
        piece.index,
        vertex_map,
        &mesh,
        topo,
        &weights,
        min_angle_deg,
    )
    .ok()?;
    // Every constrained vertex must be interior in the region (its whole star is there):
    // otherwise the region's rows would not be the piece's.
    let all_rows = parent_of
        .iter()
        .enumerate()
        .all(|(k, &p)| !constrained[p as usize] || sub.layout.index_of[k] != flatcut_mesh::INVALID);
    all_rows.then_some(Region {
        piece: sub,
        parent_of,
    })
}

/// Options for the region's run: the plain damped steps of the zero target (no pull-backs:
/// the region is polished, not reshaped), the parent's tolerance and guards.
pub(crate) fn region_options(opts: &ProcessOptions) -> ProcessOptions {
    ProcessOptions {
        target: Target::Zero,
        update: Update::Direct,
        ..opts.clone()
    }
}

/// The region's positions taken from the parent's `positions`.
pub(crate) fn restrict(region: &Region, positions: &[[f64; 3]]) -> Vec<[f64; 3]> {
    region
        .parent_of
        .iter()
        .map(|&p| positions[p as usize])
        .collect()
}

/// The parent's `positions` with the region's interior vertices replaced from `local`.
pub(crate) fn extend(region: &Region, positions: &[[f64; 3]], local: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut out = positions.to_vec();
    for &v in &region.piece.layout.interior {
        out[region.parent_of[v as usize] as usize] = local[v as usize];
    }
    out
}

/// Adds a region run's cost to the parent's report.
pub(crate) fn account(parent: &mut PieceReport, sub: &PieceReport) {
    parent.factorizations += sub.factorizations;
    parent.corrections += sub.corrections;
    parent.smoothed_steps += sub.smoothed_steps;
    parent.rejected_steps += sub.rejected_steps;
    parent.backtracked_steps += sub.backtracked_steps;
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::f64::consts::TAU;

    use super::*;

    /// A 20×20 sphere-cap grid as a piece, and its input θ per interior vertex.
    fn cap() -> (Piece, Vec<f64>) {
        let mesh = flatcut_mesh::shapes::sphere_cap_grid(20, 1.0, 100.0);
        let topo = Topology::build(&mesh).unwrap();
        let n = mesh.vertex_count();
        let piece =
            Piece::new(0, (0..n as u32).collect(), &mesh, topo, &vec![1.0; n], 0.5).unwrap();
        let mut theta = vec![0.0; piece.layout.n()];
        piece.layout.theta(&piece.pos0, &mut theta);
        (piece, theta)
    }

    /// The interior index nearest the grid's centre.
    fn centre(piece: &Piece) -> usize {
        let c = piece
            .pos0
            .iter()
            .fold([0.0; 3], |a, p| flatcut_mesh::vec3::add(a, *p));
        let c = flatcut_mesh::vec3::scale(c, 1.0 / piece.pos0.len() as f64);
        (0..piece.layout.n())
            .min_by(|&a, &b| {
                let d = |i: usize| {
                    flatcut_mesh::vec3::dist(piece.pos0[piece.layout.interior[i] as usize], c)
                };
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    }

    /// The region's rows are the piece's: moved anywhere, its vertices give every region row
    /// the θ the piece has there, and every interior vertex of the piece outside the region
    /// keeps its θ bit for bit (its star holds no moving vertex).
    #[test]
    fn a_region_has_the_pieces_rows_and_nothing_outside_it_changes() {
        let (piece, theta) = cap();
        let active = [centre(&piece)];
        let region = region(&piece, &active, &theta, 1e-9, usize::MAX, 0.5).unwrap();
        let sub = &region.piece;
        // Move every moving vertex of the region by a few percent of an edge.
        let mut local = restrict(&region, &piece.pos0);
        let mut moved = 0;
        for (i, &v) in sub.layout.interior.iter().enumerate() {
            if sub.weights[i] < HELD_WEIGHT {
                let k = v as f64;
                local[v as usize][2] += 0.3 * (0.7 * k).sin();
                local[v as usize][0] += 0.2 * (1.3 * k).cos();
                moved += 1;
            }
        }
        // The active vertex and three rings: 1 + 6 + 12 + 18 on a regular grid (37), or a few
        // more with alternating diagonals.
        assert!(moved >= 25, "{moved}");
        let whole = extend(&region, &piece.pos0, &local);
        let mut theta_whole = vec![0.0; piece.layout.n()];
        piece.layout.theta(&whole, &mut theta_whole);
        let mut theta_sub = vec![0.0; sub.layout.n()];
        sub.layout.theta(&local, &mut theta_sub);
        let mut in_region = vec![false; piece.layout.n()];
        for (i, &v) in sub.layout.interior.iter().enumerate() {
            let p = region.parent_of[v as usize];
            let j = piece.layout.index_of[p as usize] as usize;
            assert_eq!(theta_sub[i].to_bits(), theta_whole[j].to_bits());
            in_region[j] = true;
        }
        let mut changed_inside = 0;
        for j in 0..piece.layout.n() {
            if in_region[j] {
                changed_inside += usize::from(theta_whole[j] != theta[j]);
            } else {
                assert_eq!(theta_whole[j].to_bits(), theta[j].to_bits(), "vertex {j}");
            }
        }
        assert!(changed_inside >= moved, "{changed_inside}");
    }

    /// Held vertices keep their rows and a weight that pins them; a rim vertex near the
    /// tolerance moves instead of being held.
    #[test]
    fn the_rim_is_held_unless_it_is_near_the_tolerance() {
        let (piece, _) = cap();
        let n = piece.layout.n();
        let active = centre(&piece);
        let tol = 1e-9;
        // Synthetic residuals: the active vertex far above the tolerance, the rest flat.
        let mut theta = vec![TAU; n];
        theta[active] = TAU + 100.0 * tol;
        let held = |r: &Region| -> Vec<u32> {
            r.piece
                .layout
                .interior
                .iter()
                .enumerate()
                .filter(|&(i, _)| r.piece.weights[i] == HELD_WEIGHT)
                .map(|(_, &v)| r.parent_of[v as usize])
                .collect()
        };
        let first = region(&piece, &[active], &theta, tol, usize::MAX, 0.5).unwrap();
        let rim = held(&first);
        assert!(!rim.is_empty());
        // One rim vertex just under the tolerance: it moves now, and the rim goes around it.
        let near = rim[0];
        theta[piece.layout.index_of[near as usize] as usize] = TAU - 0.9 * tol;
        let second = region(&piece, &[active], &theta, tol, usize::MAX, 0.5).unwrap();
        assert!(!held(&second).contains(&near));
        assert!(second.piece.layout.n() > first.piece.layout.n());
        // Far below the tolerance it stays held.
        theta[piece.layout.index_of[near as usize] as usize] = TAU - 0.1 * tol;
        let third = region(&piece, &[active], &theta, tol, usize::MAX, 0.5).unwrap();
        assert!(held(&third).contains(&near));
        // A region larger than allowed is not built.
        let size = third.piece.layout.n();
        assert!(region(&piece, &[active], &theta, tol, size / 2, 0.5).is_none());
    }
}
