//! `Mode::Robust` (the default) on the patches and on the invariants of the method.

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use flatcut_flattenable::{
    AREA_TIE_PERCENT, FlattenableError, PieceReport, ProcessOptions, Processed, Target, Update,
    process,
};
use flatcut_mesh::TriMesh;
use flatcut_mesh::geometry::corner_angles;

/// The piece's report has a message containing `text`.
fn assert_says(piece: &PieceReport, text: &str) {
    assert!(
        piece.messages.iter().any(|m| m.contains(text)),
        "no message with {text:?}: {:?}",
        piece.messages
    );
}

fn robust(mesh: &TriMesh, opts: &ProcessOptions) -> Processed {
    match process(mesh, opts) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    }
}

fn assert_flat_unfolded(mesh: &TriMesh, r: &Processed) {
    let rep = &r.report;
    assert!(rep.converged);
    assert!(rep.final_theta_err <= 1e-9, "θ_err {}", rep.final_theta_err);
    assert_eq!(rep.folded_faces, 0);
    assert_eq!(common::boundary_changed(mesh, &r.mesh), 0);
    // Independent check of the fold claim: no normal turned by 90° or more.
    let n0 = flatcut_mesh::geometry::face_normals(&mesh.positions, &mesh.faces);
    let n1 = flatcut_mesh::geometry::face_normals(&r.mesh.positions, &r.mesh.faces);
    for (a, b) in n0.iter().zip(&n1) {
        assert!(flatcut_mesh::vec3::dot(*a, *b) > 0.0);
    }
    let min = corner_angles(&r.mesh.positions, &r.mesh.faces)
        .iter()
        .flatten()
        .fold(f64::INFINITY, |m, a| m.min(*a));
    assert!(min.to_degrees() >= 0.5);
    // θ recomputed independently by the mesh crate.
    let theta = flatcut_mesh::geometry::angle_sums(&r.mesh.positions, &r.mesh.faces);
    let topo = flatcut_mesh::Topology::build(mesh).unwrap();
    for (v, t) in theta.iter().enumerate() {
        if topo.is_interior_vertex(flatcut_mesh::VertexId(v as u32)) {
            assert!((t - std::f64::consts::TAU).abs() <= 1e-9);
        }
    }
}

#[test]
fn planar_disk_and_cylinder_come_back_unchanged() {
    let disk = flatcut_mesh::shapes::planar_disk(50.0, 6);
    let cyl = flatcut_mesh::shapes::cylinder_patch(30.0, 2.0, 40.0, 9, 7);
    for mesh in [disk, cyl, common::planar(9)] {
        for opts in [
            ProcessOptions::default(),
            ProcessOptions::paper(Update::LeastSquare),
        ] {
            let r = process(&mesh, &opts).unwrap();
            let diag = mesh.diagonal();
            let moved = mesh
                .positions
                .iter()
                .zip(&r.mesh.positions)
                .map(|(a, b)| flatcut_mesh::vec3::dist(*a, *b))
                .fold(0.0, f64::max);
            assert!(moved <= 1e-12 * diag, "moved {moved}");
            assert!(r.report.converged);
        }
    }
}

#[test]
fn sphere_cap_25_converges_to_1e_9_without_folds() {
    let mesh = common::sphere_cap(25);
    let r = robust(&mesh, &ProcessOptions::default());
    assert_flat_unfolded(&mesh, &r);
    // A developable surface spanning the cap's boundary has less area (−6.5 % per the
    // prototype; the flat disk over this boundary would be about −6.7 %).
    let a = r.report.area_change_percent;
    assert!((-8.0..-5.0).contains(&a), "area change {a}");
}

#[test]
fn sphere_cap_50_converges_to_1e_9_without_folds() {
    let mesh = common::sphere_cap(50);
    let r = robust(&mesh, &ProcessOptions::default());
    assert_flat_unfolded(&mesh, &r);
}

#[test]
fn saddle_12_and_25_converge_with_the_normal_metric() {
    for n in [12, 25] {
        let mesh = common::saddle(n);
        let r = robust(&mesh, &ProcessOptions::default());
        assert_flat_unfolded(&mesh, &r);
    }
}

