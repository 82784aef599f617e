//! Darts: a slit from a piece's boundary to a tip inside it, cut open so the piece can open
//! there instead of deforming when it is made flattenable (Wang's wetsuit, §5.2, Fig. 9e–f).
//!
//! * [`dart`]: darts given by start + tip, or start + direction + length, joined by exact
//!   geodesics, embedded exactly (flatcut_trim) and cut open; the tip stays one vertex.
//! * [`dart_seams`] / [`append_dart_seams`]: each dart as a seam of its piece with itself.
//! * [`suggest`]: where darts would help most (concentrated angle defect).
//!
//! See docs/algorithms/darts.md.

mod dart;
mod error;
mod seams;
mod suggest;
mod trace;

pub use dart::{
    DEFAULT_BOUNDARY_TOLERANCE_MM, DEFAULT_TIP_TOLERANCE_MM, DartLegs, DartOptions, DartSpec,
    Darted, dart,
};
pub use error::DartError;
pub use seams::{append_dart_seams, dart_seam_id, dart_seams};
pub use suggest::{
    DEFAULT_MIN_DEFECT_RAD, DEFAULT_RADIUS_FRACTION, SuggestOptions, Suggestion, suggest,
    total_abs_defect,
};
