//! Robust mode on the real disk patches of FLATCUT_DATA (skipped when the variable is unset;
//! a missing file fails). What must hold on every one: either θ_err ≤ 1e-9 with no fold, or
//! the clean `NotConverged` error whose partial result is unfolded, has bit-identical
//! boundary, and is better than the input. The numbers reached are in
//! docs/algorithms/flattenable.md.

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use flatcut_flattenable::{FlattenableError, HoleRims, ProcessOptions, Processed, Target, process};
use flatcut_mesh::{Topology, TriMesh, VertexId};

mod common;
use common::{body_pieces, loop_subdivide};

fn data(name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("FLATCUT_DATA")?;
    let path = PathBuf::from(dir).join(name);
    assert!(
        path.exists(),
        "FLATCUT_DATA is set but {} is missing",
        path.display()
    );
    Some(path)
}

fn check(name: &str, max_iterations: usize) {
    check_with(name, max_iterations, false);
}

fn check_with(name: &str, max_iterations: usize, must_converge: bool) {
    let Some(path) = data(name) else {
        eprintln!("FLATCUT_DATA unset: skipping {name}");
        return;
    };
    let mesh: TriMesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
        .unwrap()
        .mesh;
    check_mesh(name, &mesh, max_iterations, must_converge);
}

/// What must hold on `mesh` (see the module comment); `must_converge` also asks for θ_err ≤
/// 1e-9. Returns the processed (or best partial) result.
fn check_mesh(name: &str, mesh: &TriMesh, max_iterations: usize, must_converge: bool) -> Processed {
    let opts = ProcessOptions {
        max_iterations: Some(max_iterations),
        ..Default::default()
    };
    let r: Processed = match process(mesh, &opts) {
        Ok(r) => {
            assert!(r.report.final_theta_err <= 1e-9);
            r
        }
        Err(FlattenableError::NotConverged {
            best_theta_err,
            partial,
            ..
        }) => {
            eprintln!("{name}: not converged, best θ_err {best_theta_err:.3e}");
            assert!(
                !must_converge,
                "{name}: did not converge ({best_theta_err:.3e})"
            );
            assert!(best_theta_err > 1e-9);
            let p = &partial.report.pieces[0];
            // Best by the merit ‖θ − 2π‖: its RMS is below the input's.
            let mut theta0 = flatcut_mesh::geometry::angle_sums(&mesh.positions, &mesh.faces);
            let topo = Topology::build(mesh).unwrap();
            let (mut s, mut n) = (0.0, 0usize);
            for (v, t) in theta0.iter_mut().enumerate() {
                if topo.is_interior_vertex(VertexId(v as u32)) {
                    s += (*t - std::f64::consts::TAU).powi(2);
                    n += 1;
                }
            }
            assert!(p.final_theta_rms < (s / n as f64).sqrt());
            *partial
        }
        Err(e) => panic!("{name}: {e}"),
    };
    assert_eq!(r.report.folded_faces, 0, "{name}");
    assert!(r.mesh.positions.iter().flatten().all(|c| c.is_finite()));
    let topo = Topology::build(mesh).unwrap();
    for v in 0..mesh.vertex_count() {
        if topo.is_boundary_vertex(VertexId(v as u32)) {
            assert_eq!(
                mesh.positions[v], r.mesh.positions[v],
                "{name}: boundary moved"
            );
        }
    }
    r
}

/// A body of FLATCUT_DATA in its model units (None, said on stderr, when unset).
fn body(name: &str) -> Option<TriMesh> {
    let Some(path) = data(name) else {
        eprintln!("FLATCUT_DATA unset: skipping the pieces of {name}");
        return None;
    };
    Some(
        flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
            .unwrap()
            .mesh,
    )
}

