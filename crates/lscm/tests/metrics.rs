//! Metrics against closed forms: similarities and affine stretches of a planar piece.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_lscm::distortion;
use flatcut_lscm::metrics::face_distortion;
use flatcut_mesh::Topology;
use proptest::prelude::*;

#[test]
fn affine_stretch_has_the_closed_form_values() {
    // A planar piece in z = 0, mapped by (x, y) ↦ R(θ)·(sx·x, sy·y): σ = {sx, sy}.
    let mesh = common::grid(7, 5, |u, v| [100.0 * u + 7.0 * v * v, 60.0 * v, 0.0]);
    let topo = Topology::build(&mesh).unwrap();
    let (sx, sy, t) = (1.3, 0.8, 0.4f64);
    let (s, c) = t.sin_cos();
    let uv: Vec<[f64; 2]> = mesh
        .positions
        .iter()
        .map(|p| {
            let (x, y) = (sx * p[0], sy * p[1]);
            [c * x - s * y, s * x + c * y]
        })
        .collect();
    let d = distortion(&mesh, &topo, &uv);
    let e_h = (sx * sy - 1.0f64).abs();
    let e_r = 1.0 - sy / sx;
    for f in &d.per_face {
        assert!((f.e_h - e_h).abs() < 1e-12 && (f.e_r - e_r).abs() < 1e-12);
        assert!((f.sigma1 - sx).abs() < 1e-12 && (f.sigma2 - sy).abs() < 1e-12);
    }
    assert!((d.e_h.mean - e_h).abs() < 1e-12 && (d.e_h.p95 - e_h).abs() < 1e-12);
    assert!((d.area_2d_mm2 - sx * sy * d.area_3d_mm2).abs() < 1e-9 * d.area_3d_mm2);
    // The bottom row (y = 0) is stretched by exactly sx: the strain is at least sx − 1.
    assert!(d.max_edge_strain >= sx - 1.0 - 1e-12);
    assert!(d.max_edge_strain <= sx - 1.0 + 1e-12); // no edge stretches more than σ₁
    for &v in &d.per_vertex_e_r {
        assert!((v - e_r).abs() < 1e-12);
    }
    // Boundary: the outer loop of the stretched piece vs 3D.
    assert_eq!(d.boundary_loops.len(), 1);
    assert!(d.boundary_loops[0].length_2d_mm > d.boundary_loops[0].length_3d_mm);
}

#[test]
fn flipped_faces_are_counted() {
    let mesh = common::grid(4, 4, |u, v| [30.0 * u, 30.0 * v, 0.0]);
    let topo = Topology::build(&mesh).unwrap();
    let mirrored: Vec<[f64; 2]> = mesh.positions.iter().map(|p| [-p[0], p[1]]).collect();
    let d = distortion(&mesh, &topo, &mirrored);
    assert_eq!(d.flipped_faces, mesh.face_count());
    assert!(d.area_2d_mm2 < 0.0);
    // A mirror image is isometric: the singular values do not see orientation.
    assert!(d.e_h.max < 1e-12 && d.e_r.max < 1e-12);
}

#[test]
fn percentile_is_area_weighted() {
    // Two faces: one big with value 0, one small with a stretch; the big one covers > 95 %.
    let p = [
        [0.0, 0.0, 0.0],
        [100.0, 0.0, 0.0],
        [0.0, 100.0, 0.0],
        [1.0, -1.0, 0.0],
    ];
    let mesh = flatcut_mesh::TriMesh::new(p.to_vec(), vec![[0, 1, 2], [0, 3, 1]]).unwrap();
    let topo = Topology::build(&mesh).unwrap();
    let mut uv: Vec<[f64; 2]> = p.iter().map(|q| [q[0], q[1]]).collect();
    uv[3] = [1.0, -2.0];
    let d = distortion(&mesh, &topo, &uv);
    assert_eq!(d.e_h.p95, 0.0);
    assert!(d.e_h.max > 0.5);
    assert!(d.e_h.mean > 0.0 && d.e_h.mean < 0.05 * d.e_h.max);
}

proptest! {
    #[test]
    fn similarity_values(scale in 0.2f64..5.0, t in -3.0f64..3.0, ax in -50.0f64..50.0,
                         bx in 1.0f64..80.0, cx in -40.0f64..40.0, cy in 1.0f64..80.0) {
        let p = [[ax, 0.0, 3.0], [ax + bx, 0.0, 3.0], [cx, cy, 3.0]];
        let (s, c) = t.sin_cos();
        let uv = p.map(|q| [scale * (c * q[0] - s * q[1]), scale * (s * q[0] + c * q[1])]);
        let f = face_distortion(p, uv);
        prop_assert!((f.e_h - (scale * scale - 1.0).abs()).abs() < 1e-9 * scale * scale);
        prop_assert!(f.e_r.abs() < 1e-9);
        prop_assert!((f.edge_strain - (scale - 1.0).abs()).abs() < 1e-9 * scale);
    }
}
