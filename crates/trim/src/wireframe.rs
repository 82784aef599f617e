//! Surface from a wire-frame: a triangulated patch inside a closed loop of 3D boundary
//! curves (and through optional interior guide curves).
//!
//! 1. The curves are joined end to end into one closed loop ([`WireframeOptions::join_tolerance_mm`]).
//! 2. Parameter domain: the loop projected to its best-fit (PCA) plane when that projection is
//!    a simple polygon; otherwise the loop laid around a circle by arc length (always simple,
//!    convex; used only without guide curves). See docs/algorithms/wireframe_surface.md.
//! 3. The boundary is resampled at the target edge length keeping every input point; spade's
//!    constrained Delaunay refinement fills the domain (minimum angle, maximum area); vertices
//!    it inserts on constraint edges are mapped back onto the 3D segment they split.
//! 4. Lift: boundary and guide vertices sit at their 3D points; the interior solves the
//!    discrete Laplace equation (cotan weights of the domain triangulation, faer sparse
//!    Cholesky). In the plane domain only the height over the plane is solved (the in-plane
//!    coordinates are linear, so the cotan Laplacian reproduces them exactly).
//! 5. The 3D triangle quality is measured; where lifting squeezes triangles below
//!    [`WireframeOptions::min_angle_3d_deg`], the patch is flattened conformally (LSCM), the
//!    same boundary and guide samples are re-triangulated in that flattening (where 2D angles
//!    are close to 3D angles), and lifted again (all three coordinates harmonic in the new
//!    domain); a few passes, keeping the best.

mod spd;

use std::collections::{HashMap, HashSet};

use flatcut_mesh::geometry::corner_angles;
use flatcut_mesh::vec3::{add, cross, dist, dot, norm, scale, sub};
use flatcut_mesh::{TriMesh, VertexAttributes};
use serde::{Deserialize, Serialize};
use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, HasPosition, Point2, RefinementParameters,
    Triangulation,
};

/// Two input points closer than this × the loop's diagonal are "the same point" (a repeated
/// point in a curve is an error: a zero-length segment has no direction). Far above f64
/// round-off of mm coordinates, far below any drawn feature.
const REPEATED_POINT_RELATIVE: f64 = 1e-9;

/// Projected loop segments closer than this × the loop's diagonal count as touching: the
/// projection is then not a usable simple polygon (the CDT would get slivers or overlaps).
const TOUCH_RELATIVE: f64 = 1e-6;

/// The tag of a vertex spade inserted during refinement (not one of ours).
const NEW_VERTEX: u32 = u32::MAX;

/// The tag of a bounding-box vertex (keeps the convex hull away from the loop, so that the
/// refinement's circumcentres never fall outside the hull and get skipped).
const BOX_VERTEX: u32 = u32::MAX - 1;

/// Padding of the bounding box around the domain, relative to the domain's extent: enough
/// to keep hull effects off the loop, small enough that refining the outside (needed when
/// guides make spade's own inside/outside test unusable) stays cheap.
const BOX_PAD_RELATIVE: f64 = 0.25;

/// How the parameter domain is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DomainChoice {
    /// The best-fit plane when the loop projects to a simple polygon there, else the circle.
    #[default]
    Auto,
    /// The best-fit plane only: a loop whose projection crosses itself is an error.
    Plane,
    /// The loop laid around a circle by arc length (no guide curves).
    Circle,
}

/// The parameter domain that was used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DomainKind {
    /// Orthogonal projection to the loop's best-fit (PCA) plane.
    Plane,
    /// Loop laid around a circle of the loop's length by arc length.
    Circle,
}

/// Tuning of [`wireframe_surface`]; the `[options]` table of WIRE.toml.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct WireframeOptions {
    /// Curve ends closer than this join (mm). Default 0.1 mm: CAD snaps are exact, hand
    /// digitised ends are not.
    pub join_tolerance_mm: f64,
    /// Which parameter domain to use. Default `auto`.
    pub domain: DomainChoice,
    /// Minimum triangle angle the Delaunay refinement keeps in the domain (degrees). Default
    /// 28°: above the 20° asked in 3D, leaving room for the lift's distortion; spade's
    /// refinement is only guaranteed to terminate up to about 30°.
    pub domain_min_angle_deg: f64,
    /// The minimum 3D angle the patch should reach (degrees); below it the patch is re-meshed
    /// in a conformal flattening of itself.
    /// Default 20°.
    pub min_angle_3d_deg: f64,
    /// At most this many re-parametrisation passes when the 3D minimum angle is below
    /// `min_angle_3d_deg`. Default 3.
    pub reparam_passes: usize,
    /// Refuse patches needing more vertices than this (a target edge far too small for the
    /// loop). Default 2 000 000.
    pub max_vertices: usize,
}

impl Default for WireframeOptions {
    fn default() -> Self {
        Self {
            join_tolerance_mm: 0.1,
            domain: DomainChoice::Auto,
            domain_min_angle_deg: 28.0,
            min_angle_3d_deg: 20.0,
            reparam_passes: 3,
            max_vertices: 2_000_000,
        }
    }
}

/// One named 3D polyline of a wire-frame.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WireCurve {
    /// The name errors and reports use.
    pub name: String,
    /// The points, in the wire-frame's `units`.
    pub points: Vec<[f64; 3]>,
}

/// A wire-frame: WIRE.toml.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WireFrame {
    /// Units of all `points`: mm, cm, dm, m or in (default mm). The caller converts
    /// (see [`WireFrame::scaled`]); [`wireframe_surface`] takes millimetres.
    #[serde(default = "default_units")]
    pub units: String,
    /// Target triangle edge length (mm, whatever `units` says).
    pub target_edge_mm: f64,
    /// Boundary curves: one closed curve, or open curves that join end to end into one loop
    /// (in any order and direction).
    #[serde(default)]
    pub curve: Vec<WireCurve>,
    /// Interior guide curves the surface must pass through (open polylines; an end may sit on
    /// the boundary within the join tolerance).
    #[serde(default)]
    pub guide: Vec<WireCurve>,
    /// Tuning from the file's `[options]` table; every field optional. [`wireframe_surface`]
    /// takes its options as a separate argument (callers pass `&wire.options` or their own).
    #[serde(default)]
    pub options: WireframeOptions,
}

fn default_units() -> String {
    "mm".to_string()
}

impl WireFrame {
    /// The wire-frame with every curve and guide point multiplied by `factor_to_mm`
    /// (`target_edge_mm` and the options are already in mm), and `units` = "mm".
    pub fn scaled(&self, factor_to_mm: f64) -> WireFrame {
        let sc = |c: &WireCurve| WireCurve {
            name: c.name.clone(),
            points: c.points.iter().map(|p| scale(*p, factor_to_mm)).collect(),
        };
        WireFrame {
            units: "mm".to_string(),
            target_edge_mm: self.target_edge_mm,
            curve: self.curve.iter().map(sc).collect(),
            guide: self.guide.iter().map(sc).collect(),
            options: self.options.clone(),
        }
    }
}

/// Where a patch vertex comes from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum VertexOrigin {
    /// Exactly input point `point` of boundary curve `curve` (indices into `WireFrame::curve`).
    CurvePoint { curve: usize, point: usize },
    /// On boundary curve `curve`'s segment from point `segment` to `segment + 1`, at
    /// parameter `t` ∈ (0, 1) measured from point `segment`.
    OnCurve {
        curve: usize,
        segment: usize,
        t: f64,
    },
    /// Exactly input point `point` of guide `guide`.
    GuidePoint { guide: usize, point: usize },
    /// On guide `guide`'s segment `segment`→`segment + 1` at parameter `t`.
    OnGuide {
        guide: usize,
        segment: usize,
        t: f64,
    },
    /// An interior vertex placed by the refinement and the harmonic lift.
    Interior,
}

/// Measurements of a patch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WireframeReport {
    /// The first parameter domain (see `conformal_domain` for the one kept).
    pub domain: DomainKind,
    /// Triangles.
    pub faces: usize,
    /// Vertices.
    pub vertices: usize,
    /// Vertices on the boundary loop.
    pub boundary_vertices: usize,
    /// Length of the joined boundary loop (mm).
    pub loop_length_mm: f64,
    /// Largest gap closed when joining curve ends (mm).
    pub max_join_gap_mm: f64,
    /// Smallest triangle angle in the domain (degrees).
    pub min_angle_domain_deg: f64,
    /// Smallest triangle angle of the 3D patch after the first lift, before any
    /// re-parametrisation pass (degrees).
    pub min_angle_lifted_deg: f64,
    /// Smallest triangle angle of the final 3D patch (degrees).
    pub min_angle_3d_deg: f64,
    /// Re-parametrisation passes made (conformal flattening of the lifted patch, re-mesh,
    /// re-lift); the best pass is kept.
    pub reparam_passes: usize,
    /// True when the kept patch comes from a re-parametrisation pass: its domain (the mesh's
    /// texture coordinates) is then a conformal flattening, not `domain`.
    pub conformal_domain: bool,
    /// Largest distance of a boundary or guide vertex from the input segment it comes from (mm).
    pub max_boundary_deviation_mm: f64,
    /// Patch area (mm²).
    pub area_mm2: f64,
    /// Warnings (e.g. the 3D minimum angle stayed below the goal).
    pub warnings: Vec<String>,
}

