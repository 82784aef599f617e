//! Assembly of a symmetric (Hermitian) matrix's lower triangle from entries.

use crate::SparseError;
use crate::spd::{SpdPattern, Value};

/// Entries of an n×n symmetric (real) or Hermitian (complex) matrix, kept as its lower
/// triangle: `pairs()[k]` = (row, col) with row ≥ col and `values()[k]` its value.
/// Duplicates stay separate here and are summed by the factorisation, so the same
/// assembly loop can refill [`Triplets::values`] for a refactorisation.
#[derive(Clone, Debug, Default)]
pub struct Triplets<T: Value = f64> {
    n: usize,
    pairs: Vec<(usize, usize)>,
    values: Vec<T>,
}

impl<T: Value> Triplets<T> {
    /// An empty n×n matrix.
    pub fn new(n: usize) -> Self {
        Self {
            n,
            pairs: Vec::new(),
            values: Vec::new(),
        }
    }

    /// An empty n×n matrix with room for `entries` entries.
    pub fn with_capacity(n: usize, entries: usize) -> Self {
        Self {
            n,
            pairs: Vec::with_capacity(entries),
            values: Vec::with_capacity(entries),
        }
    }

    /// Adds `value` to entry (row, col). An entry above the diagonal is stored as its
    /// mirror (col, row) with the conjugate value, which is the same matrix for a
    /// symmetric/Hermitian one; give each off-diagonal coupling once (either half).
    /// Out-of-range indices are reported by [`crate::SpdPattern::new`].
    pub fn push(&mut self, row: usize, col: usize, value: T) {
        if row >= col {
            self.pairs.push((row, col));
            self.values.push(value);
        } else {
            self.pairs.push((col, row));
            self.values.push(value.conj_value());
        }
    }

    /// The pattern of these entries, analysed ([`SpdPattern::new`]).
    ///
    /// # Errors
    /// [`SparseError::IndexOutOfRange`] for an entry outside the n×n matrix, or
    /// [`SparseError::OutOfMemory`].
    pub fn pattern(&self) -> Result<SpdPattern, SparseError> {
        SpdPattern::new(self.n, &self.pairs)
    }

    /// The matrix size n.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The (row, col) of every entry, row ≥ col.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// The value of every entry (one per pair).
    pub fn values(&self) -> &[T] {
        &self.values
    }

    /// Number of entries (duplicates counted).
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// True when no entry was pushed.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }
}
