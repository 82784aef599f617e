//! Surfaces from wire-frames: boundary fidelity, triangle quality, topology, closed forms.

#![allow(clippy::unwrap_used)]

use flatcut_mesh::geometry::{corner_angles, total_area};
use flatcut_mesh::{Topology, TriMesh};
use flatcut_trim::wireframe::{
    DomainChoice, DomainKind, VertexOrigin, WireCurve, WireFrame, WireframeError, WireframeOptions,
    wireframe_surface,
};

fn curve(name: &str, points: Vec<[f64; 3]>) -> WireCurve {
    WireCurve {
        name: name.to_string(),
        points,
    }
}

fn frame(curves: Vec<WireCurve>, target_edge_mm: f64) -> WireFrame {
    WireFrame {
        units: "mm".to_string(),
        target_edge_mm,
        curve: curves,
        guide: Vec::new(),
        options: WireframeOptions::default(),
    }
}

/// Samples `f(s)` for s in [0, 1] at n + 1 points.
fn sample(n: usize, f: impl Fn(f64) -> [f64; 3]) -> Vec<[f64; 3]> {
    (0..=n).map(|i| f(i as f64 / n as f64)).collect()
}

/// The seat: a 500 × 450 mm saddle z = 40 (x²/a² − y²/b²), its four sides as four curves
/// (two of them given backwards, so joining has to reverse them).
fn seat(n_side: usize) -> Vec<WireCurve> {
    let (a, b) = (250.0, 225.0);
    let z = move |x: f64, y: f64| 40.0 * (x * x / (a * a) - y * y / (b * b));
    let p = move |x: f64, y: f64| [x, y, z(x, y)];
    vec![
        curve("front", sample(n_side, |s| p(-a + 2.0 * a * s, -b))),
        // Given from back-right to front-right (reversed).
        curve("right", sample(n_side, |s| p(a, b - 2.0 * b * s))),
        curve("back", sample(n_side, |s| p(a - 2.0 * a * s, b))),
        // Given from front-left to back-left (reversed).
        curve("left", sample(n_side, |s| p(-a, -b + 2.0 * b * s))),
    ]
}

fn diag(curves: &[WireCurve]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in curves.iter().flat_map(|c| c.points.iter()) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    flatcut_mesh::vec3::dist(lo, hi)
}