/// A patch made by [`wireframe_surface`].
#[derive(Clone, Debug)]
pub struct WireframePatch {
    /// The triangulated surface (mm), faces counter-clockwise in the domain.
    pub mesh: TriMesh,
    /// Each vertex's position in the parameter domain (mm).
    pub domain: Vec<[f64; 2]>,
    /// Each vertex's origin.
    pub origins: Vec<VertexOrigin>,
    /// The boundary loop's vertices in order, following the joined curves.
    pub boundary: Vec<u32>,
    /// Measurements.
    pub report: WireframeReport,
}

/// Errors of [`wireframe_surface`]. (Kept separate from trim's main error enum for now.)
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WireframeError {
    /// No boundary curve given.
    #[error(
        "the wire-frame has no [[curve]]: give one closed curve or open curves that join into a loop"
    )]
    NoCurves,
    /// A curve (or guide) with too few points.
    #[error("{what} '{name}' has {points} points; it needs at least {needed}")]
    TooFewPoints {
        /// "curve" or "guide".
        what: &'static str,
        name: String,
        points: usize,
        needed: usize,
    },
    /// A NaN or infinite coordinate.
    #[error(
        "{what} '{name}' point {point} has a non-finite coordinate {value:?}; give finite numbers"
    )]
    NonFinite {
        what: &'static str,
        name: String,
        point: usize,
        value: [f64; 3],
    },
    /// Two consecutive points coincide.
    #[error("{what} '{name}' points {point} and {} coincide; remove the repeated point", point + 1)]
    RepeatedPoint {
        what: &'static str,
        name: String,
        point: usize,
    },
    /// target_edge_mm ≤ 0, non-finite, or too large for the loop.
    #[error(
        "target_edge_mm = {target_edge_mm} is unusable for a loop {loop_length_mm:.3} mm long: give a positive length at most a third of the loop"
    )]
    BadTargetEdge {
        target_edge_mm: f64,
        loop_length_mm: f64,
    },
    /// An options value out of range.
    #[error("option {name} = {value} is out of range: {expected}")]
    BadOption {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// A curve end has no other curve end within the join tolerance.
    #[error(
        "curve '{curve}' ends at {end:?}, {gap_mm:.6} mm from the nearest free curve end ('{nearest}'); the join tolerance is {tolerance_mm} mm: close the gap or raise options.join_tolerance_mm"
    )]
    CurvesDoNotJoin {
        curve: String,
        end: [f64; 3],
        nearest: String,
        gap_mm: f64,
        tolerance_mm: f64,
    },
    /// The joined curves do not come back to the start.
    #[error(
        "the loop does not close: curve '{last}' ends {gap_mm:.6} mm from the start of curve '{first}' (tolerance {tolerance_mm} mm); close the gap"
    )]
    LoopNotClosed {
        first: String,
        last: String,
        gap_mm: f64,
        tolerance_mm: f64,
    },
    /// The 3D loop touches or crosses itself.
    #[error(
        "the boundary loop touches itself: curve '{curve_a}' segment at point {point_a} comes within {gap_mm:.6} mm of curve '{curve_b}' segment at point {point_b}; no surface patch is bounded by it"
    )]
    LoopTouchesItself {
        curve_a: String,
        point_a: usize,
        curve_b: String,
        point_b: usize,
        gap_mm: f64,
    },
    /// The loop's projection to its best-fit plane crosses itself (and the plane was required).
    #[error(
        "the loop projected to its best-fit plane crosses itself (curve '{curve_a}' segment at point {point_a} and curve '{curve_b}' segment at point {point_b}): no plane domain; use options.domain = \"auto\" or \"circle\", or split the loop"
    )]
    SelfIntersectingProjection {
        curve_a: String,
        point_a: usize,
        curve_b: String,
        point_b: usize,
    },
    /// Guide curves need the plane domain.
    #[error(
        "guide '{guide}' needs the best-fit-plane domain, but the loop's projection is not a simple polygon (or options.domain = \"circle\"); drop the guides or split the loop"
    )]
    GuidesNeedPlane { guide: String },
    /// A guide point outside the loop.
    #[error(
        "guide '{guide}' point {point} projects outside the boundary loop; guides must lie inside"
    )]
    GuideOutside { guide: String, point: usize },
    /// A guide that crosses the boundary, itself or another guide.
    #[error(
        "guide '{guide}' crosses the boundary or another guide (or itself) in the domain; guides may only meet the boundary at their ends"
    )]
    GuideCrosses { guide: String },
    /// Two domain points coincide.
    #[error(
        "{count} points project onto the same domain point (e.g. a guide point on the boundary away from an end); move them apart"
    )]
    CoincidentDomainPoints { count: usize },
    /// Too many vertices would be needed.
    #[error(
        "the patch would need about {needed} vertices (more than options.max_vertices = {max}); raise target_edge_mm"
    )]
    TooManyVertices { needed: usize, max: usize },
    /// The Delaunay refinement ran out of its vertex budget.
    #[error(
        "Delaunay refinement stopped at its budget of {budget} vertices without reaching the angle limit; lower options.domain_min_angle_deg or raise target_edge_mm"
    )]
    RefinementIncomplete { budget: usize },
    /// The triangulation failed (coordinates out of spade's range).
    #[error("the domain triangulation failed: {0}; check the coordinates' magnitude")]
    Triangulation(String),
    /// The Laplace solve failed (should not happen for a valid triangulation).
    #[error(
        "the harmonic lift's linear solve failed ({0}); this is a bug, please report the wire-frame"
    )]
    Solve(&'static str),
}

/// A segment of the joined loop, as a segment of an input curve.
#[derive(Clone, Copy, Debug)]
struct LoopSeg {
    /// Start point (3D, mm).
    p0: [f64; 3],
    /// End point.
    p1: [f64; 3],
    /// The input curve.
    curve: usize,
    /// The curve's point index at `p0` and at `p1`.
    i0: usize,
    i1: usize,
}

/// A vertex of the domain triangulation that we placed (boundary or guide sample).
#[derive(Clone, Copy, Debug)]
struct Node {
    p3: [f64; 3],
    p2: [f64; 2],
    origin: VertexOrigin,
}

/// The spade vertex: domain position and our tag.
#[derive(Clone, Copy, Debug)]
struct DomVertex {
    p: Point2<f64>,
    tag: u32,
}

impl HasPosition for DomVertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.p
    }
}

impl From<Point2<f64>> for DomVertex {
    fn from(p: Point2<f64>) -> Self {
        Self { p, tag: NEW_VERTEX }
    }
}

