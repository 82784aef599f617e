//! Least-norm flattenable mesh processing (Wang, "A Least-norm Approach to Flattenable Mesh
//! Surface Processing"): move the interior vertices of a piece as little as possible until
//! every interior vertex has summed angle θ = 2π, so that the piece flattens without
//! stretch.
//!
//! Entry point: [`process`]. Two modes: [`Mode::Paper`] (the paper as printed) and
//! [`Mode::Robust`] (the default: damped steps with a merit test, fold guards, scale-free
//! thresholds, polish to 1e-9 rad). Every connected component is processed on its own, in
//! parallel, with results independent of the thread count. See
//! docs/algorithms/flattenable.md for equations, decisions and measurements.

// Sparse kernels walk CSR ranges and index several parallel arrays at once; the index
// loops say that more plainly than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod angle_gradient;
mod coarse_to_fine;
pub mod coarsen;
mod error;
pub mod hole_closure;
mod hole_fill;
pub mod laplacian;
pub mod least_norm;
mod local_polish;
mod options;
mod paper;
mod piece;
mod process;
mod progress;
mod pull_back;
mod report;
mod robust;
mod smoothed_step;

pub use error::FlattenableError;
pub use options::{
    CoarseToFine, Damping, HoleRims, Laplacian, Mode, ProcessOptions, Prolongation, Target, Update,
};
pub use process::{AREA_TIE_PERCENT, Processed, process};
pub use progress::{IterationDone, ProgressHook};
pub use report::{CREASE_DEFECT_NEUTRAL_RAD, CREASE_DEG, CreaseKind, PieceReport, ProcessReport};
