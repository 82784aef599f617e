//! Discrete differential geometry of a triangle mesh: corner angles, face areas and
//! normals, the summed angle θ(v) and angle defect 2π − θ(v), the mixed Voronoi area of
//! Meyer et al. 2003, and cotangent weights.
//!
//! Every function takes positions and faces separately, so that an algorithm moving the
//! vertices (the flattenable iteration) can evaluate geometry on its own position buffer.

use std::f64::consts::{PI, TAU};

use crate::vec3::{angle, cross, dot, norm, sub};
use crate::{Topology, TriMesh, VertexId};

/// The length of the closed polygon through `vertices`, the last joined back to the first:
/// a boundary loop's length.
pub fn loop_length(positions: &[[f64; 3]], vertices: &[VertexId]) -> f64 {
    (0..vertices.len())
        .map(|i| {
            crate::vec3::dist(
                positions[vertices[i].idx()],
                positions[vertices[(i + 1) % vertices.len()].idx()],
            )
        })
        .sum()
}

/// The three corner angles of a triangle in radians, at `p0`, `p1`, `p2`, in the atan2 form
/// (stable near 0 and π).
#[inline]
pub fn triangle_angles(p0: [f64; 3], p1: [f64; 3], p2: [f64; 3]) -> [f64; 3] {
    [
        angle(sub(p1, p0), sub(p2, p0)),
        angle(sub(p2, p1), sub(p0, p1)),
        angle(sub(p0, p2), sub(p1, p2)),
    ]
}

