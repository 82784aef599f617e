//! Darts on a bump z = h·exp(−r²/σ²) over a disk, on a flat disk and on bad input.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::collections::HashSet;

use flatcut_dart::{DartError, DartSpec, Darted, dart, dart_seams};
use flatcut_flattenable::{ProcessOptions, process};
use flatcut_lscm::{FlattenOptions, flatten};
use flatcut_mesh::{SeamKind, SeamLedger, Topology, TriMesh, geometry, shapes, vec3};

const RINGS: usize = 8;
const R: f64 = 100.0;
const H: f64 = 30.0;
const SIGMA: f64 = 40.0;

/// First vertex of the outer ring (at angle 0, on the rim).
fn rim_vertex() -> usize {
    1 + 3 * RINGS * (RINGS - 1)
}

fn boundary_edges(m: &TriMesh) -> HashSet<(u32, u32)> {
    let topo = Topology::build(m).unwrap();
    (0..3 * m.faces.len() as u32)
        .filter(|&h| topo.twin(h).is_none())
        .map(|h| {
            let (a, b) = (topo.from_vertex(h).0, topo.to_vertex(h).0);
            (a.min(b), a.max(b))
        })
        .collect()
}

/// Checks the darted piece's structure: a disk still, legs along boundary edges, copies of
/// one point pairwise, the tip one vertex, provenance and area conserved.
fn check_structure(src: &TriMesh, d: &Darted) {
    let topo = Topology::build(&d.mesh).unwrap();
    assert_eq!(topo.boundary_loops().len(), 1, "still one boundary loop");
    assert_eq!(topo.euler_characteristic(), 1, "still a disk");
    let be = boundary_edges(&d.mesh);
    for legs in &d.darts {
        assert_eq!(legs.leg_a[0], legs.tip);
        assert_eq!(legs.leg_b[0], legs.tip);
        assert_eq!(legs.leg_a.len(), legs.leg_b.len());
        // The tip is one vertex: no copy of it was made.
        let tip_src = d.split_from[legs.tip as usize];
        assert_eq!(
            d.split_from.iter().filter(|&&s| s == tip_src).count(),
            1,
            "tip copied"
        );
        for k in 1..legs.leg_a.len() {
            let (a, b) = (legs.leg_a[k], legs.leg_b[k]);
            assert_ne!(a, b, "leg vertex {k} not split");
            assert_eq!(d.mesh.positions[a as usize], d.mesh.positions[b as usize]);
            for leg in [&legs.leg_a, &legs.leg_b] {
                let (u, v) = (leg[k - 1], leg[k]);
                assert!(
                    be.contains(&(u.min(v), u.max(v))),
                    "leg edge {u}-{v} not boundary"
                );
            }
        }
        let len: f64 = legs
            .leg_a
            .windows(2)
            .map(|w| {
                vec3::dist(
                    d.mesh.positions[w[0] as usize],
                    d.mesh.positions[w[1] as usize],
                )
            })
            .sum();
        assert!((len - legs.length_mm).abs() <= 1e-12 * len);
    }
    // Provenance: every vertex where its source point says, every face inside its source face.
    for (v, sp) in d.vertex_source.iter().enumerate() {
        let p = sp.position(src);
        assert!(
            vec3::dist(p, d.mesh.positions[v]) <= 1e-9 * src.diagonal(),
            "vertex {v}"
        );
    }
    for (f, &sf) in d.face_source.iter().enumerate() {
        let c = d.mesh.triangle(flatcut_mesh::FaceId(f as u32));
        let cen = vec3::scale(vec3::add(vec3::add(c[0], c[1]), c[2]), 1.0 / 3.0);
        let t = src.triangle(flatcut_mesh::FaceId(sf));
        let (cp, _) = flatcut_mesh::bvh::closest_point_on_triangle(cen, t[0], t[1], t[2]);
        assert!(
            vec3::dist(cp, cen) <= 1e-9 * src.diagonal(),
            "face {f} off its source face {sf}"
        );
    }
    let (a0, a1) = (geometry::total_area(src), geometry::total_area(&d.mesh));
    assert!((a0 - a1).abs() <= 1e-12 * a0, "area {a0} → {a1}");
}

