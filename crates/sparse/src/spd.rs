//! faer's sparse Cholesky with the symbolic analysis done once per pattern.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::LltError;
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par, Side};

use crate::SparseError;

/// Parallelism of the numeric factorisation and of the triangular solves: sequential.
/// Measured on the 2-core CI machine under load (release, 200k-face saddle, 100k unknowns):
/// faer's Rayon solve of the ARAP Laplacian took 190–300 ms per two-column solve against
/// 24 ms sequentially, and the factorisation was no faster in parallel. Callers parallelise
/// one level up instead (one piece per Rayon task).
const FACTOR_PAR: Par = Par::Seq;

/// Values a factorisation accepts: `f64` (real symmetric) and [`faer::c64`] (Hermitian).
pub trait Value: ComplexField + Copy {
    /// True when no component is NaN or infinite.
    fn finite(&self) -> bool;
    /// The complex conjugate (the value itself for reals).
    fn conj_value(&self) -> Self;
}

impl Value for f64 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
    fn conj_value(&self) -> Self {
        *self
    }
}

impl Value for faer::c64 {
    fn finite(&self) -> bool {
        self.re.is_finite() && self.im.is_finite()
    }
    fn conj_value(&self) -> Self {
        self.conj()
    }
}

/// The pattern of the lower triangle of an n×n SPD (HPD) matrix, with its symbolic
/// Cholesky factorisation (fill-reducing AMD ordering, elimination tree, supernodes).
/// Computing it is the expensive, value-independent part; factor it as often as needed.
pub struct SpdPattern {
    /// Number of (row, col) entries given, duplicates included; values must match.
    entries: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    llt: SymbolicCholesky<usize>,
}

/// A numeric Cholesky factorisation L Lᴴ = P A Pᵀ of an [`SpdPattern`], real symmetric or
/// complex Hermitian.
pub struct SpdFactor<'a, T: Value = f64> {
    pattern: &'a SpdPattern,
    l_values: Vec<T>,
    /// Set when the last [`SpdFactor::refactor`] failed: L is then unusable.
    failed: Option<SparseError>,
}

impl std::fmt::Debug for SpdPattern {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpdPattern")
            .field("n", &self.n())
            .field("entries", &self.entries)
            .field("factor_entries", &self.llt.len_val())
            .finish()
    }
}

impl<T: Value> std::fmt::Debug for SpdFactor<'_, T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpdFactor")
            .field("pattern", self.pattern)
            .field("failed", &self.failed)
            .finish()
    }
}

fn oom(n: usize) -> SparseError {
    SparseError::OutOfMemory { n }
}

impl SpdPattern {
    /// Analyses the pattern of an n×n matrix given as the (row, col) of every entry of its
    /// lower triangle (row ≥ col); duplicates are allowed (their values are summed).
    ///
    /// # Errors
    /// [`SparseError::IndexOutOfRange`], [`SparseError::UpperEntry`], or
    /// [`SparseError::OutOfMemory`].
    pub fn new(n: usize, pairs: &[(usize, usize)]) -> Result<Self, SparseError> {
        for &(row, col) in pairs {
            if row >= n || col >= n {
                return Err(SparseError::IndexOutOfRange { row, col, n });
            }
            if row < col {
                return Err(SparseError::UpperEntry { row, col });
            }
        }
        let idx: Vec<Pair<usize, usize>> = pairs.iter().map(|&(r, c)| Pair::new(r, c)).collect();
        let (symbolic, argsort) =
            SymbolicSparseColMat::try_new_from_indices(n, n, &idx).map_err(|_| oom(n))?;
        let llt = factorize_symbolic_cholesky(
            symbolic.as_ref(),
            Side::Lower,
            Default::default(),
            Default::default(),
        )
        .map_err(|_| oom(n))?;
        Ok(Self {
            entries: pairs.len(),
            symbolic,
            argsort,
            llt,
        })
    }

    /// The matrix size n.
    pub fn n(&self) -> usize {
        self.llt.nrows()
    }

    /// Number of entries (pairs) the values must match.
    pub fn entries(&self) -> usize {
        self.entries
    }