fn point_segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let t = ((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2).clamp(0.0, 1.0);
    let q = [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// Distance from p to the nearest segment of any of the curves.
fn distance_to_curves(p: [f64; 3], curves: &[WireCurve]) -> f64 {
    curves
        .iter()
        .flat_map(|c| c.points.windows(2).map(|w| (w[0], w[1])))
        .map(|(a, b)| point_segment_distance(p, a, b))
        .fold(f64::INFINITY, f64::min)
}

fn min_angle_deg(m: &TriMesh) -> f64 {
    corner_angles(&m.positions, &m.faces)
        .iter()
        .flatten()
        .fold(f64::INFINITY, |a, &b| a.min(b))
        .to_degrees()
}

/// The patch boundary follows the curves: every input point is a vertex, every boundary
/// vertex lies on an input segment (both to `tol`), and the patch is one disk.
fn assert_disk_on_curves(m: &TriMesh, curves: &[WireCurve], tol: f64) {
    let topo = Topology::build(m).unwrap();
    assert_eq!(topo.component_count(), 1);
    assert_eq!(topo.boundary_loops().len(), 1, "one boundary loop");
    assert_eq!(topo.euler_characteristic(), 1, "a disk");
    assert!(topo.non_manifold_edges().is_empty());
    for c in curves {
        for (i, q) in c.points.iter().enumerate() {
            let d = m
                .positions
                .iter()
                .map(|p| flatcut_mesh::vec3::dist(*p, *q))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= tol,
                "curve {} point {i} is {d} from the nearest vertex",
                c.name
            );
        }
    }
    let mut worst: f64 = 0.0;
    for v in &topo.boundary_loops()[0] {
        worst = worst.max(distance_to_curves(m.positions[v.0 as usize], curves));
    }
    assert!(
        worst <= tol,
        "boundary vertex {worst} mm off the curves (tol {tol})"
    );
}

#[test]
fn seat_saddle_from_four_curves() {
    let curves = seat(25);
    let wire = frame(curves.clone(), 20.0);
    let patch = wireframe_surface(&wire, &wire.options).unwrap();
    let m = &patch.mesh;
    let d = diag(&curves);
    assert_disk_on_curves(m, &curves, 1e-9 * d);
    let min3 = min_angle_deg(m);
    eprintln!("seat: {:?}", patch.report);
    assert!(min3 >= 20.0, "min 3D angle {min3}°");
    assert!((min3 - patch.report.min_angle_3d_deg).abs() < 1e-9);
    assert_eq!(patch.report.domain, DomainKind::Plane);
    assert!(patch.report.max_boundary_deviation_mm <= 1e-9 * d);
    // The boundary loop the patch reports is the mesh's boundary loop, in curve order.
    let topo = Topology::build(m).unwrap();
    assert_eq!(patch.boundary.len(), topo.boundary_loops()[0].len());
    // Every input point is a vertex with that origin, at exactly that point.
    for (ci, c) in curves.iter().enumerate() {
        for (pi, q) in c.points.iter().enumerate() {
            let found = patch.origins.iter().enumerate().any(|(v, o)| {
                matches!(o, VertexOrigin::CurvePoint { curve, point } if *curve == ci && *point == pi)
                    && m.positions[v] == *q
            });
            // Shared corners appear once, under one of the two curves.
            let corner = pi == 0 || pi == c.points.len() - 1;
            assert!(found || corner, "curve {ci} point {pi} is not a vertex");
        }
    }
    // Edge lengths near the target (the refinement's max area is the equilateral one).
    let mut max_edge: f64 = 0.0;
    for f in &m.faces {
        for k in 0..3 {
            let a = m.positions[f[k] as usize];
            let b = m.positions[f[(k + 1) % 3] as usize];
            max_edge = max_edge.max(flatcut_mesh::vec3::dist(a, b));
        }
    }
    assert!(max_edge < 2.0 * 20.0, "longest edge {max_edge}");
    // Orientation follows the loop by the right-hand rule: front (+x), right (+y), back, left
    // run counter-clockwise seen from +z, so every face normal points up.
    for n in flatcut_mesh::geometry::face_normals(&m.positions, &m.faces) {
        assert!(n[2] > 0.5, "normal {n:?}");
    }
}

/// A square frame in a tilted plane: the patch is planar and its area is the square's.
#[test]
fn planar_square_frame_gives_planar_patch_of_the_square_area() {
    // An orthonormal in-plane basis of a tilted plane through (10, -20, 30).
    let u = [0.8, 0.0, 0.6];
    let v = [-0.36, 0.8, 0.48];
    let n = [-0.48, -0.6, 0.64];
    let o = [10.0, -20.0, 30.0];
    let at = |s: f64, t: f64| [0, 1, 2].map(|k| o[k] + s * u[k] + t * v[k]);
    let side = 300.0;
    let corners = [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)];
    let curves: Vec<WireCurve> = (0..4)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % 4]);
            curve(
                &format!("side{i}"),
                sample(7, |s| at(a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1))),
            )
        })
        .collect();
    let wire = frame(curves.clone(), 15.0);
    let patch = wireframe_surface(&wire, &wire.options).unwrap();
    let m = &patch.mesh;
    let d = diag(&curves);
    assert_disk_on_curves(m, &curves, 1e-9 * d);
    let off_plane = m
        .positions
        .iter()
        .map(|p| ((p[0] - o[0]) * n[0] + (p[1] - o[1]) * n[1] + (p[2] - o[2]) * n[2]).abs())
        .fold(0.0, f64::max);
    assert!(off_plane <= 1e-9 * d, "off the plane by {off_plane}");
    let area = total_area(m);
    assert!(
        (area - side * side).abs() <= 1e-9 * side * side,
        "area {area} vs {}",
        side * side
    );
    assert!(
        min_angle_deg(m) >= 28.0 - 1e-9,
        "planar: the domain angle limit holds in 3D"
    );
}

