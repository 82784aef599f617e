//! Cutting: conservation (area, coverage, the embedded line on its polyline), pieces and
//! their topology, the seam ledger, and every kind of bad input.

#![allow(clippy::unwrap_used)]

use flatcut_mesh::{geometry, shapes, vec3};
use flatcut_trim::{CutSpec, Cuts, PieceSpec, TrimError, trim};

mod common;
use common::check_conservation;

fn line(name: &str, points: Vec<[f64; 3]>, closed: bool) -> CutSpec {
    CutSpec {
        name: name.into(),
        points,
        vertices: Vec::new(),
        closed,
    }
}

fn seed(name: &str, p: [f64; 3]) -> PieceSpec {
    PieceSpec {
        name: name.into(),
        seed: p,
    }
}

fn sphere_cuts(r: f64) -> Cuts {
    let at = |deg: f64| {
        let a = deg.to_radians();
        [r * a.cos(), 0.0, r * a.sin()]
    };
    Cuts {
        cuts: vec![
            line(
                "equator",
                vec![at(7.0), at(97.0), at(187.0), at(277.0)],
                true,
            ),
            line("crown", vec![at(7.0), [0.0, r, 0.0], at(187.0)], false),
        ],
        pieces: vec![
            seed("south", [0.0, -r, 0.0]),
            seed(
                "north-front",
                vec3::scale(vec3::normalize([0.1, 0.7, 0.7]), r),
            ),
            seed(
                "north-back",
                vec3::scale(vec3::normalize([0.1, 0.7, -0.7]), r),
            ),
        ],
        ..Default::default()
    }
}

#[test]
fn sphere_cut_by_a_loop_and_a_t_line() {
    let r = 100.0;
    let mesh = shapes::icosphere(r, 3);
    let t = trim(&mesh, &sphere_cuts(r)).unwrap();
    check_conservation(&mesh, &t);
    let names: Vec<&str> = t.pieces.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["south", "north-front", "north-back"]);
    assert!(
        t.report.pieces.iter().all(|p| p.disk),
        "{:?}",
        t.report.pieces
    );
    // The equator is split at the two T-junctions; the crown is one seam.
    let ids: Vec<&str> = t.ledger.seams.iter().map(|s| s.id.as_str()).collect();
    assert_eq!(ids, ["crown/0", "equator/0", "equator/1"]);
    let crown = &t.ledger.seams[0];
    let mut pair = [crown.a.piece.as_str(), crown.b.piece.as_str()];
    pair.sort();
    assert_eq!(pair, ["north-back", "north-front"]);
    // Seam lengths add up to the lines' lengths.
    let eq: f64 = t.ledger.seams[1..].iter().map(|s| s.length_3d_mm).sum();
    assert!((eq - t.lines[0].length).abs() < 1e-9 * eq);
    // A polyhedral great circle is a bit shorter than the smooth one, never longer.
    assert!(
        t.lines[0].length < std::f64::consts::TAU * r
            && t.lines[0].length > 0.99 * std::f64::consts::TAU * r
    );
    // The half-spheres: areas within the polyhedral sphere's.
    let area = geometry::total_area(&mesh);
    let south = t.report.pieces[0].area_mm2;
    assert!((south / area - 0.5).abs() < 0.01, "{}", south / area);
}

#[test]
fn tube_cut_open_along_its_length_is_two_disks() {
    // A closed tube (two boundary loops), cut by a ring and by a line from bottom to top.
    let (r, h) = (50.0, 200.0);
    let mesh = shapes::cylinder_patch(r, std::f64::consts::TAU, h, 32, 21);
    let ring = |y: f64| -> Vec<[f64; 3]> {
        (0..3)
            .map(|k| {
                let a = 0.3 + k as f64 * std::f64::consts::TAU / 3.0;
                [r * a.cos(), y, -r * a.sin()]
            })
            .collect()
    };
    let a = 1.0f64;
    let cuts = Cuts {
        cuts: vec![
            line("waist", ring(0.47 * h), true),
            line(
                "side",
                vec![
                    [r * a.cos(), 0.0, -r * a.sin()],
                    [r * a.cos(), h, -r * a.sin()],
                ],
                false,
            ),
        ],
        pieces: vec![
            seed("lower", [-r, 10.0, 0.0]),
            seed("upper", [-r, 190.0, 0.0]),
        ],
        ..Default::default()
    };
    let t = trim(&mesh, &cuts).unwrap();
    check_conservation(&mesh, &t);
    assert_eq!(t.pieces.len(), 2);
    assert!(
        t.report.pieces.iter().all(|p| p.disk),
        "{:?}",
        t.report.pieces
    );
    // The side line sews each tube to itself: two seams with one piece on both sides; the
    // waist runs all round from the crossing back to it.
    let side: Vec<_> = t.ledger.seams.iter().filter(|s| s.line == "side").collect();
    assert_eq!(side.len(), 2);
    assert!(side.iter().all(|s| s.a.piece == s.b.piece));
    let waist: Vec<_> = t
        .ledger
        .seams
        .iter()
        .filter(|s| s.line == "waist")
        .collect();
    assert_eq!(waist.len(), 1);
    assert_eq!(waist[0].start_mm, waist[0].end_mm);
    // The side line is straight on the developed cylinder: exactly the height.
    assert!(
        (t.lines[1].length - h).abs() < 1e-9 * h,
        "{}",
        t.lines[1].length
    );
}

