//! The supernodal L Lᵀ solve against the matrix it factors (M x = b) and against faer's own
//! solve on the same factor, on patterns that give one-column supernodes without rows below
//! (diagonal), one dense supernode, and the many narrow supernodes of a grid's two-ring
//! stencil (the shape of A G Aᵀ).

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use common::{Spd, banded_with_dense_border, grid_two_ring, max_abs, rhs};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholeskyRaw};
use faer::{Conj, MatMut, Par};
use flatcut_sparse::{GROUP_COLUMNS, GROUP_MIN_ROWS, solve_llt_in_place};

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
    check(&grid_two_ring(20), 20, 400);
}

#[test]
fn a_banded_matrix_with_a_dense_border() {
    // Narrow supernodes whose rows below reach one far block: the scatter and gather of
    // the rows below a supernode, beyond its own columns.
    check(&banded_with_dense_border(300), 2, 300);
}

/// The solve as it was before supernodes were swept in groups: column by column, forward
/// an axpy into the rows below, backward a dot product with them in four interleaved
/// partial sums. The grouped sweeps must give these bits exactly.
fn column_by_column(symbolic: &SymbolicSupernodalCholesky<u32>, values: &[f64], x: &mut [f64]) {
    fn dot(a: &[f64], b: &[f64]) -> f64 {
        let n = a.len().min(b.len());
        let n4 = n - n % 4;
        let mut partial = [0.0; 4];
        for i in (0..n4).step_by(4) {
            for k in 0..4 {
                partial[k] += a[i + k] * b[i + k];
            }
        }
        let mut sum = (partial[0] + partial[2]) + (partial[1] + partial[3]);
        for i in n4..n {
            sum += a[i] * b[i];
        }
        sum
    }
    let supernode = |s: usize| {
        let start = symbolic.supernode_begin()[s] as usize;
        let size = symbolic.supernode_end()[s] as usize - start;
        let ptr = symbolic.col_ptr_for_row_idx();
        let pattern =
            &symbolic.row_idx()[ptr[s] as usize..][..symbolic.nnz_per_super()[s] as usize];
        let vals = symbolic.col_ptr_for_val();
        let block = &values[vals[s] as usize..vals[s + 1] as usize];
        (start, size, pattern, block)
    };
    for s in 0..symbolic.n_supernodes() {
        let (start, size, pattern, block) = supernode(s);
        let rows = size + pattern.len();
        let mut below = vec![0.0; pattern.len()];
        for j in 0..size {
            let column = &block[j * rows..(j + 1) * rows];
            let xj = x[start + j] / column[j];
            x[start + j] = xj;
            for i in j + 1..size {
                x[start + i] -= column[i] * xj;
            }
            for (t, l) in below.iter_mut().zip(&column[size..]) {
                *t += l * xj;
            }
        }
        for (&i, t) in pattern.iter().zip(&below) {
            x[i as usize] -= t;
        }
    }
    for s in (0..symbolic.n_supernodes()).rev() {
        let (start, size, pattern, block) = supernode(s);
        let rows = size + pattern.len();
        let below: Vec<f64> = pattern.iter().map(|&i| x[i as usize]).collect();
        for j in (0..size).rev() {
            let column = &block[j * rows..(j + 1) * rows];
            let acc = x[start + j]
                - dot(&column[j + 1..size], &x[start + j + 1..start + size])
                - dot(&column[size..], &below);
            x[start + j] = acc / column[j];
        }
    }
}

#[test]
fn grouped_sweeps_give_the_column_by_column_bits() {
    // Patterns with supernodes on both sides of the grouping thresholds: narrow ones, wide
    // ones with few rows below, and wide ones with many (which the test asserts exist).
    let mut grouped = 0;
    for matrix in [
        grid_two_ring(20),
        grid_two_ring(31).amd_ordered(),
        banded_with_dense_border(300),
        Spd::new(40, |_, _| true),
    ] {
        let n = matrix.n();
        let (symbolic, values) = matrix.factor();
        let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
            panic!("forced supernodal");
        };
        grouped += (0..supernodal.n_supernodes())
            .filter(|&s| {
                let width =
                    (supernodal.supernode_end()[s] - supernodal.supernode_begin()[s]) as usize;
                let below = supernodal.nnz_per_super()[s] as usize;
                width >= GROUP_COLUMNS && below >= GROUP_MIN_ROWS
            })
            .count();
        let mut x = rhs(n);
        solve_llt_in_place(supernodal, &values, &mut x);
        let mut reference = rhs(n);
        column_by_column(supernodal, &values, &mut reference);
        for (i, (a, b)) in x.iter().zip(&reference).enumerate() {
            assert_eq!(
                a.to_bits(),
                b.to_bits(),
                "unknown {i} of {n}: {a:e} vs {b:e}"
            );
        }
    }
    assert!(
        grouped >= 3,
        "{grouped} grouped supernodes: the test does not exercise them"
    );
}