/// Every piece of the base body either converges or stops cleanly; the back, the shoulder
/// and the thigh (|total defect| ≤ 1.9 rad, measured 6–19 iterations) must converge, the
/// chest (+2.06 rad over both breasts, a dart case: measured best 3.7e-3) need not. Where
/// it converges, the default (detail) target ends no farther from the input than the zero
/// target, the paper's, with no larger area change (the criterion, on real pieces;
/// measured: the upper back 0.0306 against 0.0309 RMS through a kept pull-back, at area
/// change −1.57600 % for both, equal to 1e-13; the shoulder and the thigh equal).
#[test]
fn mh_body_pieces() {
    let Some(body) = body("mh_body.obj") else {
        return;
    };
    for (name, piece) in body_pieces(&body) {
        let r = check_mesh(name, &piece, 500, name != "chest");
        let p = &r.report.pieces[0];
        if p.converged {
            // No corner newly under the floor, and a pattern, not a crumpled sheet.
            assert!(p.min_angle_deg >= 0.5, "{name}: {}", p.min_angle_deg);
            assert!(
                p.area_change_percent.abs() < 10.0,
                "{name}: {}",
                p.area_change_percent
            );
            let zero_target = ProcessOptions {
                target: Target::Zero,
                ..Default::default()
            };
            // Wherever both converge. Where no pull-back is kept the two end on the same
            // surface, equal to round-off (measured on pipeline pieces: 5e-11 relative).
            if let Ok(zero) = process(&piece, &zero_target) {
                let (detail, zero_rms) = (p.rms_displacement_mm, zero.report.rms_displacement_mm);
                assert!(
                    detail <= zero_rms * (1.0 + 1e-9),
                    "{name}: RMS displacement {detail} (detail) against {zero_rms} (zero)"
                );
                // …and with no larger area change: the pull-backs hold the zero target's
                // area, to 1e-9 of the input's (1e-7 %).
                let (detail, zero_area) = (p.area_change_percent, zero.report.area_change_percent);
                assert!(
                    detail.abs() <= zero_area.abs() + 1e-7,
                    "{name}: area change {detail} % (detail) against {zero_area} % (zero)"
                );
            }
        }
    }
}

/// The same pieces at scan-like resolution (the 2× subdivided body, 2–6k faces, solved
/// coarse-to-fine): the back, the thigh and the shoulder must converge (measured 14, 12 and
/// 30 iterations; the shoulder, −2.15 rad, saddle-like, two loops, only through the rescue
/// hierarchy: the default one and the direct solve stall at 4–8e-3), and the chest box gives
/// a non-manifold vertex, refused with a named error.
#[test]
#[ignore = "2–6k-face pieces of a 428k-face body: run in release"]
fn mh_body_subdiv2_pieces() {
    let Some(body) = body("mh_body_subdiv2.obj") else {
        return;
    };
    for (name, piece) in body_pieces(&body) {
        if name == "chest" {
            let err = process(&piece, &ProcessOptions::default()).unwrap_err();
            assert!(
                matches!(err, FlattenableError::NonManifoldVertex { .. }),
                "{err}"
            );
            continue;
        }
        let r = check_mesh(name, &piece, 500, true);
        let p = &r.report.pieces[0];
        assert!(p.faces > 2000, "{name}");
        assert!(p.min_angle_deg >= 0.5, "{name}: {}", p.min_angle_deg);
        // The shoulder's flattenable surface is −10.6 % smaller (the base body's −9.0 %).
        assert!(
            p.area_change_percent.abs() < 12.0,
            "{name}: {}",
            p.area_change_percent
        );
    }
}

/// The upper back cut from mh_body_subdiv2 (None when FLATCUT_DATA is unset).
fn subdiv2_upper_back() -> Option<TriMesh> {
    let body = body("mh_body_subdiv2.obj")?;
    body_pieces(&body)
        .into_iter()
        .find(|(name, _)| *name == "upper back")
        .map(|(_, piece)| piece)
}

/// The upper back of mh_body_subdiv2 at scan resolution: one Loop subdivision, 21k faces.
/// Its direct solve, which runs first above 15k faces, sits at θ_err ~8e-4 under heavy
/// damping from its 20th iteration; it hands the piece over to coarse-to-fine, whose
/// hierarchy converges it. Before the hand-over the direct solve ran 291 factorisations
/// (lifts, then the stall test) first: 361 in all, 7.6 s instead of 2.5 s in release
/// (docs/algorithms/flattenable.md, "Body pieces at scan resolution").
#[test]
#[ignore = "a 21k-face piece of a 428k-face body: run in release"]
fn mh_body_subdiv2_upper_back_at_scan_resolution_is_handed_over() {
    let Some(piece) = subdiv2_upper_back() else {
        return;
    };
    let fine = loop_subdivide(&piece);
    assert_eq!(fine.faces.len(), 4 * piece.faces.len());
    let r = check_mesh("upper back, subdivided", &fine, 500, true);
    let p = &r.report.pieces[0];
    let direct = p
        .messages
        .iter()
        .find(|m| m.starts_with("the direct solve"))
        .unwrap();
    assert!(direct.contains("handed over"), "{direct}");
    assert!(p.factorizations < 200, "{}: {direct}", p.factorizations);
}

