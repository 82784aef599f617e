//! The one sparse symmetric (or Hermitian) positive definite solver of flatcut: a thin
//! wrapper over faer's sparse Cholesky (AMD ordering, supernodal or simplicial as faer
//! chooses) with the analysis split from the numbers.
//!
//! - [`Triplets`]: assembly of the lower triangle from (row, col, value) entries;
//!   duplicates are summed, entries above the diagonal are mirrored (conjugated).
//! - [`SpdPattern`]: the sparsity pattern with its symbolic Cholesky, computed once.
//! - [`SpdFactor`]: a numeric factorisation of that pattern for one set of values;
//!   [`SpdFactor::refactor`] replaces the values in place (Gauss–Newton, reweighted
//!   Laplacians) without redoing the analysis or reallocating L.
//! - [`SpdFactor::solve_in_place`]: several right-hand sides at once.
//! - [`solve_llt_in_place`]: an L Lᵀ solve of our own on a faer supernodal factor, for
//!   factors with many narrow supernodes, where faer's per-supernode dispatch costs more than
//!   the arithmetic (`flatcut_flattenable`'s A G Aᵀ).
//! - [`SupernodalLltPlan`]: the numeric factorisation of our own on faer's supernodal
//!   symbolic factor, for the same patterns factorised again and again: each supernode's
//!   updates worked out once, register tiles where faer's dispatch would cost more than the
//!   arithmetic, faer's dense kernels where it would not.
//!
//! Used by `flatcut_lscm` (LSCM, ARAP, Gauss–Newton) and `flatcut_trim` (the wire-frame
//! surface's harmonic lift); `flatcut_flattenable` uses the supernodal factorisation and
//! solve on faer's symbolic analysis. It depends on
//! faer only (and pulp, faer's SIMD dispatch), so every crate that needs a sparse SPD solve
//! can sit on top of it without the crate DAG growing other edges (see
//! docs/architecture.md).
//!
//! ```
//! use flatcut_sparse::{SpdPattern, Triplets};
//! // [2 -1; -1 2] x = [1, 1] → x = [1, 1].
//! let mut t = Triplets::<f64>::new(2);
//! t.push(0, 0, 2.0);
//! t.push(1, 1, 2.0);
//! t.push(1, 0, -1.0);
//! let pattern = SpdPattern::new(2, t.pairs()).unwrap();
//! let factor = pattern.factor(t.values()).unwrap();
//! let mut x = vec![1.0, 1.0];
//! factor.solve_in_place(&mut x, 1).unwrap();
//! assert!((x[0] - 1.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15);
//! ```

mod error;
mod spd;
mod supernodal_llt;
mod supernodal_solve;
mod supernodes;
mod triplets;

pub use error::SparseError;
pub use faer::c64;
pub use spd::{SpdFactor, SpdPattern, Value};
pub use supernodal_llt::{DENSE_MIN_COLUMNS, GEMM_MIN_DEPTH, LltWorkspace, SupernodalLltPlan};
pub use supernodal_solve::{GROUP_COLUMNS, GROUP_MIN_ROWS, solve_llt_in_place};
pub use triplets::Triplets;