/// RMS displacement over the input's interior vertices (the same points with and without a
/// dart: the darted piece keeps the input's vertex indices).
fn rms_on_input(src: &TriMesh, out: &TriMesh) -> f64 {
    let topo = Topology::build(src).unwrap();
    let (mut s, mut n) = (0.0, 0);
    for v in 0..src.positions.len() {
        if topo.is_interior_vertex(flatcut_mesh::VertexId(v as u32)) {
            s += vec3::norm2(vec3::sub(out.positions[v], src.positions[v]));
            n += 1;
        }
    }
    (s / n as f64).sqrt()
}

#[test]
fn bump_dart_lowers_displacement_and_legs_flatten_to_equal_length() {
    let m = common::bump(RINGS, R, H, SIGMA);
    let top = m.positions[0];
    let d = dart(
        &m,
        &[DartSpec::to_tip("back", m.positions[rim_vertex()], top)],
        &Default::default(),
    )
    .unwrap();
    check_structure(&m, &d);
    assert_eq!(d.darts[0].tip, 0, "the tip is the top vertex");

    let opts = ProcessOptions::default();
    let plain = process(&m, &opts).unwrap();
    let darted = process(&d.mesh, &opts).unwrap();
    assert!(plain.report.converged && darted.report.converged);
    let (rms0, rms1) = (
        rms_on_input(&m, &plain.mesh),
        rms_on_input(&m, &darted.mesh),
    );
    println!(
        "bump rings {RINGS}: RMS displacement on the input's interior vertices: no dart {rms0:.4} mm, dart {rms1:.4} mm; report RMS {:.4} / {:.4} mm; iterations {} / {}; area change {:.3} % / {:.3} %",
        plain.report.rms_displacement_mm,
        darted.report.rms_displacement_mm,
        plain.report.iterations,
        darted.report.iterations,
        plain.report.area_change_percent,
        darted.report.area_change_percent
    );
    // Measured 9.350 → 2.970 mm (docs/algorithms/darts.md); a dart that did nothing would
    // leave it at 9.35.
    assert!(rms1 < 0.5 * rms0, "{rms1} vs {rms0}");

    // Flattened, both legs have the same 2D length; the tip is one vertex of the pattern.
    let flat = flatten(&darted.mesh, &FlattenOptions::default()).unwrap();
    let uv = &flat.flattening.uv;
    for legs in &d.darts {
        let l2 = |leg: &[u32]| -> f64 {
            leg.windows(2)
                .map(|w| {
                    let (a, b) = (uv[w[0] as usize], uv[w[1] as usize]);
                    (a[0] - b[0]).hypot(a[1] - b[1])
                })
                .sum()
        };
        let (la, lb) = (l2(&legs.leg_a), l2(&legs.leg_b));
        println!(
            "legs in 2D: {la:.12} / {lb:.12} mm (3D {:.12})",
            legs.length_mm
        );
        assert!((la - lb).abs() <= 1e-6 * la, "legs {la} vs {lb}");
        // The legs open into a wedge: their ends are apart in 2D.
        let (ea, eb) = (
            uv[*legs.leg_a.last().unwrap() as usize],
            uv[*legs.leg_b.last().unwrap() as usize],
        );
        assert!(
            (ea[0] - eb[0]).hypot(ea[1] - eb[1]) > 1.0,
            "the dart did not open"
        );
    }
}

#[test]
fn direction_and_length_on_a_flat_disk_is_a_straight_line() {
    let m = shapes::planar_disk(100.0, 6);
    let from = [100.0, 0.0, 0.0];
    let dir = [-1.0, 0.4, 3.0]; // the normal component is projected away
    let d = dart(
        &m,
        &[DartSpec::along("d", from, dir, 60.0)],
        &Default::default(),
    )
    .unwrap();
    let u = vec3::normalize([-1.0, 0.4, 0.0]);
    let expect = vec3::add(from, vec3::scale(u, 60.0));
    let tip = d.darts[0].tip_mm;
    assert!(vec3::dist(tip, expect) < 1e-9, "{tip:?} vs {expect:?}");
    assert!((d.darts[0].length_mm - 60.0).abs() < 1e-9);
    check_structure(&m, &d);
}