#[test]
fn unnamed_pieces_are_reported_and_dropped_or_kept() {
    let r = 100.0;
    let mesh = shapes::icosphere(r, 2);
    let mut cuts = sphere_cuts(r);
    cuts.pieces.truncate(1);
    let t = trim(&mesh, &cuts).unwrap();
    assert_eq!(t.pieces.len(), 1);
    assert_eq!(t.report.pieces.len(), 3);
    assert_eq!(t.report.pieces.iter().filter(|p| !p.kept).count(), 2);
    // Faces of dropped pieces still have a fate: the dropped piece's index.
    let dropped: Vec<u32> = (1..3).collect();
    assert!(
        t.report
            .face_fates
            .iter()
            .any(|f| f.iter().any(|p| dropped.contains(p)))
    );
    // Seams beside dropped pieces are not in the ledger.
    assert!(t.ledger.seams.is_empty());
    assert!(t.report.unsewn_edges > 0);
    cuts.options.keep_unnamed = true;
    let t = trim(&mesh, &cuts).unwrap();
    assert_eq!(t.pieces.len(), 3);
    assert_eq!(t.pieces[2].name, "unnamed-2");
    check_conservation(&mesh, &t);
}

#[test]
fn a_handle_is_reported() {
    // A torus cut by one meridian loop is a tube: not a disk (two boundary loops).
    let mesh = shapes::torus(60.0, 20.0, 24, 12);
    let ring: Vec<[f64; 3]> = (0..4)
        .map(|k| {
            let a = 0.2 + k as f64 * std::f64::consts::TAU / 4.0;
            [60.0 + 20.0 * a.cos(), 20.0 * a.sin(), 0.0]
        })
        .collect();
    let cuts = Cuts {
        cuts: vec![line("meridian", ring, true)],
        pieces: vec![seed("tube", [-80.0, 0.0, 0.0])],
        ..Default::default()
    };
    let t = trim(&mesh, &cuts).unwrap();
    check_conservation(&mesh, &t);
    let p = &t.report.pieces[0];
    assert_eq!((p.boundary_loops, p.genus, p.disk), (2, 0, false));
    // Uncut, the torus has genus 1.
    let t = trim(
        &mesh,
        &Cuts {
            pieces: cuts.pieces.clone(),
            ..Default::default()
        },
    )
    .unwrap();
    let p = &t.report.pieces[0];
    assert_eq!((p.boundary_loops, p.genus, p.disk), (0, 1, false));
}