/// Corner angles of every face: `angles[f][k]` is the angle at `faces[f][k]`.
pub fn corner_angles(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<[f64; 3]> {
    faces
        .iter()
        .map(|f| {
            triangle_angles(
                positions[f[0] as usize],
                positions[f[1] as usize],
                positions[f[2] as usize],
            )
        })
        .collect()
}

/// Area of a triangle.
#[inline]
pub fn triangle_area(p0: [f64; 3], p1: [f64; 3], p2: [f64; 3]) -> f64 {
    0.5 * norm(cross(sub(p1, p0), sub(p2, p0)))
}

/// Area of every face.
pub fn face_areas(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<f64> {
    faces
        .iter()
        .map(|f| {
            triangle_area(
                positions[f[0] as usize],
                positions[f[1] as usize],
                positions[f[2] as usize],
            )
        })
        .collect()
}

/// Unit normal of every face (counter-clockwise corners); zero for a degenerate face.
pub fn face_normals(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<[f64; 3]> {
    faces
        .iter()
        .map(|f| {
            let (p0, p1, p2) = (
                positions[f[0] as usize],
                positions[f[1] as usize],
                positions[f[2] as usize],
            );
            crate::vec3::normalize(cross(sub(p1, p0), sub(p2, p0)))
        })
        .collect()
}

/// Per vertex, the sum of its faces' unit normals weighted by twice their area (not
/// normalised: callers normalise where they need a direction; zero at a vertex without
/// faces or with only degenerate ones).
pub fn area_weighted_vertex_normals(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let unit = face_normals(positions, faces);
    let mut out = vec![[0.0; 3]; positions.len()];
    for (f, face) in faces.iter().enumerate() {
        let [a, b, c] = face.map(|i| positions[i as usize]);
        let twice_area = norm(cross(sub(b, a), sub(c, a)));
        for &v in face {
            out[v as usize] =
                crate::vec3::add(out[v as usize], crate::vec3::scale(unit[f], twice_area));
        }
    }
    out
}

/// ∂(total area)/∂v per vertex: Σ over v's faces of ½ n̂ × (v_next − v_prev), the
/// half-edge opposite v turned a quarter in the face's plane (zero for a degenerate face).
pub fn area_gradient(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut grad = vec![[0.0; 3]; positions.len()];
    for f in faces {
        let p = [
            positions[f[0] as usize],
            positions[f[1] as usize],
            positions[f[2] as usize],
        ];
        let n = crate::vec3::normalize(cross(sub(p[1], p[0]), sub(p[2], p[0])));
        for k in 0..3 {
            let g = cross(n, sub(p[(k + 2) % 3], p[(k + 1) % 3]));
            let out = &mut grad[f[k] as usize];
            for c in 0..3 {
                out[c] += 0.5 * g[c];
            }
        }
    }
    grad
}

/// Total surface area.
pub fn total_area(mesh: &TriMesh) -> f64 {
    face_areas(&mesh.positions, &mesh.faces).iter().sum()
}

/// θ(v): the sum of the corner angles at each vertex (0 for unused vertices).
pub fn angle_sums(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<f64> {
    let mut theta = vec![0.0; positions.len()];
    for f in faces {
        let a = triangle_angles(
            positions[f[0] as usize],
            positions[f[1] as usize],
            positions[f[2] as usize],
        );
        for k in 0..3 {
            theta[f[k] as usize] += a[k];
        }
    }
    theta
}

/// The angle defect 2π − θ(v) at each interior vertex (`None` elsewhere): the discrete
/// Gaussian curvature integrated over the vertex's area; zero everywhere iff the patch is
/// developable.
pub fn angle_defects(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    topo: &Topology,
) -> Vec<Option<f64>> {
    angle_sums(positions, faces)
        .into_iter()
        .enumerate()
        .map(|(v, t)| {
            topo.is_interior_vertex(VertexId(v as u32))
                .then_some(TAU - t)
        })
        .collect()
}

/// The mixed Voronoi area of each vertex (Meyer, Desbrun, Schröder, Barr 2003, Fig. 4):
/// in a non-obtuse triangle each corner gets its Voronoi region
/// (|e|² cot of the opposite angles / 8); in an obtuse triangle the obtuse corner gets half
/// the area and the others a quarter. The areas sum to the total area exactly.
pub fn mixed_areas(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<f64> {
    let mut area = vec![0.0; positions.len()];
    for f in faces {
        let p = [
            positions[f[0] as usize],
            positions[f[1] as usize],
            positions[f[2] as usize],
        ];
        let a = triangle_area(p[0], p[1], p[2]);
        if a <= 0.0 {
            continue;
        }
        let ang = triangle_angles(p[0], p[1], p[2]);
        if let Some(obtuse) = (0..3).find(|&k| ang[k] > PI / 2.0) {
            for k in 0..3 {
                area[f[k] as usize] += if k == obtuse { a / 2.0 } else { a / 4.0 };
            }
        } else {
            for k in 0..3 {
                // Corner k's Voronoi share: the two edges at k, each weighted by the cotangent
                // of the angle opposite that edge.
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                let e_ki = crate::vec3::norm2(sub(p[i], p[k]));
                let e_kj = crate::vec3::norm2(sub(p[j], p[k]));
                area[f[k] as usize] += (e_ki * cot(ang[j]) + e_kj * cot(ang[i])) / 8.0;
            }
        }
    }
    area
}

#[inline]
fn cot(theta: f64) -> f64 {
    theta.cos() / theta.sin()
}

/// Cotangent of the corner angle at `p0` computed from the vectors (dot / |cross|).
#[inline]
pub fn corner_cot(p0: [f64; 3], p1: [f64; 3], p2: [f64; 3]) -> f64 {
    let (u, w) = (sub(p1, p0), sub(p2, p0));
    dot(u, w) / norm(cross(u, w))
}

/// Cotangent weights per undirected edge of `topo`, w_ij = (cot α_ij + cot β_ij) / 2, the
/// angles opposite the edge in its faces (one term on a boundary edge). Degenerate faces
/// contribute nothing rather than infinity.
pub fn cotan_weights(positions: &[[f64; 3]], faces: &[[u32; 3]], topo: &Topology) -> Vec<f64> {
    let mut w = vec![0.0; topo.edges().len()];
    for (fi, f) in faces.iter().enumerate() {
        let p = [
            positions[f[0] as usize],
            positions[f[1] as usize],
            positions[f[2] as usize],
        ];
        for k in 0..3 {
            // Halfedge 3f+k runs f[k] → f[k+1]; the opposite corner is k+2.
            let o = (k + 2) % 3;
            let c = corner_cot(p[o], p[(o + 1) % 3], p[(o + 2) % 3]);
            if c.is_finite() {
                w[topo.edge_of((3 * fi + k) as u32) as usize] += 0.5 * c;
            }
        }
    }
    w
}

/// Relative area below which a triangle counts as degenerate: area ≤ (ε · diagonal)² with
/// ε = 1e-10. At that size the triangle's angles and normal are no longer meaningful in f64
/// (its edge vectors cancel to ~1e-16 relative), while any sliver a scanner produces at a
/// real resolution (≥ 1e-6 of the part size) stays well above it.
pub const DEGENERATE_AREA_RELATIVE: f64 = 1e-10;

/// The bounding-box diagonal of each of `components` groups of faces (`face_components[f]`
/// the group of face f, as [`Topology::face_components`] gives them), computed by its longest
/// side first so that it is exact where the square of a diagonal would overflow or
/// underflow (a 1e300-wide piece gives 1.4e300, not infinity). A group without faces gives
/// 0; sides that overflow (coordinates near ±f64::MAX) give infinity.
pub fn component_extents(mesh: &TriMesh, face_components: &[u32], components: usize) -> Vec<f64> {
    let mut boxes = vec![([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]); components];
    for (face, &c) in mesh.faces.iter().zip(face_components) {
        let (lo, hi) = &mut boxes[c as usize];
        for &v in face {
            let p = mesh.positions[v as usize];
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    boxes
        .iter()
        .map(|(lo, hi)| {
            if lo[0] > hi[0] {
                return 0.0;
            }
            let side = sub(*hi, *lo);
            let longest = side[0].max(side[1]).max(side[2]);
            if longest > 0.0 && longest.is_finite() {
                longest * norm(side.map(|x| x / longest))
            } else {
                longest
            }
        })
        .collect()
}

/// Is a face degenerate: a repeated vertex index, or an area ≤ (ε · `diagonal`)² with
/// ε = [`DEGENERATE_AREA_RELATIVE`] (`diagonal` is the mesh's bounding-box diagonal)?
pub fn is_degenerate_face(face: [u32; 3], corners: [[f64; 3]; 3], diagonal: f64) -> bool {
    if face[0] == face[1] || face[1] == face[2] || face[0] == face[2] {
        return true;
    }
    let limit = DEGENERATE_AREA_RELATIVE * diagonal;
    triangle_area(corners[0], corners[1], corners[2]) <= limit * limit
}
