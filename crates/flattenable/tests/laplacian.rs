//! The least-square update (Eq. 9–12, 17) against identities: the detail target keeps the
//! input as its fixed point; the zero target shrinks a curved piece and keeps a planar one
//! (linear precision of the cotan Laplacian).

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use flatcut_flattenable::laplacian::LeastSquareUpdate;
use flatcut_flattenable::least_norm::Layout;
use flatcut_flattenable::{Laplacian, Target};
use flatcut_mesh::{Topology, TriMesh};

fn filter(mesh: &TriMesh, lap: Laplacian, target: Target, w: f64) -> (Layout, LeastSquareUpdate) {
    let topo = Topology::build(mesh).unwrap();
    let layout = Layout::build(&topo, &mesh.faces).unwrap();
    let weights = vec![w; layout.n()];
    let f = LeastSquareUpdate::new(
        &layout,
        &topo,
        &mesh.positions,
        &mesh.faces,
        lap,
        target,
        &weights,
    )
    .unwrap();
    (layout, f)
}

fn interior(layout: &Layout, mesh: &TriMesh) -> Vec<[f64; 3]> {
    layout
        .interior
        .iter()
        .map(|&p| mesh.positions[p as usize])
        .collect()
}

fn max_dev(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| flatcut_mesh::vec3::dist(*x, *y))
        .fold(0.0, f64::max)
}

#[test]
fn detail_target_has_the_input_as_fixed_point() {
    let mesh = common::sphere_cap(10);
    for lap in [Laplacian::Cotan, Laplacian::Uniform] {
        let (layout, f) = filter(&mesh, lap, Target::Detail, 1.0);
        let v0 = interior(&layout, &mesh);
        assert!(max_dev(&f.apply(&layout, &v0), &v0) < 1e-12, "{lap:?}");
    }
}

#[test]
fn zero_target_shrinks_a_cap_and_keeps_a_plane() {
    let cap = common::sphere_cap(10);
    let (layout, f) = filter(&cap, Laplacian::Cotan, Target::Zero, 1.0);
    let v0 = interior(&layout, &cap);
    let out = f.apply(&layout, &v0);
    // Thin-plate smoothing pulls the dome down (limitation 3 of the paper).
    let mean_z = |v: &[[f64; 3]]| v.iter().map(|p| p[2]).sum::<f64>() / v.len() as f64;
    assert!(mean_z(&out) < mean_z(&v0) - 1e-4);
    // A planar irregular grid: the cotan Laplacian of a plane's positions is zero.
    let mut plane = common::planar(8);
    for (i, p) in plane.positions.iter_mut().enumerate() {
        let (x, y) = (i % 8, i / 8);
        if x > 0 && x < 7 && y > 0 && y < 7 {
            p[0] += 0.05 * ((i * 7) % 5) as f64 / 5.0;
            p[1] -= 0.04 * ((i * 3) % 4) as f64 / 4.0;
        }
    }
    let (layout, f) = filter(&plane, Laplacian::Cotan, Target::Zero, 1.0);
    let v0 = interior(&layout, &plane);
    assert!(max_dev(&f.apply(&layout, &v0), &v0) < 1e-12);
}

#[test]
fn larger_weight_follows_the_target_more_closely() {
    let cap = common::sphere_cap(10);
    let dev = |w: f64| {
        let (layout, f) = filter(&cap, Laplacian::Cotan, Target::Zero, w);
        let v0 = interior(&layout, &cap);
        max_dev(&f.apply(&layout, &v0), &v0)
    };
    assert!(dev(10.0) < dev(1.0));
}