/// Makes a triangulated patch spanning a wire-frame whose points are in millimetres (use
/// [`WireFrame::scaled`] first if `wire.units` is not mm).
///
/// # Errors
/// [`WireframeError`] naming the curve, guide or point at fault.
pub fn wireframe_surface(
    wire: &WireFrame,
    opts: &WireframeOptions,
) -> Result<WireframePatch, WireframeError> {
    check_options(opts)?;
    if wire.curve.is_empty() {
        return Err(WireframeError::NoCurves);
    }
    for c in &wire.curve {
        check_polyline("curve", c, 2)?;
    }
    for g in &wire.guide {
        check_polyline("guide", g, 2)?;
    }
    let (segs, max_join_gap_mm) = join_loop(&wire.curve, opts.join_tolerance_mm)?;
    let loop_length_mm: f64 = segs.iter().map(|s| dist(s.p0, s.p1)).sum();
    let h = wire.target_edge_mm;
    if !(h.is_finite() && h > 0.0 && 3.0 * h <= loop_length_mm) {
        return Err(WireframeError::BadTargetEdge {
            target_edge_mm: h,
            loop_length_mm,
        });
    }
    // Samples the boundary and guides will need, checked before anything is allocated (a
    // tiny target edge or astronomically large coordinates must not hang or exhaust memory).
    let guide_length: f64 = wire
        .guide
        .iter()
        .flat_map(|g| g.points.windows(2).map(|w| dist(w[0], w[1])))
        .sum();
    let samples = (loop_length_mm + guide_length) / h + (segs.len() + wire.guide.len()) as f64;
    if !(samples.is_finite() && samples <= opts.max_vertices as f64) {
        return Err(WireframeError::TooManyVertices {
            needed: if samples.is_finite() {
                samples as usize
            } else {
                usize::MAX
            },
            max: opts.max_vertices,
        });
    }
    let diag = diagonal(segs.iter().map(|s| s.p0));
    check_loop_in_3d(&segs, &wire.curve, diag, opts.join_tolerance_mm)?;

    // Domain.
    let frame = Frame::pca(&segs);
    let projected: Vec<[f64; 2]> = segs.iter().map(|s| frame.project(s.p0)).collect();
    let crossing = first_crossing(&projected, TOUCH_RELATIVE * diag);
    let kind = match (opts.domain, crossing) {
        (DomainChoice::Circle, _) => DomainKind::Circle,
        (DomainChoice::Auto | DomainChoice::Plane, None) => DomainKind::Plane,
        (DomainChoice::Auto, Some(_)) => DomainKind::Circle,
        (DomainChoice::Plane, Some((a, b))) => {
            return Err(WireframeError::SelfIntersectingProjection {
                curve_a: wire.curve[segs[a].curve].name.clone(),
                point_a: segs[a].i0,
                curve_b: wire.curve[segs[b].curve].name.clone(),
                point_b: segs[b].i0,
            });
        }
    };
    if kind == DomainKind::Circle {
        if let Some(g) = wire.guide.first() {
            return Err(WireframeError::GuidesNeedPlane {
                guide: g.name.clone(),
            });
        }
    }
    // Orient the plane domain counter-clockwise (faces then face along the frame normal).
    let frame = if kind == DomainKind::Plane && signed_area(&projected) < 0.0 {
        frame.flipped()
    } else {
        frame
    };

    // Guide ends on the boundary (within the join tolerance of a segment's interior) become
    // boundary samples, so the guide meets the boundary at a vertex.
    let mut breaks: Vec<Vec<f64>> = vec![Vec::new(); segs.len()];
    for g in &wire.guide {
        for end in [g.points[0], g.points[g.points.len() - 1]] {
            if let Some((si, t)) = nearest_on_loop(&segs, end, opts.join_tolerance_mm) {
                if t > 0.0 && t < 1.0 {
                    breaks[si].push(t);
                }
            }
        }
    }
    // Boundary samples: every input point, plus points on each segment at ≤ h spacing.
    let mut nodes: Vec<Node> = Vec::new();
    let mut edge_info: Vec<EdgeOnInput> = Vec::new();
    let mut s_acc = 0.0;
    let radius = loop_length_mm / std::f64::consts::TAU;
    for (si, s) in segs.iter().enumerate() {
        let len = dist(s.p0, s.p1);
        let mut cuts = vec![0.0];
        cuts.extend(breaks[si].iter().copied());
        cuts.push(1.0);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        // Parameters of the samples on this segment: every piece at ≤ h spacing.
        let mut ts = Vec::new();
        for w in cuts.windows(2) {
            let k = (((w[1] - w[0]) * len / h).ceil() as usize).max(1);
            ts.extend((0..k).map(|j| w[0] + (w[1] - w[0]) * j as f64 / k as f64));
        }
        ts.push(1.0);
        for j in 0..ts.len() - 1 {
            let t = ts[j];
            let p3 = if j == 0 { s.p0 } else { lerp3(s.p0, s.p1, t) };
            let origin = if j == 0 {
                VertexOrigin::CurvePoint {
                    curve: s.curve,
                    point: s.i0,
                }
            } else {
                on_curve(s, t)
            };
            let p2 = match kind {
                DomainKind::Plane => frame.project(p3),
                DomainKind::Circle => {
                    let a = (s_acc + t * len) / radius;
                    [radius * a.cos(), radius * a.sin()]
                }
            };
            nodes.push(Node { p3, p2, origin });
            // The constraint edge from this sample to the next lies on this segment.
            let local = |t: f64| if s.i1 > s.i0 { t } else { 1.0 - t };
            edge_info.push(EdgeOnInput {
                curve: true,
                index: s.curve,
                segment: s.i0.min(s.i1),
                t: [local(t), local(ts[j + 1])],
            });
        }
        s_acc += len;
    }
    let n_boundary = nodes.len();
    let mut edges: Vec<[usize; 2]> = (0..n_boundary).map(|i| [i, (i + 1) % n_boundary]).collect();
    let boundary_poly: Vec<[f64; 2]> = nodes.iter().map(|n| n.p2).collect();
    for (gi, g) in wire.guide.iter().enumerate() {
        add_guide(
            gi,
            g,
            &frame,
            h,
            opts.join_tolerance_mm,
            &boundary_poly,
            &mut nodes,
            &mut edges,
            &mut edge_info,
        )?;
    }

    // Estimated size: boundary samples + interior at the equilateral density of h.
    let domain_area = signed_area(&boundary_poly).abs();
    let tri_area = 3f64.sqrt() / 4.0 * h * h;
    let estimate = nodes.len() + (domain_area / tri_area).ceil() as usize;
    if estimate > opts.max_vertices {
        return Err(WireframeError::TooManyVertices {
            needed: estimate,
            max: opts.max_vertices,
        });
    }

    let meshed = triangulate(
        &nodes,
        n_boundary,
        &edges,
        &edge_info,
        tri_area,
        opts.domain_min_angle_deg,
        opts.max_vertices,
        &wire.guide,
    )?;
    let first_lift = match kind {
        DomainKind::Plane => Lift::Height(frame),
        DomainKind::Circle => Lift::Xyz,
    };
    let positions = lift(&meshed.domain, &meshed.faces, &meshed.fixed3, first_lift)?;
    let min_angle_lifted_deg = min_angle_deg(&positions, &meshed.faces);
    let mut best = (meshed.clone(), positions, min_angle_lifted_deg);
    let mut conformal_domain = false;
    let mut current = best.clone();
    let mut reparam_passes = 0;
    // Where the lift squeezed triangles, re-mesh in a conformal flattening of the lifted
    // surface (angles there ≈ angles on the surface) and lift again; keep the best pass.
    while best.2 < opts.min_angle_3d_deg && reparam_passes < opts.reparam_passes {
        let Some(next) = reparametrise(
            &current.0,
            &current.1,
            &nodes,
            n_boundary,
            &edges,
            &edge_info,
            tri_area,
            opts,
            &wire.guide,
        ) else {
            break;
        };
        reparam_passes += 1;
        current = next;
        if current.2 > best.2 {
            best = current.clone();
            conformal_domain = true;
        }
    }
    let (meshed, positions, min3) = best;
    let Meshed {
        faces,
        domain,
        origins,
        ..
    } = meshed;
    let min_angle_domain_deg = min_angle_deg(
        &domain.iter().map(|p| [p[0], p[1], 0.0]).collect::<Vec<_>>(),
        &faces,
    );
    let mut warnings = Vec::new();
    if min3 < opts.min_angle_3d_deg {
        warnings.push(format!(
            "the smallest 3D triangle angle is {min3:.2}° (goal {}°): the surface bends too much for its domain; lower target_edge_mm or split the loop",
            opts.min_angle_3d_deg
        ));
    }

    let mesh = TriMesh {
        positions,
        faces,
        attributes: VertexAttributes {
            texcoords: Some(domain.clone()),
            ..Default::default()
        },
        face_labels: None,
    };
    let boundary = boundary_order(&mesh, &origins);
    let max_boundary_deviation_mm = origins
        .iter()
        .zip(&mesh.positions)
        .filter_map(|(o, p)| deviation(*o, *p, &wire.curve, &wire.guide))
        .fold(0.0, f64::max);
    let area_mm2 = flatcut_mesh::geometry::total_area(&mesh);
    let report = WireframeReport {
        domain: kind,
        faces: mesh.faces.len(),
        vertices: mesh.positions.len(),
        boundary_vertices: boundary.len(),
        loop_length_mm,
        max_join_gap_mm,
        min_angle_domain_deg,
        min_angle_lifted_deg,
        min_angle_3d_deg: min3,
        reparam_passes,
        conformal_domain,
        max_boundary_deviation_mm,
        area_mm2,
        warnings,
    };
    Ok(WireframePatch {
        mesh,
        domain,
        origins,
        boundary,
        report,
    })
}

