//! A sparse symmetric positive definite solve (faer's sparse Cholesky, analysed once): the
//! Dirichlet block of the cotan Laplacian. Same shape as the wrapper in `flatcut_lscm`
//! (which trim may not depend on: see the crate DAG).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

/// Sequential: the patches are small and the machine's 2 cores are shared (the lscm crate
/// measured Rayon slower than sequential for solves of this size).
const PAR: Par = Par::Seq;

/// The pattern of the lower triangle of an n×n SPD matrix with its symbolic Cholesky.
pub(super) struct SpdPattern {
    entries: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    llt: SymbolicCholesky<usize>,
}

/// A numeric Cholesky factor of an [`SpdPattern`].
pub(super) struct SpdFactor<'a> {
    pattern: &'a SpdPattern,
    values: Vec<f64>,
}

impl SpdPattern {
    /// `pairs` are (row, col) with row ≥ col; duplicates are summed. `None` if faer refuses.
    pub(super) fn new(n: usize, pairs: &[(usize, usize)]) -> Option<Self> {
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

    /// Factorises with these values (one per pair). `None` if not positive definite.
    pub(super) fn factor(&self, values: &[f64]) -> Option<SpdFactor<'_>> {
        if values.len() != self.entries || values.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let mat =
            SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, values).ok()?;
        let mut l = Vec::new();
        l.try_reserve_exact(self.llt.len_val()).ok()?;
        l.resize(self.llt.len_val(), 0.0);
        let mut buf = MemBuffer::try_new(
            self.llt
                .factorize_numeric_llt_scratch::<f64>(PAR, Default::default()),
        )
        .ok()?;
        self.llt
            .factorize_numeric_llt(
                &mut l,
                mat.as_ref(),
                Side::Lower,
                Default::default(),
                PAR,
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

impl SpdFactor<'_> {
    /// Solves A x = b in place for `k` column-major right-hand sides. False if not finite.
    pub(super) fn solve_in_place(&self, rhs: &mut [f64], k: usize) -> bool {
        let sym = &self.pattern.llt;
        let n = sym.nrows();
        if rhs.len() != n * k {
            return false;
        }
        let m = MatMut::from_column_major_slice_mut(rhs, n, k);
        let Ok(mut buf) = MemBuffer::try_new(sym.solve_in_place_scratch::<f64>(k, PAR)) else {
            return false;
        };
        LltRef::new(sym, &self.values).solve_in_place_with_conj(
            Conj::No,
            m,
            PAR,
            MemStack::new(&mut buf),
        );
        rhs.iter().all(|v| v.is_finite())
    }
}
