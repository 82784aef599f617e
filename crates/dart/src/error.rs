//! The one error type of the dart crate: every variant names the dart at fault (its index in
//! the caller's list and its name) and says what to do.

use flatcut_mesh::MeshError;
use flatcut_trim::TrimError;

/// What went wrong while cutting darts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DartError {
    /// The piece itself is unusable (index out of range, non-manifold, …).
    #[error("the piece is unusable: {0}")]
    Mesh(#[from] MeshError),
    /// The piece has no faces or no boundary: a dart needs a boundary to start from.
    #[error("the piece {reason}; a dart runs from the piece's boundary to a tip inside it")]
    BadPiece {
        /// What is wrong.
        reason: String,
    },
    /// A dart is described wrongly (no tip and no direction, a non-finite number, …).
    #[error("dart {index} {name:?}: {reason}")]
    BadSpec {
        /// Index of the dart in the list given.
        index: usize,
        /// Its name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// The start point is farther from the piece's boundary than the tolerance.
    #[error(
        "dart {index} {name:?}: its start is {distance_mm:.3} mm from the piece's boundary (tolerance {tolerance_mm} mm); a dart starts on the boundary — move the start onto it"
    )]
    StartOffBoundary {
        /// Index of the dart.
        index: usize,
        /// Its name.
        name: String,
        /// Distance from the start to the nearest boundary point, mm.
        distance_mm: f64,
        /// The tolerance, mm.
        tolerance_mm: f64,
    },
    /// The tip is not on the piece (farther from its surface than the tolerance).
    #[error(
        "dart {index} {name:?}: its tip is {distance_mm:.3} mm from the piece's surface (tolerance {tolerance_mm} mm); put the tip on the piece"
    )]
    TipOffPiece {
        /// Index of the dart.
        index: usize,
        /// Its name.
        name: String,
        /// Distance from the tip to the surface, mm.
        distance_mm: f64,
        /// The tolerance, mm.
        tolerance_mm: f64,
    },
    /// The tip is on (or within the boundary tolerance of) the piece's boundary.
    #[error(
        "dart {index} {name:?}: its tip is {distance_mm:.3} mm from the piece's boundary (at least {tolerance_mm} mm needed); a dart's tip lies inside the piece — move it inwards"
    )]
    TipOnBoundary {
        /// Index of the dart.
        index: usize,
        /// Its name.
        name: String,
        /// Distance from the tip to the boundary, mm.
        distance_mm: f64,
        /// The boundary tolerance, mm.
        tolerance_mm: f64,
    },
    /// The dart's path touches the boundary between its start and its tip: it would cut the
    /// piece in two instead of opening a dart.
    #[error(
        "dart {index} {name:?}: its path from start to tip touches the piece's boundary at {point_mm:?} mm; move the tip or the start so the dart stays inside the piece"
    )]
    TouchesBoundary {
        /// Index of the dart.
        index: usize,
        /// Its name.
        name: String,
        /// Where.
        point_mm: [f64; 3],
    },
    /// Two darts cross or share a point.
    #[error(
        "darts {a} {a_name:?} and {b} {b_name:?} cross or touch at {point_mm:?} mm; darts must not meet — move one"
    )]
    Crossing {
        /// Index of the first dart.
        a: usize,
        /// Its name.
        a_name: String,
        /// Index of the second dart.
        b: usize,
        /// Its name.
        b_name: String,
        /// Where.
        point_mm: [f64; 3],
    },
    /// A dart given by a direction and a length leaves the piece before reaching its length.
    #[error(
        "dart {index} {name:?}: it is {length_mm:.3} mm long but leaves the piece after {reach_mm:.3} mm in its direction; shorten it or turn it"
    )]
    TooLong {
        /// Index of the dart.
        index: usize,
        /// Its name.
        name: String,
        /// The length asked, mm.
        length_mm: f64,
        /// How far the piece reaches in that direction, mm.
        reach_mm: f64,
    },
    /// A dart's direction points out of the piece at its start.
    #[error(
        "dart {index} {name:?}: its direction {direction:?} points out of the piece at its start; give a direction into the piece"
    )]
    DirectionOutward {
        /// Index of the dart.
        index: usize,
        /// Its name.
        name: String,
        /// The direction given.
        direction: [f64; 3],
    },
    /// No path on the piece joins the start and the tip.
    #[error(
        "dart {index} {name:?}: no path on the piece joins its start and its tip; are both on the same connected part?"
    )]
    NoPath {
        /// Index of the dart.
        index: usize,
        /// Its name.
        name: String,
    },
    /// Two darts share a name.
    #[error(
        "dart name {name:?} is used twice (darts {first} and {second}); give each a unique name"
    )]
    DuplicateName {
        /// The name.
        name: String,
        /// The first dart with it.
        first: usize,
        /// The second.
        second: usize,
    },
    /// The embedding of the dart lines failed (a numerical corner case in trim).
    #[error("cannot embed the darts: {0}; move the dart slightly")]
    Embedding(TrimError),
    /// Appending to a seam ledger: the piece is not listed there.
    #[error("the seam ledger lists no piece {piece:?}; add the piece before its darts")]
    UnknownPiece {
        /// The piece name.
        piece: String,
    },
    /// Appending to a seam ledger: a dart starts inside a boundary edge that an existing seam
    /// uses, so that seam's mate would need the same new vertex.
    #[error(
        "dart {name:?} starts inside an edge of seam {seam:?}; start it at a vertex of that seam (or before cutting the seam's mate)"
    )]
    StartSplitsSeam {
        /// The dart.
        name: String,
        /// The seam id.
        seam: String,
    },
    /// Appending to a seam ledger: a seam id is already used.
    #[error("seam id {seam:?} is already in the ledger; give the dart another name")]
    DuplicateSeam {
        /// The id.
        seam: String,
    },
}
