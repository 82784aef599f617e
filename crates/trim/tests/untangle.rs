//! Untangling lines on a noisy surface (`untangle.rs`): a noise saddle — a vertex whose angle
//! sum exceeds 2π — pulls shortest paths through itself, so two lines meeting at a landmark
//! near it share a stretch, a T-line runs along its host line, and a zig-zag landmark chain
//! folds back on itself. Each case first shows the raw geodesics doing so (the failure), then
//! that `trim` cuts with the lines sharing only one point, the seam mates equal to 1e-9.

#![allow(clippy::unwrap_used)]

mod common;

use common::check_conservation;
use flatcut_mesh::{TriMesh, geometry, shapes, vec3};
use flatcut_trim::{
    CutSpec, Cuts, GeodesicOptions, Location, PieceSpec, SurfacePoint, SurfacePointOptions,
    TrimError, TrimOptions, geodesic, surface_point, trim,
};

/// The saddle vertex: the centre of the grid.
const V: u32 = 220;

/// A flat 21 × 21 grid over [−50, 50]² mm (5 mm spacing) whose centre vertex is a noise
/// saddle: its eight lattice neighbours go up and down by 3 mm as cos 2θ (a scan's crease
/// noise, exaggerated). Its angle sum is 421°.
fn saddle() -> TriMesh {
    shapes::grid_patch(21, 21, 100.0, |x, y| {
        let r = x.hypot(y);
        if r > 1.0 && r < 7.5 {
            3.0 * (2.0 * y.atan2(x)).cos()
        } else {
            0.0
        }
    })
}

fn sp(mesh: &TriMesh, p: [f64; 3]) -> SurfacePoint {
    let bvh = flatcut_mesh::bvh::Bvh::build(mesh);
    surface_point(&bvh, p, "p", &SurfacePointOptions::default()).unwrap()
}

/// The mesh vertices the raw geodesic from `a` to `b` passes.
fn raw_vertices(mesh: &TriMesh, a: [f64; 3], b: [f64; 3]) -> Vec<u32> {
    let g = geodesic(mesh, sp(mesh, a), sp(mesh, b), &GeodesicOptions::default())
        .unwrap()
        .unwrap();
    g.points
        .iter()
        .filter_map(|p| match p.location(mesh) {
            Location::Vertex(v) => Some(v),
            _ => None,
        })
        .collect()
}

fn line(name: &str, points: Vec<[f64; 3]>) -> CutSpec {
    CutSpec {
        name: name.into(),
        points,
        vertices: Vec::new(),
        closed: false,
    }
}