/// A non-convex planar frame (an L) in the xy plane: area equals the shoelace area.
#[test]
fn planar_l_frame_area() {
    let l = [
        [0.0, 0.0],
        [400.0, 0.0],
        [400.0, 150.0],
        [150.0, 150.0],
        [150.0, 350.0],
        [0.0, 350.0],
    ];
    let pts: Vec<[f64; 3]> = l
        .iter()
        .chain(std::iter::once(&l[0]))
        .map(|p| [p[0], p[1], 5.0])
        .collect();
    let curves = vec![curve("outline", pts)];
    let wire = frame(curves.clone(), 25.0);
    let patch = wireframe_surface(&wire, &wire.options).unwrap();
    let shoelace = 400.0 * 150.0 + 150.0 * 200.0;
    let area = total_area(&patch.mesh);
    assert!(
        (area - shoelace).abs() <= 1e-9 * shoelace,
        "area {area} vs {shoelace}"
    );
    assert!(patch.mesh.positions.iter().all(|p| p[2] == 5.0));
    assert_disk_on_curves(&patch.mesh, &curves, 1e-9 * diag(&curves));
}

/// z = c·x·y is harmonic and linear along the sides of an axis-aligned square, so the
/// square's four corners define it exactly: the lifted interior heights must converge to
/// it (second order for the cotan Laplacian on a quasi-uniform Delaunay mesh).
#[test]
fn harmonic_lift_reproduces_the_hyperbolic_paraboloid() {
    let c = 1.0 / 250.0;
    let half = 100.0;
    let p = |x: f64, y: f64| [x, y, c * x * y];
    let curves = vec![
        curve("s", vec![p(-half, -half), p(half, -half)]),
        curve("e", vec![p(half, -half), p(half, half)]),
        curve("n", vec![p(half, half), p(-half, half)]),
        curve("w", vec![p(-half, half), p(-half, -half)]),
    ];
    let mut errors = Vec::new();
    for h in [20.0, 10.0, 5.0] {
        let wire = frame(curves.clone(), h);
        let patch = wireframe_surface(&wire, &wire.options).unwrap();
        let err = patch
            .mesh
            .positions
            .iter()
            .map(|q| (q[2] - c * q[0] * q[1]).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "h = {h}: max |z - cxy| = {err:.3e} mm over {} vertices",
            patch.mesh.positions.len()
        );
        errors.push(err);
    }
    // Heights span ±40 mm. Measured 8.6e-2, 2.2e-2, 6.6e-3 mm: second order (each halving
    // of h divides the error by 3.4–3.9); demand clearly better than first order.
    assert!(errors[0] < 0.2, "coarse error {}", errors[0]);
    assert!(errors[1] < errors[0] / 2.5, "{errors:?}");
    assert!(errors[2] < errors[1] / 2.5, "{errors:?}");
}

/// A loop wound 300° around a cylinder projects onto itself in every plane: `auto` falls
/// back to the circle domain, `plane` refuses naming the crossing curves.
#[test]
fn wrapped_loop_uses_the_circle_domain() {
    let r = 200.0;
    let hgt = 300.0;
    let span = 300f64.to_radians();
    let cyl = move |th: f64, z: f64| [r * th.cos(), r * th.sin(), z];
    let curves = vec![
        curve("bottom", sample(40, |s| cyl(s * span, 0.0))),
        curve("end", sample(6, |s| cyl(span, s * hgt))),
        curve("top", sample(40, |s| cyl(span * (1.0 - s), hgt))),
        curve("start", sample(6, |s| cyl(0.0, hgt * (1.0 - s)))),
    ];
    let mut wire = frame(curves.clone(), 30.0);
    wire.options.domain = DomainChoice::Plane;
    let err = wireframe_surface(&wire, &wire.options).unwrap_err();
    assert!(
        matches!(err, WireframeError::SelfIntersectingProjection { .. }),
        "{err}"
    );
    wire.options.domain = DomainChoice::Auto;
    let patch = wireframe_surface(&wire, &wire.options).unwrap();
    eprintln!("wrapped: {:?}", patch.report);
    assert_eq!(patch.report.domain, DomainKind::Circle);
    assert_disk_on_curves(&patch.mesh, &curves, 1e-9 * diag(&curves));
    assert!(patch.mesh.positions.iter().flatten().all(|x| x.is_finite()));
}

