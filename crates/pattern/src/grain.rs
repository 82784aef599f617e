//! The grain direction carried from 3D to the pattern through the piece's own map.

use flatcut_mesh::TriMesh;

use crate::geom::{norm, unit};

/// Below this length (relative) the grain's image in a face is ignored: the grain is normal to
/// that face.
const GRAIN_NORMAL_RELATIVE: f64 = 1e-9;

/// The 2D unit direction that the 3D direction `grain` maps to: per face, the grain's tangential
/// part is written in the face's edge basis and carried to the 2D triangle by the same
/// coefficients (the face's affine map); the unit images are summed weighted by 3D area.
/// `None` when the grain is normal to every face.
pub fn grain_direction_2d(mesh: &TriMesh, uv: &[[f64; 2]], grain: [f64; 3]) -> Option<[f64; 2]> {
    let g = flatcut_mesh::vec3::normalize(grain);
    let mut sum = [0.0f64; 2];
    for f in &mesh.faces {
        let [i, j, k] = f.map(|x| x as usize);
        let (p0, p1, p2) = (mesh.positions[i], mesh.positions[j], mesh.positions[k]);
        let e1 = flatcut_mesh::vec3::sub(p1, p0);
        let e2 = flatcut_mesh::vec3::sub(p2, p0);
        let (a11, a12, a22) = (
            flatcut_mesh::vec3::dot(e1, e1),
            flatcut_mesh::vec3::dot(e1, e2),
            flatcut_mesh::vec3::dot(e2, e2),
        );
        let det = a11 * a22 - a12 * a12;
        if det <= 0.0 {
            continue;
        }
        let (b1, b2) = (
            flatcut_mesh::vec3::dot(g, e1),
            flatcut_mesh::vec3::dot(g, e2),
        );
        let a = (a22 * b1 - a12 * b2) / det;
        let b = (a11 * b2 - a12 * b1) / det;
        let (q0, q1, q2) = (uv[i], uv[j], uv[k]);
        let img = [
            a * (q1[0] - q0[0]) + b * (q2[0] - q0[0]),
            a * (q1[1] - q0[1]) + b * (q2[1] - q0[1]),
        ];
        let area = 0.5 * det.sqrt();
        let tangential = (a * a * a11 + 2.0 * a * b * a12 + b * b * a22)
            .max(0.0)
            .sqrt();
        if tangential <= GRAIN_NORMAL_RELATIVE || norm(img) == 0.0 {
            continue;
        }
        let u = unit(img);
        // Weighted by how much of the grain lies in the face, so faces nearly normal to it
        // (whose image direction is ill-defined) count little.
        sum[0] += area * tangential * u[0];
        sum[1] += area * tangential * u[1];
    }
    (norm(sum) > 0.0).then(|| unit(sum))
}
