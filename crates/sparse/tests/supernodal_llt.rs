//! Our supernodal numeric L Lᵀ against faer's numeric factorisation of the same matrix (the
//! same factor to round-off), against the matrix it factors (M x = b through the factor),
//! and by identities: a matrix scaled by 4 gives L scaled by 2 bit for bit, and a matrix
//! that is not positive definite is refused. The patterns exercise every path: register
//! tiles for narrow supernodes and updates, faer's matrix product for updates from
//! descendants at least `GEMM_MIN_DEPTH` wide, faer's dense Cholesky for supernodes at
//! least `DENSE_MIN_COLUMNS` wide.

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

mod common;

use common::{Spd, banded_with_dense_border, grid_two_ring, max_abs, rhs};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use flatcut_sparse::{
    DENSE_MIN_COLUMNS, GEMM_MIN_DEPTH, SparseError, SupernodalLltPlan, solve_llt_in_place,
};

/// Supernode widths of a symbolic factor.
fn widths(symbolic: &SymbolicSupernodalCholesky<u32>) -> Vec<usize> {
    symbolic
        .supernode_begin()
        .iter()
        .zip(symbolic.supernode_end())
        .map(|(&b, &e)| (e - b) as usize)
        .collect()
}

/// The factor's entries that are L's: each supernode's own columns on and below the
/// diagonal, and the rows below them.
fn l_entries(symbolic: &SymbolicSupernodalCholesky<u32>, values: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    let ptr = symbolic.col_ptr_for_val();
    for (s, &size) in widths(symbolic).iter().enumerate() {
        let block = &values[ptr[s] as usize..ptr[s + 1] as usize];
        let rows = block.len() / size;
        for j in 0..size {
            out.extend_from_slice(&block[j * rows + j..(j + 1) * rows]);
        }
    }
    out
}

/// Our factorisation of `values` (lower entries of `matrix`'s pattern).
fn factorize(matrix: &Spd, values: &[f64]) -> Result<Vec<f64>, SparseError> {
    let (symbolic, _) = matrix.factor();
    let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
        panic!("forced supernodal");
    };
    let n = matrix.n();
    let (col_ptr, row_idx, _) = matrix.lower();
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
    let plan = SupernodalLltPlan::new(supernodal, pattern).unwrap();
    let mut workspace = plan.workspace().unwrap();
    let mut l = vec![f64::NAN; supernodal.len_val()];
    plan.factorize(supernodal, values, &mut l, &mut workspace)?;
    Ok(l)
}

/// Checks our factor against faer's and against M, and returns the supernode widths.
fn check(matrix: &Spd) -> Vec<usize> {
    let n = matrix.n();
    let (symbolic, faer_values) = matrix.factor();
    let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
        panic!("forced supernodal");
    };
    let ours = factorize(matrix, &matrix.lower().2).unwrap();

    let (l_faer, l_ours) = (
        l_entries(supernodal, &faer_values),
        l_entries(supernodal, &ours),
    );
    let scale = max_abs(l_faer.iter().copied());
    let difference = max_abs(l_faer.iter().zip(&l_ours).map(|(a, b)| a - b));
    assert!(
        difference <= 1e-14 * scale * (n as f64).sqrt(),
        "differs from faer's factor by {difference:e} (scale {scale:e})"
    );
    assert!(l_ours.iter().all(|v| v.is_finite()), "L's entries are set");

    // M x = b through our factor.
    let b = rhs(n);
    let mut x = b.clone();
    solve_llt_in_place(supernodal, &ours, &mut x);
    let residual = max_abs(matrix.times(&x).iter().zip(&b).map(|(mx, b)| mx - b));
    assert!(residual < 1e-13 * n as f64, "‖M x − b‖∞ = {residual:e}");
    widths(supernodal)
}

#[test]
fn a_diagonal_matrix_factors_to_its_square_roots() {
    let matrix = Spd::new(50, |_, _| false);
    assert_eq!(check(&matrix), vec![1; 50]);
    let (symbolic, _) = matrix.factor();
    let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
        panic!("forced supernodal");
    };
    let l = l_entries(supernodal, &factorize(&matrix, &matrix.lower().2).unwrap());
    for (i, v) in l.iter().enumerate() {
        assert_eq!(*v, matrix.dense[i][i].sqrt(), "row {i}");
    }
}

