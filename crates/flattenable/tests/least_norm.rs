//! The weighted least-norm step (Eq. 6–8, 14–16) against its defining identity A d = b
//! and against an independent dense path (faer dense SVD pseudo-inverse).

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use std::f64::consts::TAU;

use faer::Mat;
use faer::linalg::solvers::Solve;
use flatcut_flattenable::angle_gradient::angle_sum_gradient;
use flatcut_flattenable::least_norm::{Layout, Metric, least_norm_step};
use flatcut_mesh::Topology;

fn setup(mesh: &flatcut_mesh::TriMesh) -> (Layout, Vec<f64>, Vec<[f64; 3]>) {
    let at = common::AtInput::new(mesh);
    (at.layout, at.theta, at.grad)
}

/// The undamped least-norm step under `metric`: A G Aᵀ assembled, then d = G Aᵀ x.
fn step_under(layout: &Layout, grad: &[[f64; 3]], metric: &Metric<'_>, b: &[f64]) -> Vec<[f64; 3]> {
    let mut normal = vec![0.0; layout.normal_nnz()];
    layout.normal_matrix(grad, metric, &mut normal);
    least_norm_step(layout, grad, metric, &normal, b, 0.0).unwrap()
}

fn dense_a(layout: &Layout, grad: &[[f64; 3]]) -> Mat<f64> {
    let n = layout.n();
    let mut a = Mat::<f64>::zeros(n, 3 * n);
    for i in 0..n {
        for e in layout.row_ptr[i]..layout.row_ptr[i + 1] {
            let c = layout.col[e] as usize;
            for k in 0..3 {
                a[(i, 3 * c + k)] = grad[e][k];
            }
        }
    }
    a
}

#[test]
fn weighted_step_solves_constraints_and_equals_dense_pseudo_inverse() {
    for mesh in [common::sphere_cap(6), common::saddle(6)] {
        let (layout, theta, grad) = setup(&mesh);
        let n = layout.n();
        // Weights 1..10 varying over the vertices.
        let w: Vec<f64> = (0..n).map(|i| 1.0 + 9.0 * (i % 4) as f64 / 3.0).collect();
        let scale: Vec<f64> = w.iter().map(|w| 1.0 / (w * w)).collect();
        let metric = Metric {
            scale: &scale,
            normals: None,
            tangential: 1.0,
        };
        let mut normal = vec![0.0; layout.normal_nnz()];
        layout.normal_matrix(&grad, &metric, &mut normal);
        let b: Vec<f64> = theta.iter().map(|t| TAU - t).collect();
        let d = least_norm_step(&layout, &grad, &metric, &normal, &b, 0.0).unwrap();

        // A d = b.
        let ad = layout.apply(&grad, &d);
        let bn = b.iter().map(|x| x * x).sum::<f64>().sqrt();
        let res = ad
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
            .sqrt();
        assert!(res / bn < 1e-12, "relative residual {}", res / bn);

        // Dense: d = W (A W)⁺ b with W = diag(1/w) per coordinate.
        let a = dense_a(&layout, &grad);
        let aw = Mat::<f64>::from_fn(n, 3 * n, |i, j| a[(i, j)] / w[j / 3]);
        let pinv = aw.svd().unwrap().pseudoinverse();
        let bm = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
        let r = &pinv * &bm;
        let dn = d.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
        let mut diff = 0.0;
        for c in 0..n {
            for k in 0..3 {
                let dense = r[(3 * c + k, 0)] / w[c];
                diff += (dense - d[c][k]).powi(2);
            }
        }
        assert!(
            diff.sqrt() / dn < 1e-10,
            "sparse vs dense {}",
            diff.sqrt() / dn
        );
    }
}

