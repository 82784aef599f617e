//! Distortion of a flattening, at true scale (a pattern must be the right size, so nothing
//! is rescaled before measuring).
//!
//! Per triangle, with σ₁ ≥ σ₂ the singular values of the Jacobian J of the affine map from
//! the 3D triangle (in its own frame) to its 2D image:
//! - E_h = |σ₁σ₂ − 1|: area distortion ("homogeneity of distortion");
//! - E_r = 1 − σ₂/σ₁: shape distortion ("aspect ratio");
//! - edge strain = max over its three edges of |ℓ2D/ℓ3D − 1|.
//!
//! All three vanish exactly for an isometry. These definitions are ours: the paper (its
//! Fig. 8) cites another work for the formulas, which was not available; we inferred them
//! from its statement that both vanish for an isometric mapping (docs/algorithms/metrics.md).

use flatcut_mesh::vec3::dist;
use flatcut_mesh::{Topology, TriMesh};
use serde::Serialize;

use crate::triangle::{jacobian, local_frame, signed_area2, singular_values};

/// Distortion of one triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FaceDistortion {
    /// Larger singular value of the 3D→2D map.
    pub sigma1: f64,
    /// Smaller singular value.
    pub sigma2: f64,
    /// |σ₁σ₂ − 1|.
    pub e_h: f64,
    /// 1 − σ₂/σ₁ (1 for a triangle collapsed to a point).
    pub e_r: f64,
    /// max |ℓ2D/ℓ3D − 1| over the three edges.
    pub edge_strain: f64,
    /// 3D area (mm²).
    pub area_3d: f64,
    /// Signed 2D area (mm², negative when flipped).
    pub signed_area_2d: f64,
}

/// Mean (weighted by 3D area), maximum and area-weighted 95th percentile of a per-face value.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Summary {
    /// Σ A_T x_T / Σ A_T.
    pub mean: f64,
    /// max x_T.
    pub max: f64,
    /// The smallest value x such that faces with x_T ≤ x cover ≥ 95 % of the 3D area.
    pub p95: f64,
}

/// Length of one boundary loop in 3D and in the flattening.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LoopLength {
    /// Vertices on the loop.
    pub vertices: usize,
    /// 3D length (mm).
    pub length_3d_mm: f64,
    /// 2D length (mm).
    pub length_2d_mm: f64,
}

/// All distortion measures of a flattening.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DistortionReport {
    /// Faces measured.
    pub faces: usize,
    /// Area distortion |σ₁σ₂ − 1|.
    pub e_h: Summary,
    /// Shape distortion 1 − σ₂/σ₁.
    pub e_r: Summary,
    /// Per-face edge strain.
    pub edge_strain: Summary,
    /// max |ℓ2D/ℓ3D − 1| over all edges (equals `edge_strain.max`).
    pub max_edge_strain: f64,
    /// Total 3D area (mm²).
    pub area_3d_mm2: f64,
    /// Total signed 2D area (mm²; flipped faces count negative).
    pub area_2d_mm2: f64,
    /// Faces with a negative signed 2D area (a counter-clockwise face shown clockwise).
    pub flipped_faces: usize,
    /// Boundary loop lengths, in [`Topology::boundary_loops`] order.
    pub boundary_loops: Vec<LoopLength>,
    /// Per face.
    #[serde(skip)]
    pub per_face: Vec<FaceDistortion>,
    /// Per vertex: area-weighted mean of E_h over its faces (0 for unused vertices).
    #[serde(skip)]
    pub per_vertex_e_h: Vec<f64>,
    /// Per vertex: area-weighted mean of E_r over its faces (0 for unused vertices).
    #[serde(skip)]
    pub per_vertex_e_r: Vec<f64>,
}

/// Distortion of one triangle from its 3D corners and 2D image. A 3D triangle of zero area
/// gets all-zero values (it carries no weight in any summary).
pub fn face_distortion(p: [[f64; 3]; 3], uv: [[f64; 2]; 3]) -> FaceDistortion {
    let q = local_frame(p[0], p[1], p[2]);
    let area_3d = 0.5 * signed_area2(q[0], q[1], q[2]);
    let signed_area_2d = 0.5 * signed_area2(uv[0], uv[1], uv[2]);
    let Some(j) = jacobian(q, uv).filter(|_| area_3d > 0.0) else {
        return FaceDistortion {
            signed_area_2d,
            ..Default::default()
        };
    };
    let (sigma1, sigma2) = singular_values(j);
    let e_r = if sigma1 > 0.0 {
        1.0 - sigma2 / sigma1
    } else {
        1.0
    };
    let mut edge_strain: f64 = 0.0;
    for k in 0..3 {
        let l3 = dist(p[k], p[(k + 1) % 3]);
        let l2 = (uv[k][0] - uv[(k + 1) % 3][0]).hypot(uv[k][1] - uv[(k + 1) % 3][1]);
        if l3 > 0.0 {
            edge_strain = edge_strain.max((l2 / l3 - 1.0).abs());
        }
    }
    FaceDistortion {
        sigma1,
        sigma2,
        e_h: (sigma1 * sigma2 - 1.0).abs(),
        e_r,
        edge_strain,
        area_3d,
        signed_area_2d,
    }
}

