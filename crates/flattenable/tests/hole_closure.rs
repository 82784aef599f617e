//! How holes develop (`hole_closure.rs`) against closed forms and Gauss–Bonnet, and holes left
//! open by fixed rims and closed by free ones (`fan_fill.rs`).

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use std::f64::consts::{PI, TAU};

use flatcut_flattenable::hole_closure::Holes;
use flatcut_mesh::geometry::angle_sums;
use flatcut_mesh::{Topology, TriMesh};

/// `patch_with_holes` (two holes) of side `size` on a sphere of radius `radius` (z up), or
/// flat with `radius` infinite.
fn sheet_with_holes(size: f64, n: usize, radius: f64) -> TriMesh {
    if radius.is_finite() {
        flatcut_mesh::shapes::patch_with_holes_on_sphere(size, n, radius)
    } else {
        flatcut_mesh::shapes::patch_with_holes(size, n)
    }
}

/// A ring of `rings` × `sectors` quads (two triangles each) on the surface of a regular
/// `sectors`-sided pyramid of half-angle `half_angle` around its apex, between slant
/// distances 1 and 2: every interior vertex has θ = 2π exactly (each sector is a plane), and
/// the inner loop encloses the apex's angle defect 2π − sectors · ψ, ψ the apex angle of a
/// sector.
fn pyramid_ring(sectors: usize, rings: usize, half_angle: f64) -> TriMesh {
    let mut positions = Vec::new();
    for r in 0..=rings {
        let s = 1.0 + r as f64 / rings as f64;
        for k in 0..sectors {
            let a = TAU * k as f64 / sectors as f64;
            positions.push([
                s * half_angle.sin() * a.cos(),
                s * half_angle.sin() * a.sin(),
                -s * half_angle.cos(),
            ]);
        }
    }
    let id = |r: usize, k: usize| (r * sectors + k % sectors) as u32;
    let mut faces = Vec::new();
    for r in 0..rings {
        for k in 0..sectors {
            // Outward (away from the axis) normals: counter-clockwise seen from outside.
            let (a, b, c, d) = (id(r, k), id(r, k + 1), id(r + 1, k + 1), id(r + 1, k));
            faces.push([a, c, b]);
            faces.push([a, d, c]);
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

#[test]
fn a_flat_sheets_holes_close_and_its_loops_obey_gauss_bonnet() {
    let mesh = sheet_with_holes(2.0, 13, f64::INFINITY);
    let topo = Topology::build(&mesh).unwrap();
    let holes = Holes::of(&topo, &mesh.positions);
    assert_eq!(holes.len(), 2);
    for h in holes.closures(&mesh.positions, &mesh.faces) {
        assert!(h.turning_residual_rad.abs() < 1e-12, "{h:?}");
        assert!(h.gap_mm < 1e-12, "{h:?}");
    }
    // Discrete Gauss–Bonnet on a curved sheet: Σ over the holes of their turning residuals
    // (each the curvature the hole encloses) plus the outline's turning and the interior's
    // angle defects is 2πχ, χ = 1 − holes. Read from the mesh crate's angle sums.
    let curved = sheet_with_holes(2.0, 13, 3.0);
    let topo = Topology::build(&curved).unwrap();
    let sums = angle_sums(&curved.positions, &curved.faces);
    let interior: f64 = (0..curved.vertex_count())
        .filter(|&v| topo.is_interior_vertex(flatcut_mesh::VertexId(v as u32)))
        .map(|v| TAU - sums[v])
        .sum();
    let loops = topo.boundary_loops();
    let turning =
        |l: &[flatcut_mesh::VertexId]| -> f64 { l.iter().map(|v| PI - sums[v.idx()]).sum() };
    let holes = Holes::of(&topo, &curved.positions).closures(&curved.positions, &curved.faces);
    let outline = (0..loops.len())
        .find(|i| holes.iter().all(|h| h.loop_index != *i))
        .unwrap();
    let hole_turning: f64 = holes.iter().map(|h| h.turning_residual_rad - TAU).sum();
    let total = interior + turning(&loops[outline]) + hole_turning;
    assert!((total - TAU * (1.0 - 2.0)).abs() < 1e-10, "{total}");
    // On a sphere each hole encloses positive curvature, and the two are mirror images.
    assert!(holes[0].turning_residual_rad > 0.0);
    assert!((holes[0].turning_residual_rad - holes[1].turning_residual_rad).abs() < 1e-12);
}

#[test]
fn a_ring_around_a_pyramids_apex_turns_short_by_the_apex_defect() {
    for (sectors, half_angle) in [(8, 0.5), (12, 1.0), (24, 1.3)] {
        let mesh = pyramid_ring(sectors, 3, half_angle);
        let topo = Topology::build(&mesh).unwrap();
        assert_eq!(topo.boundary_loops().len(), 2);
        let holes = Holes::of(&topo, &mesh.positions);
        let closure = &holes.closures(&mesh.positions, &mesh.faces)[0];
        // The outline is the longer, outer loop; the hole's residual is the apex's defect.
        let chord = 2.0 * half_angle.sin() * (PI / sectors as f64).sin();
        let sector_angle = 2.0 * (0.5 * chord).asin();
        let defect = TAU - sectors as f64 * sector_angle;
        assert!(
            (closure.turning_residual_rad - defect).abs() < 1e-12,
            "{sectors} sectors: {} against {defect}",
            closure.turning_residual_rad
        );
        assert!((closure.length_mm - sectors as f64 * chord).abs() < 1e-12);
    }
}

/// The interior's θ and the outline's turning of `mesh` at its own positions (the mesh
/// crate's angle sums): Σ (2π − θ) over interior vertices and Σ (π − β) over the outline.
fn interior_defect_and_outline_turning(mesh: &TriMesh, outline: usize) -> (f64, f64, f64) {
    let topo = Topology::build(mesh).unwrap();
    let sums = angle_sums(&mesh.positions, &mesh.faces);
    let interior: Vec<f64> = (0..mesh.vertex_count())
        .filter(|&v| topo.is_interior_vertex(flatcut_mesh::VertexId(v as u32)))
        .map(|v| TAU - sums[v])
        .collect();
    let worst = interior.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    let turning = topo.boundary_loops()[outline]
        .iter()
        .map(|v| PI - sums[v.idx()])
        .sum();
    (interior.iter().sum(), turning, worst)
}

#[test]
fn fixed_rims_leave_a_curved_sheets_holes_open_and_free_rims_close_them() {
    use flatcut_flattenable::{HoleRims, ProcessOptions, process};
    let mesh = sheet_with_holes(200.0, 25, 400.0);
    let topo = Topology::build(&mesh).unwrap();
    let outline = 0;
    assert_eq!(
        topo.boundary_loops()[outline].len(),
        96,
        "the outline is loop 0"
    );
    let rims: Vec<u32> = topo.boundary_loops()[1..]
        .iter()
        .flatten()
        .map(|v| v.0)
        .collect();

    // Fixed rims (the default): θ = 2π, but each hole keeps the curvature it enclosed, and
    // more: Gauss–Bonnet with θ = 2π puts the interior's whole curvature into the loops.
    let fixed = process(&mesh, &ProcessOptions::default()).unwrap();
    let p = &fixed.report.pieces[0];
    assert!(p.converged && p.final_theta_err <= 1e-9);
    assert_eq!(p.holes.len(), 2);
    let (defect, outline_turning, _) = interior_defect_and_outline_turning(&fixed.mesh, outline);
    assert!(defect.abs() < 1e-7, "{defect}");
    let residuals: f64 = p.holes.iter().map(|h| h.turning_residual_rad).sum();
    // T_outline + Σ (residual − 2π) = 2π χ = −2π, so T_outline − 2π = −Σ residuals.
    assert!(
        (outline_turning - TAU + residuals).abs() < 1e-7,
        "{outline_turning} against {residuals}"
    );
    for h in &p.holes {
        assert!(h.turning_residual_rad > 0.05 && h.gap_mm > 1.0, "{h:?}");
        assert!(!h.closes(1e-9));
    }
    assert!(
        p.messages.iter().any(|m| m.contains("do not close")),
        "{:?}",
        p.messages
    );
    for &v in &rims {
        assert_eq!(fixed.mesh.positions[v as usize], mesh.positions[v as usize]);
    }

    // Free rims: the same piece, its holes filled for the processing.
    let opts = ProcessOptions {
        hole_rims: HoleRims::Free,
        ..Default::default()
    };
    let free = process(&mesh, &opts).unwrap();
    let p = &free.report.pieces[0];
    assert_eq!(free.mesh.faces, mesh.faces);
    assert_eq!(free.mesh.vertex_count(), mesh.vertex_count());
    assert!(p.converged && p.final_theta_err <= 1e-9, "{p:?}");
    assert_eq!((p.boundary_loops, p.folded_faces), (3, 0));
    let (_, _, worst) = interior_defect_and_outline_turning(&free.mesh, outline);
    assert!(worst <= 1e-9, "{worst}");
    for h in &p.holes {
        assert!(h.closes(1e-9), "{h:?}");
        assert!(h.turning_residual_rad.abs() < 25e-9 && h.gap_mm < 25e-9 * h.length_mm);
    }
    assert!(!p.messages.iter().any(|m| m.contains("do not close")));
    // The outline is bit for bit; the rims moved.
    for v in &topo.boundary_loops()[outline] {
        assert_eq!(free.mesh.positions[v.idx()], mesh.positions[v.idx()]);
    }
    let moved = rims
        .iter()
        .map(|&v| {
            flatcut_mesh::vec3::dist(free.mesh.positions[v as usize], mesh.positions[v as usize])
        })
        .fold(0.0f64, f64::max);
    assert!(moved > 1.0, "{moved}");
    assert!(p.messages.iter().any(|m| m.contains("rims moved by up to")));
}

#[test]
fn a_flat_sheet_with_holes_is_returned_unchanged_with_either_rims() {
    use flatcut_flattenable::{HoleRims, ProcessOptions, process};
    let mesh = sheet_with_holes(2.0, 13, f64::INFINITY);
    for hole_rims in [HoleRims::Fixed, HoleRims::Free] {
        let opts = ProcessOptions {
            hole_rims,
            ..Default::default()
        };
        let r = process(&mesh, &opts).unwrap();
        assert_eq!(r.mesh.positions, mesh.positions, "{hole_rims:?}");
        let p = &r.report.pieces[0];
        assert!(
            p.holes.iter().all(|h| h.error_rad() < 1e-12),
            "{:?}",
            p.holes
        );
    }
}

#[test]
fn a_ring_around_a_pyramids_apex_is_called_a_band_to_cut_open() {
    use flatcut_flattenable::{HoleRims, ProcessOptions, process};
    // Flat at every interior vertex, but the hole encloses the apex's defect of 3.3 rad.
    let mesh = pyramid_ring(8, 3, 0.5);
    let r = process(&mesh, &ProcessOptions::default()).unwrap();
    assert_eq!(r.mesh.positions, mesh.positions);
    let p = &r.report.pieces[0];
    assert!(p.final_hole_err > 3.0, "{:?}", p.holes);
    assert!(
        p.messages.iter().any(|m| m.contains("band or tube")),
        "{:?}",
        p.messages
    );
    // Filled, it is the pyramid's cap with the apex's curvature (the fill's centre continues
    // the surface) inside a held outline, which does not converge: the run with the rims
    // fixed is returned instead, and both are said.
    let free = ProcessOptions {
        hole_rims: HoleRims::Free,
        ..Default::default()
    };
    let r = process(&mesh, &free).unwrap();
    assert_eq!(r.mesh.positions, mesh.positions);
    let p = &r.report.pieces[0];
    assert!(p.converged && p.final_hole_err > 3.0);
    assert!(
        p.messages
            .iter()
            .any(|m| m.contains("the run with the rims fixed is returned")),
        "{:?}",
        p.messages
    );
    assert!(
        p.messages
            .iter()
            .any(|m| m.contains("band or tube") && !m.contains("hole_rims")),
        "{:?}",
        p.messages
    );
}

#[test]
fn free_rims_report_the_pieces_own_creases_once_in_its_own_numbering() {
    use flatcut_flattenable::{HoleRims, ProcessOptions, process};
    // A strong saddle with two holes: both runs crease (the fixed one along 52 edges, the
    // free one along ~500 of the 1 024 faces' edges: pleated, though θ = 2π and every hole
    // closed).
    let mut mesh = flatcut_mesh::shapes::patch_with_holes(200.0, 25);
    for p in &mut mesh.positions {
        p[2] = 0.006 * (p[0] * p[0] - p[1] * p[1]);
    }
    let opts = ProcessOptions {
        hole_rims: HoleRims::Free,
        ..Default::default()
    };
    let r = process(&mesh, &opts).unwrap();
    let p = &r.report.pieces[0];
    assert!(p.converged && p.holes.iter().all(|h| h.closes(1e-9)));
    assert!(p.creased_edges > 0);
    // One note, the piece's own (the filled copy's, which counts the fill's edges and names
    // its vertices, is replaced), naming an input vertex at the position it prints.
    let notes: Vec<&String> = p
        .messages
        .iter()
        .filter(|m| m.starts_with("the processed surface creases"))
        .collect();
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].starts_with(&format!(
        "the processed surface creases: {} edges",
        p.creased_edges
    )));
    let at = p.sharpest_crease_position_mm.unwrap();
    let named: usize = notes[0]
        .split("at input vertex ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    assert_eq!(mesh.positions[named], at);
}