/// The upper back of mh_body_subdiv2 twice Loop-subdivided: 85k faces, the scan resolution
/// of the 100k row. Under the default identity damping its attempts stall (best
/// θ_err 4.5e-6; before the twenty-third session the piece ended there, unconverged, after
/// 113 s); the rescue hierarchy under the graph-Laplacian-shaped damping converges it
/// (measured: 64 fine iterations, RMS displacement 0.0274, area −1.13 %). Since the
/// twenty-fourth session that hierarchy runs right after the direct solve hands the piece
/// over, before the identity hierarchies (where they ran first: 20.1 s in all in release on a
/// quiet host), and its levels measure their merit in that damping's norm (35 fine
/// iterations, RMS 0.0273, area −1.12 %; 5.3–5.5 s in all; docs/algorithms/flattenable.md,
/// "A damping shaped like the graph Laplacian").
#[test]
#[ignore = "an 85k-face piece of a 428k-face body: run in release"]
fn mh_body_subdiv2_upper_back_at_85k_faces_converges_through_the_shaped_damping() {
    let Some(piece) = subdiv2_upper_back() else {
        return;
    };
    let fine = loop_subdivide(&loop_subdivide(&piece));
    assert_eq!(fine.faces.len(), 16 * piece.faces.len());
    let r = process(&fine, &ProcessOptions::default()).unwrap();
    let p = &r.report.pieces[0];
    assert!(p.converged && p.final_theta_err <= 1e-9, "{:?}", p.messages);
    assert_eq!(p.folded_faces, 0);
    assert!(p.min_angle_deg >= 0.5, "{}", p.min_angle_deg);
    // The direct solve, its hand-over, then the shaped hierarchy and nothing between.
    assert!(
        p.messages[0].starts_with("the direct solve") && p.messages[0].contains("handed over"),
        "{:?}",
        p.messages
    );
    assert!(
        p.messages[1].starts_with(
            "rescue coarse-to-fine with graph-Laplacian damping (Displacement prolongation)"
        ),
        "{:?}",
        p.messages
    );
    // The fine level measures its merit in the shaped damping's norm: 35 iterations (63
    // with the plain merit, twenty-fourth session).
    let fine_iterations: usize = p.messages[1]
        .split("fine level (")
        .nth(1)
        .and_then(|s| s.split("faces): ").nth(1))
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    assert!(fine_iterations < 50, "{}", p.messages[1]);
    // The identity damping's best state lies at −1.14 %: the shaped damping ends on a
    // surface of the same size, not on a crumpled one.
    assert!(
        (p.area_change_percent + 1.13).abs() < 0.1,
        "{}",
        p.area_change_percent
    );
    // Above 50 000 faces the default detail target takes no pull-back (this piece's was
    // undone after four iterations, 7.3 s against the zero target's 6.1 s, twenty-seventh
    // session), says so, and returns the zero target's result, bit for bit.
    assert_eq!(p.pull_backs, 0);
    assert!(
        p.messages.iter().any(|m| m.contains("no pull-backs")),
        "{:?}",
        p.messages
    );
    let zero = ProcessOptions {
        target: flatcut_flattenable::Target::Zero,
        ..Default::default()
    };
    let z = process(&fine, &zero).unwrap();
    assert_eq!(z.report.pieces[0].iterations, p.iterations);
    assert!(z.mesh.positions == r.mesh.positions);
}

