//! A symmetric (or Hermitian) positive definite sparse system whose pattern is analysed once
//! and whose values may change (the ARAP Laplacian is factorised once; Gauss–Newton
//! refactorises the same pattern every step). Thin wrapper over faer's sparse Cholesky,
//! at its lower level so that the parallelism is chosen here (see [`FACTOR_PAR`]).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par, Side};

/// Parallelism of the numeric factorisation and of the triangular solves: sequential.
/// Measured on the 2-core CI machine under load (release, 200k-face saddle, 100k unknowns):
/// faer's Rayon solve of the ARAP Laplacian took 190–300 ms per two-column solve against
/// 24 ms sequentially, and the factorisation was no faster in parallel. Pieces are
/// flattened in parallel one level up instead (one piece per Rayon task).
const FACTOR_PAR: Par = Par::Seq;

/// The pattern of the lower triangle of an n×n SPD matrix, with its symbolic Cholesky.
pub(crate) struct SpdPattern {
    /// Number of (row, col) entries given, duplicates included; `values` must match.
    entries: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    llt: SymbolicCholesky<usize>,
}

/// A numeric factorisation of an [`SpdPattern`], real symmetric or complex Hermitian.
pub(crate) struct SpdFactor<'a, T: ComplexField = f64> {
    pattern: &'a SpdPattern,
    values: Vec<T>,
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
        let llt = factorize_symbolic_cholesky(
            symbolic.as_ref(),
            Side::Lower,
            Default::default(),
            Default::default(),
        )
        .ok()?;
        Some(Self {
            entries: pairs.len(),
            symbolic,
            argsort,
            llt,
        })
    }

    /// Factorises the matrix with these values (one per pair given to [`SpdPattern::new`]).
    /// `None` if the matrix is not numerically positive definite.
    pub(crate) fn factor<T: Value>(&self, values: &[T]) -> Option<SpdFactor<'_, T>> {
        if values.len() != self.entries || values.iter().any(|v| !v.finite()) {
            return None;
        }
        let mat =
            SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, values).ok()?;
        let mut l = Vec::new();
        l.try_reserve_exact(self.llt.len_val()).ok()?;
        l.resize(self.llt.len_val(), T::zero_impl());
        let mut buf = MemBuffer::try_new(
            self.llt
                .factorize_numeric_llt_scratch::<T>(FACTOR_PAR, Default::default()),
        )
        .ok()?;
        self.llt
            .factorize_numeric_llt(
                &mut l,
                mat.as_ref(),
                Side::Lower,
                Default::default(),
                FACTOR_PAR,
                MemStack::new(&mut buf),
                Default::default(),
            )
            .ok()?;
        Some(SpdFactor {
            pattern: self,
            values: l,
        })
    }
}

impl<T: Value> SpdFactor<'_, T> {
    /// Solves A x = b in place for `k` right-hand sides stored column-major in `rhs`
    /// (`rhs.len() == n·k`). Returns false if the solution is not finite.
    pub(crate) fn solve_in_place(&self, rhs: &mut [T], k: usize) -> bool {
        let sym = &self.pattern.llt;
        let n = sym.nrows();
        debug_assert_eq!(rhs.len(), n * k);
        let m = MatMut::from_column_major_slice_mut(rhs, n, k);
        let Ok(mut buf) = MemBuffer::try_new(sym.solve_in_place_scratch::<T>(k, FACTOR_PAR)) else {
            return false;
        };
        LltRef::new(sym, &self.values).solve_in_place_with_conj(
            Conj::No,
            m,
            FACTOR_PAR,
            MemStack::new(&mut buf),
        );
        rhs.iter().all(|v| v.finite())
    }
}