#[test]
fn normal_metric_keeps_saddle_triangles_better_shaped_than_the_isotropic_one() {
    // With the paper's isotropic metric the 12×12 saddle now converges too (it stalled at
    // 9e-3 under the old damping rule), but by sliding vertices sideways: measured min corner
    // 4.2° against 30° with the normal-preferring metric. Either run either converges flat
    // and unfolded or stops with the clean error.
    let mesh = common::saddle(12);
    let min_angle = |tangential_penalty: f64| -> f64 {
        let opts = ProcessOptions {
            tangential_penalty,
            ..Default::default()
        };
        let r = match process(&mesh, &opts) {
            Ok(r) => {
                assert_flat_unfolded(&mesh, &r);
                r
            }
            Err(FlattenableError::NotConverged {
                best_theta_err,
                partial,
                ..
            }) => {
                assert!(best_theta_err < partial.report.theta_err[0]);
                assert_eq!(partial.report.folded_faces, 0);
                assert!(
                    partial
                        .report
                        .messages
                        .iter()
                        .any(|m| m.contains("negative total angle defect"))
                );
                *partial
            }
            Err(e) => panic!("{e}"),
        };
        r.report.pieces[0].min_angle_deg
    };
    let (iso, normal) = (min_angle(1.0), min_angle(10.0));
    assert!(iso < normal, "isotropic {iso}° vs normal {normal}°");
}

#[test]
fn scaling_the_input_scales_the_result() {
    // The paper's Fig. 4: with the normalised mixed area the result does not depend on the
    // size. Every threshold of robust mode is relative, so the whole run is scale free.
    let mesh = common::sphere_cap(10);
    for opts in [
        ProcessOptions::default(),
        ProcessOptions {
            update: Update::LeastSquare,
            target: Target::Zero,
            ..Default::default()
        },
    ] {
        let base = robust(&mesh, &opts);
        for s in [0.01, 100.0] {
            let mut scaled = mesh.clone();
            scaled.scale(s);
            let r = robust(&scaled, &opts);
            let diag = scaled.diagonal();
            for (a, b) in base.mesh.positions.iter().zip(&r.mesh.positions) {
                let d = flatcut_mesh::vec3::dist(flatcut_mesh::vec3::scale(*a, s), *b);
                assert!(d <= 1e-6 * diag, "scale {s}: {d}");
            }
            assert_eq!(r.report.iterations, base.report.iterations);
        }
    }
}

#[test]
fn weighted_vertices_move_less() {
    // On the cap the flattenable shape through the fixed boundary is nearly determined, so
    // the weights change the row's motion only a little (measured 0.892 vs 0.896); the
    // per-step effect is tested in least_norm.rs.
    let mesh = common::sphere_cap(12);
    let plain = robust(&mesh, &ProcessOptions::default());
    // Weight 10 on the middle row (a feature curve across the cap).
    let row: Vec<u32> = (1..11).map(|i| 6 * 12 + i).collect();
    let opts = ProcessOptions {
        feature_curves: vec![row.clone()],
        ..Default::default()
    };
    let weighted = robust(&mesh, &opts);
    let moved = |r: &Processed| -> f64 {
        row.iter()
            .map(|&v| {
                flatcut_mesh::vec3::dist(mesh.positions[v as usize], r.mesh.positions[v as usize])
            })
            .sum()
    };
    assert_flat_unfolded(&mesh, &weighted);
    assert!(
        moved(&weighted) < moved(&plain),
        "{} vs {}",
        moved(&weighted),
        moved(&plain)
    );
    // Per-vertex weights from the caller are the same thing.
    let mut w = vec![1.0; mesh.vertex_count()];
    for &v in &row {
        w[v as usize] = 10.0;
    }
    let by_caller = robust(
        &mesh,
        &ProcessOptions {
            weights: Some(w),
            ..Default::default()
        },
    );
    assert_eq!(by_caller.mesh.positions, weighted.mesh.positions);
}