#[test]
fn tangential_metric_step_equals_the_dense_formula() {
    // The robust mode's metric G_c = s_c (t I + (1 − t) n nᵀ), which `normal_matrix`
    // applies through its square root: against d = G Aᵀ (A G Aᵀ)⁻¹ b with G formed
    // densely block by block, on a rough saddle, with varying weights and normals tilted
    // off the surface's.
    let mesh = rough_saddle(7);
    let (layout, theta, grad) = setup(&mesh);
    let n = layout.n();
    let scale: Vec<f64> = (0..n).map(|i| 1.0 / (1.0 + (i % 5) as f64)).collect();
    let normals: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let a = 0.3 * ((i * 37 % 11) as f64 / 11.0 - 0.5);
            flatcut_mesh::vec3::normalize([a, -0.5 * a, 1.0])
        })
        .collect();
    let t = 0.01;
    let metric = Metric {
        scale: &scale,
        normals: Some(&normals),
        tangential: t,
    };
    let b: Vec<f64> = theta.iter().map(|t| TAU - t).collect();
    let d = step_under(&layout, &grad, &metric, &b);

    let a = dense_a(&layout, &grad);
    let g = Mat::<f64>::from_fn(3 * n, 3 * n, |r, c| {
        if r / 3 != c / 3 {
            return 0.0;
        }
        let (v, nv) = (r / 3, normals[r / 3]);
        let identity = if r == c { t } else { 0.0 };
        scale[v] * (identity + (1.0 - t) * nv[r % 3] * nv[c % 3])
    });
    let aga = &a * &g * a.transpose();
    let bm = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
    let x = aga.partial_piv_lu().solve(&bm);
    let dense = &g * a.transpose() * &x;
    let dn = d.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    let mut diff = 0.0;
    for c in 0..n {
        for k in 0..3 {
            diff += (dense[(3 * c + k, 0)] - d[c][k]).powi(2);
        }
    }
    assert!(dn > 1e-3, "a step to compare: |d| = {dn:e}");
    assert!(
        diff.sqrt() / dn < 1e-10,
        "sparse vs dense {}",
        diff.sqrt() / dn
    );
}

#[test]
fn damped_step_is_smaller_and_tends_to_the_undamped_one() {
    let at = common::AtInput::new(&common::sphere_cap(8));
    let (layout, grad, normal, m) = (&at.layout, &at.grad, &at.normal, at.mean_diagonal);
    let metric = at.metric();
    let b: Vec<f64> = at.theta.iter().map(|t| TAU - t).collect();
    let norm = |d: &[[f64; 3]]| d.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    let d0 = least_norm_step(layout, grad, &metric, normal, &b, 0.0).unwrap();
    let d1 = least_norm_step(layout, grad, &metric, normal, &b, 1.0 * m).unwrap();
    let dt = least_norm_step(layout, grad, &metric, normal, &b, 1e-12 * m).unwrap();
    assert!(norm(&d1) < norm(&d0));
    let diff: Vec<[f64; 3]> = d0
        .iter()
        .zip(&dt)
        .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
        .collect();
    assert!(norm(&diff) < 1e-8 * norm(&d0));
}

#[test]
fn normal_metric_moves_mostly_along_normals() {
    // On the unit-sphere cap the exact normal is the position.
    let mesh = common::sphere_cap(8);
    let (layout, theta, grad) = setup(&mesh);
    let n = layout.n();
    let scale = vec![1.0; n];
    let normals: Vec<[f64; 3]> = layout
        .interior
        .iter()
        .map(|&p| mesh.positions[p as usize])
        .collect();
    let b: Vec<f64> = theta.iter().map(|t| TAU - t).collect();
    let tangential_share = |t: f64| {
        let metric = Metric {
            scale: &scale,
            normals: Some(&normals),
            tangential: t,
        };
        let d = step_under(&layout, &grad, &metric, &b);
        // Still solves A d = b.
        let ad = layout.apply(&grad, &d);
        let res: f64 = ad
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(res < 1e-10 * b.iter().fold(0.0f64, |m, x| m.max(x.abs())));
        let (mut tan, mut all) = (0.0, 0.0);
        for (dv, nv) in d.iter().zip(&normals) {
            let dn = dv[0] * nv[0] + dv[1] * nv[1] + dv[2] * nv[2];
            let d2 = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
            tan += d2 - dn * dn;
            all += d2;
        }
        tan / all
    };
    let (t1, t001) = (tangential_share(1.0), tangential_share(0.01));
    eprintln!("tangential share t=1: {t1}, t=0.01: {t001}");
    assert!(t001 < 0.5 * t1);
}