#[test]
fn a_small_dense_matrix_is_one_supernode_of_register_tiles() {
    // 13 columns: three blocks of four and one of one, rows in tiles of 8 and single rows.
    let widths = check(&Spd::new(13, |_, _| true));
    assert_eq!(widths, vec![13]);
    assert!(widths[0] < DENSE_MIN_COLUMNS);
}

#[test]
fn a_wide_dense_matrix_goes_to_faers_dense_cholesky() {
    let widths = check(&Spd::new(40, |_, _| true));
    assert_eq!(widths, vec![40]);
    assert!(widths[0] >= DENSE_MIN_COLUMNS);
}

#[test]
fn a_grid_two_ring_stencil_in_amd_order_takes_every_path() {
    let widths = check(&grid_two_ring(20).amd_ordered());
    assert!(widths.iter().filter(|&&w| w < 4).count() > 20, "{widths:?}");
    assert!(
        widths
            .iter()
            .any(|&w| (GEMM_MIN_DEPTH..DENSE_MIN_COLUMNS).contains(&w)),
        "{widths:?}"
    );
    assert!(widths.iter().any(|&w| w >= DENSE_MIN_COLUMNS), "{widths:?}");
}

#[test]
fn a_banded_matrix_with_a_dense_border() {
    let widths = check(&banded_with_dense_border(300));
    assert!(widths.len() > 2, "{widths:?}");
}

#[test]
fn scaling_by_four_scales_the_factor_by_two_bit_for_bit() {
    // Every operation is a product, sum, square root or quotient of values all scaled by
    // powers of two, each rounded once: the factor of 4 M is exactly 2 L.
    let matrix = grid_two_ring(16).amd_ordered();
    let values = matrix.lower().2;
    let quadrupled: Vec<f64> = values.iter().map(|v| 4.0 * v).collect();
    let (l, l4) = (
        factorize(&matrix, &values).unwrap(),
        factorize(&matrix, &quadrupled).unwrap(),
    );
    let (symbolic, _) = matrix.factor();
    let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
        panic!("forced supernodal");
    };
    let (l, l4) = (l_entries(supernodal, &l), l_entries(supernodal, &l4));
    for (k, (a, b)) in l.iter().zip(&l4).enumerate() {
        assert_eq!(2.0 * a, *b, "entry {k}");
    }
}

#[test]
fn a_matrix_that_is_not_positive_definite_is_refused() {
    for (matrix, column) in [
        (grid_two_ring(20).amd_ordered(), 0),
        (grid_two_ring(20).amd_ordered(), 399),
        (Spd::new(13, |_, _| true), 7),
        (Spd::new(40, |_, _| true), 30),
    ] {
        // A diagonal entry made negative: the pivot of its column, or of a later one,
        // is ≤ 0 (the leading minor through it is not positive).
        let n = matrix.n();
        let (col_ptr, row_idx, mut values) = matrix.lower();
        let k = (col_ptr[column] as usize..col_ptr[column + 1] as usize)
            .find(|&k| row_idx[k] as usize == column)
            .unwrap();
        values[k] = -values[k];
        assert_eq!(
            factorize(&matrix, &values),
            Err(SparseError::NotPositiveDefinite { n }),
            "column {column} of {n}"
        );
        values[k] = f64::NAN;
        assert!(factorize(&matrix, &values).is_err(), "NaN, column {column}");
    }
}

#[test]
fn a_pattern_that_is_not_the_factors_is_refused() {
    let matrix = grid_two_ring(10);
    let (symbolic, _) = matrix.factor();
    let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
        panic!("forced supernodal");
    };
    let n = matrix.n();
    // An entry far below the diagonal that the factor's pattern does not have.
    let (mut col_ptr, mut row_idx, _) = matrix.lower();
    row_idx.insert(col_ptr[1] as usize, (n - 1) as u32);
    for p in &mut col_ptr[1..] {
        *p += 1;
    }
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
    match SupernodalLltPlan::new(supernodal, pattern) {
        Err(SparseError::PatternMismatch { reason }) => {
            assert!(reason.contains("outside the factor's pattern"), "{reason}")
        }
        other => panic!("{other:?}"),
    }
    // A pattern of another size.
    let small = grid_two_ring(5);
    let (col_ptr, row_idx, _) = small.lower();
    let pattern = SymbolicSparseColMatRef::new_checked(25, 25, &col_ptr, None, &row_idx);
    assert!(matches!(
        SupernodalLltPlan::new(supernodal, pattern),
        Err(SparseError::PatternMismatch { .. })
    ));
}
