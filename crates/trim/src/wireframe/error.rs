//! The errors of the wire-frame surface.

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
    /// The harmonic lift's sparse solve failed (should not happen for a valid
    /// triangulation: the Dirichlet block of a cotan Laplacian with a boundary is SPD).
    #[error(
        "the harmonic lift's linear solve failed: {0}; this is a bug, please report the wire-frame"
    )]
    LiftSolve(flatcut_sparse::SparseError),
    /// An internal step failed (should not happen for a valid triangulation).
    #[error(
        "the harmonic lift's linear solve failed ({0}); this is a bug, please report the wire-frame"
    )]
    Solve(&'static str),
}