#[test]
fn weighted_vertices_take_a_smaller_share_of_the_step() {
    // Eq. 14–16: weight 10 on every other interior vertex; those vertices' step shrinks.
    let mesh = common::sphere_cap(9);
    let (layout, theta, grad) = setup(&mesh);
    let n = layout.n();
    let b: Vec<f64> = theta.iter().map(|t| TAU - t).collect();
    let step = |w: &dyn Fn(usize) -> f64| {
        let scale: Vec<f64> = (0..n).map(|i| 1.0 / (w(i) * w(i))).collect();
        let metric = Metric {
            scale: &scale,
            normals: None,
            tangential: 1.0,
        };
        let mut normal = vec![0.0; layout.normal_nnz()];
        layout.normal_matrix(&grad, &metric, &mut normal);
        least_norm_step(&layout, &grad, &metric, &normal, &b, 0.0).unwrap()
    };
    let plain = step(&|_| 1.0);
    let weighted = step(&|i| if i % 2 == 0 { 10.0 } else { 1.0 });
    let norm = |d: &[f64; 3]| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let (mut p, mut w) = (0.0, 0.0);
    for i in (0..n).step_by(2) {
        p += norm(&plain[i]);
        w += norm(&weighted[i]);
    }
    assert!(w < p, "{w} vs {p}");
}

/// The n×n saddle with its heights jittered by up to ±0.005 (a fixed pattern): no two
/// stars alike, so that mix-ups of rows, corners or blocks show.
fn rough_saddle(n: usize) -> flatcut_mesh::TriMesh {
    let mut mesh = common::saddle(n);
    for (i, p) in mesh.positions.iter_mut().enumerate() {
        p[2] += 0.01 * ((i * 7919 % 13) as f64 / 13.0 - 0.5);
    }
    mesh
}

#[test]
fn rows_of_a_equal_the_per_vertex_gradient() {
    // A's rows come from corners scattered into a CSR pattern (`Layout::gradient`); each
    // must equal the gradient of that vertex's θ built independently from its one-ring
    // (`angle_sum_gradient`, checked against central differences in tests/angle_gradient.rs),
    // with the boundary columns dropped.
    let mesh = rough_saddle(9);
    let topo = Topology::build(&mesh).unwrap();
    let (layout, theta, grad) = setup(&mesh);
    let mut alone = vec![[1.0; 3]; layout.entries()];
    layout.gradient(&mesh.positions, &mut alone);
    assert_eq!(alone, grad, "evaluate's A is gradient's");
    let mut compared = 0;
    for i in 0..layout.n() {
        let v = layout.interior[i];
        let (t, reference) = angle_sum_gradient(
            &mesh.positions,
            &mesh.faces,
            &topo,
            flatcut_mesh::VertexId(v),
        );
        assert!((t - theta[i]).abs() <= 1e-14, "θ {t} vs {}", theta[i]);
        let entries = layout.row_ptr[i]..layout.row_ptr[i + 1];
        let interior_refs = reference
            .iter()
            .filter(|(q, _)| layout.index_of[q.idx()] != flatcut_mesh::INVALID)
            .count();
        assert_eq!(
            entries.len(),
            interior_refs,
            "row {i}: one entry per interior vertex"
        );
        // Bit for bit: the block loop of `Layout::gradient` does corner_gradient's
        // operations, and scatters them in the same corner order as the one-ring sum.
        for e in entries {
            let q = layout.interior[layout.col[e] as usize];
            let (_, g) = reference.iter().find(|(r, _)| r.0 == q).unwrap();
            assert_eq!(grad[e], *g, "row {i}, entry {e}");
            compared += 1;
        }
    }
    assert!(
        compared > 5 * layout.n(),
        "{compared} entries of {} rows",
        layout.n()
    );
}

