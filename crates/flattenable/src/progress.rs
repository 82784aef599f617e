//! Progress of a run, for a caller that shows it (the CLI's spinner, the pipeline's bars):
//! an optional callback in [`crate::ProcessOptions::progress`], called after every
//! iteration. It only observes; results are the same with or without it.

use std::fmt;
use std::sync::Arc;

use crate::piece::Piece;

/// The state after an iteration (or at the start, iteration 0) of one run: a piece, one
/// level of its coarse-to-fine hierarchy, or a local polish region, told apart by `faces`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationDone {
    /// The piece (connected component), numbered as in the report.
    pub piece: usize,
    /// Faces of the mesh iterated on: the piece's, a coarse level's or a region's.
    pub faces: usize,
    /// Iterations this run has taken so far.
    pub iteration: usize,
    /// max |θ − 2π| over its interior vertices now (radians).
    pub theta_err: f64,
}

type Callback = dyn Fn(&IterationDone) + Send + Sync;

/// An optional progress callback. Pieces run in parallel, so it is called from several
/// threads at once; it should return quickly (it runs between the iterations).
#[derive(Clone, Default)]
pub struct ProgressHook(Option<Arc<Callback>>);

impl ProgressHook {
    /// A hook calling `f` after every iteration.
    pub fn new(f: impl Fn(&IterationDone) + Send + Sync + 'static) -> Self {
        Self(Some(Arc::new(f)))
    }

    /// Tells the callback, if any, that the run on `piece` (a piece, a coarse level or a
    /// region) is at `iteration` with θ_err `theta_err`.
    pub(crate) fn notify(&self, piece: &Piece, iteration: usize, theta_err: f64) {
        if let Some(f) = &self.0 {
            f(&IterationDone {
                piece: piece.index,
                faces: piece.faces.len(),
                iteration,
                theta_err,
            });
        }
    }
}

impl fmt::Debug for ProgressHook {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() {
            "ProgressHook(set)"
        } else {
            "ProgressHook(none)"
        })
    }
}

/// Two hooks are equal when both are unset or both call the same closure.
impl PartialEq for ProgressHook {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}
