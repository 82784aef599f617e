//! The one error type of the crate.

use flatcut_mesh::{FaceId, MeshError, VertexId};

use crate::Processed;

/// What can go wrong in [`crate::process`]. Piece numbers are connected components in
/// order of first appearance; vertex and face ids refer to the input mesh.
#[derive(Debug, thiserror::Error)]
pub enum FlattenableError {
    /// The mesh itself is invalid (index out of range, NaN or infinite coordinate, …).
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    /// A piece has no boundary: its vertices cannot all reach 2π with nothing fixed
    /// (Gauss–Bonnet), and there is nothing to hold it in place.
    #[error(
        "piece {piece} is closed (no boundary loop): cut it open into disk-like pieces before processing"
    )]
    ClosedPiece { piece: usize },
    /// An edge has more than two faces.
    #[error(
        "piece {piece}: the edge {a}–{b} has more than two faces (non-manifold); clean the mesh first"
    )]
    NonManifoldEdge { piece: usize, a: u32, b: u32 },
    /// A vertex joins several fans of faces.
    #[error(
        "piece {piece}: {vertex} is non-manifold (its faces form several fans); clean the mesh first"
    )]
    NonManifoldVertex { piece: usize, vertex: VertexId },
    /// Two faces traverse an edge in the same direction.
    #[error(
        "piece {piece}: the faces at edge {a}–{b} are inconsistently oriented; orient the mesh first"
    )]
    InconsistentOrientation { piece: usize, a: u32, b: u32 },
    /// A piece is so large or so small that the solver's products of lengths leave the range
    /// of f64 (`process`'s `EXTENT_RANGE`).
    #[error(
        "piece {piece} spans {extent:.3e} (its bounding-box diagonal), outside {min:.0e} to {max:.0e}, the extents whose squared and higher powers of lengths stay finite and normal in f64; rescale the mesh (to millimetres, say) before processing"
    )]
    ExtentOutOfRange {
        piece: usize,
        extent: f64,
        min: f64,
        max: f64,
    },
    /// A face has zero area or a repeated vertex.
    #[error("piece {piece}: {face} is degenerate (zero area or repeated vertex); remove it first")]
    DegenerateFace { piece: usize, face: FaceId },
    /// An interior vertex with fewer than three neighbours.
    #[error("piece {piece}: interior {vertex} has valence {valence} < 3; clean the mesh first")]
    LowValence {
        piece: usize,
        vertex: VertexId,
        valence: usize,
    },
    /// An option is out of range.
    #[error("invalid option {name}: {reason}")]
    InvalidOption { name: &'static str, reason: String },
    /// The sparse normal matrix could not be factorised (a rank-deficient Jacobian).
    #[error(
        "piece {piece}: iteration {iteration}: the normal matrix A Aᵀ is not positive definite ({detail}); the paper's undamped step needs independent constraints — use the robust mode"
    )]
    Singular {
        piece: usize,
        iteration: usize,
        detail: String,
    },
    /// Paper mode produced folded faces or non-finite positions (the paper's direct update
    /// diverges on some inputs, its Fig. 3a).
    #[error(
        "piece {piece}: paper mode diverged at iteration {iteration} (θ_err {theta_err:.3e} rad, {folded_faces} folded faces); try the least-square update or the robust mode"
    )]
    Diverged {
        piece: usize,
        iteration: usize,
        theta_err: f64,
        folded_faces: usize,
    },
    /// Robust mode could not reach the tolerance; the best unfolded state is in `partial`.
    /// The best state is the one of least ‖θ − 2π‖² (what the steps decrease): its θ_err
    /// (the max) is `best_theta_err`, its RMS `best_theta_rms`, and on a rough piece the max
    /// can be above the input's while the RMS is below it, so both are given with the
    /// input's.
    #[error(
        "piece {piece} did not converge: best θ_err {best_theta_err:.3e} rad, RMS {best_theta_rms:.3e} (input {input_theta_err:.3e}, RMS {input_theta_rms:.3e}; tolerance {tolerance:.1e}) after {iterations} iterations: {reason}{}",
        least_flat(partial, *piece)
    )]
    NotConverged {
        piece: usize,
        best_theta_err: f64,
        best_theta_rms: f64,
        input_theta_err: f64,
        input_theta_rms: f64,
        tolerance: f64,
        iterations: usize,
        reason: String,
        /// The whole result with every piece at its best unfolded state (the
        /// non-converged pieces marked in the report).
        partial: Box<Processed>,
    },
}

/// Where the unconverged `piece` of `partial` is least flat, as a clause for the message
/// (empty when its report has no interior vertex to name).
fn least_flat(partial: &Processed, piece: usize) -> String {
    let Some(p) = partial.report.pieces.iter().find(|p| p.piece == piece) else {
        return String::new();
    };
    let (Some(v), Some([x, y, z])) = (p.worst_vertex, p.worst_vertex_position_mm) else {
        return String::new();
    };
    format!(
        " (least flat at input vertex {v} at ({x:.2}, {y:.2}, {z:.2}) mm; half of the remaining ‖θ − 2π‖² on {} of {} interior vertices, all within {:.2} mm of it)",
        p.vertices_holding_half_residual, p.interior_vertices, p.half_residual_radius_mm
    )
}
