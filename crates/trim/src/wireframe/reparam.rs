//! Re-parametrisation passes: where the lift squeezes triangles, the patch is flattened
//! conformally, its boundary and guide samples re-triangulated in that flattening (where 2D
//! angles are close to 3D angles) and lifted again.

use flatcut_lscm::LscmOptions;
use flatcut_mesh::TriMesh;

use super::cdt::{Meshed, triangulate};
use super::geom::{cross2, diagonal, first_crossing, signed_area};
use super::lift::{Lift, lift};
use super::measure::min_angle_deg;
use super::sampling::{EdgeOnInput, Node};
use super::{TOUCH_RELATIVE, WireCurve, WireframeOptions};

/// One re-parametrisation pass: conformal flattening (LSCM) of the lifted patch, the nodes
/// re-placed there, re-triangulated and lifted. `None` if the flattening is unusable (folds,
/// a self-crossing boundary) or the triangulation fails; the caller keeps what it has.
#[allow(clippy::too_many_arguments)]
pub(super) fn reparametrise(
    meshed: &Meshed,
    positions: &[[f64; 3]],
    nodes: &[Node],
    n_boundary: usize,
    edges: &[[usize; 2]],
    edge_info: &[EdgeOnInput],
    tri_area: f64,
    opts: &WireframeOptions,
    guides: &[WireCurve],
) -> Option<(Meshed, Vec<[f64; 3]>, f64)> {
    let flat = conformal_flattening(positions, &meshed.faces)?;
    let mut nodes2 = nodes.to_vec();
    let mut seen = vec![false; nodes.len()];
    for (v, n) in meshed.node_of.iter().enumerate() {
        if let Some(n) = *n {
            nodes2[n].p2 = flat[v];
            seen[n] = true;
        }
    }
    if seen.iter().any(|s| !s) {
        return None;
    }
    let poly: Vec<[f64; 2]> = nodes2[..n_boundary].iter().map(|n| n.p2).collect();
    let area2 = signed_area(&poly);
    if area2 <= 0.0 {
        return None;
    }
    let d = diagonal(positions.iter().copied());
    if first_crossing(&poly, TOUCH_RELATIVE * d).is_some() {
        return None;
    }
    // Same number of triangles as asked in 3D: scale the area limit by the flattening's
    // overall area ratio.
    let area3 = flatcut_mesh::geometry::face_areas(positions, &meshed.faces)
        .iter()
        .sum::<f64>();
    let m = triangulate(
        &nodes2,
        n_boundary,
        edges,
        edge_info,
        tri_area * area2 / area3,
        opts.domain_min_angle_deg,
        opts.max_vertices,
        guides,
    )
    .ok()?;
    let p = lift(&m.domain, &m.faces, &m.fixed3, Lift::Xyz).ok()?;
    let a = min_angle_deg(&p, &m.faces);
    Some((m, p, a))
}

/// Conformal flattening of the lifted patch: `flatcut_lscm`'s free-boundary LSCM (Lévy et
/// al. 2002; pins: the boundary's 3D diameter pair at their true distance, so a developable
/// patch comes out at true size). `None` if the patch is refused (e.g. a degenerate face) or
/// a triangle comes out folded; the caller then keeps the patch it has.
fn conformal_flattening(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Option<Vec<[f64; 2]>> {
    let mesh = TriMesh {
        positions: positions.to_vec(),
        faces: faces.to_vec(),
        ..TriMesh::default()
    };
    let flat = flatcut_lscm::lscm(&mesh, &LscmOptions::default()).ok()?;
    if flat.pieces.len() != 1 {
        return None;
    }
    let uv = flat.uv;
    let folded = faces
        .iter()
        .any(|f| cross2(uv[f[0] as usize], uv[f[1] as usize], uv[f[2] as usize]) <= 0.0);
    (!folded).then_some(uv)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::super::geom::dist2;
    use super::*;
    use flatcut_mesh::vec3::dist;

    /// LSCM of a planar, irregular mesh is the mesh itself up to a rigid motion (the pins
    /// are at their true distance): every edge keeps its length.
    #[test]
    fn lscm_reproduces_a_planar_mesh() {
        // A 5×4 grid, jittered, in a tilted plane.
        let (nx, ny) = (5, 4);
        let mut pos = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (
                    10.0 * i as f64 + 1.7 * ((i * 7 + j * 3) % 5) as f64 / 5.0,
                    10.0 * j as f64 + 1.3 * ((i * 2 + j * 5) % 7) as f64 / 7.0,
                );
                pos.push([x, 0.6 * y, 0.8 * y + 5.0]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let v = (i + nx * j) as u32;
                let n = nx as u32;
                faces.push([v, v + 1, v + n + 1]);
                faces.push([v, v + n + 1, v + n]);
            }
        }
        let uv = conformal_flattening(&pos, &faces).unwrap();
        for f in &faces {
            for k in 0..3 {
                let (a, b) = (f[k] as usize, f[(k + 1) % 3] as usize);
                let l3 = dist(pos[a], pos[b]);
                let l2 = dist2(uv[a], uv[b]);
                assert!((l3 - l2).abs() < 1e-9 * l3, "edge {a}-{b}: {l3} vs {l2}");
            }
        }
    }
}
