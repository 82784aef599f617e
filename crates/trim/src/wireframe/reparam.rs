//! Re-parametrisation passes: where the lift squeezes triangles, the patch is flattened
//! conformally, its boundary and guide samples re-triangulated in that flattening (where 2D
//! angles are close to 3D angles) and lifted again.

use flatcut_mesh::vec3::{cross, dist, dot, norm, scale, sub};

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
    let flat = lscm(positions, &meshed.faces)?;
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

/// Least-squares conformal map (Lévy et al. 2002) of a disk patch, two far-apart vertices
/// pinned at their 3D distance: per face the residual Σ_k W_k U_k / √(2A) with
/// W_k = z_(k+2) − z_(k+1) in the face's own 2D frame (zero for every orientation-preserving
/// similarity). `None` if the solve fails or a triangle comes out folded.
fn lscm(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Option<Vec<[f64; 2]>> {
    let n = positions.len();
    // Pins: a vertex farthest from vertex 0, then the one farthest from it.
    let far = |from: usize| {
        (0..n)
            .max_by(|&a, &b| {
                dist(positions[a], positions[from]).total_cmp(&dist(positions[b], positions[from]))
            })
            .unwrap_or(0)
    };
    let p0 = far(0);
    let p1 = far(p0);
    if p0 == p1 {
        return None;
    }
    let pinned = |v: usize| v == p0 || v == p1;
    let pin_value = |v: usize| -> [f64; 2] {
        if v == p0 {
            [0.0, 0.0]
        } else {
            [dist(positions[p0], positions[p1]), 0.0]
        }
    };
    // Free unknowns: (u, v) of every unpinned vertex.
    let mut col = vec![usize::MAX; n];
    let mut m = 0;
    for (v, c) in col.iter_mut().enumerate() {
        if !pinned(v) {
            *c = m;
            m += 1;
        }
    }
    let nf = 2 * m;
    let mut pairs = Vec::with_capacity(faces.len() * 36);
    let mut vals = Vec::with_capacity(faces.len() * 36);
    let mut rhs = vec![0.0; nf];
    for f in faces {
        let [a, b, c] = f.map(|v| positions[v as usize]);
        let e1 = sub(b, a);
        let l1 = norm(e1);
        let nrm = cross(e1, sub(c, a));
        let twice_area = norm(nrm);
        if l1 == 0.0 || twice_area == 0.0 {
            continue;
        }
        let x = scale(e1, 1.0 / l1);
        let y = cross(scale(nrm, 1.0 / twice_area), x);
        let z = [
            [0.0, 0.0],
            [l1, 0.0],
            [dot(sub(c, a), x), dot(sub(c, a), y)],
        ];
        let w = 1.0 / twice_area.sqrt();
        // Two real rows: Re and Im of Σ W_k (u_k + i v_k).
        let mut rows = [[(0usize, 0.0f64); 6]; 2];
        for k in 0..3 {
            let wr = (z[(k + 2) % 3][0] - z[(k + 1) % 3][0]) * w;
            let wi = (z[(k + 2) % 3][1] - z[(k + 1) % 3][1]) * w;
            let v = f[k] as usize;
            rows[0][2 * k] = (2 * v, wr);
            rows[0][2 * k + 1] = (2 * v + 1, -wi);
            rows[1][2 * k] = (2 * v, wi);
            rows[1][2 * k + 1] = (2 * v + 1, wr);
        }
        let free = |var: usize| {
            let c = col[var / 2];
            (c != usize::MAX).then(|| 2 * c + var % 2)
        };
        for row in &rows {
            // Pinned part moves to the right-hand side.
            let mut fixed_part = 0.0;
            for &(var, coef) in row {
                if free(var).is_none() {
                    fixed_part += coef * pin_value(var / 2)[var % 2];
                }
            }
            for &(vi, ci) in row {
                let Some(i) = free(vi) else { continue };
                rhs[i] -= ci * fixed_part;
                for &(vj, cj) in row {
                    let Some(j) = free(vj) else { continue };
                    if i >= j {
                        pairs.push((i, j));
                        vals.push(ci * cj);
                    }
                }
            }
        }
    }
    let pattern = flatcut_sparse::SpdPattern::new(nf, &pairs).ok()?;
    let factor = pattern.factor(&vals).ok()?;
    factor.solve_in_place(&mut rhs, 1).ok()?;
    let uv: Vec<[f64; 2]> = (0..n)
        .map(|v| {
            if pinned(v) {
                pin_value(v)
            } else {
                [rhs[2 * col[v]], rhs[2 * col[v] + 1]]
            }
        })
        .collect();
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
        let uv = lscm(&pos, &faces).unwrap();
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
