//! Local polish (`local_polish.rs`): the end of a robust run solved on a region of the piece.
//! The region's identities (its rows are the piece's, nothing outside it moves) are unit
//! tests in the module; here the outcome on whole pieces.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_flattenable::{ProcessOptions, Processed, Target, process};
use flatcut_mesh::TriMesh;

fn run(mesh: &TriMesh, local_polish: bool) -> Processed {
    let opts = ProcessOptions {
        target: Target::Zero,
        local_polish,
        ..Default::default()
    };
    process(mesh, &opts).unwrap()
}

fn polish_message(r: &Processed) -> Option<&String> {
    r.report.pieces[0]
        .messages
        .iter()
        .find(|m| m.starts_with("local polish"))
}

/// The 54×54 bench cap (5 618 faces, 2 704 interior vertices) ends with a region of 613
/// vertices (the 53×53 cap did until the damping's descent learnt the step cap; its global
/// steps now finish first): the result is flat to the tolerance, unfolded, its boundary untouched, and the
/// same surface as the run with global steps to the end (both are the end of the same path,
/// which differs only after the last full factorisation).
#[test]
fn the_polished_end_is_the_same_flattenable_surface() {
    let mesh = common::bench_cap(54);
    let polished = run(&mesh, true);
    let global = run(&mesh, false);
    for r in [&polished, &global] {
        let rep = &r.report.pieces[0];
        assert!(rep.converged, "{:?}", rep.stop_reason);
        assert!(rep.final_theta_err <= 1e-9);
        assert_eq!(rep.folded_faces, 0);
        assert_eq!(common::boundary_changed(&mesh, &r.mesh), 0);
    }
    // θ recomputed by the mesh crate, not by the crate's own layout.
    let theta = flatcut_mesh::geometry::angle_sums(&polished.mesh.positions, &mesh.faces);
    let topo = flatcut_mesh::Topology::build(&mesh).unwrap();
    for (v, t) in theta.iter().enumerate() {
        if topo.is_interior_vertex(flatcut_mesh::VertexId(v as u32)) {
            assert!((t - std::f64::consts::TAU).abs() <= 1e-9, "vertex {v}: {t}");
        }
    }
    let message = polish_message(&polished)
        .unwrap_or_else(|| panic!("{:?}", polished.report.pieces[0].messages));
    assert!(message.contains("of 2704 interior vertices"), "{message}");
    assert!(polish_message(&global).is_none());
    // Same surface: the two runs share their path up to the region and differ by its last
    // corrections, steps of about a hundredth of an edge (measured on the 53×53 cap: 0.9 %
    // of the grid spacing at most, RMS displacement equal to 1.5e-6 relative). Bounds: 2 %
    // of the spacing, 1e-5 relative.
    let spacing = 1.0 / 53.0;
    let farthest = polished
        .mesh
        .positions
        .iter()
        .zip(&global.mesh.positions)
        .map(|(a, b)| flatcut_mesh::vec3::dist(*a, *b))
        .fold(0.0f64, f64::max);
    assert!(farthest < 0.02 * spacing, "{farthest}");
    let (a, b) = (
        polished.report.pieces[0].rms_displacement_mm,
        global.report.pieces[0].rms_displacement_mm,
    );
    assert!((a - b).abs() <= 1e-5 * b, "{a} vs {b}");
}

/// Small pieces never split: a factorisation of the whole piece costs about what building
/// a region does.
#[test]
fn small_pieces_end_with_global_steps() {
    let mesh = common::bench_cap(24);
    let r = run(&mesh, true);
    assert!(r.report.pieces[0].interior_vertices < 1000);
    assert!(polish_message(&r).is_none());
    let plain = run(&mesh, false);
    assert_eq!(r.mesh.positions, plain.mesh.positions);
}