fn check_options(o: &WireframeOptions) -> Result<(), WireframeError> {
    let bad = |name, value, expected| {
        Err(WireframeError::BadOption {
            name,
            value,
            expected,
        })
    };
    if !(o.join_tolerance_mm.is_finite() && o.join_tolerance_mm >= 0.0) {
        return bad(
            "join_tolerance_mm",
            o.join_tolerance_mm,
            "a length ≥ 0 (mm)",
        );
    }
    if !(o.domain_min_angle_deg.is_finite()
        && o.domain_min_angle_deg > 0.0
        && o.domain_min_angle_deg <= 33.0)
    {
        return bad(
            "domain_min_angle_deg",
            o.domain_min_angle_deg,
            "an angle in (0, 33] degrees (Delaunay refinement may not terminate above ~30°)",
        );
    }
    if !(o.min_angle_3d_deg.is_finite() && (0.0..60.0).contains(&o.min_angle_3d_deg)) {
        return bad(
            "min_angle_3d_deg",
            o.min_angle_3d_deg,
            "an angle in [0, 60) degrees",
        );
    }
    Ok(())
}

fn check_polyline(what: &'static str, c: &WireCurve, needed: usize) -> Result<(), WireframeError> {
    if c.points.len() < needed {
        return Err(WireframeError::TooFewPoints {
            what,
            name: c.name.clone(),
            points: c.points.len(),
            needed,
        });
    }
    if let Some(i) = c
        .points
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        return Err(WireframeError::NonFinite {
            what,
            name: c.name.clone(),
            point: i,
            value: c.points[i],
        });
    }
    let d = diagonal(c.points.iter().copied());
    for i in 0..c.points.len() - 1 {
        if dist(c.points[i], c.points[i + 1]) <= REPEATED_POINT_RELATIVE * d.max(1.0) {
            return Err(WireframeError::RepeatedPoint {
                what,
                name: c.name.clone(),
                point: i,
            });
        }
    }
    Ok(())
}

/// Joins the curves end to end into one closed loop of segments; returns the largest gap
/// closed. A curve is used forwards or reversed, whichever end is nearest the loop's end.
fn join_loop(curves: &[WireCurve], tol: f64) -> Result<(Vec<LoopSeg>, f64), WireframeError> {
    let segs_of = |ci: usize, reversed: bool| -> Vec<LoopSeg> {
        let p = &curves[ci].points;
        let n = p.len();
        (0..n - 1)
            .map(|k| {
                let (i0, i1) = if reversed {
                    (n - 1 - k, n - 2 - k)
                } else {
                    (k, k + 1)
                };
                LoopSeg {
                    p0: p[i0],
                    p1: p[i1],
                    curve: ci,
                    i0,
                    i1,
                }
            })
            .collect()
    };
    let mut segs = segs_of(0, false);
    let mut used = vec![false; curves.len()];
    used[0] = true;
    let mut max_gap: f64 = 0.0;
    let first = curves[0].points[0];
    for _ in 1..curves.len() {
        let end = segs.last().map_or(first, |s| s.p1);
        let last_curve = segs.last().map_or(0, |s| s.curve);
        // Nearest free end.
        let mut best: Option<(f64, usize, bool)> = None;
        for (ci, c) in curves.iter().enumerate() {
            if used[ci] {
                continue;
            }
            for (rev, p) in [(false, c.points[0]), (true, c.points[c.points.len() - 1])] {
                let d = dist(end, p);
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, ci, rev));
                }
            }
        }
        let Some((gap, ci, rev)) = best else { break };
        if gap > tol {
            return Err(WireframeError::CurvesDoNotJoin {
                curve: curves[last_curve].name.clone(),
                end,
                nearest: curves[ci].name.clone(),
                gap_mm: gap,
                tolerance_mm: tol,
            });
        }
        max_gap = max_gap.max(gap);
        used[ci] = true;
        let mut more = segs_of(ci, rev);
        // The junction point is the earlier curve's end (the gap ≤ tol is closed here).
        more[0].p0 = end;
        segs.extend(more);
    }
    let (last, end) = segs.last().map(|s| (s.curve, s.p1)).unwrap_or((0, first));
    let gap = dist(end, first);
    if gap > tol {
        return Err(WireframeError::LoopNotClosed {
            first: curves[0].name.clone(),
            last: curves[last].name.clone(),
            gap_mm: gap,
            tolerance_mm: tol,
        });
    }
    max_gap = max_gap.max(gap);
    // The closing point is the start point: drop the duplicate by ending the last segment there.
    if let Some(s) = segs.last_mut() {
        s.p1 = first;
    }
    if segs.len() < 3 {
        return Err(WireframeError::TooFewPoints {
            what: "curve",
            name: curves[0].name.clone(),
            points: segs.len(),
            needed: 3,
        });
    }
    // A zero-length closing segment (a closed curve that repeats its first point within the
    // tolerance, but after the join the point is the same): drop it.
    if dist(segs[segs.len() - 1].p0, segs[segs.len() - 1].p1) == 0.0 {
        segs.pop();
    }
    Ok((segs, max_gap))
}

/// Errors if two non-adjacent loop segments come closer than the join tolerance in 3D.
fn check_loop_in_3d(
    segs: &[LoopSeg],
    curves: &[WireCurve],
    diag: f64,
    tol: f64,
) -> Result<(), WireframeError> {
    let n = segs.len();
    let limit = tol.max(TOUCH_RELATIVE * diag);
    let boxes: Vec<([f64; 3], [f64; 3])> = segs
        .iter()
        .map(|s| {
            let lo = [0, 1, 2].map(|k| s.p0[k].min(s.p1[k]) - limit);
            let hi = [0, 1, 2].map(|k| s.p0[k].max(s.p1[k]) + limit);
            (lo, hi)
        })
        .collect();
    for a in 0..n {
        for b in a + 2..n {
            if a == 0 && b == n - 1 {
                continue;
            }
            let (la, ha) = boxes[a];
            let (lb, hb) = boxes[b];
            if (0..3).any(|k| la[k] > hb[k] || lb[k] > ha[k]) {
                continue;
            }
            let d = segment_distance(segs[a].p0, segs[a].p1, segs[b].p0, segs[b].p1);
            if d < limit {
                return Err(WireframeError::LoopTouchesItself {
                    curve_a: curves[segs[a].curve].name.clone(),
                    point_a: segs[a].i0,
                    curve_b: curves[segs[b].curve].name.clone(),
                    point_b: segs[b].i0,
                    gap_mm: d,
                });
            }
        }
    }
    Ok(())
}

/// Distance between two 3D segments (clamped closest points, Ericson §5.1.9).
fn segment_distance(p1: [f64; 3], q1: [f64; 3], p2: [f64; 3], q2: [f64; 3]) -> f64 {
    let d1 = sub(q1, p1);
    let d2 = sub(q2, p2);
    let r = sub(p1, p2);
    let a = dot(d1, d1);
    let e = dot(d2, d2);
    let f = dot(d2, r);
    let c = dot(d1, r);
    let b = dot(d1, d2);
    let denom = a * e - b * b;
    let mut s = if denom > 0.0 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    dist(add(p1, scale(d1, s)), add(p2, scale(d2, t)))
}

/// The loop segment nearest to `p` and the parameter of the closest point on it, if
/// within `tol`.
fn nearest_on_loop(segs: &[LoopSeg], p: [f64; 3], tol: f64) -> Option<(usize, f64)> {
    let mut best: Option<(f64, usize, f64)> = None;
    for (i, s) in segs.iter().enumerate() {
        let ab = sub(s.p1, s.p0);
        let t = (dot(sub(p, s.p0), ab) / dot(ab, ab)).clamp(0.0, 1.0);
        let d = dist(p, add(s.p0, scale(ab, t)));
        if d <= tol && best.is_none_or(|b| d < b.0) {
            best = Some((d, i, t));
        }
    }
    best.map(|(_, i, t)| (i, t))
}

/// An orthonormal frame: origin, two in-plane axes and the normal.
#[derive(Clone, Copy, Debug)]
struct Frame {
    c: [f64; 3],
    e1: [f64; 3],
    e2: [f64; 3],
    n: [f64; 3],
}

