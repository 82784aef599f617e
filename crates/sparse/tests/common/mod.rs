//! Test matrices shared by the supernodal solve and factorisation tests.
#![allow(dead_code, clippy::unwrap_used)]

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::{SupernodalThreshold, amd};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Par, Side};

/// A symmetric positive definite matrix as dense rows and as full (both triangles) CSC.
pub struct Spd {
    pub dense: Vec<Vec<f64>>,
    pub col_ptr: Vec<u32>,
    pub row_idx: Vec<u32>,
    pub values: Vec<f64>,
}

impl Spd {
    /// Off-diagonal entries where `coupled(i, j)`, with values from a fixed pseudo-random
    /// sequence in [−1, 1]; the diagonal is the row's absolute sum plus one (strictly
    /// diagonally dominant, hence positive definite).
    pub fn new(n: usize, coupled: impl Fn(usize, usize) -> bool) -> Self {
        let mut dense = vec![vec![0.0; n]; n];
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for j in 0..n {
            for i in j + 1..n {
                if coupled(i, j) {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    let v = (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
                    dense[i][j] = v;
                    dense[j][i] = v;
                }
            }
        }
        for i in 0..n {
            dense[i][i] = dense[i].iter().map(|v| v.abs()).sum::<f64>() + 1.0;
        }
        Self::from_dense(dense)
    }

    /// The matrix of `dense`'s nonzero entries.
    pub fn from_dense(dense: Vec<Vec<f64>>) -> Self {
        let n = dense.len();
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if dense[i][j] != 0.0 {
                    row_idx.push(i as u32);
                    values.push(dense[i][j]);
                }
            }
            col_ptr.push(row_idx.len() as u32);
        }
        Spd {
            dense,
            col_ptr,
            row_idx,
            values,
        }
    }

    pub fn n(&self) -> usize {
        self.dense.len()
    }

    /// faer's supernodal symbolic and numeric factors, in the matrix's own order.
    pub fn factor(&self) -> (SymbolicCholesky<u32>, Vec<f64>) {
        let n = self.n();
        let pattern =
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern, Side::Upper, SymmetricOrdering::Identity, params)
                .unwrap();
        let mut values = vec![0.0; symbolic.len_val()];
        let mut scratch = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut values,
                SparseColMatRef::new(pattern, &self.values),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .unwrap();
        (symbolic, values)
    }

    /// The same matrix in faer's AMD order (as `flatcut_flattenable` stores A G Aᵀ): row i
    /// of the result is row `fwd[i]` of this one.
    pub fn amd_ordered(&self) -> Spd {
        let n = self.n();
        let (mut fwd, mut inv) = (vec![0u32; n], vec![0u32; n]);
        let pattern =
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let mut mem = MemBuffer::new(amd::order_maybe_unsorted_scratch::<u32>(
            n,
            self.row_idx.len(),
        ));
        amd::order_maybe_unsorted(
            &mut fwd,
            &mut inv,
            pattern,
            amd::Control::default(),
            MemStack::new(&mut mem),
        )
        .unwrap();
        let dense: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| self.dense[fwd[i] as usize][fwd[j] as usize])
                    .collect()
            })
            .collect();
        Spd::from_dense(dense)
    }

    /// The lower triangle (row ≥ col) as CSC: column pointers, rows, values.
    pub fn lower(&self) -> (Vec<u32>, Vec<u32>, Vec<f64>) {
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for j in 0..self.n() {
            for k in self.col_ptr[j] as usize..self.col_ptr[j + 1] as usize {
                if self.row_idx[k] as usize >= j {
                    row_idx.push(self.row_idx[k]);
                    values.push(self.values[k]);
                }
            }
            col_ptr.push(row_idx.len() as u32);
        }
        (col_ptr, row_idx, values)
    }

    pub fn times(&self, x: &[f64]) -> Vec<f64> {
        self.dense
            .iter()
            .map(|row| row.iter().zip(x).map(|(a, b)| a * b).sum())
            .collect()
    }
}

pub fn rhs(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0)
        .collect()
}

pub fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, |m, x| m.max(x.abs()))
}

/// A `side` × `side` grid, vertices coupled when within two steps (the reach of A G Aᵀ):
/// many narrow supernodes, a few wide ones at the top of the elimination tree.
pub fn grid_two_ring(side: usize) -> Spd {
    Spd::new(side * side, |i, j| {
        let (ri, ci) = ((i / side) as i64, (i % side) as i64);
        let (rj, cj) = ((j / side) as i64, (j % side) as i64);
        (ri - rj).abs() + (ci - cj).abs() <= 2
    })
}

/// A band of half-width 3 with a dense border of 10 rows and scattered far couplings:
/// narrow supernodes whose rows below reach one far block.
pub fn banded_with_dense_border(n: usize) -> Spd {
    Spd::new(n, |i, j| {
        i - j <= 3 || i >= n - 10 || (i * 31 + j * 17) % 97 == 0
    })
}
