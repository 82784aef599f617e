//! The one error type of the sparse solver.

/// Why a sparse SPD system could not be set up, factorised or solved. The indices are the
/// caller's unknowns (row/column numbers as given), so the caller can name its element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SparseError {
    /// An entry's row or column is not below `n`.
    #[error("entry ({row}, {col}) lies outside the {n}×{n} matrix")]
    IndexOutOfRange { row: usize, col: usize, n: usize },
    /// An entry above the diagonal given to [`crate::SpdPattern::new`], which takes the
    /// lower triangle only ([`crate::Triplets`] mirrors upper entries for you).
    #[error("entry ({row}, {col}) lies above the diagonal; give the lower triangle (row ≥ col)")]
    UpperEntry { row: usize, col: usize },
    /// The number of values does not match the number of pattern entries.
    #[error("{got} values given for a pattern of {expected} entries; give one value per entry")]
    ValueCount { expected: usize, got: usize },
    /// A NaN or infinite value (`entry` indexes the values, i.e. the pattern's pairs).
    #[error("value {entry} of the matrix is not finite; check the weights assembled into it")]
    NonFiniteValue { entry: usize },
    /// The n×n matrix is not numerically positive definite (a Cholesky pivot was ≤ 0): a
    /// singular or indefinite system, e.g. a missing constraint (pin, Dirichlet value) or
    /// degenerate (negative, huge) weights.
    #[error(
        "the {n}×{n} matrix is not positive definite (a Cholesky pivot is ≤ 0); the system is singular or indefinite: check its constraints and weights"
    )]
    NotPositiveDefinite { n: usize },
    /// The right-hand side is not n × k values.
    #[error("the right-hand side has {got} values; expected n × k = {expected}")]
    RhsLength { expected: usize, got: usize },
    /// The solve produced a NaN or infinity (a nearly singular matrix).
    #[error("the solution is not finite; the matrix is numerically singular")]
    NonFiniteSolution,
    /// A pattern given to [`crate::SupernodalLltPlan::new`] is not the one its symbolic
    /// factor was analysed from.
    #[error("the matrix's pattern does not match its symbolic factorisation: {reason}")]
    PatternMismatch { reason: String },
    /// faer could not allocate the factor or its workspace, or an index overflowed.
    #[error("the sparse factorisation ran out of memory (n = {n}); the system is too large")]
    OutOfMemory { n: usize },
}
