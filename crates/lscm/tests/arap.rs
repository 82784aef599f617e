//! Isometric refinement: ARAP then Gauss–Newton on edge lengths.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_lscm::{
    ArapOptions, FlattenOptions, LscmOptions, Method, RefineOptions, arap, distortion, flatten,
    lscm, refine_isometric,
};
use flatcut_mesh::{Topology, TriMesh};

fn refined(mesh: &TriMesh) -> flatcut_lscm::DistortionReport {
    let out = flatten(mesh, &FlattenOptions::default()).unwrap();
    let topo = Topology::build(mesh).unwrap();
    distortion(mesh, &topo, &out.flattening.uv)
}

#[test]
fn cylinder_becomes_an_isometry() {
    let mesh = common::cylinder(25, 12);
    let topo = Topology::build(&mesh).unwrap();
    // LSCM alone leaves a scale drift (pins at their chord, not arc, distance).
    let raw = lscm(&mesh, &LscmOptions::default()).unwrap();
    let d0 = distortion(&mesh, &topo, &raw.uv);
    assert!(
        d0.e_h.max > 1e-3,
        "LSCM should not be isometric here: {}",
        d0.e_h.max
    );
    assert!(d0.e_r.max < 1e-9, "but it is conformal: {}", d0.e_r.max);
    let d = refined(&mesh);
    assert!(d.e_h.max < 1e-9, "E_h {}", d.e_h.max);
    assert!(d.e_r.max < 1e-9, "E_r {}", d.e_r.max);
    assert!(d.max_edge_strain < 1e-9, "strain {}", d.max_edge_strain);
    assert_eq!(d.flipped_faces, 0);
    // Boundary lengths are kept.
    for l in &d.boundary_loops {
        assert!((l.length_2d_mm / l.length_3d_mm - 1.0).abs() < 1e-9);
    }
}

#[test]
fn cone_patch_becomes_an_isometry() {
    let d = refined(&common::cone(30, 10));
    assert!(d.e_h.max < 1e-9, "E_h {}", d.e_h.max);
    assert!(d.e_r.max < 1e-9, "E_r {}", d.e_r.max);
    assert!(d.max_edge_strain < 1e-9, "strain {}", d.max_edge_strain);
    assert_eq!(d.flipped_faces, 0);
    assert!((d.area_2d_mm2 / d.area_3d_mm2 - 1.0).abs() < 1e-9);
}

#[test]
fn arap_alone_reaches_1e6_on_a_developable_piece_and_never_raises_its_energy() {
    let mesh = common::cone(20, 8);
    let mut flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    let r = arap(&mut flat.pieces[0], &ArapOptions::default()).unwrap();
    assert!(r.energy_after <= r.energy_before);
    assert!(r.max_edge_strain <= 1e-6, "{}", r.max_edge_strain);
}

#[test]
fn non_developable_pieces_get_less_edge_strain_and_stay_unflipped() {
    for mesh in [common::saddle(16), common::sphere_band(20, 10)] {
        let mut flat = lscm(&mesh, &LscmOptions::default()).unwrap();
        let r = refine_isometric(&mut flat.pieces[0], &RefineOptions::default()).unwrap();
        assert!(
            r.max_edge_strain_after < r.max_edge_strain_before,
            "{} → {}",
            r.max_edge_strain_before,
            r.max_edge_strain_after
        );
        assert!(r.arap.energy_after < r.arap.energy_before);
        flat.gather();
        let topo = Topology::build(&mesh).unwrap();
        let d = distortion(&mesh, &topo, &flat.uv);
        assert_eq!(d.flipped_faces, 0);
        // A doubly curved piece cannot be isometric: the strain stays clearly non-zero.
        assert!(d.max_edge_strain > 1e-4, "{}", d.max_edge_strain);
    }
}

#[test]
fn lscm_method_skips_refinement() {
    let mesh = common::cylinder(10, 5);
    let out = flatten(
        &mesh,
        &FlattenOptions {
            method: Method::Lscm,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(out.refine.is_empty());
    let topo = Topology::build(&mesh).unwrap();
    assert!(distortion(&mesh, &topo, &out.flattening.uv).e_h.max > 1e-3);
}