#[test]
fn theta_in_blocks_equals_the_sum_of_corner_angles() {
    // `Layout::theta` takes the corners in blocks of 256 and their angles in a vectorised
    // loop; `theta_at` one vertex at a time. They must agree to the bit (the lift and the
    // local polish mix them), across block boundaries, and agree with the angle sums of the
    // mesh crate and with a sum of the platform's atan2 (an independent angle function).
    let mesh = rough_saddle(30);
    let topo = Topology::build(&mesh).unwrap();
    let layout = Layout::build(&topo, &mesh.faces).unwrap();
    let mut theta = vec![f64::NAN; layout.n()];
    layout.theta(&mesh.positions, &mut theta);
    assert!(6 * layout.n() > 10 * 256, "the corners span several blocks");
    let sums = flatcut_mesh::geometry::angle_sums(&mesh.positions, &mesh.faces);
    let mut platform = vec![0.0; mesh.vertex_count()];
    for f in &mesh.faces {
        for k in 0..3 {
            let p = mesh.positions[f[k] as usize];
            let u = flatcut_mesh::vec3::sub(mesh.positions[f[(k + 1) % 3] as usize], p);
            let w = flatcut_mesh::vec3::sub(mesh.positions[f[(k + 2) % 3] as usize], p);
            let c = flatcut_mesh::vec3::cross(u, w);
            platform[f[k] as usize] +=
                flatcut_mesh::vec3::norm(c).atan2(flatcut_mesh::vec3::dot(u, w));
        }
    }
    for (i, &t) in theta.iter().enumerate() {
        assert_eq!(t.to_bits(), layout.theta_at(i, &mesh.positions).to_bits());
        let v = layout.interior[i] as usize;
        assert!((t - sums[v]).abs() <= 1e-14, "{t} vs {}", sums[v]);
        assert!((t - platform[v]).abs() <= 1e-14, "{t} vs {}", platform[v]);
        assert!((t - TAU).abs() < 0.5, "a saddle vertex: θ near 2π, got {t}");
    }
}

#[test]
fn evaluate_in_one_pass_equals_theta_and_gradient_bit_for_bit() {
    // `Layout::evaluate` forms θ and A in one pass over the corners (one gather of their
    // edges, one kernel); a run mixes it with `theta` (backtracking, corrections) and
    // `gradient` (accepted points), so they must agree to the bit, across block boundaries.
    let mesh = rough_saddle(30);
    let topo = Topology::build(&mesh).unwrap();
    let layout = Layout::build(&topo, &mesh.faces).unwrap();
    assert!(6 * layout.n() > 10 * 256, "the corners span several blocks");
    let mut theta = vec![f64::NAN; layout.n()];
    let mut grad = vec![[f64::NAN; 3]; layout.entries()];
    layout.evaluate(&mesh.positions, &mut theta, &mut grad);
    let mut theta_alone = vec![f64::NAN; layout.n()];
    let mut grad_alone = vec![[f64::NAN; 3]; layout.entries()];
    layout.theta(&mesh.positions, &mut theta_alone);
    layout.gradient(&mesh.positions, &mut grad_alone);
    for i in 0..layout.n() {
        assert_eq!(theta[i].to_bits(), theta_alone[i].to_bits(), "θ at {i}");
    }
    for (e, (a, b)) in grad.iter().zip(&grad_alone).enumerate() {
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "entry {e}");
    }
}

#[test]
fn refactor_reuses_buffers_and_recovers_after_a_failed_factorisation() {
    let (layout, theta, grad) = setup(&common::sphere_cap(8));
    // A Aᵀ through the unit metric; b = 2π − θ.
    let unit = vec![1.0; layout.n()];
    let mut normal = vec![0.0; layout.normal_nnz()];
    layout.normal_matrix(&grad, &Metric::isotropic(&unit), &mut normal);
    let m = layout.mean_diagonal(&normal);
    let b: Vec<f64> = theta.iter().map(|t| TAU - t).collect();
    let solve = |f: &flatcut_flattenable::least_norm::Factor| {
        let mut x = b.clone();
        layout.solve(f, &mut x, 1);
        x
    };
    let fresh = solve(&layout.factor(&normal, 1e-3 * m, None).unwrap());
    let mut reused = layout.new_factor().unwrap();
    // A first factorisation at another shift, then a failing one (indefinite: −10 m I),
    // then the one to compare: the buffers carry nothing over.
    layout
        .refactor(&mut reused, &normal, 1.0 * m, None)
        .unwrap();
    assert!(
        layout
            .refactor(&mut reused, &normal, -10.0 * m, None)
            .is_err()
    );
    layout
        .refactor(&mut reused, &normal, 1e-3 * m, None)
        .unwrap();
    let again = solve(&reused);
    for (a, b) in again.iter().zip(&fresh) {
        assert_eq!(a.to_bits(), b.to_bits());
    }
}

