//! Placement: never mirrored, grain along +y, bounding box at the origin, side by side.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_lscm::{
    FlattenOptions, LscmOptions, Method, PlacementOptions, distortion, flatten, lscm, place,
    place_piece, unfold,
};
use flatcut_mesh::{Topology, TriMesh};

fn shapes() -> Vec<(&'static str, TriMesh)> {
    vec![
        ("planar", common::planar(8)),
        ("cylinder", common::cylinder(12, 6)),
        ("cone", common::cone(14, 6)),
        ("saddle", common::saddle(10)),
        ("sphere band", common::sphere_band(12, 8)),
        ("annulus", common::annulus(20, 4)),
    ]
}

#[test]
fn never_mirrored_on_any_shape_or_method() {
    for (name, mesh) in shapes() {
        for method in [Method::Lscm, Method::LscmArap] {
            let opts = FlattenOptions {
                method,
                ..Default::default()
            };
            let out = flatten(&mesh, &opts).unwrap();
            let areas = common::signed_areas(&mesh, &out.flattening.uv);
            let min = areas.iter().copied().fold(f64::INFINITY, f64::min);
            assert!(min > 0.0, "{name} {method:?}: min signed area {min}");
        }
    }
}

#[test]
fn a_mirrored_input_mesh_gives_the_other_side() {
    // Reversing every face shows the other side of the surface: the flattening is the
    // mirror image, and is still counter-clockwise for the reversed faces.
    let mesh = common::cylinder(10, 5);
    let mut rev = mesh.clone();
    for f in &mut rev.faces {
        f.swap(1, 2);
    }
    let a = flatten(&mesh, &FlattenOptions::default()).unwrap();
    let b = flatten(&rev, &FlattenOptions::default()).unwrap();
    assert!(
        common::signed_areas(&rev, &b.flattening.uv)
            .iter()
            .all(|&x| x > 0.0)
    );
    // Same faces, opposite orientation: the signed areas of the original faces in b are negative.
    assert!(
        common::signed_areas(&mesh, &b.flattening.uv)
            .iter()
            .all(|&x| x < 0.0)
    );
    assert!(
        common::signed_areas(&mesh, &a.flattening.uv)
            .iter()
            .all(|&x| x > 0.0)
    );
}

#[test]
fn grain_points_along_plus_y_and_bbox_starts_at_origin() {
    // The cylinder's axis is 3D +y; its rulings must come out vertical in the pattern.
    let mesh = common::cylinder(16, 7);
    let nu = 16;
    for grain in [[0.0, 1.0, 0.0], [0.0, -3.0, 0.0]] {
        let opts = FlattenOptions {
            placement: PlacementOptions {
                grain: Some(grain),
                ..Default::default()
            },
            ..Default::default()
        };
        let uv = flatten(&mesh, &opts).unwrap().flattening.uv;
        for i in 0..nu {
            // Ruling i runs from vertex i (bottom) to i + nu·6 (top).
            let (a, b) = (uv[i], uv[i + nu * 6]);
            let dir = [(b[0] - a[0]) / 120.0, (b[1] - a[1]) / 120.0];
            let sign = grain[1].signum();
            assert!((dir[0]).abs() < 1e-9, "{dir:?}");
            assert!((dir[1] - sign).abs() < 1e-9, "{dir:?}");
        }
        let min_x = uv.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min);
        let min_y = uv.iter().map(|q| q[1]).fold(f64::INFINITY, f64::min);
        assert_eq!((min_x, min_y), (0.0, 0.0));
    }
}

#[test]
fn default_grain_is_the_principal_axis() {
    // A long thin planar strip along 3D x: its principal axis is x, which must become +y.
    let mesh = common::grid(30, 4, |u, v| [300.0 * u, 20.0 * v, 0.0]);
    let uv = flatten(&mesh, &FlattenOptions::default())
        .unwrap()
        .flattening
        .uv;
    let (a, b) = (uv[0], uv[29]);
    assert!(
        (b[0] - a[0]).abs() < 1e-9 && (b[1] - a[1] - 300.0).abs() < 1e-9,
        "{a:?} {b:?}"
    );
}

#[test]
fn pieces_lie_side_by_side() {
    let mesh = common::union(&common::cylinder(10, 5), &common::annulus(16, 3));
    let gap = 7.5;
    let opts = FlattenOptions {
        placement: PlacementOptions {
            component_gap_mm: gap,
            ..Default::default()
        },
        ..Default::default()
    };
    let out = flatten(&mesh, &opts).unwrap();
    let p = &out.flattening.pieces;
    let max0 = p[0].uv.iter().map(|q| q[0]).fold(f64::MIN, f64::max);
    let min1 = p[1].uv.iter().map(|q| q[0]).fold(f64::MAX, f64::min);
    assert!((min1 - max0 - gap).abs() < 1e-9, "{max0} {min1}");
    // The combined array agrees with the pieces.
    for piece in p {
        for (v, q) in piece.piece.vertices.iter().zip(&piece.uv) {
            assert_eq!(out.flattening.uv[v.idx()], *q);
        }
    }
    let topo = Topology::build(&mesh).unwrap();
    let d = distortion(&mesh, &topo, &out.flattening.uv);
    assert!(d.max_edge_strain < 1e-9);
}

#[test]
fn placement_is_rigid() {
    // Placing changes no length: LSCM metrics before and after agree.
    let mesh = common::saddle(8);
    let topo = Topology::build(&mesh).unwrap();
    let mut flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    let before = distortion(&mesh, &topo, &flat.uv);
    place(&mut flat, &PlacementOptions::default()).unwrap();
    let after = distortion(&mesh, &topo, &flat.uv);
    assert!((before.e_h.mean - after.e_h.mean).abs() < 1e-12);
    assert!((before.max_edge_strain - after.max_edge_strain).abs() < 1e-12);
}

#[test]
fn unfolding_and_refinement_agree_after_placement() {
    for mesh in [common::cylinder(14, 6), common::cone(16, 6)] {
        let grain = Some([0.3, 1.0, 0.2]);
        let opts = FlattenOptions {
            placement: PlacementOptions {
                grain,
                ..Default::default()
            },
            ..Default::default()
        };
        let refined = flatten(&mesh, &opts).unwrap().flattening;
        let mut unfolded = lscm(&mesh, &LscmOptions::default())
            .unwrap()
            .pieces
            .remove(0);
        let u = unfold(&unfolded.piece);
        assert!(u.max_mismatch_mm < 1e-9, "{}", u.max_mismatch_mm);
        unfolded.uv = u.uv;
        place_piece(&mut unfolded, grain).unwrap();
        for (a, b) in refined.pieces[0].uv.iter().zip(&unfolded.uv) {
            assert!((a[0] - b[0]).hypot(a[1] - b[1]) < 1e-8, "{a:?} vs {b:?}");
        }
    }
}

#[test]
fn zero_grain_is_refused() {
    let mesh = common::planar(4);
    let mut flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    let err = place(
        &mut flat,
        &PlacementOptions {
            grain: Some([0.0; 3]),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("grain"));
}