/// The left shoulder of mh_body_subdiv2 twice Loop-subdivided (88k faces, two loops,
/// −2.31 rad, saddle-like) cannot become flat with its boundary fixed: it ends with the clean
/// error near its best θ_err (measured 1.9e-3), unfolded. Its configured hierarchy and its
/// displacement rescue hierarchy build the same levels and are abandoned at the same one
/// (276 iterations on 5 506 faces): the second is not solved again.
#[test]
#[ignore = "an 88k-face piece of a 428k-face body: run in release"]
fn mh_body_subdiv2_left_shoulder_at_88k_faces_ends_cleanly_without_repeating_a_hierarchy() {
    let Some(body) = body("mh_body_subdiv2.obj") else {
        return;
    };
    let (_, piece) = body_pieces(&body)
        .into_iter()
        .find(|(name, _)| *name == "left shoulder")
        .unwrap();
    let fine = loop_subdivide(&loop_subdivide(&piece));
    assert_eq!(fine.faces.len(), 16 * piece.faces.len());
    let err = process(&fine, &ProcessOptions::default()).unwrap_err();
    let FlattenableError::NotConverged { partial, .. } = err else {
        panic!("{err}");
    };
    let p = &partial.report.pieces[0];
    assert!(!p.converged);
    assert!(p.final_theta_err < 3e-3, "{}", p.final_theta_err);
    assert_eq!(p.folded_faces, 0);
    let abandoned: Vec<&String> = p
        .messages
        .iter()
        .filter(|m| m.starts_with("rescue coarse-to-fine abandoned"))
        .collect();
    assert!(
        abandoned
            .iter()
            .any(|m| m.contains("the same levels as an earlier attempt, not solved again")),
        "{:?}",
        p.messages
    );
}

#[test]
fn igl_snail() {
    check("igl_snail.obj", 100);
}

#[test]
fn smpl_hand_lowres() {
    check("smpl_hand_lowres.obj", 100);
}

#[test]
#[ignore = "8k vertices: run in release"]
fn bust_demosthenes() {
    check("bust_demosthenes.obj", 500);
}

#[test]
#[ignore = "8k vertices: run in release"]
fn igl_lion() {
    check("igl_lion.obj", 500);
}

/// A disk-like relief (negative total defect −0.65 rad) that robust mode takes to 1e-9:
/// measured 85 iterations solved directly, 14 fine-level ones with the default coarse-to-fine
/// start (docs/algorithms/flattenable.md).
#[test]
#[ignore = "2k vertices: run in release"]
fn igl_inspired_mesh_converges() {
    check_with("igl_inspired_mesh.obj", 500, true);
}

/// Geodesic balls cut from two bodies of different makers and units (SMPL in metres,
/// MakeHuman in decimetres): 16 centres each, spread by farthest-point sampling, radius 7 %
/// of the body's height (a patch ~25 cm across on a 1.7 m body). Every patch ends converged or
/// with the clean error (`check_mesh`); every one with one boundary loop and a total angle
/// defect under 0.9 rad — nearly developable already — converges. Measured with `measure --
/// patches` on six bodies (docs/algorithms/flattenable.md, "Patches cut from six bodies"):
/// 57 of 57 such patches converge; smpl_woman and mh_male_generic 12 of 16 each (the
/// rest: hands, feet, the crown of the head and limb junctions, cup- or tube-like, and two
/// SMPL patches whose cut leaves a non-manifold vertex, skipped here).
#[test]
#[ignore = "32 real patches: run in release"]
fn patches_cut_from_bodies() {
    for (name, converged_at_least) in [("smpl_woman.obj", 12), ("mh_male_generic.obj", 12)] {
        let Some(body) = body(name) else { return };
        let height = common::largest_side(&body);
        let mut converged = 0;
        for centre in common::spread_vertices(&body, 16) {
            let piece = common::geodesic_ball(&body, centre, 0.07 * height);
            let topo = Topology::build(&piece).unwrap();
            if !topo.non_manifold_vertices().is_empty() {
                // The cut's artefact (two fans meeting at a vertex), refused by process with
                // a named error (tests/process.rs).
                continue;
            }
            let label = format!("{name} v{centre}");
            let r = check_mesh(&label, &piece, 500, false);
            let p = &r.report.pieces[0];
            if p.final_theta_err <= 1e-9 {
                converged += 1;
            } else {
                assert!(
                    topo.boundary_loops().len() > 1 || p.input_total_defect_rad.abs() >= 0.9,
                    "{label}: a nearly developable disk did not converge ({:.2e}, defect {:+.3})",
                    p.final_theta_err,
                    p.input_total_defect_rad
                );
            }
        }
        assert!(
            converged >= converged_at_least,
            "{name}: {converged} converged"
        );
    }
}