#[test]
fn boundary_ring_weight_keeps_the_ring_closer() {
    let mesh = common::sphere_cap(12);
    let ring: Vec<usize> = (0..144)
        .filter(|&v| {
            let (i, j) = (v % 12, v / 12);
            (i == 1 || i == 10 || j == 1 || j == 10)
                && (1..=10).contains(&i)
                && (1..=10).contains(&j)
        })
        .collect();
    let moved = |r: &Processed| -> f64 {
        ring.iter()
            .map(|&v| flatcut_mesh::vec3::dist(mesh.positions[v], r.mesh.positions[v]))
            .sum()
    };
    let run = |target, boundary_ring_weight| {
        robust(
            &mesh,
            &ProcessOptions {
                target,
                boundary_ring_weight,
                ..Default::default()
            },
        )
    };
    // The ring of `nearer` moved less than that of `farther`.
    let moves_less = |nearer: &Processed, farther: &Processed| {
        let (a, b) = (moved(nearer), moved(farther));
        assert!(a < b, "{a} vs {b}");
    };
    // Fig. 5 is about the paper's steps: with the zero target the weighted ring moves less
    // (measured 1.0620 against 1.0652, summed over the ring).
    let (plain, g1) = (run(Target::Zero, 1.0), run(Target::Zero, 10.0));
    moves_less(&g1, &plain);
    // The default (detail) target too, whose pull-backs bring the ring back nearer still:
    // weighted 1.0262 against 1.0420 unweighted (before the long pull-backs, 1.0466 against
    // 1.0420: the pull-back's projection is in the same metric and moves a weighted ring
    // less, back towards the input too).
    let (plain_detail, g1_detail) = (run(Target::Detail, 1.0), run(Target::Detail, 10.0));
    moves_less(&g1_detail, &plain_detail);
    moves_less(&g1_detail, &g1);
}

/// The large grids (release only): robust mode converges on all three to 1e-9 with
/// no fold (docs/algorithms/flattenable.md: cap 100×100 in ~130 iterations, saddle 50×50 in
/// ~130, saddle 100×100 in ~290 after a long slow phase while the excess angle moves to the
/// boundary). None takes a smoothed step or jump: their damped steps never gain < 1 % five
/// times in a row within 1e-5 rad of θ = 2π, so the shallow pieces' escapes leave their paths
/// as they were ("Shallow pieces: a smoothed step", "Irregular shallow pieces: a smoothed
/// jump").
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn large_grids_converge_without_folds() {
    for mesh in [
        common::sphere_cap(100),
        common::saddle(50),
        common::saddle(100),
    ] {
        let r = robust(&mesh, &ProcessOptions::default());
        assert_flat_unfolded(&mesh, &r);
        let piece = &r.report.pieces[0];
        assert_eq!(piece.smoothed_steps, 0);
        // Nor a smoothed jump, kept or undone: no smoothed try is made on these paths.
        assert!(
            !piece
                .messages
                .iter()
                .any(|m| m.starts_with("smoothed jumps")),
            "{:?}",
            piece.messages
        );
    }
}