impl Frame {
    /// The best-fit plane of the loop: principal axes of the segment-length-weighted
    /// covariance of the loop (so the result does not depend on how densely a side is sampled).
    fn pca(segs: &[LoopSeg]) -> Frame {
        let mut w_sum = 0.0;
        let mut c = [0.0; 3];
        for s in segs {
            let w = dist(s.p0, s.p1);
            c = add(c, scale(add(s.p0, s.p1), 0.5 * w));
            w_sum += w;
        }
        let c = scale(c, 1.0 / w_sum);
        let mut m = [[0.0; 3]; 3];
        for s in segs {
            // Exact second moment of a uniform segment: (a a' + b b' + (a b' + b a')/2)/3 · len.
            let w = dist(s.p0, s.p1);
            let a = sub(s.p0, c);
            let b = sub(s.p1, c);
            for i in 0..3 {
                for j in 0..3 {
                    m[i][j] +=
                        w * (a[i] * a[j] + b[i] * b[j] + 0.5 * (a[i] * b[j] + b[i] * a[j])) / 3.0;
                }
            }
        }
        let (vals, vecs) = jacobi_eigen(m);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| vals[j].total_cmp(&vals[i]));
        let col = |k: usize| [vecs[0][k], vecs[1][k], vecs[2][k]];
        let e1 = col(order[0]);
        let n = normalize(cross(e1, col(order[1])));
        let e2 = cross(n, e1);
        Frame { c, e1, e2, n }
    }

    fn flipped(self) -> Frame {
        Frame {
            c: self.c,
            e1: self.e2,
            e2: self.e1,
            n: scale(self.n, -1.0),
        }
    }

    fn project(&self, p: [f64; 3]) -> [f64; 2] {
        let d = sub(p, self.c);
        [dot(d, self.e1), dot(d, self.e2)]
    }

    fn height(&self, p: [f64; 3]) -> f64 {
        dot(sub(p, self.c), self.n)
    }

    fn point(&self, q: [f64; 2], h: f64) -> [f64; 3] {
        add(
            self.c,
            add(
                add(scale(self.e1, q[0]), scale(self.e2, q[1])),
                scale(self.n, h),
            ),
        )
    }
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = norm(a);
    if l > 0.0 { scale(a, 1.0 / l) } else { a }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: eigenvalues and