    /// Factorises the matrix with these values (one per pair given to [`SpdPattern::new`],
    /// in that order; duplicates summed).
    ///
    /// # Errors
    /// [`SparseError::ValueCount`], [`SparseError::NonFiniteValue`],
    /// [`SparseError::NotPositiveDefinite`] or [`SparseError::OutOfMemory`].
    pub fn factor<T: Value>(&self, values: &[T]) -> Result<SpdFactor<'_, T>, SparseError> {
        let mut l_values = Vec::new();
        l_values
            .try_reserve_exact(self.llt.len_val())
            .map_err(|_| oom(self.n()))?;
        l_values.resize(self.llt.len_val(), T::zero_impl());
        let mut f = SpdFactor {
            pattern: self,
            l_values,
            failed: None,
        };
        f.refactor(values)?;
        Ok(f)
    }

    /// The numeric factorisation into `l`, which has the symbolic factor's length.
    fn factor_into<T: Value>(&self, values: &[T], l: &mut [T]) -> Result<(), SparseError> {
        if values.len() != self.entries {
            return Err(SparseError::ValueCount {
                expected: self.entries,
                got: values.len(),
            });
        }
        if let Some(entry) = values.iter().position(|v| !v.finite()) {
            return Err(SparseError::NonFiniteValue { entry });
        }
        let n = self.n();
        let mat = SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, values)
            .map_err(|_| oom(n))?;
        let mut buf = MemBuffer::try_new(
            self.llt
                .factorize_numeric_llt_scratch::<T>(FACTOR_PAR, Default::default()),
        )
        .map_err(|_| oom(n))?;
        let result = self.llt.factorize_numeric_llt(
            l,
            mat.as_ref(),
            Side::Lower,
            Default::default(),
            FACTOR_PAR,
            MemStack::new(&mut buf),
            Default::default(),
        );
        match result {
            Ok(_) => Ok(()),
            // faer's pivot index is in its fill-reducing order and counted differently by
            // its simplicial and supernodal paths: not reported as a caller's unknown.
            Err(LltError::NonPositivePivot { .. }) => Err(SparseError::NotPositiveDefinite { n }),
        }
    }
}

impl<T: Value> SpdFactor<'_, T> {
    /// Refactorises with new values on the same pattern (the symbolic analysis and L's
    /// storage are reused). After an error the factor is unusable until a later
    /// `refactor` succeeds (solves return that error).
    ///
    /// # Errors
    /// As [`SpdPattern::factor`].
    pub fn refactor(&mut self, values: &[T]) -> Result<(), SparseError> {
        let r = self.pattern.factor_into(values, &mut self.l_values);
        self.failed = r.clone().err();
        r
    }

    /// The matrix size n.
    pub fn n(&self) -> usize {
        self.pattern.n()
    }

    /// Solves A x = b in place for `k` right-hand sides stored column-major in `rhs`
    /// (`rhs.len() == n·k`; column c is `rhs[c·n..(c + 1)·n]`).
    ///
    /// # Errors
    /// [`SparseError::RhsLength`], [`SparseError::NonFiniteSolution`], the error of a failed
    /// [`SpdFactor::refactor`], or [`SparseError::OutOfMemory`].
    pub fn solve_in_place(&self, rhs: &mut [T], k: usize) -> Result<(), SparseError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let sym = &self.pattern.llt;
        let n = sym.nrows();
        if rhs.len() != n * k {
            return Err(SparseError::RhsLength {
                expected: n * k,
                got: rhs.len(),
            });
        }
        if n == 0 {
            return Ok(());
        }
        let m = MatMut::from_column_major_slice_mut(rhs, n, k);
        let mut buf = MemBuffer::try_new(sym.solve_in_place_scratch::<T>(k, FACTOR_PAR))
            .map_err(|_| oom(n))?;
        LltRef::new(sym, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            m,
            FACTOR_PAR,
            MemStack::new(&mut buf),
        );
        if rhs.iter().all(|v| v.finite()) {
            Ok(())
        } else {
            Err(SparseError::NonFiniteSolution)
        }
    }
}