/// `HoleRims::Free` on body patches with a hole (`measure -- holes`, docs/algorithms/
/// flattenable.md, "Holes"): patches of mh_male_generic (read in decimetres, as MakeHuman
/// exports) around 60 spread vertices, with 25 mm holes in 150 mm balls and 50 mm holes in
/// 180 mm ones. Where the fixed-rim run converges and its hole encloses less than π/2 of
/// Gaussian curvature (its development's turning residual; a quarter of a hemisphere's 2π),
/// free rims must close the hole with θ = 2π. Measured: 72 patches, 68 converging with fixed
/// rims; of those, the 64 under π/2 and one at 1.64 rad close, and the 3 that fall back
/// enclose 1.82, 2.73 and 2.85 rad. Wherever free rims fall back, the result is the
/// fixed-rim run's, bit for bit, and the message says the filled piece did not converge
/// and, for a hole over π/2, how much curvature it encloses.
#[test]
fn free_rims_close_the_holes_of_body_patches_that_enclose_under_a_quarter_hemisphere() {
    /// Enclosed curvature under which a hole must close (radians; measured: the holes closed
    /// enclose up to 1.64 rad, the holes left from 1.82 rad).
    const MUST_CLOSE_BELOW_RAD: f64 = std::f64::consts::FRAC_PI_2;
    let Some(path) = data("mh_male_generic.obj") else {
        eprintln!("FLATCUT_DATA unset: skipping the holed patches of mh_male_generic");
        return;
    };
    let body = flatcut_io::read_mesh(&path, flatcut_io::Units::Dm)
        .unwrap()
        .mesh;
    let centres = common::spread_vertices(&body, 60);
    let (mut checked, mut closed) = (0usize, 0usize);
    for (radius_mm, hole_mm, max_faces) in [(150.0, 25.0, 1500), (180.0, 50.0, 2000)] {
        for &centre in &centres {
            let Some(patch) =
                common::ball_with_hole(&body, centre, (radius_mm, hole_mm), max_faces)
            else {
                continue;
            };
            let opts = |hole_rims| ProcessOptions {
                hole_rims,
                ..Default::default()
            };
            let run = |hole_rims| match process(&patch, &opts(hole_rims)) {
                Ok(r) => r,
                Err(FlattenableError::NotConverged { partial, .. }) => *partial,
                Err(e) => panic!("v{centre}: {e}"),
            };
            let fixed = run(HoleRims::Fixed);
            let free = run(HoleRims::Free);
            let (pf, pr) = (&fixed.report.pieces[0], &free.report.pieces[0]);
            let label = format!("v{centre} ({hole_mm} mm hole)");
            let enclosed_rad = pf.holes[0].turning_residual_rad.abs();
            let fell_back = pr
                .messages
                .iter()
                .any(|m| m.starts_with("hole rims free") && m.contains("did not converge"));
            if fell_back {
                assert_eq!(free.mesh.positions, fixed.mesh.positions, "{label}");
                assert_eq!(pr.converged, pf.converged, "{label}");
                // The message names the enclosed curvature where it explains the failure.
                let explained = pr.messages.iter().any(|m| {
                    m.starts_with("hole rims free") && m.contains("rad of Gaussian curvature")
                });
                assert_eq!(explained, enclosed_rad > MUST_CLOSE_BELOW_RAD, "{label}");
            }
            checked += 1;
            if pf.converged && enclosed_rad < MUST_CLOSE_BELOW_RAD {
                assert!(
                    !fell_back
                        && pr.converged
                        && pr
                            .holes
                            .iter()
                            .all(|h| h.closes(opts(HoleRims::Free).tolerance_rad)),
                    "{label}: a hole enclosing {enclosed_rad:.3} rad stayed open with free rims: {:?}",
                    pr.messages
                );
                closed += 1;
            }
        }
    }
    // The patches are deterministic (measured: 72 checked, 64 required to close): the
    // property is not to hold vacuously.
    assert!(
        checked >= 70 && closed >= 60,
        "{checked} patches, {closed} closed"
    );
}