#[test]
fn direction_and_length_on_a_cylinder_follows_the_developed_line() {
    // A faceted cylinder (radius 50 around y, 2 rad, 40 × 20 vertices) is developable: the
    // straightest line from the bottom corner at slope α from the axis develops into a
    // straight line, so after arc length L it is at height L cos α and L sin α across the
    // facets (each facet a chord 2r sin(Δ/2) wide).
    let (r, span, n_around) = (50.0, 2.0, 40);
    let m = shapes::cylinder_patch(r, span, 100.0, n_around, 20);
    let from = [r, 0.0, 0.0];
    let alpha: f64 = 0.5;
    let dir = [0.0, alpha.cos(), -alpha.sin()];
    let l = 60.0;
    // The direction is the round cylinder's tangent; the walk starts in the first facet,
    // whose plane holds the axis direction but meets the tangent at Δ/2: projected, the
    // slope from the axis becomes α'.
    let d = dart(
        &m,
        &[DartSpec::along("d", from, dir, l)],
        &Default::default(),
    )
    .unwrap();
    let tip = d.darts[0].tip_mm;
    let delta = span / (n_around - 1) as f64;
    let chord = 2.0 * r * (delta / 2.0).sin();
    let alpha = (alpha.sin() * r * delta.sin() / chord).atan2(alpha.cos());
    let across = l * alpha.sin() / chord;
    let (k, frac) = (across.floor(), across.fract());
    let at = |a: f64| [r * a.cos(), -r * a.sin()];
    let (p0, p1) = (at(k * delta), at((k + 1.0) * delta));
    let expect = [
        p0[0] + frac * (p1[0] - p0[0]),
        l * alpha.cos(),
        p0[1] + frac * (p1[1] - p0[1]),
    ];
    assert!(vec3::dist(tip, expect) < 1e-9 * l, "{tip:?} vs {expect:?}");
    check_structure(&m, &d);
}

#[test]
fn several_darts_and_their_seams() {
    let m = common::bump(RINGS, R, H, SIGMA);
    let n = m.positions.len();
    let outer = 1 + 3 * RINGS * (RINGS - 1);
    let count = 6 * RINGS;
    let rim = |s: usize| m.positions[outer + s % count];
    let tip_at = |a: f64, r: f64| {
        let z = H * (-(r * r) / (SIGMA * SIGMA)).exp();
        [r * a.cos(), r * a.sin(), z]
    };
    let specs = [
        DartSpec::to_tip("left", rim(0), tip_at(0.0, 30.0)),
        DartSpec::to_tip("right", rim(count / 2), tip_at(std::f64::consts::PI, 30.0)),
        DartSpec::to_tip(
            "",
            rim(count / 4),
            tip_at(std::f64::consts::FRAC_PI_2, 40.0),
        ),
    ];
    let d = dart(&m, &specs, &Default::default()).unwrap();
    assert_eq!(d.darts.len(), 3);
    assert_eq!(d.darts[2].name, "dart-3");
    check_structure(&m, &d);
    assert!(d.mesh.positions.len() > n);

    let mut ledger = SeamLedger::new(vec!["back".into()]);
    flatcut_dart::append_dart_seams(&mut ledger, "back", &d).unwrap();
    ledger.check().unwrap();
    assert_eq!(ledger.seams.len(), 3);
    let seams = dart_seams(&d, "back");
    for (s, legs) in seams.iter().zip(&d.darts) {
        assert_eq!(s.kind, SeamKind::Dart);
        assert_eq!(s.a.vertices, legs.leg_a);
        assert_eq!(s.b.vertices, legs.leg_b);
        assert_eq!(s.start_mm, d.mesh.positions[legs.tip as usize]);
        assert_eq!(s.end_mm, legs.start_mm);
        // The 3D length is the geodesic's: at least the chord, within the bump's extent.
        assert!(s.length_3d_mm >= vec3::dist(s.start_mm, s.end_mm));
        assert!(ledger.seams.iter().any(|x| x.id == s.id));
    }
    // Appending twice names the clash.
    assert!(matches!(
        flatcut_dart::append_dart_seams(&mut ledger, "back", &d),
        Err(DartError::DuplicateSeam { .. })
    ));
    assert!(matches!(
        flatcut_dart::append_dart_seams(&mut ledger, "front", &d),
        Err(DartError::UnknownPiece { .. })
    ));
}