/// max |ℓ2D/ℓ3D − 1| over the edges of `faces` (positions 3D, `uv` 2D, same indexing).
pub fn max_edge_strain(positions: &[[f64; 3]], faces: &[[u32; 3]], uv: &[[f64; 2]]) -> f64 {
    let mut m: f64 = 0.0;
    for f in faces {
        for k in 0..3 {
            let (i, j) = (f[k] as usize, f[(k + 1) % 3] as usize);
            let l3 = dist(positions[i], positions[j]);
            let l2 = (uv[i][0] - uv[j][0]).hypot(uv[i][1] - uv[j][1]);
            if l3 > 0.0 {
                m = m.max((l2 / l3 - 1.0).abs());
            }
        }
    }
    m
}

fn summary(values: impl Iterator<Item = f64>, faces: &[FaceDistortion]) -> Summary {
    let mut pairs: Vec<(f64, f64)> = values.zip(faces.iter().map(|f| f.area_3d)).collect();
    let total: f64 = pairs.iter().map(|p| p.1).sum();
    if pairs.is_empty() || total <= 0.0 {
        return Summary::default();
    }
    let mean = pairs.iter().map(|(x, a)| x * a).sum::<f64>() / total;
    let max = pairs.iter().map(|p| p.0).fold(0.0, f64::max);
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut acc = 0.0;
    let mut p95 = max;
    for (x, a) in &pairs {
        acc += a;
        if acc >= 0.95 * total {
            p95 = *x;
            break;
        }
    }
    Summary { mean, max, p95 }
}

/// Measures the flattening `uv` (one 2D point per vertex of `mesh`, mm).
///
/// `topo` must have been built from `mesh`. Panics never; `uv.len()` shorter than the
/// vertex count is a caller bug caught by an assertion in debug builds only.
pub fn distortion(mesh: &TriMesh, topo: &Topology, uv: &[[f64; 2]]) -> DistortionReport {
    debug_assert_eq!(uv.len(), mesh.vertex_count());
    let per_face: Vec<FaceDistortion> = mesh
        .faces
        .iter()
        .map(|f| {
            face_distortion(
                f.map(|v| mesh.positions[v as usize]),
                f.map(|v| uv[v as usize]),
            )
        })
        .collect();
    let n = mesh.vertex_count();
    let mut w = vec![0.0; n];
    let mut vh = vec![0.0; n];
    let mut vr = vec![0.0; n];
    for (f, d) in mesh.faces.iter().zip(&per_face) {
        for &v in f {
            w[v as usize] += d.area_3d;
            vh[v as usize] += d.area_3d * d.e_h;
            vr[v as usize] += d.area_3d * d.e_r;
        }
    }
    for v in 0..n {
        if w[v] > 0.0 {
            vh[v] /= w[v];
            vr[v] /= w[v];
        }
    }
    let edge_strain = summary(per_face.iter().map(|d| d.edge_strain), &per_face);
    let boundary_loops = topo
        .boundary_loops()
        .iter()
        .map(|lp| {
            let mut l3 = 0.0;
            let mut l2 = 0.0;
            for k in 0..lp.len() {
                let (a, b) = (lp[k].idx(), lp[(k + 1) % lp.len()].idx());
                l3 += dist(mesh.positions[a], mesh.positions[b]);
                l2 += (uv[a][0] - uv[b][0]).hypot(uv[a][1] - uv[b][1]);
            }
            LoopLength {
                vertices: lp.len(),
                length_3d_mm: l3,
                length_2d_mm: l2,
            }
        })
        .collect();
    DistortionReport {
        faces: per_face.len(),
        e_h: summary(per_face.iter().map(|d| d.e_h), &per_face),
        e_r: summary(per_face.iter().map(|d| d.e_r), &per_face),
        max_edge_strain: edge_strain.max,
        edge_strain,
        area_3d_mm2: per_face.iter().map(|d| d.area_3d).sum(),
        area_2d_mm2: per_face.iter().map(|d| d.signed_area_2d).sum(),
        flipped_faces: per_face.iter().filter(|d| d.signed_area_2d < 0.0).count(),
        boundary_loops,
        per_face,
        per_vertex_e_h: vh,
        per_vertex_e_r: vr,
    }
}
