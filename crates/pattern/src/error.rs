//! The one error type of the pattern crate.

/// What went wrong building or laying out pattern pieces; every variant names the piece (and
/// the element) and says what to do.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PatternError {
    /// The piece has no faces or its 2D coordinates do not match its vertices.
    #[error("piece {piece:?}: {what}")]
    BadPiece {
        /// Piece name.
        piece: String,
        /// What is wrong and what to do.
        what: String,
    },
    /// A 2D or 3D coordinate is NaN or infinite.
    #[error("piece {piece:?}: vertex {vertex} has a non-finite coordinate; re-run the flattening")]
    NotFinite {
        /// Piece name.
        piece: String,
        /// Piece-local vertex index.
        vertex: u32,
    },
    /// The flattened outline crosses itself (the flattening folded over).
    #[error(
        "piece {piece:?}: its 2D outline crosses itself near ({x:.2}, {y:.2}) mm (boundary edges {edge_a} and {edge_b}); \
         the flattening folded over: cut the piece further or re-flatten with lscm+arap"
    )]
    SelfIntersecting {
        /// Piece name.
        piece: String,
        /// Where (mm, in the piece's 2D frame).
        x: f64,
        /// Where (mm).
        y: f64,
        /// Index of one crossing boundary edge along the sew line.
        edge_a: usize,
        /// Index of the other.
        edge_b: usize,
    },
    /// A width, factor or limit is negative, zero where it must not be, or not finite.
    #[error("{what} = {value} is not allowed: {hint}")]
    BadOption {
        /// Which option (e.g. `seam_allowance_mm`, `seam_overrides["side/0"]`).
        what: String,
        /// The value given.
        value: f64,
        /// The accepted range.
        hint: &'static str,
    },
    /// The allowance is larger than half the piece.
    #[error(
        "piece {piece:?}: seam allowance {allowance_mm} mm is more than half the piece ({half_mm:.2} mm, half its narrower extent); use a smaller allowance"
    )]
    AllowanceTooLarge {
        /// Piece name.
        piece: String,
        /// The offending allowance.
        allowance_mm: f64,
        /// Half the piece's narrower bounding-box extent.
        half_mm: f64,
    },
    /// The grain direction is (nearly) normal to the whole piece.
    #[error(
        "piece {piece:?}: the grain direction is normal to the piece and has no direction in its pattern; give another grain"
    )]
    GrainNormalToPiece {
        /// Piece name.
        piece: String,
    },
    /// A seam of the ledger does not fit the piece it names.
    #[error("seam {seam:?} on piece {piece:?}: {what}")]
    Seam {
        /// Seam id.
        seam: String,
        /// Piece name.
        piece: String,
        /// What is wrong and what to do.
        what: String,
    },
    /// The ledger names a piece that was not given.
    #[error(
        "seam {seam:?} names piece {piece:?}, which is not among the pieces given; pass every piece of the ledger"
    )]
    MissingPiece {
        /// Seam id.
        seam: String,
        /// Piece name.
        piece: String,
    },
    /// The seam ledger itself is inconsistent.
    #[error(transparent)]
    Ledger(#[from] flatcut_mesh::SeamLedgerError),
    /// The offset produced no outline (should not happen on a valid outline).
    #[error(
        "piece {piece:?}: the seam allowance offset produced no outline; this is a bug, please report it"
    )]
    OffsetFailed {
        /// Piece name.
        piece: String,
    },
    /// A piece does not fit the sheet.
    #[error(
        "piece {piece:?} is {width_mm:.1} mm wide with its allowance and does not fit a {sheet_mm:.1} mm sheet; use a wider sheet"
    )]
    TooWide {
        /// Piece name.
        piece: String,
        /// Its cut-line width (mm).
        width_mm: f64,
        /// Usable sheet width (mm).
        sheet_mm: f64,
    },
}
