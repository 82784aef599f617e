//! The straightest geodesic from a surface point in a given direction: the walk that a dart
//! given by a boundary point, a direction and a length follows to find its tip.
//!
//! Inside a face the walk is a straight line; crossing an edge, the direction is unfolded
//! into the next face by rotating it about the edge (its component along the edge is kept,
//! the perpendicular component turns into the new face's plane), which is exactly what
//! laying the two faces flat and drawing a straight line does (Polthier & Schmies 1998).

use flatcut_mesh::{Topology, TriMesh, VertexId, geometry, vec3};
use flatcut_trim::lines::bary_in;
use flatcut_trim::{Location, SurfacePoint};

/// A start face accepts a direction when it enters the face by at least this much
/// (barycentric rate per mm × face size, dimensionless): directions grazing the boundary are
/// "outward", since the walk would run along the boundary edge.
const INTO_FACE: f64 = 1e-12;

/// Where the walk ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Traced {
    /// It went the whole length; the tip.
    Tip(SurfacePoint),
    /// It reached the boundary after this distance (mm).
    LeftPiece(f64),
    /// The direction points out of the piece at the start.
    Outward,
}

/// Barycentric rate of change of moving along unit 3D direction `d` in face `f`.
fn bary_dir(mesh: &TriMesh, f: usize, d: [f64; 3]) -> [f64; 3] {
    let face = mesh.faces[f];
    let a = mesh.positions[face[0] as usize];
    let e1 = vec3::sub(mesh.positions[face[1] as usize], a);
    let e2 = vec3::sub(mesh.positions[face[2] as usize], a);
    let (g11, g12, g22) = (vec3::dot(e1, e1), vec3::dot(e1, e2), vec3::dot(e2, e2));
    let (r1, r2) = (vec3::dot(d, e1), vec3::dot(d, e2));
    let det = g11 * g22 - g12 * g12;
    if det <= 0.0 {
        return [0.0; 3];
    }
    let u = (r1 * g22 - r2 * g12) / det;
    let v = (r2 * g11 - r1 * g12) / det;
    [-u - v, u, v]
}

fn face_normal(mesh: &TriMesh, f: usize) -> [f64; 3] {
    let face = mesh.faces[f];
    let p = |k: usize| mesh.positions[face[k] as usize];
    vec3::normalize(vec3::cross(vec3::sub(p(1), p(0)), vec3::sub(p(2), p(0))))
}

/// `d` projected into face `f`'s plane, unit (zero if `d` is normal to the face).
fn in_plane(mesh: &TriMesh, f: usize, d: [f64; 3]) -> [f64; 3] {
    let n = face_normal(mesh, f);
    let t = vec3::sub(d, vec3::scale(n, vec3::dot(d, n)));
    if vec3::norm(t) > 0.0 {
        vec3::normalize(t)
    } else {
        [0.0; 3]
    }
}

/// Walks `length` mm from `start` along the straightest geodesic leaving in `direction`
/// (projected onto the surface at the start).
pub(crate) fn trace(
    mesh: &TriMesh,
    topo: &Topology,
    start: SurfacePoint,
    direction: [f64; 3],
    length: f64,
) -> Traced {
    let faces: Vec<usize> = match start.location(mesh) {
        Location::Vertex(v) => topo.vertex_faces(VertexId(v)).map(|f| f.idx()).collect(),
        Location::Edge { a, b, .. } => topo
            .vertex_faces(VertexId(a))
            .map(|f| f.idx())
            .filter(|&f| mesh.faces[f].contains(&b))
            .collect(),
        Location::Face(f) => vec![f as usize],
    };
    // The start face: the one the projected direction enters.
    let mut state = None;
    for f in faces {
        let Some(w) = bary_in(mesh, start, f as u32) else {
            continue;
        };
        let d = in_plane(mesh, f, direction);
        let dw = bary_dir(mesh, f, d);
        let size = geometry::triangle_area(
            mesh.positions[mesh.faces[f][0] as usize],
            mesh.positions[mesh.faces[f][1] as usize],
            mesh.positions[mesh.faces[f][2] as usize],
        )
        .sqrt();
        let enters = (0..3).all(|k| w[k] > 0.0 || dw[k] * size > INTO_FACE);
        if vec3::norm(d) > 0.0 && enters {
            state = Some((f, w, d));
            break;
        }
    }
    let Some((mut f, mut w, mut d)) = state else {
        return Traced::Outward;
    };
    let mut travelled = 0.0;
    // Each face is crossed at most a few times by a straight walk; the cap only stops a
    // rounding loop.
    for _ in 0..4 * mesh.faces.len() + 16 {
        let dw = bary_dir(mesh, f, d);
        let (mut t_exit, mut k_exit) = (f64::INFINITY, 3);
        for k in 0..3 {
            if dw[k] < 0.0 {
                let t = w[k].max(0.0) / -dw[k];
                if t < t_exit {
                    t_exit = t;
                    k_exit = k;
                }
            }
        }
        let remaining = length - travelled;
        if remaining <= t_exit || k_exit == 3 {
            let mut wt = [0.0; 3];
            for k in 0..3 {
                wt[k] = (w[k] + remaining * dw[k]).max(0.0);
            }
            let s: f64 = wt.iter().sum();
            for c in &mut wt {
                *c /= s;
            }
            return Traced::Tip(
                SurfacePoint {
                    face: flatcut_mesh::FaceId(f as u32),
                    barycentric: wt,
                }
                .snapped(),
            );
        }
        let mut we = [0.0; 3];
        for k in 0..3 {
            we[k] = (w[k] + t_exit * dw[k]).max(0.0);
        }
        we[k_exit] = 0.0;
        travelled += t_exit;
        let (i, j) = ((k_exit + 1) % 3, (k_exit + 2) % 3);
        let h = 3 * f as u32 + i as u32;
        let Some(tw) = topo.twin(h) else {
            return Traced::LeftPiece(travelled);
        };
        let g = (tw / 3) as usize;
        let tk = (tw % 3) as usize;
        // The twin runs from corner j's vertex to corner i's vertex.
        let mut wg = [0.0; 3];
        wg[tk] = we[j];
        wg[(tk + 1) % 3] = we[i];
        let s: f64 = wg.iter().sum();
        for c in &mut wg {
            *c /= s;
        }
        let face = mesh.faces[f];
        let (pi, pj) = (
            mesh.positions[face[i] as usize],
            mesh.positions[face[j] as usize],
        );
        let e = vec3::normalize(vec3::sub(pj, pi));
        let along = vec3::dot(d, e);
        let perp = vec3::norm(vec3::sub(d, vec3::scale(e, along)));
        let ng = face_normal(mesh, g);
        let mut m = vec3::cross(ng, e);
        let opp = mesh.positions[mesh.faces[g][(tk + 2) % 3] as usize];
        if vec3::dot(m, vec3::sub(opp, pi)) < 0.0 {
            m = vec3::scale(m, -1.0);
        }
        d = vec3::normalize(vec3::add(vec3::scale(e, along), vec3::scale(m, perp)));
        f = g;
        w = wg;
    }
    Traced::LeftPiece(travelled)
}