#[test]
fn existing_seams_follow_a_split_start_vertex() {
    // A piece whose whole rim is one seam with another piece; a dart starting at a rim
    // vertex splits it, and the seam's chain must move to the copy its edges now use.
    let m = common::bump(4, R, H, SIGMA);
    let topo = Topology::build(&m).unwrap();
    let rim: Vec<u32> = topo.boundary_loops()[0].iter().map(|v| v.0).collect();
    let mut ledger = SeamLedger::new(vec!["p".into(), "q".into()]);
    ledger.seams.push(flatcut_mesh::Seam {
        id: "rim/0".into(),
        line: "rim".into(),
        kind: SeamKind::Seam,
        a: flatcut_mesh::SeamSide {
            piece: "p".into(),
            vertices: rim.clone(),
        },
        b: flatcut_mesh::SeamSide {
            piece: "q".into(),
            vertices: (0..rim.len() as u32).collect(),
        },
        length_3d_mm: 1.0,
        start_mm: [0.0; 3],
        end_mm: [0.0; 3],
    });
    let original = ledger.clone();
    let s = rim[3];
    let d = dart(
        &m,
        &[DartSpec::to_tip(
            "d",
            m.positions[s as usize],
            m.positions[0],
        )],
        &Default::default(),
    )
    .unwrap();
    flatcut_dart::append_dart_seams(&mut ledger, "p", &d).unwrap();
    ledger.check().unwrap();
    // The rim seam now stops at the dart's mouth and goes on from the start's other copy.
    let be = boundary_edges(&d.mesh);
    let parts: Vec<_> = ledger.seams.iter().filter(|x| x.line == "rim").collect();
    assert_eq!(parts.len(), 2);
    assert_eq!(
        (parts[0].id.as_str(), parts[1].id.as_str()),
        ("rim/0.1", "rim/0.2")
    );
    let legs = &d.darts[0];
    let mouth = [*legs.leg_a.last().unwrap(), *legs.leg_b.last().unwrap()];
    assert_eq!(
        parts[0].a.vertices.len() + parts[1].a.vertices.len(),
        rim.len() + 1
    );
    assert!(mouth.contains(parts[0].a.vertices.last().unwrap()));
    assert!(mouth.contains(&parts[1].a.vertices[0]));
    assert_ne!(*parts[0].a.vertices.last().unwrap(), parts[1].a.vertices[0]);
    // The mate is split at the same index: its shared vertex ends one part and starts the next.
    assert_eq!(parts[0].b.vertices.last(), parts[1].b.vertices.first());
    let mut total = 0.0;
    for p in &parts {
        assert_eq!(p.a.vertices.len(), p.b.vertices.len());
        for w in p.a.vertices.windows(2) {
            assert!(be.contains(&(w[0].min(w[1]), w[0].max(w[1]))), "{w:?}");
        }
        total += p.length_3d_mm;
    }
    let rim_len: f64 = rim
        .windows(2)
        .map(|w| vec3::dist(m.positions[w[0] as usize], m.positions[w[1] as usize]))
        .sum();
    assert!(
        (total - rim_len).abs() < 1e-9 * rim_len,
        "{total} vs {rim_len}"
    );
    // A dart starting inside a seam edge is refused, named.
    let mid = vec3::scale(
        vec3::add(m.positions[rim[5] as usize], m.positions[rim[6] as usize]),
        0.5,
    );
    let d2 = dart(
        &m,
        &[DartSpec::to_tip("mid", mid, m.positions[0])],
        &Default::default(),
    )
    .unwrap();
    let mut l2 = original;
    match flatcut_dart::append_dart_seams(&mut l2, "p", &d2) {
        Err(DartError::StartSplitsSeam { name, seam }) => {
            assert_eq!(name, "mid");
            assert_eq!(seam, "rim/0");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_darts_are_named() {
    let m = common::bump(RINGS, R, H, SIGMA);
    let rim0 = m.positions[rim_vertex()];
    let top = m.positions[0];
    let o = Default::default();
    let ok = DartSpec::to_tip("ok", rim0, top);
    // Start far from the boundary.
    match dart(
        &m,
        &[ok.clone(), DartSpec::to_tip("far", [30.0, 0.0, 20.0], top)],
        &o,
    ) {
        Err(DartError::StartOffBoundary {
            index: 1,
            name,
            distance_mm,
            ..
        }) => {
            assert_eq!(name, "far");
            assert!(distance_mm > 50.0);
        }
        r => panic!("{r:?}"),
    }
    // Tip off the piece (above it).
    match dart(&m, &[DartSpec::to_tip("high", rim0, [0.0, 0.0, 80.0])], &o) {
        Err(DartError::TipOffPiece {
            index: 0,
            name,
            distance_mm,
            ..
        }) => {
            assert_eq!(name, "high");
            assert!((distance_mm - 50.0).abs() < 1.0);
        }
        r => panic!("{r:?}"),
    }
    // Tip on the boundary.
    let rim_other = m.positions[rim_vertex() + 10];
    assert!(matches!(
        dart(&m, &[DartSpec::to_tip("edge", rim0, rim_other)], &o),
        Err(DartError::TipOnBoundary { index: 0, .. })
    ));
    // Two darts crossing.
    let c = 6 * RINGS;
    let a = DartSpec::to_tip(
        "a",
        m.positions[rim_vertex()],
        [-30.0, 0.0, H * (-(900.0) / (SIGMA * SIGMA)).exp()],
    );
    let b = DartSpec::to_tip(
        "b",
        m.positions[rim_vertex() + c / 4],
        [0.0, -30.0, H * (-(900.0) / (SIGMA * SIGMA)).exp()],
    );
    match dart(&m, &[a, b], &o) {
        Err(DartError::Crossing {
            a,
            b,
            a_name,
            b_name,
            ..
        }) => {
            assert_eq!((a, b), (0, 1));
            assert_eq!((a_name.as_str(), b_name.as_str()), ("a", "b"));
        }
        r => panic!("{r:?}"),
    }
    // Longer than the piece in its direction.
    match dart(
        &m,
        &[DartSpec::along("long", rim0, [-1.0, 0.0, 0.0], 500.0)],
        &o,
    ) {
        Err(DartError::TooLong {
            index: 0,
            name,
            reach_mm,
            ..
        }) => {
            assert_eq!(name, "long");
            // It crossed the whole bump: more than the diameter.
            assert!(reach_mm > 2.0 * R, "{reach_mm}");
        }
        r => panic!("{r:?}"),
    }
    // Pointing outwards.
    assert!(matches!(
        dart(
            &m,
            &[DartSpec::along("out", rim0, [1.0, 0.0, 0.0], 10.0)],
            &o
        ),
        Err(DartError::DirectionOutward { index: 0, .. })
    ));
    // Neither tip nor direction; duplicate names; NaN.
    let mut neither = ok.clone();
    neither.tip = None;
    assert!(matches!(
        dart(&m, &[neither], &o),
        Err(DartError::BadSpec { index: 0, .. })
    ));
    assert!(matches!(
        dart(&m, &[ok.clone(), ok.clone()], &o),
        Err(DartError::DuplicateName {
            first: 0,
            second: 1,
            ..
        })
    ));
    let nan = DartSpec::to_tip("nan", [f64::NAN, 0.0, 0.0], top);
    assert!(matches!(
        dart(&m, &[nan], &o),
        Err(DartError::BadSpec { index: 0, .. })
    ));
    // A closed surface has no boundary to start from.
    let s = shapes::icosphere(50.0, 1);
    assert!(matches!(
        dart(
            &s,
            &[DartSpec::to_tip("x", [0.0, 0.0, 50.0], [50.0, 0.0, 0.0])],
            &o
        ),
        Err(DartError::BadPiece { .. })
    ));
    // Every message names the dart.
    let e = dart(
        &m,
        &[DartSpec::to_tip("shoulder", [30.0, 0.0, 20.0], top)],
        &o,
    )
    .unwrap_err();
    assert!(e.to_string().contains("\"shoulder\""), "{e}");
}
