//! A piece with holes, processed and then flattened (crates/flattenable, crates/lscm): with
//! its hole rims fixed, θ = 2π leaves the curvature in the holes and the pattern stretches
//! by about what the report's hole measure says; with free rims it flattens without stretch.

#![allow(clippy::unwrap_used)]

use flatcut_flattenable::{HoleRims, ProcessOptions, process};
use flatcut_mesh::{Topology, TriMesh};

/// Two holes in a 200 mm sheet on a sphere of radius 400 mm.
fn sheet() -> TriMesh {
    flatcut_mesh::shapes::patch_with_holes_on_sphere(200.0, 25, 400.0)
}

/// The largest edge strain |l₂D / l₃D − 1| of `mesh` flattened by LSCM + the isometric
/// refinement (the default `flatcut flatten`).
fn max_edge_strain(mesh: &TriMesh) -> f64 {
    let out = flatcut_lscm::flatten(mesh, &flatcut_lscm::FlattenOptions::default()).unwrap();
    let topo = Topology::build(mesh).unwrap();
    flatcut_lscm::distortion(mesh, &topo, &out.flattening.uv).max_edge_strain
}

#[test]
fn holes_left_open_stretch_the_pattern_and_closed_ones_do_not() {
    let mesh = sheet();
    let fixed = process(&mesh, &ProcessOptions::default()).unwrap();
    let p = &fixed.report.pieces[0];
    assert!(p.converged && p.final_theta_err <= 1e-9);
    let open = p
        .holes
        .iter()
        .map(|h| h.gap_mm / h.length_mm)
        .fold(0.0, f64::max);
    let strain = max_edge_strain(&fixed.mesh);
    // A gap of g over a hole of length L cannot be closed by less than about g / L strain
    // somewhere around it (measured: gap / length 9.0e-3, strain 1.2e-2).
    assert!(open > 5e-3, "{open}");
    assert!(
        strain > 0.5 * open,
        "strain {strain} for an open hole {open}"
    );

    let free = process(
        &mesh,
        &ProcessOptions {
            hole_rims: HoleRims::Free,
            ..Default::default()
        },
    )
    .unwrap();
    let strain = max_edge_strain(&free.mesh);
    assert!(strain < 1e-8, "{strain}");
}
