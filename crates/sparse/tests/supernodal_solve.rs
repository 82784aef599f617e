//! The supernodal L Lᵀ solve against the matrix it factors (M x = b) and against faer's own
//! solve on the same factor, on patterns that give one-column supernodes without rows below
//! (diagonal), one dense supernode, and the many narrow supernodes of a grid's two-ring
//! stencil (the shape of A G Aᵀ).

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use common::{Spd, banded_with_dense_border, grid_two_ring, max_abs, rhs};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholeskyRaw};
use faer::{Conj, MatMut, Par};
use flatcut_sparse::solve_llt_in_place;

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