/// A guide curve across the seat: its points are vertices, its vertices lie on it.
#[test]
fn guide_curve_is_followed() {
    // An even number of intervals per side: the middle of each side is a curve point, where
    // the guide starts and ends.
    let curves = seat(24);
    let mut wire = frame(curves.clone(), 20.0);
    // From the middle of the front side to the middle of the back side, bulging up 30 mm.
    let guide = sample(12, |s| {
        let y = -225.0 + 450.0 * s;
        let z = 40.0 * (-(y * y) / (225.0 * 225.0)) + 30.0 * (std::f64::consts::PI * s).sin();
        [0.0, y, z]
    });
    wire.guide.push(curve("spine", guide.clone()));
    let patch = wireframe_surface(&wire, &wire.options).unwrap();
    eprintln!("guide: {:?}", patch.report);
    let m = &patch.mesh;
    let d = diag(&curves);
    assert_disk_on_curves(m, &curves, 1e-9 * d);
    let g = [curve("spine", guide.clone())];
    for q in &guide {
        let near = m
            .positions
            .iter()
            .map(|p| flatcut_mesh::vec3::dist(*p, *q))
            .fold(f64::INFINITY, f64::min);
        assert!(near <= 1e-9 * d);
    }
    let mut on_guide = 0;
    for (v, o) in patch.origins.iter().enumerate() {
        if matches!(
            o,
            VertexOrigin::OnGuide { .. } | VertexOrigin::GuidePoint { .. }
        ) {
            on_guide += 1;
            assert!(distance_to_curves(m.positions[v], &g) <= 1e-9 * d);
        }
    }
    assert!(on_guide >= 450 / 20, "{on_guide} guide vertices");
    // The guide's top (30 mm over the saddle's centre line) is on the surface.
    let top = m
        .positions
        .iter()
        .map(|p| p[2])
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(top >= 29.0, "top {top}");
    assert!(min_angle_deg(m) >= 20.0);
}

fn err_of(wire: &WireFrame) -> WireframeError {
    wireframe_surface(wire, &wire.options).unwrap_err()
}

