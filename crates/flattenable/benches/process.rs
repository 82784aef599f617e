//! Time of `process` (robust mode) on 60° sphere-cap pieces of ~250 to ~10k faces (100k with
//! FLATCUT_BENCH_LARGE=1), beside the time of one numeric Cholesky factorisation of A Aᵀ of the
//! same piece (the cost an iteration is measured against). Iterations, θ_err and the time per
//! factorisation (CPU time) are printed once per size.
//!
//! Also the coarsening of the 3.5k and 10k caps (`-- coarsen`), a fixed cost of coarse-to-fine.
//!
//! `cargo bench -p flatcut_flattenable --bench process`

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_flattenable::least_norm::Metric;
use flatcut_flattenable::{ProcessOptions, process};

#[path = "../tests/common/mod.rs"]
mod common;
use common::{AtInput, bench_cap as cap};

/// CPU time of this process so far (ns, Linux: summed /proc/self/task/*/schedstat; 0
/// elsewhere). The machine is shared: wall time mostly measures the other agents' load.
fn cpu_ns() -> u64 {
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return 0;
    };
    dir.filter_map(|e| e.ok())
        .filter_map(|e| std::fs::read_to_string(e.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum()
}

fn bench(c: &mut Criterion) {
    // FLATCUT_BENCH_LARGE=1 adds the 100k-face cap (one run each); =only runs just that.
    let large = std::env::var("FLATCUT_BENCH_LARGE").ok();
    let mut sizes = if large.as_deref() == Some("only") {
        Vec::new()
    } else {
        vec![12usize, 24, 33, 43, 72]
    };
    if large.is_some() {
        sizes.push(225);
    }
    let mut group = c.benchmark_group("flattenable");
    group.sample_size(10);
    for n in sizes {
        let mesh = cap(n);
        let faces = mesh.face_count();
        let opts = ProcessOptions::default();
        // One run for the numbers beside the timing.
        let t = Instant::now();
        let c0 = cpu_ns();
        let r = process(&mesh, &opts);
        let secs = t.elapsed().as_secs_f64();
        let cpu = (cpu_ns() - c0) as f64 * 1e-9;
        let report = match &r {
            Ok(p) => p.report.clone(),
            Err(flatcut_flattenable::FlattenableError::NotConverged { partial, .. }) => {
                eprintln!("{faces} faces: NOT converged");
                partial.report.clone()
            }
            Err(e) => {
                eprintln!("{faces} faces: {e}");
                continue;
            }
        };
        let (iters, err) = (report.iterations, report.final_theta_err);
        // One numeric factorisation of A Aᵀ at the input.
        let at_input = AtInput::new(&mesh);
        let AtInput {
            layout,
            normal,
            mean_diagonal: m,
            ..
        } = &at_input;
        // Best of 5: the least disturbed by the other agents' load.
        let chol = (0..5)
            .map(|_| {
                let t = Instant::now();
                black_box(
                    layout
                        .factor(normal, 1e-3 * m, None)
                        .unwrap_or_else(|e| panic!("{e:?}")),
                );
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min);
        // The zero target (no pull-backs) once, for the iteration count beside the default.
        let zero = ProcessOptions {
            target: flatcut_flattenable::Target::Zero,
            ..Default::default()
        };
        let t = Instant::now();
        let c0 = cpu_ns();
        let rz = process(&mesh, &zero);
        let zsecs = t.elapsed().as_secs_f64();
        let zcpu = (cpu_ns() - c0) as f64 * 1e-9;
        if let Ok(p) = &rz {
            eprintln!(
                "{faces} faces, zero target: {} iterations (+{} rejected, {} factorisations), {:.1} ms wall, {:.1} ms CPU",
                p.report.iterations,
                p.report.pieces[0].rejected_steps,
                p.report.pieces[0].factorizations,
                zsecs * 1e3,
                zcpu * 1e3
            );
        }
        let rej = report.pieces[0].rejected_steps;
        let facts = report.pieces[0].factorizations;
        eprintln!(
            "{faces} faces, {} interior: {iters} iterations (+{rej} rejected, {facts} factorisations), θ_err {err:.1e}, {:.1} ms wall, {:.1} ms CPU, {:.2} ms CPU per factorisation = {:.2}× one Cholesky of A Aᵀ ({:.3} ms, best of 5)",
            layout.n(),
            secs * 1e3,
            cpu * 1e3,
            cpu * 1e3 / facts.max(1) as f64,
            cpu / facts.max(1) as f64 / chol,
            chol * 1e3,
        );
        // A step alone: the whole-run ratio above includes the set-up and the coarse levels
        // (35× one Cholesky at 242 faces on the thirty-second session's host), so the issue's "an iteration within 2× of one
        // sparse Cholesky" is read on the direct solve, its set-up subtracted (minima of
        // five, timed in turn with faer's numeric Cholesky of the same A Aᵀ).
        if faces < 50_000 {
            let direct = ProcessOptions {
                coarse_to_fine: flatcut_flattenable::CoarseToFine {
                    levels: 0,
                    ..Default::default()
                },
                ..Default::default()
            };
            if let Ok(p) = process(&mesh, &direct) {
                let facts = p.report.pieces[0].factorizations;
                let cost = at_input.step_cost(&mesh, &direct, 5);
                eprintln!(
                    "{faces} faces: a step of the direct solve ({facts} factorisations, set-up {:.2} ms subtracted) = {:.2}× faer's numeric Cholesky ({:.3} ms)",
                    cost.set_up * 1e3,
                    cost.per_factorization(facts) / cost.faer_cholesky,
                    cost.faer_cholesky * 1e3
                );
            }
        }
        // The 100k-face piece is timed by the single run above (a criterion sample of ten
        // runs would take minutes on the 2 shared cores).
        if r.is_err() || faces > 50_000 {
            continue;
        }
        group.bench_function(format!("robust_cap_{faces}_faces"), |b| {
            b.iter(|| black_box(process(black_box(&mesh), &opts).is_ok()))
        });
    }
    group.finish();
}

/// What a step is made of besides the iteration's logic, per kernel, on the bench caps at
/// the input: θ (every trial and correction), A (every accepted point), A G Aᵀ, one numeric
/// Cholesky (symbolic reused) and one solve — so that a step's cost against one Cholesky can
/// be read kernel by kernel (docs/benchmarks.md).
fn bench_step_kernels(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_kernels");
    group.sample_size(30);
    for n in [12usize, 24, 43, 72] {
        let mesh = cap(n);
        let faces = mesh.face_count();
        let at_input = AtInput::new(&mesh);
        let normals = at_input.interior_normals(&mesh);
        let tangential = at_input.tangential_metric(&normals);
        let AtInput {
            layout,
            theta,
            grad,
            scale,
            normal,
            mean_diagonal,
        } = &at_input;
        let (mut theta, mut grad, mut normal) = (theta.clone(), grad.clone(), normal.clone());
        let mean_diagonal = *mean_diagonal;
        let metric = Metric::isotropic(scale);
        let shift = 1e-3 * mean_diagonal;
        let mut factor = layout
            .factor(&normal, shift, None)
            .unwrap_or_else(|e| panic!("{e:?}"));
        group.bench_function(format!("theta_{faces}_faces"), |b| {
            b.iter(|| layout.theta(black_box(&mesh.positions), &mut theta))
        });
        group.bench_function(format!("gradient_{faces}_faces"), |b| {
            b.iter(|| layout.gradient(black_box(&mesh.positions), &mut grad))
        });
        // θ and A in one pass: a trial where no correction can follow.
        group.bench_function(format!("evaluate_{faces}_faces"), |b| {
            b.iter(|| layout.evaluate(black_box(&mesh.positions), &mut theta, &mut grad))
        });
        group.bench_function(format!("normal_matrix_{faces}_faces"), |b| {
            b.iter(|| layout.normal_matrix(black_box(&grad), &metric, &mut normal))
        });
        // Robust mode's metric (the default tangential penalty), into its own buffer: the
        // factorisations below take the isotropic A Aᵀ.
        let mut tangential_normal = normal.clone();
        group.bench_function(format!("normal_matrix_tangential_{faces}_faces"), |b| {
            b.iter(|| layout.normal_matrix(black_box(&grad), &tangential, &mut tangential_normal))
        });
        group.bench_function(format!("cholesky_{faces}_faces"), |b| {
            b.iter(|| {
                layout
                    .refactor(&mut factor, black_box(&normal), shift, None)
                    .unwrap_or_else(|e| panic!("{e:?}"))
            })
        });
        // faer's own numeric factorisation of the same matrix: the reference of the issue's
        // "a step within 2× of one sparse Cholesky".
        group.bench_function(format!("faer_cholesky_{faces}_faces"), |b| {
            b.iter(|| {
                layout
                    .refactor_with_faer(&mut factor, black_box(&normal), shift, None)
                    .unwrap_or_else(|e| panic!("{e:?}"))
            })
        });
        let rhs: Vec<f64> = theta.iter().map(|t| std::f64::consts::TAU - t).collect();
        group.bench_function(format!("solve_{faces}_faces"), |b| {
            b.iter(|| {
                let mut x = rhs.clone();
                layout.solve(&factor, &mut x, 1);
                black_box(x)
            })
        });
    }
    group.finish();
}

/// The coarsening coarse-to-fine runs once per level before any iteration (to a quarter of
/// the faces): a fixed cost of every piece of 2 000–15 000 faces.
fn bench_coarsen(c: &mut Criterion) {
    let mut group = c.benchmark_group("coarsen");
    group.sample_size(20);
    for n in [12usize, 24, 43, 72] {
        let mesh = cap(n);
        let target = mesh.face_count() / 4;
        group.bench_function(format!("cap_{}_faces", mesh.face_count()), |b| {
            b.iter(|| {
                black_box(flatcut_flattenable::coarsen::coarsen(black_box(&mesh), target).is_ok())
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench, bench_step_kernels, bench_coarsen);
criterion_main!(benches);