/// Shallow pieces at scan resolution (release only, ~15 s on two cores): the paraboloids
/// z = A (x² + y²) on [−1, 1]² at 160×160 vertices (50.6k faces) with A = 0.1 and 0.03 stalled
/// near θ_err 2.7e-7 after ~26 s, their damped steps gaining 0.001–0.01 % each on a smooth
/// residual; the smoothed Gauss–Newton steps of such plateaus (`smoothed_step.rs`) take both
/// to 1e-9 unfolded (docs/algorithms/flattenable.md, "Shallow pieces: a smoothed step").
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn shallow_paraboloids_at_scan_resolution_converge_through_smoothed_steps() {
    let runs: Vec<(TriMesh, Result<Processed, FlattenableError>)> = std::thread::scope(|s| {
        let handles: Vec<_> = [0.1, 0.03]
            .into_iter()
            .map(|a| {
                s.spawn(move || {
                    let mesh = common::grid(160, 1.0, |x, y| a * (x * x + y * y));
                    let r = process(&mesh, &ProcessOptions::default());
                    (mesh, r)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (mesh, r) in &runs {
        let r = r
            .as_ref()
            .unwrap_or_else(|e| panic!("a shallow paraboloid did not converge: {e}"));
        assert_flat_unfolded(mesh, r);
        let piece = &r.report.pieces[0];
        assert!(piece.smoothed_steps >= 1, "{:?}", piece.messages);
        assert!(
            piece.messages.iter().any(|m| m.contains("smoothed steps")),
            "{:?}",
            piece.messages
        );
    }
}

/// Shallow pieces on an irregular triangulation (release only, ~6 s): the paraboloid
/// z = 0.03 (x² + y²) at 200×200 vertices with every interior vertex jittered by up to 0.3 of
/// the spacing stalled at θ_err 1.9e-8 after 793 factorisations, every smoothed step failing:
/// there the angle sums answer a smooth move with a rough residual as large as the smooth one
/// it removes. A quarter of the jump that removes the smooth part, restored by the plain
/// steps, converges it in ~54 factorisations (docs/algorithms/flattenable.md, "Irregular
/// shallow pieces: a smoothed jump"), and the restores leave no crease: the largest growth of
/// an edge's bend is 0.7° (an 18.9° crease appeared on another jittered paraboloid with the
/// whole jump).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn irregular_shallow_paraboloid_converges_through_smoothed_jumps() {
    let mesh = common::jittered_paraboloid(200, 0.03, 0.3);
    let r = process(&mesh, &ProcessOptions::default())
        .unwrap_or_else(|e| panic!("the jittered paraboloid did not converge: {e}"));
    assert_flat_unfolded(&mesh, &r);
    let piece = &r.report.pieces[0];
    assert!(
        piece
            .messages
            .iter()
            .any(|m| m.starts_with("smoothed jumps") && !m.contains(": 0 kept")),
        "{:?}",
        piece.messages
    );
    assert!(piece.max_crease_deg < 3.0, "{}", piece.max_crease_deg);
}

/// The 100×100 saddle's long wandering phase (the excess angle migrating to the boundary)
/// is path-sensitive: inputs within one ulp of the grid (every coordinate ×(1 + k·2.2e-16),
/// k ∈ {−1, 0, 1} from a fixed xorshift sequence per seed) converge or stall near θ_err
/// 1e-4 by the luck of their paths — the direct solve converged on 37 of 44 such inputs
/// (seeds 0–43, ninth session). Above `max_faces` the coarse-to-fine hierarchy is now a
/// rescue after the direct solve, and it converges the others (docs/algorithms/flattenable.md,
/// "Large pieces rescued by a hierarchy"). On the exact grid and seeds 1–6 and 13 every input
/// must converge unfolded, at least one through the second-order lift of nearly flat
/// excess-angle vertices (without which such inputs stalled on a line of them) and at least
/// one through the rescue. Which seeds stall in the direct solve depends on round-off: 2 and
/// 3 with the system atan2, others since the tenth session's polynomial one, and with the
/// seventeenth session's own numeric factorisation seeds 0–12 all converge directly and 13
/// through the rescue — so 13 is here for the rescue, not as a tuned pass (release only:
/// ~45 s on two cores).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn one_ulp_from_the_saddle_every_input_converges_some_through_the_rescue() {
    let runs: Vec<(TriMesh, Result<Processed, FlattenableError>)> = std::thread::scope(|s| {
        let handles: Vec<_> = [0, 1, 2, 3, 4, 5, 6, 13u64]
            .into_iter()
            .map(|seed| {
                s.spawn(move || {
                    let mut mesh = common::saddle(100);
                    common::perturb_by_one_ulp(&mut mesh, seed);
                    let r = process(&mesh, &ProcessOptions::default());
                    (mesh, r)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let (mut lifted, mut rescued) = (0, 0);
    for (k, (mesh, r)) in runs.iter().enumerate() {
        let r = r
            .as_ref()
            .unwrap_or_else(|e| panic!("input {k} did not converge: {e}"));
        assert_flat_unfolded(mesh, r);
        let messages = &r.report.pieces[0].messages;
        lifted += usize::from(messages.iter().any(|m| m.contains("lifts")));
        rescued += usize::from(
            messages
                .iter()
                .any(|m| m.starts_with("the direct solve did not converge")),
        );
    }
    assert!(lifted >= 1, "no run used a lift");
    assert!(rescued >= 1, "no run needed the rescue");
}

/// The 160×160 cap of the bench's generator (alternating diagonals, 50k faces): at damping
/// 1e-8 the least-norm step moved a vertex 4 edge lengths, the linear model rated it well,
/// and the run then stalled at θ_err 1.7e-5 with both targets; a step capped at two of each
/// vertex's edge lengths made it converge. On the 175×175 cap (60k faces) a step shortened
/// to that length (7.7 edge lengths before, rated ρ = 2.7) stalled the run at 1.5e-5; a long
/// step is now refused and the damping raised, and both converge (release only: ~12 s).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn long_steps_refused_unstall_the_160_and_175_caps() {
    for n in [160, 175] {
        bench_cap_with_the_zero_target(n, 0);
    }
}

/// A trial that blows up near θ = 2π (ρ < −1000 below θ_err 1e-5: the near-flat vertices
/// answering at second order, from θ_err ~2e-6 on the large caps) is backtracked deep like the
/// rejected steps below 1e-6, instead of costing a factorisation per raise of the damping.
/// On the 175×175 cap (60k faces, zero target) that takes 62 factorisations; with deep
/// backtracking only below 1e-6, 88 (release only: ~6 s).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn blow_ups_near_theta_2pi_are_backtracked_deep() {
    let r = bench_cap_with_the_zero_target(175, 0);
    let p = &r.report.pieces[0];
    assert!(p.factorizations < 75, "{} factorisations", p.factorizations);
}

/// Second-order corrections pay where a factorisation is dear: a piece below 1 000 faces
/// solved directly takes none (at 242 faces a correction's solve, θ and fold check cost ~40 %
/// of the 8 µs-factorisation iteration it may save), a piece above keeps them, and so does a
/// coarse level of a hierarchy however small, whose solution only starts the next level (the
/// 3.5k cap's fine level took 31 → 39 ms when its 882-face level went without).
#[test]
fn corrections_are_kept_above_a_thousand_faces_and_on_coarse_levels() {
    let small = common::bench_cap(12);
    let r = robust(&small, &ProcessOptions::default());
    assert_flat_unfolded(&small, &r);
    let p = &r.report.pieces[0];
    assert_eq!((p.faces, p.corrections), (242, 0), "{p:?}");
    // Without corrections each accepted iteration is a step from a new factorisation.
    assert!(p.factorizations >= p.iterations, "{p:?}");

    let large = common::bench_cap(24);
    let r = robust(&large, &ProcessOptions::default());
    assert_flat_unfolded(&large, &r);
    let p = &r.report.pieces[0];
    assert_eq!(p.faces, 1058);
    assert!(p.corrections > 0, "{p:?}");

    // A 722-face piece through a hierarchy (its configured range lowered to 400 faces): its
    // own level takes none, its 180-face coarse level does.
    let mid = common::bench_cap(20);
    let mut opts = ProcessOptions::default();
    let r = robust(&mid, &opts);
    assert_eq!(r.report.pieces[0].corrections, 0);
    opts.coarse_to_fine.min_faces = 400;
    let r = robust(&mid, &opts);
    assert_flat_unfolded(&mid, &r);
    let p = &r.report.pieces[0];
    assert_says(p, "level 1: 180 faces");
    assert!(p.corrections > 0, "{p:?}");
}

/// A pull-back leaves the surface up to 1e-4 rad from θ = 2π with the tiny damping of the
/// converged phase, so its first restoring step blows up (ρ ≈ −7e4 on the bench's 43×43 cap,
/// 3.5k faces, default detail target). Backtracked deep, it costs a few θ evaluations instead
/// of a factorisation per raise of the damping: 34 factorisations for the three pull-backs'
/// run, 54 when it was not. Since the projection takes the run's damping (twenty-fifth
/// session) one pull-back is taken and restored in two iterations, one of them backtracked:
/// 20 factorisations; the RMS displacement stays below the zero target's.
#[test]
fn blow_ups_while_restoring_a_pull_back_are_backtracked_deep() {
    let mesh = common::bench_cap(43);
    let r = robust(&mesh, &ProcessOptions::default());
    assert_flat_unfolded(&mesh, &r);
    let p = &r.report.pieces[0];
    assert!(p.pull_backs >= 1, "{p:?}");
    assert!(p.backtracked_steps > 0, "{p:?}");
    assert!(p.factorizations < 25, "{} factorisations", p.factorizations);
    let zero = bench_cap_with_the_zero_target(43, 0);
    assert!(
        r.report.rms_displacement_mm < zero.report.rms_displacement_mm,
        "RMS displacement {} (detail) against {} (zero)",
        r.report.rms_displacement_mm,
        zero.report.rms_displacement_mm
    );
}

/// The bench's n×n sphere cap (alternating diagonals), within one ulp of the grid for a
/// `seed` above 0 (the saddle harness's perturbation), processed with the zero target,
/// checked flat and unfolded.
fn bench_cap_with_the_zero_target(n: usize, seed: u64) -> Processed {
    let mut mesh = common::bench_cap(n);
    common::perturb_by_one_ulp(&mut mesh, seed);
    let r = robust(
        &mesh,
        &ProcessOptions {
            target: Target::Zero,
            ..Default::default()
        },
    );
    assert_flat_unfolded(&mesh, &r);
    r
}

/// A step at most 1.5× the step cap (3 edge lengths) is shortened to the cap instead of
/// refused: on the large caps most refusals were of steps just over it, each costing a
/// factorisation. The 190×190 cap (71k faces, zero target) takes 71 factorisations; when every
/// step over the cap was refused, 122 (release only: ~7 s).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn steps_just_over_the_cap_are_shortened_not_refused() {
    let r = bench_cap_with_the_zero_target(190, 0);
    let p = &r.report.pieces[0];
    assert!(p.factorizations < 95, "{} factorisations", p.factorizations);
}

/// Near θ = 2π the merit has a dead zone (half the tolerance): residuals well within the
/// tolerance, which on the cap's nearly flat top are ~1e-9 at tens of thousands of vertices
/// whose rows of A nearly vanish, are no longer chased. The 225×225 bench cap within one ulp
/// of the grid (seed 1 of the saddle harness's perturbation, zero target) took 158
/// factorisations without it, stuck with ~300 vertices just above the tolerance; with it 47
/// (release only: ~7 s).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn the_merit_ignores_residuals_well_within_the_tolerance() {
    let r = bench_cap_with_the_zero_target(225, 1);
    let p = &r.report.pieces[0];
    assert!(p.factorizations < 70, "{} factorisations", p.factorizations);
}

/// Near θ = 2π a rejected trial is followed down to 2⁻¹⁰ of its length before the damping is
/// raised, which costs a factorisation: a step there fails because a group of nearly flat
/// vertices answers at second order, while the rest of it is right. On the bench's 130×130
/// cap (33k faces, zero target) that takes 62 factorisations; with at most 1/8, as before,
/// 95 (release only: ~3 s).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn near_theta_2pi_rejected_steps_are_backtracked_deep_instead_of_refactorised() {
    let r = bench_cap_with_the_zero_target(130, 0);
    let p = &r.report.pieces[0];
    assert!(p.backtracked_steps > 0, "{p:?}");
    assert!(p.factorizations < 80, "{} factorisations", p.factorizations);
}

#[test]
fn detail_target_moves_less_than_the_zero_target_at_no_more_area_change() {
    // Target::Detail pulls the converged surface back towards the input along the
    // constraint set and along the area's level set (a stationary point of the paper's
    // Eq. 1 at the area where the zero target's path ends); the zero target ends where the
    // memoryless least-norm steps end. Both flat and unfolded; the detail one closer to the
    // input (measured: bench cap 35×35 0.0687 vs 0.0701, saddle 25×25 0.0269 vs 0.0299 RMS)
    // and with an area change no larger (the pull-backs hold the area to within
    // `AREA_TIE_PERCENT`).
    for mesh in [common::bench_cap(35), common::saddle(25)] {
        let run = |target| {
            let r = robust(
                &mesh,
                &ProcessOptions {
                    target,
                    ..Default::default()
                },
            );
            assert_flat_unfolded(&mesh, &r);
            (r.report.rms_displacement_mm, r.report.area_change_percent)
        };
        let ((detail, detail_area), (zero, zero_area)) = (run(Target::Detail), run(Target::Zero));
        assert!(detail < 0.99 * zero, "detail {detail} vs zero {zero}");
        assert!(
            detail_area.abs() <= zero_area.abs() + AREA_TIE_PERCENT,
            "area change: detail {detail_area} % vs zero {zero_area} %"
        );
    }
}

/// A run cut short after a kept pull-back (here by the iteration limit, two iterations after
/// the zero target's run converged) returns the converged state before the pull-backs, the
/// zero target's result bit for bit, and says it converged.
#[test]
fn pull_backs_cut_short_return_the_converged_state_before_them() {
    let mesh = common::saddle(25);
    let zero = robust(
        &mesh,
        &ProcessOptions {
            target: Target::Zero,
            ..Default::default()
        },
    );
    let cut = robust(
        &mesh,
        &ProcessOptions {
            max_iterations: Some(zero.report.pieces[0].iterations + 2),
            ..Default::default()
        },
    );
    let piece = &cut.report.pieces[0];
    assert!(piece.converged, "{piece:?}");
    assert!(piece.pull_backs > 0, "{piece:?}");
    assert_says(piece, "the converged state before them is returned");
    assert_eq!(cut.mesh.positions, zero.mesh.positions);
}

/// With the least-square update the detail filter (target L v⁰) takes its own path, which on
/// the 12×12 cap ends nearer the input but with more area change than the paper's zero
/// target (measured: −6.358 % against −6.333 %). The paper's path runs beside it and is
/// returned, bit for bit, with a message saying why; on the 50×50 saddle the detail path
/// wins on both (RMS 0.0162 against 0.0201 at the same area change) and is kept.
#[test]
fn least_square_detail_target_is_never_worse_than_the_papers() {
    let ls = |mesh: &TriMesh, target| {
        robust(
            mesh,
            &ProcessOptions {
                update: Update::LeastSquare,
                target,
                ..Default::default()
            },
        )
    };
    let cap = common::sphere_cap(12);
    let (detail, zero) = (ls(&cap, Target::Detail), ls(&cap, Target::Zero));
    assert_flat_unfolded(&cap, &detail);
    assert_eq!(detail.mesh.positions, zero.mesh.positions);
    assert_says(&detail.report.pieces[0], "the paper's result is returned");
    let saddle = common::saddle(50);
    let (detail, zero) = (ls(&saddle, Target::Detail), ls(&saddle, Target::Zero));
    assert_flat_unfolded(&saddle, &detail);
    let (d, z) = (&detail.report, &zero.report);
    assert!(
        d.rms_displacement_mm < 0.97 * z.rms_displacement_mm,
        "RMS {} vs {}",
        d.rms_displacement_mm,
        z.rms_displacement_mm
    );
    assert!(
        d.area_change_percent.abs() <= z.area_change_percent.abs() + AREA_TIE_PERCENT,
        "area change {} % vs {} %",
        d.area_change_percent,
        z.area_change_percent
    );
}

/// The bench's 92×92 cap (16.6k faces): the detail target's pull-back there is not restored
/// to θ = 2π (on the 100×100 cap, where this was first seen, restoring ran 30 iterations and
/// ended at more displacement than before: RMS 0.07118 → 0.07138). Until the twenty-fifth
/// session a long one and then a short one were taken and undone; since the projection takes
/// the run's damping the long one already leaves θ_err within the short bound and no short
/// one repeats it. Undoing it restores the whole iteration state, so the run ends on the zero
/// target's result: the same positions bit for bit, having spent only the pull-back's
/// iterations on top (release only: ~3 s).
#[test]
#[ignore = "large: cargo test --release -- --ignored"]
fn an_undone_pull_back_leaves_the_zero_targets_path_bit_for_bit() {
    let undone = one_undone_pull_back(92);
    // The pull-back and at most three restoring iterations (slow or refused restores are
    // undone early; ten before).
    assert!(
        (2..=4).contains(&undone.spent),
        "{} more iterations",
        undone.spent
    );
}

/// What [`one_undone_pull_back`] found.
struct UndonePullBack {
    /// Why it was undone (its message).
    message: String,
    /// Iterations the detail target spent beyond the zero target's.
    spent: usize,
}

/// The bench cap `n`×`n` with the detail and the zero target: one pull-back taken and undone,
/// the detail target's result the zero target's bit for bit, flat and unfolded.
fn one_undone_pull_back(n: usize) -> UndonePullBack {
    let mesh = common::bench_cap(n);
    let run = |target| {
        robust(
            &mesh,
            &ProcessOptions {
                target,
                ..Default::default()
            },
        )
    };
    let (detail, zero) = (run(Target::Detail), run(Target::Zero));
    assert_flat_unfolded(&mesh, &detail);
    let piece = &detail.report.pieces[0];
    assert_eq!(piece.pull_backs, 1);
    let undone: Vec<&String> = piece
        .messages
        .iter()
        .filter(|m| m.starts_with("pull-back undone"))
        .collect();
    assert_eq!(undone.len(), 1, "{:?}", piece.messages);
    assert_eq!(detail.mesh.positions, zero.mesh.positions);
    UndonePullBack {
        message: undone[0].clone(),
        spent: piece.iterations - zero.report.pieces[0].iterations,
    }
}

/// The bench's 56×56 cap (6 050 faces): its pull-back's restore passes the merit test of its
/// first three iterations (θ_err 5.1e-3 → 1.2e-4) and then crawls (1.8e-5 after five, 8.7e-7
/// after ten). Since the twenty-sixth session it is undone after five restoring iterations
/// instead of ten; undone, the run ends on the zero target's positions bit for bit, having
/// spent the pull-back and those five iterations on top.
#[test]
fn a_crawling_restore_is_undone_after_five_iterations() {
    let undone = one_undone_pull_back(56);
    assert!(
        undone.message.contains("slow, linear regime"),
        "{}",
        undone.message
    );
    assert_eq!(undone.spent, 6);
}

/// A piece that cannot become flat (a 120° cup, total defect 9.1 rad: it could only crumple)
/// stalls with about five rejected trials per accepted step; the stall is counted in
/// factorisations too, so it ends after 100 of them without a 10 % gain rather than 100
/// iterations (~600 factorisations on such pieces). Converging runs never go 23
/// factorisations without such a gain (docs: "Stalls counted in factorisations").
#[test]
fn a_hopeless_piece_stalls_within_a_hundred_factorisations_of_its_last_gain() {
    let cup = flatcut_mesh::shapes::sphere_cap(100.0, 120f64.to_radians(), 16);
    let opts = ProcessOptions {
        coarse_to_fine: flatcut_flattenable::CoarseToFine {
            levels: 0,
            ..Default::default()
        },
        ..Default::default()
    };
    let Err(FlattenableError::NotConverged {
        partial, reason, ..
    }) = process(&cup, &opts)
    else {
        panic!("the cup converged");
    };
    let p = &partial.report.pieces[0];
    // "stalled: no 10 % gain of ‖θ − 2π‖² in K iterations (F factorisations)"
    let numbers: Vec<usize> = reason
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|s| s.parse().ok())
        .collect();
    assert!(reason.starts_with("stalled"), "{reason}");
    let [_ten, _two, k, f, ..] = numbers[..] else {
        panic!("{reason}")
    };
    assert!(k < 100, "the iteration window fired first: {reason}");
    assert!((100..140).contains(&f), "{reason}");
    assert!(p.factorizations >= f && p.iterations >= k);
    assert_eq!(partial.report.pieces[0].folded_faces, 0);
}
