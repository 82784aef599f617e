//! faer's supernodal symbolic factor as the plain slices our factorisation and solve read
//! (its documented `SymbolicSupernodalCholesky` accessors): supernode s owns columns
//! `begin[s]..end[s]` of L, stored column-major in `values[val_ptr[s]..val_ptr[s + 1]]` with
//! `end[s] − begin[s] + pattern_len[s]` rows: first the dense lower triangle of its own
//! columns, then the rows `row_idx[row_ptr[s]..][..pattern_len[s]]` below them.

use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;

pub(crate) struct Supernodes<'a> {
    pub begin: &'a [u32],
    pub end: &'a [u32],
    pub val_ptr: &'a [u32],
    pub row_ptr: &'a [u32],
    pub pattern_len: &'a [u32],
    pub row_idx: &'a [u32],
}

impl<'a> Supernodes<'a> {
    pub fn of(symbolic: &'a SymbolicSupernodalCholesky<u32>) -> Self {
        Self {
            begin: symbolic.supernode_begin(),
            end: symbolic.supernode_end(),
            val_ptr: symbolic.col_ptr_for_val(),
            row_ptr: symbolic.col_ptr_for_row_idx(),
            pattern_len: symbolic.nnz_per_super(),
            row_idx: symbolic.row_idx(),
        }
    }

    /// The rows of L below supernode `s`'s own columns.
    #[inline(always)]
    pub fn pattern(&self, s: usize) -> &'a [u32] {
        &self.row_idx[self.row_ptr[s] as usize..][..self.pattern_len[s] as usize]
    }
}
