//! The gradient of θ(v) against central finite differences.

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use flatcut_flattenable::angle_gradient::angle_sum_gradient;
use flatcut_mesh::geometry::angle_sums;
use flatcut_mesh::{Topology, VertexId};

fn check(mesh: &flatcut_mesh::TriMesh) -> f64 {
    let topo = Topology::build(mesh).unwrap();
    let h = 1e-6 * mesh.diagonal();
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for v in 0..mesh.vertex_count() as u32 {
        let v = VertexId(v);
        if !topo.is_interior_vertex(v) {
            continue;
        }
        let (theta, grads) = angle_sum_gradient(&mesh.positions, &mesh.faces, &topo, v);
        assert!((theta - angle_sums(&mesh.positions, &mesh.faces)[v.idx()]).abs() < 1e-14);
        // Gradient norm scale for the relative error of this vertex's gradient.
        let scale: f64 = grads
            .iter()
            .map(|(_, g)| g.iter().map(|c| c * c).sum::<f64>())
            .sum::<f64>()
            .sqrt();
        for (q, g) in &grads {
            for c in 0..3 {
                let mut p = mesh.positions.clone();
                p[q.idx()][c] += h;
                let plus = angle_sums(&p, &mesh.faces)[v.idx()];
                p[q.idx()][c] -= 2.0 * h;
                let minus = angle_sums(&p, &mesh.faces)[v.idx()];
                let fd = (plus - minus) / (2.0 * h);
                worst = worst.max((fd - g[c]).abs() / scale);
            }
        }
        checked += 1;
    }
    assert!(checked > 0);
    worst
}

#[test]
fn gradient_matches_central_differences_on_curved_grids() {
    for mesh in [common::sphere_cap(7), common::saddle(7)] {
        let err = check(&mesh);
        assert!(err < 1e-6, "relative error {err}");
    }
}

#[test]
fn gradient_matches_central_differences_on_irregular_mesh() {
    // Jitter the saddle so that no corner is symmetric.
    let mut mesh = common::saddle(6);
    for (i, p) in mesh.positions.iter_mut().enumerate() {
        let s = (i as f64 * 12.9898).sin() * 43758.5453;
        let r = s - s.floor() - 0.5;
        p[0] += 0.05 * r;
        p[1] -= 0.04 * r;
        p[2] += 0.1 * r;
    }
    let err = check(&mesh);
    assert!(err < 1e-6, "relative error {err}");
}

#[test]
fn gradient_of_flat_vertex_has_no_normal_component() {
    let mesh = common::planar(5);
    let topo = Topology::build(&mesh).unwrap();
    let (theta, grads) = angle_sum_gradient(&mesh.positions, &mesh.faces, &topo, VertexId(12));
    assert!((theta - std::f64::consts::TAU).abs() < 1e-14);
    for (_, g) in grads {
        assert!(g[2].abs() < 1e-14);
    }
}

#[test]
fn degenerate_corners_get_zero_gradients_and_others_the_formula() {
    use flatcut_flattenable::angle_gradient::{corner_gradient, corner_gradient_next_previous};
    // Collinear edges, a zero-length edge, and a NaN coordinate: the angle is not
    // differentiable, so the gradients are zero rather than NaN or infinite (the branch-free
    // version computes them and then selects zeros).
    let p = [0.0, 0.0, 0.0];
    for (a, b) in [
        ([1.0, 0.0, 0.0], [2.0, 0.0, 0.0]),
        ([0.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ] {
        assert_eq!(corner_gradient(p, a, b), [[0.0; 3]; 3], "a {a:?} b {b:?}");
    }
    // A right angle at p with legs 2 (along x) and 1 (along y): moving a along +y closes the
    // angle at the rate 1/|u| = 1/2, moving b along +x at 1/|w| = 1.
    let [ga, gb] = corner_gradient_next_previous([2.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    assert_eq!(ga, [0.0, -0.5, 0.0]);
    assert_eq!(gb, [-1.0, 0.0, 0.0]);
}
