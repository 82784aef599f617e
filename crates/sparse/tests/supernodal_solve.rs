//! The supernodal L Lᵀ solve against the matrix it factors (M x = b) and against faer's own
//! solve on the same factor, on patterns that give one-column supernodes without rows below
//! (diagonal), one dense supernode, and the many narrow supernodes of a grid's two-ring
//! stencil (the shape of A G Aᵀ).

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use flatcut_sparse::solve_llt_in_place;

/// A symmetric positive definite matrix as dense rows and as full (both triangles) CSC.
struct Spd {
    dense: Vec<Vec<f64>>,
    col_ptr: Vec<u32>,
    row_idx: Vec<u32>,
    values: Vec<f64>,
}

impl Spd {
    /// Off-diagonal entries where `coupled(i, j)`, with values from a fixed pseudo-random
    /// sequence in [−1, 1]; the diagonal is the row's absolute sum plus one (strictly
    /// diagonally dominant, hence positive definite).
    fn new(n: usize, coupled: impl Fn(usize, usize) -> bool) -> Self {
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

    fn n(&self) -> usize {
        self.dense.len()
    }

    /// faer's supernodal symbolic and numeric factors, in the matrix's own order.
    fn factor(&self) -> (SymbolicCholesky<u32>, Vec<f64>) {
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

    fn times(&self, x: &[f64]) -> Vec<f64> {
        self.dense
            .iter()
            .map(|row| row.iter().zip(x).map(|(a, b)| a * b).sum())
            .collect()
    }
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0)
        .collect()
}

fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, |m, x| m.max(x.abs()))
}

/// Solves M x = b with `solve_llt_in_place` and checks the residual and faer's solve.
fn check(matrix: &Spd, min_supernodes: usize, max_supernodes: usize) {
    let n = matrix.n();
    let (symbolic, values) = matrix.factor();
    let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
        panic!("forced supernodal");
    };
    let supernodes = supernodal.n_supernodes();
    assert!(
        (min_supernodes..=max_supernodes).contains(&supernodes),
        "{supernodes} supernodes: the pattern does not exercise what the test names"
    );
    let b = rhs(n);
    let mut x = b.clone();
    solve_llt_in_place(supernodal, &values, &mut x);

    // The defining identity: M x = b (M's entries are O(1), its diagonal ≤ ~n).
    let residual = max_abs(matrix.times(&x).iter().zip(&b).map(|(mx, b)| mx - b));
    assert!(residual < 1e-13 * n as f64, "‖M x − b‖∞ = {residual:e}");

    // faer's own solve on the same factor.
    let mut faer_x = b.clone();
    let mut buf = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
    LltRef::<'_, u32, f64>::new(&symbolic, &values).solve_in_place_with_conj(
        Conj::No,
        MatMut::from_column_major_slice_mut(&mut faer_x, n, 1),
        Par::Seq,
        MemStack::new(&mut buf),
    );
    let scale = max_abs(faer_x.iter().copied());
    let difference = max_abs(x.iter().zip(&faer_x).map(|(a, b)| a - b));
    assert!(
        difference <= 1e-14 * scale,
        "differs from faer's solve by {difference:e} (scale {scale:e})"
    );
}

#[test]
fn a_diagonal_matrix_is_divided_out() {
    // Every column its own supernode with no rows below it; x = b / d in closed form, up
    // to the two roundings of dividing by √d twice.
    let matrix = Spd::new(50, |_, _| false);
    check(&matrix, 50, 50);
    let (symbolic, values) = matrix.factor();
    let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
        panic!("forced supernodal");
    };
    let mut x = rhs(50);
    solve_llt_in_place(supernodal, &values, &mut x);
    for (i, (xi, bi)) in x.iter().zip(rhs(50)).enumerate() {
        let exact = bi / matrix.dense[i][i];
        assert!(
            (xi - exact).abs() <= 4.0 * f64::EPSILON * exact.abs(),
            "row {i}"
        );
    }
}

#[test]
fn a_dense_matrix_is_one_supernode() {
    check(&Spd::new(40, |_, _| true), 1, 1);
}

#[test]
fn a_grid_two_ring_stencil_has_many_narrow_supernodes() {
    // 20 × 20 grid, vertices coupled when within two steps (the reach of A G Aᵀ).
    let side = 20;
    let coupled = |i: usize, j: usize| {
        let (ri, ci) = ((i / side) as i64, (i % side) as i64);
        let (rj, cj) = ((j / side) as i64, (j % side) as i64);
        (ri - rj).abs() + (ci - cj).abs() <= 2
    };
    check(&Spd::new(side * side, coupled), 20, 400);
}

#[test]
fn a_banded_matrix_with_a_dense_border() {
    // Narrow supernodes whose rows below reach one far block: the scatter and gather of
    // the rows below a supernode, beyond its own columns.
    let n = 300;
    check(
        &Spd::new(n, |i, j| {
            i - j <= 3 || i >= n - 10 || (i * 31 + j * 17) % 97 == 0
        }),
        2,
        300,
    );
}
