//! Cutting: conservation (area, coverage, the embedded line on its polyline), pieces and
//! their topology, the seam ledger, and every kind of bad input.

#![allow(clippy::unwrap_used)]

use flatcut_mesh::{TriMesh, geometry, shapes, vec3};
use flatcut_trim::{CutSpec, Cuts, PieceSpec, TrimError, Trimmed, trim};

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

/// The acceptance checks every cut must pass.
pub fn check_conservation(mesh: &TriMesh, t: &Trimmed) {
    let diag = mesh.diagonal();
    // Area: the pieces (kept and dropped) sum to the source, face by face.
    let src_area = geometry::face_areas(&mesh.positions, &mesh.faces);
    let emb_area = geometry::face_areas(&t.embedded.mesh.positions, &t.embedded.mesh.faces);
    let mut per_face = vec![0.0; mesh.faces.len()];
    for (f, &s) in t.embedded.face_source.iter().enumerate() {
        per_face[s as usize] += emb_area[f];
    }
    for (f, (&a, &b)) in src_area.iter().zip(&per_face).enumerate() {
        assert!(
            (a - b).abs() <= 1e-9 * a.max(1e-300),
            "face {f}: {a} vs {b}"
        );
    }
    let total: f64 = src_area.iter().sum();
    let pieces: f64 = t.report.pieces.iter().map(|p| p.area_mm2).sum();
    assert!(
        (total - pieces).abs() <= 1e-9 * total,
        "{total} vs {pieces}"
    );
    // Every source face has a fate.
    assert!(t.report.face_fates.iter().all(|f| !f.is_empty()));
    // Each embedded line lies on its polyline.
    for (l, chain) in t.lines.iter().zip(&t.embedded.line_vertices) {
        let segs: Vec<([f64; 3], [f64; 3])> = l
            .points
            .windows(2)
            .map(|w| (w[0].position(mesh), w[1].position(mesh)))
            .collect();
        for &v in chain {
            let x = t.embedded.mesh.positions[v as usize];
            let d = segs
                .iter()
                .map(|&(a, b)| {
                    let e = vec3::sub(b, a);
                    let s = if vec3::norm2(e) > 0.0 {
                        (vec3::dot(vec3::sub(x, a), e) / vec3::norm2(e)).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    vec3::dist(x, vec3::add(a, vec3::scale(e, s)))
                })
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 1e-9 * diag, "line {} vertex {v} is {d} off", l.name);
        }
        // The embedded chain is exactly as long as the polyline.
        let len: f64 = chain
            .windows(2)
            .map(|w| {
                vec3::dist(
                    t.embedded.mesh.positions[w[0] as usize],
                    t.embedded.mesh.positions[w[1] as usize],
                )
            })
            .sum();
        assert!(
            (len - l.length).abs() <= 1e-9 * l.length,
            "{} {len} {}",
            l.name,
            l.length
        );
    }
    // Provenance: every piece vertex is where its source point is.
    for p in &t.pieces {
        for (v, sp) in p.vertex_source.iter().enumerate() {
            assert!(vec3::dist(p.mesh.positions[v], sp.position(mesh)) <= 1e-9 * diag);
        }
        assert_eq!(p.face_source.len(), p.mesh.faces.len());
    }
    // The ledger: valid, chains on piece boundaries, mates equal in 3D length.
    t.ledger.check().unwrap();
    for s in &t.ledger.seams {
        let piece = |n: &str| t.pieces.iter().find(|p| p.name == n).unwrap();
        let len = |side: &flatcut_mesh::SeamSide| -> f64 {
            let p = piece(&side.piece);
            side.vertices
                .windows(2)
                .map(|w| {
                    vec3::dist(
                        p.mesh.positions[w[0] as usize],
                        p.mesh.positions[w[1] as usize],
                    )
                })
                .sum()
        };
        let (la, lb) = (len(&s.a), len(&s.b));
        assert!((la - lb).abs() <= 1e-9 * la, "seam {}: {la} vs {lb}", s.id);
        assert!((la - s.length_3d_mm).abs() <= 1e-9 * la);
        // Same source points, k by k.
        let (pa, pb) = (piece(&s.a.piece), piece(&s.b.piece));
        for (&va, &vb) in s.a.vertices.iter().zip(&s.b.vertices) {
            assert_eq!(
                pa.mesh.positions[va as usize],
                pb.mesh.positions[vb as usize]
            );
        }
        // Consecutive chain vertices are joined by a boundary edge of the piece.
        for side in [&s.a, &s.b] {
            let p = piece(&side.piece);
            let topo = flatcut_mesh::Topology::build(&p.mesh).unwrap();
            for w in side.vertices.windows(2) {
                let e = (w[0].min(w[1]), w[0].max(w[1]));
                let k = topo
                    .edges()
                    .iter()
                    .position(|x| (x[0], x[1]) == e)
                    .expect("edge");
                assert_eq!(
                    topo.edge_face_counts()[k],
                    1,
                    "seam {} edge {e:?} not on boundary",
                    s.id
                );
            }
        }
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
        TrimError::SeedUsedTwice { first, second } => {
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