#[test]
fn bad_input_names_the_culprit() {
    let r = 100.0;
    let mesh = shapes::icosphere(r, 2);
    let base = sphere_cuts(r);

    let mut c = base.clone();
    c.cuts[0].points[1] = [0.0, 0.0, 130.0];
    match trim(&mesh, &c).unwrap_err() {
        TrimError::OffSurface { what, .. } => assert_eq!(what, "line \"equator\" point 1"),
        e => panic!("{e}"),
    }

    let mut c = base.clone();
    c.cuts[1].points[2] = vec3::scale(vec3::normalize([-1.0, 0.5, 0.1]), r);
    match trim(&mesh, &c).unwrap_err() {
        TrimError::LineEndFree { line, end, .. } => {
            assert_eq!((line.as_str(), end), ("crown", "last"))
        }
        e => panic!("{e}"),
    }

    // A bow-tie loop round the north pole crosses itself: its two long legs both go over the
    // pole.
    let mut c = base.clone();
    let lat = |az: f64| {
        let (a, l) = (az.to_radians(), 60f64.to_radians());
        [r * l.cos() * a.cos(), r * l.sin(), r * l.cos() * a.sin()]
    };
    c.cuts = vec![line(
        "bow-tie",
        vec![lat(20.0), lat(200.0), lat(110.0), lat(290.0)],
        true,
    )];
    c.pieces.clear();
    match trim(&mesh, &c).unwrap_err() {
        TrimError::SelfCrossing { line, .. } => assert_eq!(line, "bow-tie"),
        e => panic!("{e}"),
    }

    // Two lines along one stretch.
    let mut c = base.clone();
    let mut dup = c.cuts[0].clone();
    dup.name = "equator-again".into();
    c.cuts.push(dup);
    match trim(&mesh, &c).unwrap_err() {
        TrimError::OverlappingLines { a, b, .. } => {
            let mut ab = [a, b];
            ab.sort();
            assert_eq!(ab, ["equator".to_string(), "equator-again".to_string()]);
        }
        e => panic!("{e}"),
    }

    // A seed on a line.
    let mut c = base.clone();
    c.pieces[0].seed = [0.0, r, 0.0];
    match trim(&mesh, &c).unwrap_err() {
        TrimError::SeedOnLine { piece, line } => {
            assert_eq!((piece.as_str(), line.as_str()), ("south", "crown"))
        }
        e => panic!("{e}"),
    }

    // Two seeds in one piece.
    let mut c = base.clone();
    c.pieces.push(seed(
        "south-again",
        vec3::scale(vec3::normalize([0.2, -1.0, 0.1]), r),
    ));
    match trim(&mesh, &c).unwrap_err() {
        TrimError::SeedUsedTwice { first, second, .. } => {
            assert_eq!((first.as_str(), second.as_str()), ("south", "south-again"))
        }
        e => panic!("{e}"),
    }

    // A seed off the surface, a duplicate name, a vertex out of range.
    let mut c = base.clone();
    c.pieces[0].seed = [0.0, -150.0, 0.0];
    assert!(
        matches!(trim(&mesh, &c).unwrap_err(), TrimError::OffSurface { what, .. } if what.contains("south"))
    );
    let mut c = base.clone();
    c.pieces[1].name = "south".into();
    assert!(matches!(
        trim(&mesh, &c).unwrap_err(),
        TrimError::DuplicateName { what: "piece", .. }
    ));
    let mut c = base.clone();
    c.cuts[1].points.clear();
    c.cuts[1].vertices = vec![0, 1_000_000];
    assert!(matches!(
        trim(&mesh, &c).unwrap_err(),
        TrimError::BadVertex {
            vertex: 1_000_000,
            ..
        }
    ));
}

#[test]
fn vertex_lines_follow_edges() {
    // A line of vertices along one grid row of a flat patch, from boundary to boundary.
    let n = 9;
    let mesh = shapes::grid_patch(n, n, 80.0, |_, _| 0.0);
    let row = 4;
    let cuts = Cuts {
        cuts: vec![CutSpec {
            name: "row".into(),
            vertices: (0..n as u64).map(|i| (row * n) as u64 + i).collect(),
            ..Default::default()
        }],
        options: flatcut_trim::TrimOptions {
            keep_unnamed: true,
            ..Default::default()
        },
        ..Default::default()
    };
    let t = trim(&mesh, &cuts).unwrap();
    check_conservation(&mesh, &t);
    assert_eq!(t.pieces.len(), 2);
    // No face was split: the line runs along edges.
    assert_eq!(t.embedded.mesh.faces.len(), mesh.faces.len());
    assert!((t.lines[0].length - 80.0).abs() < 1e-9);
}

#[test]
fn dress_form_wetsuit_gives_eight_disks() {
    let m = shapes::BodyMeasurements {
        resolution: 48,
        ..Default::default()
    };
    let form = shapes::dress_form(&m);
    let cuts = flatcut_trim::dress_form_wetsuit(&form, &m).unwrap();
    let t = trim(&form, &cuts).unwrap();
    check_conservation(&form, &t);
    assert_eq!(t.pieces.len(), 8);
    assert!(
        t.report.pieces.iter().all(|p| p.kept && p.disk),
        "{:#?}",
        t.report.pieces
    );
    // Waist: split at the four lines crossing it; each other line at the waist (centre front
    // and back, sides) in two; shoulders one each.
    let count = |l: &str| t.ledger.seams.iter().filter(|s| s.line == l).count();
    assert_eq!(count("waist"), 4);
    for l in ["centre-front", "centre-back", "side-left", "side-right"] {
        assert_eq!(count(l), 2, "{l}");
    }
    assert_eq!(count("shoulder-left"), 1);
    // The waist seam is the measured waist (a polygon ring of 700 mm) up to the geodesic
    // shortcut between its landmarks.
    let w = t.lines.iter().find(|l| l.name == "waist").unwrap().length;
    assert!(w <= 700.0 + 1e-6 && w > 690.0, "{w}");
}

