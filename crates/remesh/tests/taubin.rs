//! Taubin λ|μ smoothing (`taubin.rs`): noise goes, shape and fixed vertices stay.

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

use flatcut_mesh::shapes::icosphere;
use flatcut_mesh::vec3::norm;
use flatcut_mesh::{Topology, VertexId};
use flatcut_remesh::taubin::{TAUBIN_LAMBDA, TAUBIN_MU, taubin_smooth};

/// The filter's gain at the highest frequency of the uniform Laplacian (k = 2) is
/// (1 − 2λ)(1 − 2μ) = 0 for λ = ½, and ≈ 1 near k = 0: the constants do what the module says.
#[test]
fn the_constants_make_a_low_pass_filter() {
    let gain = |k: f64| (1.0 - TAUBIN_LAMBDA * k) * (1.0 - TAUBIN_MU * k);
    assert_eq!(gain(2.0), 0.0);
    assert!((gain(0.0) - 1.0).abs() < 1e-15);
    // Pass band: the gain crosses 1 again at k_PB = 1/λ + 1/μ ≈ 0.113.
    let k_pb = 1.0 / TAUBIN_LAMBDA + 1.0 / TAUBIN_MU;
    assert!((gain(k_pb) - 1.0).abs() < 1e-12);
    assert!(gain(0.05) > 1.0 && gain(0.05) < 1.003);
}

/// An exact eigenvector: on a grid with one diagonal per quad ((i, j)–(i+1, j+1)), heights
/// z = (−1)^i give every interior vertex the umbrella vector −4z/3 (its six neighbours:
/// two at −z along x, two at +z along y, two at −z on the diagonal), i.e. k = 4/3, and one
/// λ|μ step multiplies z by (1 − 4λ/3)(1 − 4μ/3) = 0.568 9. The fixed boundary disturbs only
/// vertices within two rings per step of it; beyond, ten steps give exactly 0.5689¹⁰ z.
#[test]
fn a_high_frequency_eigenmode_decays_by_the_filter_gain() {
    let n = 61;
    let mut positions = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let z = if i % 2 == 0 { 1.0 } else { -1.0 };
            positions.push([10.0 * i as f64, 10.0 * j as f64, z]);
        }
    }
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
            faces.push([a, b, d]);
            faces.push([a, d, c]);
        }
    }
    let mut mesh = flatcut_mesh::TriMesh::new(positions, faces).unwrap();
    let topo = Topology::build(&mesh).unwrap();
    let fixed: Vec<bool> = (0..mesh.vertex_count())
        .map(|v| topo.is_boundary_vertex(VertexId(v as u32)))
        .collect();
    let before = mesh.positions.clone();
    let steps = 10;
    taubin_smooth(&mut mesh, &fixed, steps);
    let k: f64 = 4.0 / 3.0;
    let gain = ((1.0 - TAUBIN_LAMBDA * k) * (1.0 - TAUBIN_MU * k)).powi(steps as i32);
    let reach = 2 * steps + 1;
    let mut checked = 0;
    for j in reach..n - reach {
        for i in reach..n - reach {
            let v = j * n + i;
            let want = gain * before[v][2];
            assert!((mesh.positions[v][2] - want).abs() < 1e-12, "({i}, {j})");
            // The mode is purely vertical: x and y do not move.
            assert!((mesh.positions[v][0] - before[v][0]).abs() < 1e-12);
            assert!((mesh.positions[v][1] - before[v][1]).abs() < 1e-12);
            checked += 1;
        }
    }
    assert!(checked > 300);
    for v in 0..mesh.vertex_count() {
        if fixed[v] {
            assert_eq!(mesh.positions[v], before[v]);
        }
    }
}

/// A closed sphere keeps its size (the point of μ): after ten steps every radius is within
/// 0.5 % of R, where ten plain Laplacian steps with the same λ (μ = 0) shrink it measurably
/// more — the radius loss of one umbrella step on a sphere is about λ·h²/(4R) per step.
#[test]
fn a_sphere_keeps_its_radius() {
    let r = 100.0;
    let mut mesh = icosphere(r, 3);
    let none = vec![false; mesh.vertex_count()];
    taubin_smooth(&mut mesh, &none, 10);
    let radii: Vec<f64> = mesh.positions.iter().map(|&p| norm(p)).collect();
    let (lo, hi) = radii
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    assert!(lo > 0.995 * r && hi < 1.005 * r, "radii in [{lo}, {hi}]");
    let mean_taubin = radii.iter().sum::<f64>() / radii.len() as f64;
    // Plain Laplacian smoothing for comparison: the same number of λ half-steps alone.
    let mut plain = icosphere(r, 3);
    let n = plain.vertex_count();
    let topo = Topology::build(&plain).unwrap();
    for _ in 0..10 {
        let prev = plain.positions.clone();
        for v in 0..n {
            let ring: Vec<usize> = topo
                .outgoing(VertexId(v as u32))
                .iter()
                .map(|&h| topo.to_vertex(h).idx())
                .collect();
            for k in 0..3 {
                let m = ring.iter().map(|&u| prev[u][k]).sum::<f64>() / ring.len() as f64;
                plain.positions[v][k] = prev[v][k] + TAUBIN_LAMBDA * (m - prev[v][k]);
            }
        }
    }
    let mean_plain = plain.positions.iter().map(|&p| norm(p)).sum::<f64>() / n as f64;
    assert!(
        r - mean_plain > 5.0 * (r - mean_taubin).abs(),
        "plain {mean_plain}, Taubin {mean_taubin}"
    );
}
