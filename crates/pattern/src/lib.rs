//! The 2D cut-pattern piece: sew line, cut line (seam allowance), notches, grain, labels,
//! material shrink, and the layout of pieces on a sheet.
//!
//! - [`build_pieces`]: flattened pieces (+ the seam ledger) → [`PatternPiece`]s;
//! - [`seam_allowance`]: the cut line of a sew loop (per-edge widths, corner rules);
//! - [`grain_direction_2d`]: a 3D grain direction carried into the pattern;
//! - [`layout`]: shelf packing on a sheet, grain vertical, mirrored pairs both placed.
//!
//! Nothing here reads or writes files.

mod error;
pub mod geom;
pub mod grain;
pub mod layout;
pub mod piece;
pub mod seam_allowance;

pub use error::PatternError;
pub use grain::grain_direction_2d;
pub use layout::{Layout, LayoutOptions, Placement, TEST_SQUARE_MM, layout};
pub use piece::{
    Dart, Label, MAX_SHRINK, NOTCH_MAX_FRACTION, Notch, PatternOptions, PatternPiece, PieceInput,
    PieceMeta, PieceSeam, ShrinkReport, build_pieces,
};
pub use seam_allowance::{CornerRule, CornerSpec, seam_allowance};