/// the eigenvectors as columns.
#[allow(clippy::needless_range_loop)] // index arithmetic mirrors the textbook rotation
fn jacobi_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let scale_ = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * scale_ || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with J the rotation in the (p, q) plane.
            for k in 0..3 {
                let akp = a[k][p];
                let akq = a[k][q];
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let apk = a[p][k];
                let aqk = a[q][k];
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let vp = row[p];
                let vq = row[q];
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

fn signed_area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    0.5 * (0..n)
        .map(|i| {
            let a = p[i];
            let b = p[(i + 1) % n];
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
}

fn bbox2(p: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for q in p {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}

fn diagonal(points: impl Iterator<Item = [f64; 3]>) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let d = dist(lo, hi);
    if d.is_finite() { d } else { 0.0 }
}

fn lerp3(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

fn cross2(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Distance between two 2D segments (0 if they cross).
fn segment_distance_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> f64 {
    let d1 = cross2(a, b, c);
    let d2 = cross2(a, b, d);
    let d3 = cross2(c, d, a);
    let d4 = cross2(c, d, b);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return 0.0;
    }
    let pt = |p: [f64; 2], s0: [f64; 2], s1: [f64; 2]| {
        let v = [s1[0] - s0[0], s1[1] - s0[1]];
        let l2 = v[0] * v[0] + v[1] * v[1];
        let t = if l2 > 0.0 {
            (((p[0] - s0[0]) * v[0] + (p[1] - s0[1]) * v[1]) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        dist2(p, [s0[0] + t * v[0], s0[1] + t * v[1]])
    };
    pt(a, c, d)
        .min(pt(b, c, d))
        .min(pt(c, a, b))
        .min(pt(d, a, b))
}

/// The first pair of non-adjacent segments of the closed polygon closer than `tol`, if any
/// (also catches a projection that folds back onto an adjacent segment).
fn first_crossing(p: &[[f64; 2]], tol: f64) -> Option<(usize, usize)> {
    let n = p.len();
    let seg = |i: usize| (p[i], p[(i + 1) % n]);
    // Adjacent segments folding back onto each other (an angle of ~0 between them).
    for i in 0..n {
        let (a, b) = seg(i);
        let c = p[(i + 2) % n];
        let u = [b[0] - a[0], b[1] - a[1]];
        let w = [c[0] - b[0], c[1] - b[1]];
        let lu = (u[0] * u[0] + u[1] * u[1]).sqrt();
        let lw = (w[0] * w[0] + w[1] * w[1]).sqrt();
        if lu <= tol || lw <= tol {
            return Some((i, (i + 1) % n));
        }
        let sin = (u[0] * w[1] - u[1] * w[0]) / (lu * lw);
        let cos = (u[0] * w[0] + u[1] * w[1]) / (lu * lw);
        if cos < 0.0 && sin.abs() < 1e-9 {
            return Some((i, (i + 1) % n));
        }
    }
    let boxes: Vec<([f64; 2], [f64; 2])> = (0..n)
        .map(|i| {
            let (a, b) = seg(i);
            (
                [a[0].min(b[0]) - tol, a[1].min(b[1]) - tol],
                [a[0].max(b[0]) + tol, a[1].max(b[1]) + tol],
            )
        })
        .collect();
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (la, ha) = boxes[i];
            let (lb, hb) = boxes[j];
            if la[0] > hb[0] || lb[0] > ha[0] || la[1] > hb[1] || lb[1] > ha[1] {
                continue;
            }
            let (a, b) = seg(i);
            let (c, d) = seg(j);
            if segment_distance_2d(a, b, c, d) <= tol {
                return Some((i, j));
            }
        }
    }
    None
}

fn point_in_polygon(q: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > q[1]) != (b[1] > q[1]) {
            let x = a[0] + (q[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if q[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

fn on_curve(s: &LoopSeg, t: f64) -> VertexOrigin {
    // Report the parameter from the curve's own lower-numbered point.
    if s.i1 > s.i0 {
        VertexOrigin::OnCurve {
            curve: s.curve,
            segment: s.i0,
            t,
        }
    } else {
        VertexOrigin::OnCurve {
            curve: s.curve,
            segment: s.i1,
            t: 1.0 - t,
        }
    }
}

/// Adds a guide's samples and constraint edges (plane domain).
#[allow(clippy::too_many_arguments)]
fn add_guide(
    gi: usize,
    g: &WireCurve,
    frame: &Frame,
    h: f64,
    tol: f64,
    boundary: &[[f64; 2]],
    nodes: &mut Vec<Node>,
    edges: &mut Vec<[usize; 2]>,
    edge_info: &mut Vec<EdgeOnInput>,
) -> Result<(), WireframeError> {
    let n_boundary = boundary.len();
    let pts = &g.points;
    let last = pts.len() - 1;
    // An end within the join tolerance of a boundary sample is that sample.
    let snap = |p: [f64; 3], nodes: &[Node]| -> Option<usize> {
        (0..n_boundary)
            .map(|i| (dist(nodes[i].p3, p), i))
            .filter(|&(d, _)| d <= tol)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, i)| i)
    };
    let mut prev: Option<usize> = None;
    for (i, &p) in pts.iter().enumerate() {
        let snapped = if i == 0 || i == last {
            snap(p, nodes)
        } else {
            None
        };
        let this = match snapped {
            Some(b) => b,
            None => {
                let p2 = frame.project(p);
                if !point_in_polygon(p2, boundary) {
                    return Err(WireframeError::GuideOutside {
                        guide: g.name.clone(),
                        point: i,
                    });
                }
                nodes.push(Node {
                    p3: p,
                    p2,
                    origin: VertexOrigin::GuidePoint {
                        guide: gi,
                        point: i,
                    },
                });
                nodes.len() - 1
            }
        };
        if let Some(a) = prev {
            // Samples on the guide segment (a → this) at ≤ h spacing.
            let (pa, pb) = (nodes[a].p3, nodes[this].p3);
            let k = ((dist(pa, pb) / h).ceil() as usize).max(1);
            let mut from = a;
            let info = |t0: f64, t1: f64| EdgeOnInput {
                curve: false,
                index: gi,
                segment: i - 1,
                t: [t0, t1],
            };
            for j in 1..k {
                let t = j as f64 / k as f64;
                let p3 = lerp3(pa, pb, t);
                nodes.push(Node {
                    p3,
                    p2: frame.project(p3),
                    origin: VertexOrigin::OnGuide {
                        guide: gi,
                        segment: i - 1,
                        t,
                    },
                });
                let id = nodes.len() - 1;
                edges.push([from, id]);
                edge_info.push(info((j - 1) as f64 / k as f64, t));
                from = id;
            }
            edges.push([from, this]);
            edge_info.push(info((k - 1) as f64 / k as f64, 1.0));
        }
        prev = Some(this);
    }
    Ok(())
}

/// For a vertex spade inserted on a constraint edge: the two of our nodes at the ends of
/// the original constraint edge it lies on (walking along constraint edges through other
/// inserted vertices). `None` for an interior vertex.
fn split_of(
    cdt: &ConstrainedDelaunayTriangulation<DomVertex>,
    v: FixedVertexHandle,
) -> Option<(usize, usize)> {
    let constraint_nbrs: Vec<FixedVertexHandle> = cdt
        .vertex(v)
        .out_edges()
        .filter(|e| e.is_constraint_edge())
        .map(|e| e.to().fix())
        .collect();
    if constraint_nbrs.len() != 2 {
        return None;
    }
    let walk = |mut prev: FixedVertexHandle, mut cur: FixedVertexHandle| -> Option<usize> {
        // A chain never revisits a vertex; the bound only guards against a malformed one.
        for _ in 0..cdt.num_vertices() {
            let tag = cdt.vertex(cur).data().tag;
            if tag != NEW_VERTEX {
                return (tag < BOX_VERTEX).then_some(tag as usize);
            }
            let next = cdt
                .vertex(cur)
                .out_edges()
                .filter(|e| e.is_constraint_edge())
                .map(|e| e.to().fix())
                .find(|&w| w != prev)?;
            prev = cur;
            cur = next;
        }
        None
    };
    let a = walk(v, constraint_nbrs[0])?;
    let b = walk(v, constraint_nbrs[1])?;
    Some((a, b))
}

/// The input segment a constraint edge lies on, and its ends' parameters there.
#[derive(Clone, Copy, Debug)]
struct EdgeOnInput {
    /// true: boundary curve, false: guide.
    curve: bool,
    /// Curve or guide index.
    index: usize,
    /// The segment (from its point `segment` to `segment + 1`).
    segment: usize,
    /// Parameters of the edge's two end nodes on that segment (in the order of `edges`).
    t: [f64; 2],
}

impl EdgeOnInput {
    fn origin(&self, t: f64) -> VertexOrigin {
        if self.curve {
            VertexOrigin::OnCurve {
                curve: self.index,
                segment: self.segment,
                t,
            }
        } else {
            VertexOrigin::OnGuide {
                guide: self.index,
                segment: self.segment,
                t,
            }
        }
    }
}

/// A triangulated domain with every vertex's origin and fixed 3D point (boundary and guide
/// vertices) or `None` (interior).
#[derive(Clone, Debug)]
struct Meshed {
    faces: Vec<[u32; 3]>,
    domain: Vec<[f64; 2]>,
    origins: Vec<VertexOrigin>,
    fixed3: Vec<Option<[f64; 3]>>,
    /// The node each vertex is (None: inserted by the refinement).
    node_of: Vec<Option<usize>>,
}

/// Constrained Delaunay triangulation with refinement of the domain spanned by `nodes`
/// (the first `n_boundary` are the boundary loop, counter-clockwise) and the constraint
/// `edges`; keeps the faces inside the loop and places vertices inserted on constraint edges
/// on the 3D segment between the edge's nodes.
#[allow(clippy::too_many_arguments)]
fn triangulate(
    nodes: &[Node],
    n_boundary: usize,
    edges: &[[usize; 2]],
    edge_info: &[EdgeOnInput],
    tri_area: f64,
    min_angle_deg: f64,
    max_vertices: usize,
    guides: &[WireCurve],
) -> Result<Meshed, WireframeError> {
    let boundary_poly: Vec<[f64; 2]> = nodes[..n_boundary].iter().map(|n| n.p2).collect();
    // Constrained Delaunay triangulation inside a padding box.
    let mut verts: Vec<DomVertex> = nodes
        .iter()
        .enumerate()
        .map(|(i, n)| DomVertex {
            p: Point2::new(n.p2[0], n.p2[1]),
            tag: i as u32,
        })
        .collect();
    let (lo, hi) = bbox2(&boundary_poly);
    let pad = BOX_PAD_RELATIVE * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    for (x, y) in [
        (lo[0] - pad, lo[1] - pad),
        (hi[0] + pad, lo[1] - pad),
        (hi[0] + pad, hi[1] + pad),
        (lo[0] - pad, hi[1] + pad),
    ] {
        verts.push(DomVertex {
            p: Point2::new(x, y),
            tag: BOX_VERTEX,
        });
    }
    let n_in = verts.len();
    let mut conflicts = Vec::new();
    let mut cdt: ConstrainedDelaunayTriangulation<DomVertex> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(verts, edges.to_vec(), |e| {
            conflicts.push(e)
        })
        .map_err(|e| WireframeError::Triangulation(format!("{e:?}")))?;
    if cdt.num_vertices() != n_in {
        // A guide sample on top of another sample: the guides cross (or touch the boundary).
        let have: HashSet<u32> = cdt.vertices().map(|v| v.data().tag).collect();
        let lost = (0..nodes.len()).find(|&i| !have.contains(&(i as u32)));
        if let Some(VertexOrigin::GuidePoint { guide, .. } | VertexOrigin::OnGuide { guide, .. }) =
            lost.map(|i| nodes[i].origin)
        {
            return Err(WireframeError::GuideCrosses {
                guide: guides[guide].name.clone(),
            });
        }
        return Err(WireframeError::CoincidentDomainPoints {
            count: n_in - cdt.num_vertices(),
        });
    }
    if let Some(e) = conflicts.first() {
        // One of the two conflicting edges; boundary edges cannot conflict with each other
        // (the loop is simple), so a guide is involved: name this one's, or the first guide.
        let guide = edges
            .iter()
            .position(|x| x == e || *x == [e[1], e[0]])
            .filter(|&i| !edge_info[i].curve)
            .map_or(0, |i| edge_info[i].index);
        return Err(WireframeError::GuideCrosses {
            guide: guides
                .get(guide)
                .map_or_else(String::new, |g| g.name.clone()),
        });
    }
    let edge_lookup: HashMap<(usize, usize), usize> = edges
        .iter()
        .enumerate()
        .map(|(i, e)| ((e[0], e[1]), i))
        .collect();
    // spade tells inside from outside by the parity of constraint crossings, which guides
    // reaching the boundary break (a region beyond a guide counts as outside). With guides the
    // whole box is refined and the inside is found below from the boundary polygon alone.
    let exclude_outside = guides.is_empty();
    let box_area = (hi[0] - lo[0] + 2.0 * pad) * (hi[1] - lo[1] + 2.0 * pad);
    let refined_area = if exclude_outside {
        signed_area(&boundary_poly).abs()
    } else {
        box_area
    };
    let budget =
        (4 * (nodes.len() + (refined_area / tri_area).ceil() as usize) + 1000).min(max_vertices);
    let result = cdt.refine(
        RefinementParameters::<f64>::new()
            .exclude_outer_faces(exclude_outside)
            .with_angle_limit(AngleLimit::from_deg(min_angle_deg))
            .with_max_allowed_area(tri_area)
            .with_max_additional_vertices(budget),
    );
    if !result.refinement_complete {
        return Err(WireframeError::RefinementIncomplete { budget });
    }
    let excluded: HashSet<_> = result.excluded_faces.iter().copied().collect();
    // A face is inside when its centroid is inside the boundary polygon (faces never straddle
    // a constraint edge, so the centroid decides for the whole face).
    let inside = |f: &spade::handles::FaceHandle<
        '_,
        spade::handles::InnerTag,
        DomVertex,
        (),
        spade::CdtEdge<()>,
        (),
    >| {
        let [a, b, c] = f.positions();
        point_in_polygon(
            [(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0],
            &boundary_poly,
        )
    };

    // Extract the inside faces, number their vertices, and place every vertex in 3D.
    let mut index: HashMap<FixedVertexHandle, u32> = HashMap::new();
    let mut handles: Vec<FixedVertexHandle> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    for f in cdt.inner_faces() {
        if excluded.contains(&f.fix()) || !inside(&f) {
            continue;
        }
        let vs = f.vertices();
        let mut tri = [0u32; 3];
        for (k, v) in vs.iter().enumerate() {
            let next = handles.len() as u32;
            tri[k] = *index.entry(v.fix()).or_insert_with(|| {
                handles.push(v.fix());
                next
            });
        }
        faces.push(tri);
    }
    if faces.is_empty() {
        return Err(WireframeError::Solve("no triangle inside the loop"));
    }
    let nv = handles.len();
    let mut domain: Vec<[f64; 2]> = Vec::with_capacity(nv);
    let mut origins = Vec::with_capacity(nv);
    let mut fixed3: Vec<Option<[f64; 3]>> = Vec::with_capacity(nv);
    for &hdl in &handles {
        let v = cdt.vertex(hdl);
        let p = v.position();
        domain.push([p.x, p.y]);
        let tag = v.data().tag;
        if (tag as usize) < nodes.len() {
            let n = &nodes[tag as usize];
            origins.push(n.origin);
            fixed3.push(Some(n.p3));
        } else if tag == NEW_VERTEX {
            let on_edge = split_of(&cdt, hdl).and_then(|(a, b)| {
                let (i, flip) = match edge_lookup.get(&(a, b)) {
                    Some(&i) => (i, false),
                    None => (*edge_lookup.get(&(b, a))?, true),
                };
                Some((a, b, edge_info[i], flip))
            });
            match on_edge {
                Some((a, b, info, flip)) => {
                    let (na, nb) = (&nodes[a], &nodes[b]);
                    // Parameter along a → b from the domain positions (the domain map is
                    // linear along every constraint edge), then the 3D point on the segment.
                    let t = (dist2(na.p2, [p.x, p.y]) / dist2(na.p2, nb.p2)).clamp(0.0, 1.0);
                    let p3 = lerp3(na.p3, nb.p3, t);
                    let [ta, tb] = if flip { [info.t[1], info.t[0]] } else { info.t };
                    origins.push(info.origin(ta + t * (tb - ta)));
                    fixed3.push(Some(p3));
                }
                None => {
                    origins.push(VertexOrigin::Interior);
                    fixed3.push(None);
                }
            }
        } else {
            // A box vertex cannot be in an inside face (the box is outside the loop).
            return Err(WireframeError::Solve("box vertex inside the domain"));
        }
    }

    let node_of = handles
        .iter()
        .map(|&hdl| {
            let tag = cdt.vertex(hdl).data().tag as usize;
            (tag < nodes.len()).then_some(tag)
        })
        .collect();
    Ok(Meshed {
        faces,
        domain,
        origins,
        fixed3,
        node_of,
    })
}

/// Distance of a boundary/guide vertex from the input segment its origin names.
fn deviation(
    o: VertexOrigin,
    p: [f64; 3],
    curves: &[WireCurve],
    guides: &[WireCurve],
) -> Option<f64> {
    let seg_dist = |pts: &[[f64; 3]], s: usize| -> f64 {
        let a = pts[s];
        let b = pts[(s + 1).min(pts.len() - 1)];
        let ab = sub(b, a);
        let l2 = dot(ab, ab);
        let t = if l2 > 0.0 {
            (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        dist(p, add(a, scale(ab, t)))
    };
    match o {
        VertexOrigin::CurvePoint { curve, point } => Some(dist(p, curves[curve].points[point])),
        VertexOrigin::OnCurve { curve, segment, .. } => {
            Some(seg_dist(&curves[curve].points, segment))
        }
        VertexOrigin::GuidePoint { guide, point } => Some(dist(p, guides[guide].points[point])),
        VertexOrigin::OnGuide { guide, segment, .. } => {
            Some(seg_dist(&guides[guide].points, segment))
        }
        VertexOrigin::Interior => None,
    }
}

/// The boundary vertices in loop order, starting at the first curve's first point.
fn boundary_order(mesh: &TriMesh, origins: &[VertexOrigin]) -> Vec<u32> {
    // Directed boundary edges (u → v) of CCW faces: edges without a twin.
    let mut directed: HashSet<(u32, u32)> = HashSet::new();
    for f in &mesh.faces {
        for k in 0..3 {
            directed.insert((f[k], f[(k + 1) % 3]));
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &(u, v) in &directed {
        if !directed.contains(&(v, u)) {
            next.insert(u, v);
        }
    }
    let start = origins
        .iter()
        .position(|o| *o == VertexOrigin::CurvePoint { curve: 0, point: 0 })
        .map(|i| i as u32)
        .or_else(|| next.keys().min().copied());
    let Some(start) = start else {
        return Vec::new();
    };
    let mut out = vec![start];
    let mut cur = start;
    while let Some(&n) = next.get(&cur) {
        if n == start || out.len() > next.len() {
            break;
        }
        out.push(n);
        cur = n;
    }
    out
}

fn min_angle_deg(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> f64 {
    corner_angles(positions, faces)
        .iter()
        .flatten()
        .fold(f64::INFINITY, |a, &b| a.min(b))
        .to_degrees()
}

/// Cotan weights of the domain triangulation: (i, j, w_ij) per face corner, w = cot/2.
fn cotan_entries(domain: &[[f64; 2]], faces: &[[u32; 3]]) -> Vec<(usize, usize, f64)> {
    let mut out = Vec::with_capacity(faces.len() * 3);
    for f in faces {
        for k in 0..3 {
            let o = domain[f[k] as usize];
            let a = domain[f[(k + 1) % 3] as usize];
            let b = domain[f[(k + 2) % 3] as usize];
            let u = [a[0] - o[0], a[1] - o[1]];
            let v = [b[0] - o[0], b[1] - o[1]];
            let cr = (u[0] * v[1] - u[1] * v[0]).abs();
            let dt = u[0] * v[0] + u[1] * v[1];
            let cot = if cr > 0.0 { dt / cr } else { 0.0 };
            out.push((f[(k + 1) % 3] as usize, f[(k + 2) % 3] as usize, 0.5 * cot));
        }
    }
    out
}

/// Harmonic lift: fixed vertices at their 3D points, the rest solves the cotan Laplace
/// equation of the domain. Plane domain: heights only (in-plane = the domain position).
fn lift(
    domain: &[[f64; 2]],
    faces: &[[u32; 3]],
    fixed: &[Option<[f64; 3]>],
    mode: Lift,
) -> Result<Vec<[f64; 3]>, WireframeError> {
    let n = domain.len();
    let mut unknown = vec![usize::MAX; n];
    let mut m = 0;
    for i in 0..n {
        if fixed[i].is_none() {
            unknown[i] = m;
            m += 1;
        }
    }
    // Fixed values per channel.
    let channels = match mode {
        Lift::Height(_) => 1,
        Lift::Xyz => 3,
    };
    let value = |i: usize, c: usize| -> f64 {
        let p = fixed[i].unwrap_or([0.0; 3]);
        match mode {
            Lift::Height(frame) => frame.height(p),
            Lift::Xyz => p[c],
        }
    };
    let mut sol = vec![0.0; m * channels];
    if m > 0 {
        let mut pairs = Vec::new();
        let mut vals = Vec::new();
        for (i, j, w) in cotan_entries(domain, faces) {
            let (ui, uj) = (unknown[i], unknown[j]);
            if ui != usize::MAX {
                pairs.push((ui, ui));
                vals.push(w);
            }
            if uj != usize::MAX {
                pairs.push((uj, uj));
                vals.push(w);
            }
            match (ui != usize::MAX, uj != usize::MAX) {
                (true, true) => {
                    pairs.push((ui.max(uj), ui.min(uj)));
                    vals.push(-w);
                }
                (true, false) => {
                    for c in 0..channels {
                        sol[c * m + ui] += w * value(j, c);
                    }
                }
                (false, true) => {
                    for c in 0..channels {
                        sol[c * m + uj] += w * value(i, c);
                    }
                }
                (false, false) => {}
            }
        }
        let pattern = spd::SpdPattern::new(m, &pairs).ok_or(WireframeError::Solve("pattern"))?;
        let factor = pattern
            .factor(&vals)
            .ok_or(WireframeError::Solve("not positive definite"))?;
        if !factor.solve_in_place(&mut sol, channels) {
            return Err(WireframeError::Solve("non-finite solution"));
        }
    }
    Ok((0..n)
        .map(|i| match fixed[i] {
            Some(p) => p,
            None => {
                let u = unknown[i];
                match mode {
                    Lift::Height(frame) => frame.point(domain[i], sol[u]),
                    Lift::Xyz => [sol[u], sol[m + u], sol[2 * m + u]],
                }
            }
        })
        .collect())
}

/// What the harmonic lift solves for.
#[derive(Clone, Copy, Debug)]
enum Lift {
    /// The domain is the orthogonal projection to this frame's plane: in-plane coordinates
    /// are the domain position, only the height is solved.
    Height(Frame),
    /// All three coordinates are harmonic functions on the domain.
    Xyz,
}

/// One re-parametrisation pass: conformal flattening (LSCM) of the lifted patch, the nodes
/// re-placed there, re-triangulated and lifted. `None` if the flattening is unusable (folds,
/// a self-crossing boundary) or the triangulation fails; the caller keeps what it has.
#[allow(clippy::too_many_arguments)]
fn reparametrise(
    meshed: &Meshed,
    positions: &[[f64; 3]],
    nodes: &[Node],
    n_boundary: usize,
    edges: &[[usize; 2]],
    edge_info: &[EdgeOnInput],
    tri_area: f64,
    opts: &WireframeOptions,
    guides: &[WireCurve],
) -> Option<(Meshed, Vec<[f64; 3]>, f64)> {
    let flat = lscm(positions, &meshed.faces)?;
    let mut nodes2 = nodes.to_vec();
    let mut seen = vec![false; nodes.len()];
    for (v, n) in meshed.node_of.iter().enumerate() {
        if let Some(n) = *n {
            nodes2[n].p2 = flat[v];
            seen[n] = true;
        }
    }
    if seen.iter().any(|s| !s) {
        return None;
    }
    let poly: Vec<[f64; 2]> = nodes2[..n_boundary].iter().map(|n| n.p2).collect();
    let area2 = signed_area(&poly);
    if area2 <= 0.0 {
        return None;
    }
    let d = diagonal(positions.iter().copied());
    if first_crossing(&poly, TOUCH_RELATIVE * d).is_some() {
        return None;
    }
    // Same number of triangles as asked in 3D: scale the area limit by the flattening's
    // overall area ratio.
    let area3 = flatcut_mesh::geometry::face_areas(positions, &meshed.faces)
        .iter()
        .sum::<f64>();
    let m = triangulate(
        &nodes2,
        n_boundary,
        edges,
        edge_info,
        tri_area * area2 / area3,
        opts.domain_min_angle_deg,
        opts.max_vertices,
        guides,
    )
    .ok()?;
    let p = lift(&m.domain, &m.faces, &m.fixed3, Lift::Xyz).ok()?;
    let a = min_angle_deg(&p, &m.faces);
    Some((m, p, a))
}

/// Least-squares conformal map (Lévy et al. 2002) of a disk patch, two far-apart vertices
/// pinned at their 3D distance: per face the residual Σ_k W_k U_k / √(2A) with
/// W_k = z_(k+2) − z_(k+1) in the face's own 2D frame (zero for every orientation-preserving
/// similarity). `None` if the solve fails or a triangle comes out folded.
fn lscm(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Option<Vec<[f64; 2]>> {
    let n = positions.len();
    // Pins: a vertex farthest from vertex 0, then the one farthest from it.
    let far = |from: usize| {
        (0..n)
            .max_by(|&a, &b| {
                dist(positions[a], positions[from]).total_cmp(&dist(positions[b], positions[from]))
            })
            .unwrap_or(0)
    };
    let p0 = far(0);
    let p1 = far(p0);
    if p0 == p1 {
        return None;
    }
    let pinned = |v: usize| v == p0 || v == p1;
    let pin_value = |v: usize| -> [f64; 2] {
        if v == p0 {
            [0.0, 0.0]
        } else {
            [dist(positions[p0], positions[p1]), 0.0]
        }
    };
    // Free unknowns: (u, v) of every unpinned vertex.
    let mut col = vec![usize::MAX; n];
    let mut m = 0;
    for (v, c) in col.iter_mut().enumerate() {
        if !pinned(v) {
            *c = m;
            m += 1;
        }
    }
    let nf = 2 * m;
    let mut pairs = Vec::with_capacity(faces.len() * 36);
    let mut vals = Vec::with_capacity(faces.len() * 36);
    let mut rhs = vec![0.0; nf];
    for f in faces {
        let [a, b, c] = f.map(|v| positions[v as usize]);
        let e1 = sub(b, a);
        let l1 = norm(e1);
        let nrm = cross(e1, sub(c, a));
        let twice_area = norm(nrm);
        if l1 == 0.0 || twice_area == 0.0 {
            continue;
        }
        let x = scale(e1, 1.0 / l1);
        let y = cross(scale(nrm, 1.0 / twice_area), x);
        let z = [
            [0.0, 0.0],
            [l1, 0.0],
            [dot(sub(c, a), x), dot(sub(c, a), y)],
        ];
        let w = 1.0 / twice_area.sqrt();
        // Two real rows: Re and Im of Σ W_k (u_k + i v_k).
        let mut rows = [[(0usize, 0.0f64); 6]; 2];
        for k in 0..3 {
            let wr = (z[(k + 2) % 3][0] - z[(k + 1) % 3][0]) * w;
            let wi = (z[(k + 2) % 3][1] - z[(k + 1) % 3][1]) * w;
            let v = f[k] as usize;
            rows[0][2 * k] = (2 * v, wr);
            rows[0][2 * k + 1] = (2 * v + 1, -wi);
            rows[1][2 * k] = (2 * v, wi);
            rows[1][2 * k + 1] = (2 * v + 1, wr);
        }
        let free = |var: usize| {
            let c = col[var / 2];
            (c != usize::MAX).then(|| 2 * c + var % 2)
        };
        for row in &rows {
            // Pinned part moves to the right-hand side.
            let mut fixed_part = 0.0;
            for &(var, coef) in row {
                if free(var).is_none() {
                    fixed_part += coef * pin_value(var / 2)[var % 2];
                }
            }
            for &(vi, ci) in row {
                let Some(i) = free(vi) else { continue };
                rhs[i] -= ci * fixed_part;
                for &(vj, cj) in row {
                    let Some(j) = free(vj) else { continue };
                    if i >= j {
                        pairs.push((i, j));
                        vals.push(ci * cj);
                    }
                }
            }
        }
    }
    let pattern = spd::SpdPattern::new(nf, &pairs)?;
    let factor = pattern.factor(&vals)?;
    if !factor.solve_in_place(&mut rhs, 1) {
        return None;
    }
    let uv: Vec<[f64; 2]> = (0..n)
        .map(|v| {
            if pinned(v) {
                pin_value(v)
            } else {
                [rhs[2 * col[v]], rhs[2 * col[v] + 1]]
            }
        })
        .collect();
    let folded = faces
        .iter()
        .any(|f| cross2(uv[f[0] as usize], uv[f[1] as usize], uv[f[2] as usize]) <= 0.0);
    (!folded).then_some(uv)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// Jacobi: A v = λ v for each eigenpair and orthonormal vectors, on a full symmetric matrix.
    #[test]
    fn jacobi_eigenpairs() {
        let a = [[4.0, 1.0, -2.0], [1.0, 3.0, 0.5], [-2.0, 0.5, 1.0]];
        let (vals, vecs) = jacobi_eigen(a);
        for k in 0..3 {
            let v = [vecs[0][k], vecs[1][k], vecs[2][k]];
            let av = [0, 1, 2].map(|i| (0..3).map(|j| a[i][j] * v[j]).sum::<f64>());
            for i in 0..3 {
                assert!((av[i] - vals[k] * v[i]).abs() < 1e-12);
            }
            assert!((norm(v) - 1.0).abs() < 1e-12);
        }
        // Trace and determinant.
        assert!((vals.iter().sum::<f64>() - 8.0).abs() < 1e-12);
    }

    /// LSCM of a planar, irregular mesh is the mesh itself up to a rigid motion (the pins
    /// are at their true distance): every edge keeps its length.
    #[test]
    fn lscm_reproduces_a_planar_mesh() {
        // A 5×4 grid, jittered, in a tilted plane.
        let (nx, ny) = (5, 4);
        let mut pos = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (
                    10.0 * i as f64 + 1.7 * ((i * 7 + j * 3) % 5) as f64 / 5.0,
                    10.0 * j as f64 + 1.3 * ((i * 2 + j * 5) % 7) as f64 / 7.0,
                );
                pos.push([x, 0.6 * y, 0.8 * y + 5.0]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let v = (i + nx * j) as u32;
                let n = nx as u32;
                faces.push([v, v + 1, v + n + 1]);
                faces.push([v, v + n + 1, v + n]);
            }
        }
        let uv = lscm(&pos, &faces).unwrap();
        for f in &faces {
            for k in 0..3 {
                let (a, b) = (f[k] as usize, f[(k + 1) % 3] as usize);
                let l3 = dist(pos[a], pos[b]);
                let l2 = dist2(uv[a], uv[b]);
                assert!((l3 - l2).abs() < 1e-9 * l3, "edge {a}-{b}: {l3} vs {l2}");
            }
        }
    }

    #[test]
    fn segment_distances() {
        // Skew 3D segments: closest points at their interiors, distance 1.
        let d = segment_distance(
            [-1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 1.0],
            [0.0, 1.0, 1.0],
        );
        assert!((d - 1.0).abs() < 1e-15);
        // Parallel, offset along the line: end to end.
        let d = segment_distance([0.0; 3], [1.0, 0.0, 0.0], [3.0, 4.0, 0.0], [5.0, 4.0, 0.0]);
        assert!((d - (4.0f64 + 16.0).sqrt()).abs() < 1e-15);
        // 2D crossing and apart.
        assert_eq!(
            segment_distance_2d([0.0, 0.0], [2.0, 2.0], [0.0, 2.0], [2.0, 0.0]),
            0.0
        );
        assert!(
            (segment_distance_2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]) - 1.0).abs()
                < 1e-15
        );
    }
}
