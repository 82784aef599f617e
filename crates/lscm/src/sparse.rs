//! A symmetric positive definite sparse system whose pattern is analysed once and whose
//! values may change (the ARAP Laplacian is factorised once; Gauss–Newton refactorises the
//! same pattern every step). Thin wrapper over faer's sparse Cholesky.

use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::traits::ComplexField;
use faer::{MatMut, Side};

/// The pattern of the lower triangle of an n×n SPD matrix, with its symbolic Cholesky.
pub(crate) struct SpdPattern {
    n: usize,
    /// Number of (row, col) entries given, duplicates included; `values` must match.
    entries: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    llt: SymbolicLlt<usize>,
}

/// A numeric factorisation of an [`SpdPattern`], real symmetric or complex Hermitian.
pub(crate) struct SpdFactor<T: ComplexField = f64> {
    llt: Llt<usize, T>,
    n: usize,
}

/// Values a factorisation accepts: f64 and faer's c64.
pub(crate) trait Value: ComplexField + Copy {
    fn finite(&self) -> bool;
}
impl Value for f64 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}
impl Value for faer::c64 {
    fn finite(&self) -> bool {
        self.re.is_finite() && self.im.is_finite()
    }
}

impl SpdPattern {
    /// `pairs` are (row, col) with row ≥ col (lower triangle); duplicates are summed when the
    /// values are given. `None` if faer refuses the pattern (out of memory, bad index).
    pub(crate) fn new(n: usize, pairs: &[(usize, usize)]) -> Option<Self> {
        let idx: Vec<Pair<usize, usize>> = pairs.iter().map(|&(r, c)| Pair::new(r, c)).collect();
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &idx).ok()?;
        let llt = SymbolicLlt::try_new(symbolic.as_ref(), Side::Lower).ok()?;
        Some(Self {
            n,
            entries: pairs.len(),
            symbolic,
            argsort,
            llt,
        })
    }

    /// Factorises the matrix with these values (one per pair given to [`SpdPattern::new`]).
    /// `None` if the matrix is not numerically positive definite.
    pub(crate) fn factor<T: Value>(&self, values: &[T]) -> Option<SpdFactor<T>> {
        if values.len() != self.entries || values.iter().any(|v| !v.finite()) {
            return None;
        }
        let mat =
            SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, values).ok()?;
        let llt = Llt::try_new_with_symbolic(self.llt.clone(), mat.as_ref(), Side::Lower).ok()?;
        Some(SpdFactor { llt, n: self.n })
    }
}

impl<T: Value> SpdFactor<T> {
    /// Solves A x = b in place for `k` right-hand sides stored column-major in `rhs`
    /// (`rhs.len() == n·k`). Returns false if the solution is not finite.
    pub(crate) fn solve_in_place(&self, rhs: &mut [T], k: usize) -> bool {
        use faer::linalg::solvers::Solve;
        debug_assert_eq!(rhs.len(), self.n * k);
        let m = MatMut::from_column_major_slice_mut(rhs, self.n, k);
        self.llt.solve_in_place(m);
        rhs.iter().all(|v| v.finite())
    }
}