fn cuts(lines: Vec<CutSpec>) -> Cuts {
    Cuts {
        cuts: lines,
        options: TrimOptions {
            keep_unnamed: true,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Embedded vertices the two lines' chains have in common.
fn common_vertices(t: &flatcut_trim::Trimmed, a: usize, b: usize) -> Vec<u32> {
    let (ca, cb) = (&t.embedded.line_vertices[a], &t.embedded.line_vertices[b]);
    let mut out: Vec<u32> = ca.iter().copied().filter(|v| cb.contains(v)).collect();
    out.sort_unstable();
    out.dedup();
    out
}

#[test]
fn the_saddle_is_one() {
    let m = saddle();
    let theta = geometry::angle_sums(&m.positions, &m.faces)[V as usize];
    assert!(theta > 2.0 * std::f64::consts::PI + 1.0, "{theta}");
    assert_eq!(m.positions[V as usize], [0.0, 0.0, 0.0]);
}

#[test]
fn lines_crossing_at_a_landmark_by_a_saddle_share_only_one_point() {
    let m = saddle();
    // Both lines pass the landmark L, 1.7 mm from the saddle; the west leg of `across` and
    // the south leg of `down` both leave L through the saddle vertex.
    let l = [1.5, 0.8, 0.0];
    let (w, e) = ([-50.0, -20.0, 0.0], [50.0, 10.0, 0.0]);
    let (s, n) = ([-20.0, -50.0, 0.0], [10.0, 50.0, 0.0]);
    assert!(raw_vertices(&m, l, w).contains(&V));
    assert!(raw_vertices(&m, l, s).contains(&V));
    let c = cuts(vec![
        line("across", vec![w, l, e]),
        line("down", vec![s, l, n]),
    ]);
    let t = trim(&m, &c).unwrap();
    check_conservation(&m, &t);
    // They cross once, at the saddle vertex (where the raw geodesics parted), not along
    // the 1.7 mm stretch to L.
    assert_eq!(common_vertices(&t, 0, 1), vec![V]);
    assert_eq!(t.pieces.len(), 4);
    assert!(t.report.pieces.iter().all(|p| p.disk));
    // Each line is cut into two seams at the crossing.
    assert_eq!(t.ledger.seams.len(), 4);
    // The earlier line keeps its landmark; the later one moved by |L − V| only.
    let lp = sp(&m, l).position(&m);
    let has = |li: usize, x: [f64; 3]| {
        t.lines[li]
            .points
            .iter()
            .any(|p| vec3::dist(p.position(&m), x) < 1e-9)
    };
    assert!(has(0, lp));
    assert!(!has(1, lp));
    assert!(has(1, [0.0, 0.0, 0.0]));
}

#[test]
fn a_t_line_running_along_its_host_is_trimmed_to_where_they_part() {
    let m = saddle();
    // The host passes the saddle vertex and then L; the T-line starts on the host at L and
    // heads south: its raw geodesic runs back along the host to the saddle vertex first.
    let l = [1.5, 0.8, 0.0];
    let (w, e, s) = ([-50.0, -20.0, 0.0], [50.0, 10.0, 0.0], [-20.0, -50.0, 0.0]);
    assert!(raw_vertices(&m, l, s).contains(&V));
    let c = cuts(vec![line("host", vec![w, l, e]), line("t", vec![l, s])]);
    let t = trim(&m, &c).unwrap();
    check_conservation(&m, &t);
    // The T-line now starts where it parts from the host, and they share only that point.
    assert_eq!(t.embedded.line_vertices[1][0], V);
    assert_eq!(common_vertices(&t, 0, 1), vec![V]);
    assert_eq!(t.pieces.len(), 3);
    assert!(t.report.pieces.iter().all(|p| p.disk));
    // The host is cut into two seams at the junction, the T-line is one.
    assert_eq!(t.ledger.seams.len(), 3);
}

#[test]
fn a_zig_zag_landmark_chain_folding_back_is_straightened() {
    let m = saddle();
    // A → M → B with M 1.7 mm off the saddle: A → M and M → B both pass the saddle, so
    // the raw line runs V → M → V, back over itself.
    let (a, mid, b) = ([-50.0, -20.0, 0.0], [1.5, 0.8, 0.0], [-20.0, -50.0, 0.0]);
    assert!(raw_vertices(&m, a, mid).contains(&V));
    assert!(raw_vertices(&m, mid, b).contains(&V));
    let c = cuts(vec![line("zig", vec![a, mid, b])]);
    let t = trim(&m, &c).unwrap();
    check_conservation(&m, &t);
    // The spur is gone: the line passes the saddle once and no longer reaches M.
    let chain = &t.embedded.line_vertices[0];
    assert_eq!(chain.iter().filter(|&&v| v == V).count(), 1);
    let mp = sp(&m, mid).position(&m);
    assert!(
        t.lines[0]
            .points
            .iter()
            .all(|p| vec3::dist(p.position(&m), mp) > 1.0)
    );
    // Straightened = the raw legs A → M and M → B with the spur V → M → V cut out: its
    // length is theirs less twice |V M| (M and V share a face: the spur is one segment).
    let raw = |x: [f64; 3], y: [f64; 3]| {
        geodesic(&m, sp(&m, x), sp(&m, y), &GeodesicOptions::default())
            .unwrap()
            .unwrap()
            .length
    };
    let expect = raw(a, mid) + raw(mid, b) - 2.0 * vec3::dist(mp, [0.0, 0.0, 0.0]);
    assert!(
        (t.lines[0].length - expect).abs() <= 1e-9 * expect,
        "{} vs {expect}",
        t.lines[0].length
    );
    // The V-shaped line cuts the south-west corner off: two disks, one seam.
    assert_eq!(t.pieces.len(), 2);
    assert!(t.report.pieces.iter().all(|p| p.disk));
    assert_eq!(t.ledger.seams.len(), 1);
}

/// Distance from `x` to a polyline of surface points.
fn to_polyline(m: &TriMesh, pts: &[SurfacePoint], x: [f64; 3]) -> f64 {
    pts.windows(2)
        .map(|w| {
            let (a, b) = (w[0].position(m), w[1].position(m));
            let d = vec3::sub(b, a);
            let t = (vec3::dot(vec3::sub(x, a), d) / vec3::norm2(d).max(1e-300)).clamp(0.0, 1.0);
            vec3::dist(x, vec3::add(a, vec3::scale(d, t)))
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn a_zig_zag_chain_crossing_itself_loses_the_loop_at_the_crossing() {
    let m = saddle();
    // M lies 4.2 mm north-west of the saddle: A → M and M → B bend round it on different
    // sides and cross — a small loop round M (as sleeve-back-right at 12 mm).
    let (a, mid, b) = ([-50.0, -20.0, 0.0], [-3.0, 3.0, 0.0], [-20.0, -50.0, 0.0]);
    let raw = |x: [f64; 3], y: [f64; 3]| {
        geodesic(&m, sp(&m, x), sp(&m, y), &GeodesicOptions::default())
            .unwrap()
            .unwrap()
    };
    let (am, mb) = (raw(a, mid), raw(mid, b));
    let c = cuts(vec![line("zig", vec![a, mid, b])]);
    let t = trim(&m, &c).unwrap();
    check_conservation(&m, &t);
    let pts = &t.lines[0].points;
    // Every point of the line lies on one of the raw legs; the crossing point on both.
    let mp = sp(&m, mid).position(&m);
    let mut crossing = None;
    for p in pts {
        let x = p.position(&m);
        let (d1, d2) = (
            to_polyline(&m, &am.points, x),
            to_polyline(&m, &mb.points, x),
        );
        assert!(d1.min(d2) < 1e-9, "{x:?} off both legs: {d1} {d2}");
        if d1 < 1e-9 && d2 < 1e-9 {
            crossing = Some(x);
        }
    }
    let x = crossing.expect("a point on both legs");
    assert!(vec3::dist(x, mp) > 1.0, "the crossing is not M");
    assert!(pts.iter().all(|p| vec3::dist(p.position(&m), mp) > 1.0));
    // The loop X → M → X cut out is at least 2 |X M| long.
    assert!(t.lines[0].length <= am.length + mb.length - 2.0 * vec3::dist(x, mp) + 1e-9);
    assert_eq!(t.pieces.len(), 2);
    assert!(t.report.pieces.iter().all(|p| p.disk));
    assert_eq!(t.ledger.seams.len(), 1);
}

#[test]
fn a_long_loop_and_a_long_overlap_stay_errors() {
    let m = saddle();
    // A line drawn round in a 40 mm loop, crossing itself: meant, so refused.
    let c = cuts(vec![line(
        "loop",
        vec![
            [-50.0, -30.0, 0.0],
            [30.0, 10.0, 0.0],
            [10.0, 30.0, 0.0],
            [-10.0, -40.0, 0.0],
            [-10.0, -50.0, 0.0],
        ],
    )]);
    match trim(&m, &c).unwrap_err() {
        TrimError::SelfCrossing { line, .. } => assert_eq!(line, "loop"),
        e => panic!("{e}"),
    }
    // Two lines drawn along each other for 60 mm: refused, naming both.
    let c = cuts(vec![
        line("one", vec![[-50.0, 20.0, 0.0], [50.0, 20.0, 0.0]]),
        line(
            "two",
            vec![
                [-30.0, -50.0, 0.0],
                [-30.0, 20.0, 0.0],
                [30.0, 20.0, 0.0],
                [30.0, -50.0, 0.0],
            ],
        ),
    ]);
    match trim(&m, &c).unwrap_err() {
        TrimError::OverlappingLines { a, b, point_mm } => {
            assert_eq!((a.as_str(), b.as_str()), ("two", "one"));
            assert!((point_mm[1] - 20.0).abs() < 1e-6, "{point_mm:?}");
        }
        e => panic!("{e}"),
    }
}

/// Seeds name the pieces in the crossing case (a use of `PieceSpec` as in a plan).
#[test]
fn seeds_name_the_four_quadrants() {
    let m = saddle();
    let l = [1.5, 0.8, 0.0];
    let mut c = cuts(vec![
        line("across", vec![[-50.0, -20.0, 0.0], l, [50.0, 10.0, 0.0]]),
        line("down", vec![[-20.0, -50.0, 0.0], l, [10.0, 50.0, 0.0]]),
    ]);
    c.options.keep_unnamed = false;
    c.pieces = [
        ("ne", [30.0, 30.0]),
        ("nw", [-30.0, 30.0]),
        ("sw", [-40.0, -40.0]),
        ("se", [30.0, -30.0]),
    ]
    .into_iter()
    .map(|(n, p)| PieceSpec {
        name: n.into(),
        seed: [p[0], p[1], 0.0],
    })
    .collect();
    let t = trim(&m, &c).unwrap();
    let names: Vec<&str> = t.pieces.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["ne", "nw", "sw", "se"]);
}