/// The graph Laplacian of `layout`'s interior vertices built from `mesh`'s faces alone: per
/// interior vertex its full valence (boundary neighbours counted), and the pairs of interior
/// neighbours (each once).
fn interior_graph(
    mesh: &flatcut_mesh::TriMesh,
    layout: &Layout,
) -> (Vec<f64>, Vec<(usize, usize)>) {
    let mut edges = std::collections::BTreeSet::new();
    for f in &mesh.faces {
        for k in 0..3 {
            let (p, q) = (f[k], f[(k + 1) % 3]);
            edges.insert((p.min(q), p.max(q)));
        }
    }
    let mut interior_of = vec![usize::MAX; mesh.vertex_count()];
    for (i, &p) in layout.interior.iter().enumerate() {
        interior_of[p as usize] = i;
    }
    let mut valence = vec![0.0; layout.n()];
    let mut pairs = Vec::new();
    for &(p, q) in &edges {
        let (ip, iq) = (interior_of[p as usize], interior_of[q as usize]);
        for i in [ip, iq] {
            if i != usize::MAX {
                valence[i] += 1.0;
            }
        }
        if ip != usize::MAX && iq != usize::MAX {
            pairs.push((ip, iq));
        }
    }
    (valence, pairs)
}

/// `Damping::GraphLaplacian` factorises A Aᵀ + s (ε I + L) / (ε + mean valence), L the graph
/// Laplacian of the interior vertices (full valence on the diagonal, −1 per interior
/// neighbour): the solve's x must satisfy that system, built here from the faces' edges
/// and the dense A alone. `Damping::Identity` is the plain shift, bit for bit.
#[test]
fn graph_laplacian_damping_solves_the_shifted_system() {
    use flatcut_flattenable::Damping;
    use flatcut_flattenable::least_norm::GRAPH_DAMPING_EPSILON;

    let mesh = rough_saddle(9);
    let at = common::AtInput::new(&mesh);
    let (layout, grad) = (&at.layout, &at.grad);
    let n = layout.n();
    let b: Vec<f64> = at.theta.iter().map(|t| TAU - t).collect();
    let shift = 0.3 * at.mean_diagonal;

    let (valence, pairs) = interior_graph(&mesh, layout);
    let mean = valence.iter().sum::<f64>() / n as f64;
    let unit = shift / (GRAPH_DAMPING_EPSILON + mean);

    // x for b under a factor made by `make`.
    let solve_with = |make: &dyn Fn(&mut flatcut_flattenable::least_norm::Factor)| {
        let mut factor = layout.new_factor().unwrap();
        make(&mut factor);
        let mut x = b.clone();
        layout.solve(&factor, &mut x, 1);
        x
    };
    let x = solve_with(&|f| {
        layout
            .refactor_damped(f, &at.normal, shift, Damping::GraphLaplacian)
            .unwrap()
    });

    // (A Aᵀ + unit (ε I + L)) x with the dense A (isotropic metric, weights 1).
    let a = dense_a(layout, grad);
    let xm = Mat::<f64>::from_fn(n, 1, |i, _| x[i]);
    let aatx = &a * (a.transpose() * &xm);
    let mut y: Vec<f64> = (0..n)
        .map(|i| aatx[(i, 0)] + unit * (GRAPH_DAMPING_EPSILON + valence[i]) * x[i])
        .collect();
    for &(i, j) in &pairs {
        y[i] -= unit * x[j];
        y[j] -= unit * x[i];
    }
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let r: Vec<f64> = y.iter().zip(&b).map(|(p, q)| p - q).collect();
    assert!(
        norm(&r) / norm(&b) < 1e-12,
        "residual {}",
        norm(&r) / norm(&b)
    );
    // The damping matters here: it is not the identity shift's solution.
    let x_plain = solve_with(&|f| layout.refactor(f, &at.normal, shift, None).unwrap());
    let gap: Vec<f64> = x.iter().zip(&x_plain).map(|(p, q)| p - q).collect();
    assert!(norm(&gap) > 1e-3 * norm(&x_plain), "{}", norm(&gap));

    let x_identity = solve_with(&|f| {
        layout
            .refactor_damped(f, &at.normal, shift, Damping::Identity)
            .unwrap()
    });
    assert_eq!(x_identity, x_plain);
}