#[test]
fn bad_inputs_name_the_curve_or_point() {
    // Open loop: a single curve that does not come back to its start.
    let u = vec![curve(
        "u",
        vec![
            [0.0; 3],
            [100.0, 0.0, 0.0],
            [100.0, 100.0, 0.0],
            [0.0, 100.0, 0.0],
        ],
    )];
    let e = err_of(&frame(u, 10.0));
    assert!(
        matches!(&e, WireframeError::LoopNotClosed { gap_mm, first, .. } if *gap_mm == 100.0 && first == "u"),
        "{e}"
    );
    // Four sides where the left one stops 90 mm short of the back-left corner.
    let mut curves = seat(5);
    let short = curves[3].points.pop().unwrap();
    let end = curves[3].points[4];
    let gap = flatcut_mesh::vec3::dist(short, end);
    let e = err_of(&frame(curves, 20.0));
    assert!(
        matches!(&e, WireframeError::CurvesDoNotJoin { gap_mm, .. } if (*gap_mm - gap).abs() < 1e-9),
        "{e}"
    );
    // A side that misses its neighbour by 2 mm.
    let mut curves = seat(5);
    curves[2].points[0][0] += 2.0;
    let e = err_of(&frame(curves, 20.0));
    assert!(
        matches!(&e, WireframeError::CurvesDoNotJoin { gap_mm, .. } if (*gap_mm - 2.0).abs() < 1e-9),
        "{e}"
    );
    assert!(
        e.to_string().contains("back") || e.to_string().contains("right"),
        "{e}"
    );
    // Non-finite.
    let mut curves = seat(5);
    curves[1].points[3][2] = f64::NAN;
    let e = err_of(&frame(curves, 20.0));
    assert!(
        matches!(&e, WireframeError::NonFinite { name, point: 3, .. } if name == "right"),
        "{e}"
    );
    // Too few points.
    let mut curves = seat(5);
    curves[0].points.truncate(1);
    let e = err_of(&frame(curves, 20.0));
    assert!(
        matches!(&e, WireframeError::TooFewPoints { name, .. } if name == "front"),
        "{e}"
    );
    // A single closed curve with two distinct points is not a loop.
    let e = err_of(&frame(
        vec![curve("c", vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0; 3]])],
        0.1,
    ));
    assert!(matches!(e, WireframeError::TooFewPoints { .. }), "{e}");
    // Repeated point.
    let mut curves = seat(5);
    let p = curves[0].points[2];
    curves[0].points.insert(2, p);
    let e = err_of(&frame(curves, 20.0));
    assert!(
        matches!(&e, WireframeError::RepeatedPoint { name, point: 2, .. } if name == "front"),
        "{e}"
    );
    // Target edge ≤ 0, NaN, or longer than a third of the loop.
    for t in [0.0, -1.0, f64::NAN, 1000.0] {
        let e = err_of(&frame(seat(5), t));
        assert!(
            matches!(e, WireframeError::BadTargetEdge { .. }),
            "{t}: {e}"
        );
    }
    // A target edge far too small for the loop: refused before any work.
    let e = err_of(&frame(seat(5), 1e-6));
    assert!(matches!(e, WireframeError::TooManyVertices { .. }), "{e}");
    // Guides with a loop that has no plane domain.
    let r = 200.0;
    let span = 300f64.to_radians();
    let cyl = move |th: f64, z: f64| [r * th.cos(), r * th.sin(), z];
    let mut wire = frame(
        vec![
            curve("bottom", sample(40, |s| cyl(s * span, 0.0))),
            curve("end", sample(6, |s| cyl(span, s * 300.0))),
            curve("top", sample(40, |s| cyl(span * (1.0 - s), 300.0))),
            curve("start", sample(6, |s| cyl(0.0, 300.0 * (1.0 - s)))),
        ],
        30.0,
    );
    wire.guide
        .push(curve("mid", vec![cyl(1.0, 150.0), cyl(2.0, 150.0)]));
    let e = err_of(&wire);
    assert!(
        matches!(&e, WireframeError::GuidesNeedPlane { guide } if guide == "mid"),
        "{e}"
    );
    // A figure-eight in 3D: the loop crosses itself.
    let eight = vec![curve(
        "eight",
        vec![
            [0.0, 0.0, 0.0],
            [100.0, 100.0, 0.0],
            [100.0, 0.0, 0.0],
            [0.0, 100.0, 0.0],
            [0.0, 0.0, 0.0],
        ],
    )];
    let e = err_of(&frame(eight, 10.0));
    assert!(matches!(e, WireframeError::LoopTouchesItself { .. }), "{e}");
    // No curves.
    assert_eq!(err_of(&frame(Vec::new(), 10.0)), WireframeError::NoCurves);
    // A guide outside the loop.
    let mut wire = frame(seat(5), 20.0);
    wire.guide
        .push(curve("stray", vec![[0.0, 0.0, 0.0], [0.0, 400.0, 0.0]]));
    let e = err_of(&wire);
    assert!(
        matches!(&e, WireframeError::GuideOutside { guide, point: 1 } if guide == "stray"),
        "{e}"
    );
    // Two guides crossing.
    let mut wire = frame(seat(5), 20.0);
    wire.guide
        .push(curve("a", vec![[-100.0, 0.0, 0.0], [100.0, 0.0, 0.0]]));
    wire.guide
        .push(curve("b", vec![[10.0, -95.0, 0.0], [10.0, 105.0, 0.0]]));
    let e = err_of(&wire);
    assert!(matches!(e, WireframeError::GuideCrosses { .. }), "{e}");
    // Crossing exactly at a sample of both.
    let mut wire = frame(seat(5), 20.0);
    wire.guide
        .push(curve("a", vec![[-100.0, 0.0, 0.0], [100.0, 0.0, 0.0]]));
    wire.guide
        .push(curve("b", vec![[0.0, -100.0, 0.0], [0.0, 100.0, 0.0]]));
    let e = err_of(&wire);
    assert!(
        matches!(&e, WireframeError::GuideCrosses { guide } if guide == "b"),
        "{e}"
    );
}

