//! Dart suggestions on the bump: the first tip lies at the top, and cutting it lowers the
//! deformation flattenable processing needs.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_dart::{SuggestOptions, dart, suggest, total_abs_defect};
use flatcut_flattenable::{ProcessOptions, process};
use flatcut_mesh::{Topology, shapes};

#[test]
fn first_suggestion_on_the_bump_is_at_the_top() {
    for rings in [8, 12] {
        let m = common::bump(rings, 100.0, 30.0, 40.0);
        let s = suggest(&m, 3, &SuggestOptions::default()).unwrap();
        assert!(!s.is_empty());
        let first = &s[0];
        println!(
            "rings {rings}: tip vertex {} (ring {}), start {}, length {:.3} mm, concentrated defect {:.4} rad, Σ|defect| {:.4} → {:.4} rad; {} suggestions",
            first.tip_vertex,
            common::ring_of(first.tip_vertex),
            first.start_vertex,
            first.length_mm,
            first.concentrated_defect_rad,
            first.abs_defect_before_rad,
            first.abs_defect_after_rad,
            s.len()
        );
        assert!(
            common::ring_of(first.tip_vertex) <= 2,
            "tip at ring {}",
            common::ring_of(first.tip_vertex)
        );
        // The start is on the rim, at the geodesic distance from the tip (≥ the 3D distance).
        let topo = Topology::build(&m).unwrap();
        assert!(topo.is_boundary_vertex(flatcut_mesh::VertexId(first.start_vertex)));
        let chord = flatcut_mesh::vec3::dist(
            m.positions[first.start_vertex as usize],
            m.positions[first.tip_vertex as usize],
        );
        assert!(first.length_mm >= chord && first.length_mm < 1.2 * chord);
        // Proxy: the cut frees curvature.
        assert!(first.abs_defect_after_rad < first.abs_defect_before_rad);
        let d = dart(&m, std::slice::from_ref(&first.spec), &Default::default()).unwrap();
        assert!((total_abs_defect(&d.mesh).unwrap() - first.abs_defect_after_rad).abs() < 1e-12);
        // Suggestions are ranked by the proxy.
        for w in s.windows(2) {
            assert!(w[0].abs_defect_after_rad <= w[1].abs_defect_after_rad);
        }
        // And all of them together are a valid set of darts.
        let specs: Vec<_> = s.iter().map(|x| x.spec.clone()).collect();
        dart(&m, &specs, &Default::default()).unwrap();

        if rings == 8 {
            // The suggested dart lowers the processing's RMS displacement.
            let p0 = process(&m, &ProcessOptions::default()).unwrap();
            let p1 = process(&d.mesh, &ProcessOptions::default()).unwrap();
            println!(
                "suggested dart: report RMS {:.4} → {:.4} mm",
                p0.report.rms_displacement_mm, p1.report.rms_displacement_mm
            );
            assert!(p1.report.rms_displacement_mm < 0.5 * p0.report.rms_displacement_mm);
        }
    }
}

#[test]
fn flat_and_saddle_pieces_get_no_dart() {
    // No positive concentration: a flat disk has none, a saddle only negative curvature.
    let flat = shapes::planar_disk(100.0, 6);
    assert!(
        suggest(&flat, 2, &SuggestOptions::default())
            .unwrap()
            .is_empty()
    );
    let saddle = shapes::saddle_grid(12);
    let s = suggest(&saddle, 2, &SuggestOptions::default()).unwrap();
    assert!(
        s.is_empty(),
        "{:?}",
        s.iter()
            .map(|x| x.concentrated_defect_rad)
            .collect::<Vec<_>>()
    );
}