#[test]
fn lines_crossing_inside_faces_on_a_flat_sheet() {
    // Flat: geodesics are straight, so lengths and the crossing point have closed forms.
    let mesh = shapes::grid_patch(12, 12, 100.0, |_, _| 0.0);
    let (a0, a1) = ([-50.0, -31.3, 0.0], [50.0, 27.1, 0.0]);
    let (b0, b1) = ([-17.7, -50.0, 0.0], [23.9, 50.0, 0.0]);
    let cuts = Cuts {
        cuts: vec![
            line("a", vec![a0, a1], false),
            line("b", vec![b0, b1], false),
        ],
        pieces: vec![
            seed("north-west", [-40.0, 0.0, 0.0]),
            seed("north-east", [40.0, 40.0, 0.0]),
            seed("south-west", [-40.0, -45.0, 0.0]),
            seed("south-east", [40.0, 0.0, 0.0]),
        ],
        ..Default::default()
    };
    let t = trim(&mesh, &cuts).unwrap();
    check_conservation(&mesh, &t);
    assert_eq!(t.pieces.len(), 4);
    assert!(t.report.pieces.iter().all(|p| p.disk));
    assert!((t.lines[0].length - vec3::dist(a0, a1)).abs() < 1e-9);
    assert!((t.lines[1].length - vec3::dist(b0, b1)).abs() < 1e-9);
    // The crossing: one vertex on both chains, at the intersection of the two segments.
    let shared: Vec<u32> = t.embedded.line_vertices[0]
        .iter()
        .copied()
        .filter(|v| t.embedded.line_vertices[1].contains(v))
        .collect();
    assert_eq!(shared.len(), 1);
    let x = t.embedded.mesh.positions[shared[0] as usize];
    let (d1, d2) = (vec3::sub(a1, a0), vec3::sub(b1, b0));
    let s = ((b0[0] - a0[0]) * d2[1] - (b0[1] - a0[1]) * d2[0]) / (d1[0] * d2[1] - d1[1] * d2[0]);
    let exact = vec3::add(a0, vec3::scale(d1, s));
    assert!(vec3::dist(x, exact) < 1e-9, "{x:?} vs {exact:?}");
    // Each line is split at the crossing into two seams.
    assert_eq!(t.ledger.seams.len(), 4);

    // A bow-tie loop crossing itself inside a face.
    let c = Cuts {
        cuts: vec![line(
            "bow-tie",
            vec![
                [-31.0, -27.0, 0.0],
                [33.0, 29.0, 0.0],
                [35.0, -24.0, 0.0],
                [-28.0, 31.0, 0.0],
            ],
            true,
        )],
        ..Default::default()
    };
    match trim(&mesh, &c).unwrap_err() {
        TrimError::SelfCrossing { line, point_mm } => {
            assert_eq!(line, "bow-tie");
            assert!(vec3::norm(point_mm) < 20.0, "{point_mm:?}");
        }
        e => panic!("{e}"),
    }
}

#[test]
fn lines_may_share_a_stretch_of_the_mesh_boundary() {
    // Along the boundary a line cuts nothing, so two lines there do not conflict (scans: lines
    // hugging one hole); inside the surface the same overlap is an error (see above).
    let mesh = shapes::grid_patch(8, 8, 70.0, |_, _| 0.0);
    let vline = |name: &str, v: &[u64]| CutSpec {
        name: name.into(),
        vertices: v.to_vec(),
        ..Default::default()
    };
    let cuts = Cuts {
        cuts: vec![vline("a", &[0, 1, 2, 3, 4]), vline("b", &[2, 3, 4, 5])],
        options: flatcut_trim::TrimOptions {
            keep_unnamed: true,
            ..Default::default()
        },
        ..Default::default()
    };
    let t = trim(&mesh, &cuts).unwrap();
    check_conservation(&mesh, &t);
    assert_eq!(t.pieces.len(), 1);
    assert!(t.ledger.seams.is_empty());
    assert_eq!(t.report.unsewn_edges, 4 + 3);
}