/// The shaped damping's merit norm (`Layout::graph_damping_triplets`, the D of
/// `Damping::GraphLaplacian` without its shift) is the matrix that damping factorises:
/// assembled from the faces' edges here. And it is the norm in which heavy damping descends:
/// for a large shift the damped step d = Aᵀ (A Aᵀ + s D)⁻¹ b lowers ‖b − A d‖²_{D⁻¹} to first
/// order (its slope −2 bᵀ D⁻¹ A d is negative), whatever the plain norm does. Checked with
/// dense matrices on a rough saddle.
#[test]
fn graph_damping_norm_is_the_damped_systems_and_heavy_damping_descends_in_it() {
    use flatcut_flattenable::Damping;
    use flatcut_flattenable::least_norm::GRAPH_DAMPING_EPSILON;

    let mesh = rough_saddle(9);
    let at = common::AtInput::new(&mesh);
    let (layout, grad) = (&at.layout, &at.grad);
    let n = layout.n();
    let b: Vec<f64> = at.theta.iter().map(|t| TAU - t).collect();

    // D from the faces' edges: (ε + full valence) on the diagonal, −1 per interior
    // neighbour, over ε + the mean valence.
    let (valence, pairs) = interior_graph(&mesh, layout);
    let mut expected = Mat::<f64>::zeros(n, n);
    for &(i, j) in &pairs {
        expected[(i, j)] = -1.0;
        expected[(j, i)] = -1.0;
    }
    let mean = valence.iter().sum::<f64>() / n as f64;
    for i in 0..n {
        expected[(i, i)] = GRAPH_DAMPING_EPSILON + valence[i];
    }
    let expected = expected * faer::Scale(1.0 / (GRAPH_DAMPING_EPSILON + mean));

    let t = layout.graph_damping_triplets();
    let mut d = Mat::<f64>::zeros(n, n);
    for (&(i, j), &v) in t.pairs().iter().zip(t.values()) {
        d[(i, j)] += v;
        if i != j {
            d[(j, i)] += v;
        }
    }
    let gap = (&d - &expected).norm_max();
    assert!(gap < 1e-15, "D differs from the edges' by {gap:e}");

    // Heavy damping: d = Aᵀ x, x = (A Aᵀ + s D)⁻¹ b, s = 1e6 × the mean diagonal.
    let mut factor = layout.new_factor().unwrap();
    layout
        .refactor_damped(
            &mut factor,
            &at.normal,
            1e6 * at.mean_diagonal,
            Damping::GraphLaplacian,
        )
        .unwrap();
    let mut x = b.clone();
    layout.solve(&factor, &mut x, 1);
    let a = dense_a(layout, grad);
    let xm = Mat::<f64>::from_fn(n, 1, |i, _| x[i]);
    let ad = &a * (a.transpose() * &xm);
    let d_inv = d.svd().unwrap().pseudoinverse();
    let bm = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
    let slope_shaped = -2.0 * (bm.transpose() * (&d_inv * &ad))[(0, 0)];
    let scale = (bm.transpose() * &ad)[(0, 0)].abs().max(f64::MIN_POSITIVE);
    assert!(
        slope_shaped < -1e-3 * scale,
        "slope {slope_shaped:e} (scale {scale:e})"
    );
}