#[test]
fn units_scale_points_only() {
    let w = frame(seat(3), 20.0);
    let s = w.scaled(10.0);
    assert_eq!(s.curve[0].points[1][0], w.curve[0].points[1][0] * 10.0);
    assert_eq!(s.target_edge_mm, 20.0);
}

/// A steep saddle (z = ±200 mm over 500 × 450 mm): projected to its plane the lift squeezes
/// triangles below 20°; re-meshing in a conformal flattening of the lifted patch restores the
/// angle while the boundary stays exact. Measured angles for amplitudes 40/100/150/200 mm:
/// lifted 26.6/19.5/14.9/11.9°, after one pass 26.6 (no pass needed)/28.4/27.9/27.5°.
#[test]
fn steep_saddle_is_reparametrised_to_good_angles() {
    let (a, b, amp) = (250.0, 225.0, 200.0);
    let p = move |x: f64, y: f64| [x, y, amp * (x * x / (a * a) - y * y / (b * b))];
    let curves = vec![
        curve("front", sample(25, |s| p(-a + 2.0 * a * s, -b))),
        curve("right", sample(25, |s| p(a, -b + 2.0 * b * s))),
        curve("back", sample(25, |s| p(a - 2.0 * a * s, b))),
        curve("left", sample(25, |s| p(-a, b - 2.0 * b * s))),
    ];
    let mut wire = frame(curves.clone(), 20.0);
    wire.options.reparam_passes = 0;
    let plain = wireframe_surface(&wire, &wire.options).unwrap();
    let plain_min = min_angle_deg(&plain.mesh);
    assert!(
        plain_min < 15.0,
        "the plain lift is poor here: {plain_min}°"
    );
    assert_eq!(plain.report.warnings.len(), 1);
    wire.options = WireframeOptions::default();
    let patch = wireframe_surface(&wire, &wire.options).unwrap();
    eprintln!("steep: {:?}", patch.report);
    let min3 = min_angle_deg(&patch.mesh);
    assert!(min3 >= 25.0, "after re-parametrisation {min3}°");
    assert!(patch.report.reparam_passes >= 1);
    assert!(patch.report.warnings.is_empty());
    assert_disk_on_curves(&patch.mesh, &curves, 1e-9 * diag(&curves));
    // Both surfaces span the same loop with harmonic interiors; they differ in the metric
    // the Laplacian uses, so their areas agree closely but not exactly.
    let (a0, a1) = (total_area(&plain.mesh), total_area(&patch.mesh));
    assert!((a0 - a1).abs() < 0.02 * a0, "areas {a0} vs {a1}");
}

/// The seat in the circle domain (forced): the first lift is poor, the conformal pass
/// repairs it; and every vertex's reported origin reproduces its position.
#[test]
fn circle_domain_seat_and_origins() {
    let curves = seat(25);
    let mut wire = frame(curves.clone(), 20.0);
    wire.options.domain = DomainChoice::Circle;
    let patch = wireframe_surface(&wire, &wire.options).unwrap();
    eprintln!("circle seat: {:?}", patch.report);
    assert_eq!(patch.report.domain, DomainKind::Circle);
    let m = &patch.mesh;
    let d = diag(&curves);
    assert_disk_on_curves(m, &curves, 1e-9 * d);
    assert!(min_angle_deg(m) >= 20.0, "{}", min_angle_deg(m));
    for (v, o) in patch.origins.iter().enumerate() {
        let want = match *o {
            VertexOrigin::CurvePoint { curve, point } => curves[curve].points[point],
            VertexOrigin::OnCurve { curve, segment, t } => {
                assert!(t > 0.0 && t < 1.0, "{o:?}");
                let (a, b) = (
                    curves[curve].points[segment],
                    curves[curve].points[segment + 1],
                );
                [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
            }
            _ => continue,
        };
        let got = m.positions[v];
        assert!(
            flatcut_mesh::vec3::dist(got, want) <= 1e-9 * d,
            "{o:?}: {got:?} vs {want:?}"
        );
    }
}
