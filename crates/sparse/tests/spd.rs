//! The SPD solver against independent evidence: residuals of the original matrix (applied
//! from the triplets, not from the factor), a closed-form solution, scaling identities, and
//! one test per error.

#![allow(clippy::unwrap_used)]

use flatcut_sparse::{SparseError, SpdPattern, Triplets, c64};

/// y = A x for the symmetric/Hermitian matrix whose lower triangle the triplets hold.
fn apply_real(t: &Triplets<f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    for (&(r, c), &v) in t.pairs().iter().zip(t.values()) {
        y[r] += v * x[c];
        if r != c {
            y[c] += v * x[r];
        }
    }
    y
}

fn apply_complex(t: &Triplets<c64>, x: &[c64]) -> Vec<c64> {
    let mut y = vec![c64::new(0.0, 0.0); x.len()];
    for (&(r, c), &v) in t.pairs().iter().zip(t.values()) {
        y[r] += v * x[c];
        if r != c {
            y[c] += v.conj() * x[r];
        }
    }
    y
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// The 5-point Laplacian of an m×m grid plus `shift`·I, with each off-diagonal coupling
/// pushed as two half entries (duplicates must be summed) and in either triangle.
fn grid_laplacian(m: usize, shift: f64) -> Triplets<f64> {
    let n = m * m;
    let mut t = Triplets::new(n);
    for j in 0..m {
        for i in 0..m {
            let v = i + m * j;
            t.push(v, v, 4.0 + shift);
            if i + 1 < m {
                t.push(v + 1, v, -0.5);
                t.push(v, v + 1, -0.5); // upper half: mirrored
            }
            if j + 1 < m {
                t.push(v + m, v, -1.0);
            }
        }
    }
    t
}

/// ‖Ax − b‖ ≤ c·ε·n·‖b‖ (well conditioned: Laplacian + I), for two right-hand sides at once.
#[test]
fn residual_of_a_shifted_grid_laplacian() {
    let m = 30;
    let n = m * m;
    let t = grid_laplacian(m, 1.0);
    let pattern = t.pattern().unwrap();
    assert_eq!(pattern.n(), n);
    let factor = pattern.factor(t.values()).unwrap();
    let b: Vec<f64> = (0..2 * n)
        .map(|k| ((k * 37 % 101) as f64 - 50.0) / 7.0)
        .collect();
    let mut x = b.clone();
    factor.solve_in_place(&mut x, 2).unwrap();
    for c in 0..2 {
        let (xc, bc) = (&x[c * n..(c + 1) * n], &b[c * n..(c + 1) * n]);
        let ax = apply_real(&t, xc);
        let r: Vec<f64> = ax.iter().zip(bc).map(|(a, b)| a - b).collect();
        assert!(
            norm(&r) <= 10.0 * f64::EPSILON * n as f64 * norm(bc),
            "{}",
            norm(&r)
        );
    }
}

/// A closed form: the Dirichlet problem −u'' = 0 on a path with u(0) = 0, u(n+1) = 1 has the
/// linear solution u_i = i/(n+1).
#[test]
fn path_dirichlet_problem_is_linear() {
    let n = 50;
    let mut t = Triplets::new(n);
    for i in 0..n {
        t.push(i, i, 2.0);
        if i + 1 < n {
            t.push(i + 1, i, -1.0);
        }
    }
    let pattern = t.pattern().unwrap();
    let factor = pattern.factor(t.values()).unwrap();
    let mut x = vec![0.0; n];
    x[n - 1] = 1.0; // the boundary value 1 moved to the right-hand side
    factor.solve_in_place(&mut x, 1).unwrap();
    for (i, v) in x.iter().enumerate() {
        let exact = (i + 1) as f64 / (n + 1) as f64;
        assert!((v - exact).abs() < 1e-13, "u_{i} = {v}, exact {exact}");
    }
}

/// Hermitian systems (the complex LSCM form): residual of the original matrix, and entries
/// given above the diagonal are the conjugate mirror of the same matrix.
#[test]
fn hermitian_residual_and_mirrored_entries() {
    let m = 12;
    let n = m * m;
    let mut lower = Triplets::<c64>::new(n);
    let mut upper = Triplets::<c64>::new(n);
    for v in 0..n {
        lower.push(v, v, c64::new(5.0, 0.0));
        upper.push(v, v, c64::new(5.0, 0.0));
        for w in [v + 1, v + m] {
            if w < n {
                // H[w, v] = −1 + 0.5 i, so H[v, w] = −1 − 0.5 i.
                lower.push(w, v, c64::new(-1.0, 0.5));
                upper.push(v, w, c64::new(-1.0, -0.5));
            }
        }
    }
    let b: Vec<c64> = (0..n)
        .map(|k| c64::new((k % 7) as f64 - 3.0, (k % 5) as f64))
        .collect();
    let mut xs = Vec::new();
    for t in [&lower, &upper] {
        let pattern = t.pattern().unwrap();
        let factor = pattern.factor(t.values()).unwrap();
        let mut x = b.clone();
        factor.solve_in_place(&mut x, 1).unwrap();
        let ax = apply_complex(t, &x);
        let r: f64 = ax
            .iter()
            .zip(&b)
            .map(|(a, b)| (a - b).norm().powi(2))
            .sum::<f64>();
        let nb: f64 = b.iter().map(|z| z.norm().powi(2)).sum::<f64>();
        assert!(r.sqrt() <= 10.0 * f64::EPSILON * n as f64 * nb.sqrt());
        xs.push(x);
    }
    for (a, b) in xs[0].iter().zip(&xs[1]) {
        assert!((a - b).norm() < 1e-13);
    }
}

/// Refactorising with the values doubled halves the solution, and matches a fresh factor.
#[test]
fn refactor_reuses_the_analysis() {
    let t = grid_laplacian(10, 0.5);
    let pattern = t.pattern().unwrap();
    let mut factor = pattern.factor(t.values()).unwrap();
    let b: Vec<f64> = (0..100).map(|k| (k as f64).sin()).collect();
    let mut x1 = b.clone();
    factor.solve_in_place(&mut x1, 1).unwrap();
    let doubled: Vec<f64> = t.values().iter().map(|v| 2.0 * v).collect();
    factor.refactor(&doubled).unwrap();
    let mut x2 = b.clone();
    factor.solve_in_place(&mut x2, 1).unwrap();
    let fresh = pattern.factor(&doubled).unwrap();
    let mut x3 = b.clone();
    fresh.solve_in_place(&mut x3, 1).unwrap();
    for k in 0..100 {
        assert!((x2[k] - 0.5 * x1[k]).abs() < 1e-14 * x1[k].abs().max(1.0));
        assert_eq!(x2[k], x3[k]);
    }
}

/// An indefinite matrix is refused by name; a failed refactor poisons the solves until a
/// good one.
#[test]
fn not_positive_definite_is_refused() {
    // diag(1, 2, −3, 4, 5) with a chain of tiny couplings (so that AMD has something to do).
    let n = 5;
    let mut t = Triplets::new(n);
    for (i, d) in [1.0, 2.0, -3.0, 4.0, 5.0].into_iter().enumerate() {
        t.push(i, i, d);
        if i + 1 < n {
            t.push(i + 1, i, 1e-3);
        }
    }
    let pattern = t.pattern().unwrap();
    let err = pattern.factor(t.values()).unwrap_err();
    assert_eq!(err, SparseError::NotPositiveDefinite { n: 5 });

    let good: Vec<f64> = t.values().iter().map(|v| v.abs()).collect();
    let mut factor = pattern.factor(&good).unwrap();
    assert_eq!(factor.refactor(t.values()).unwrap_err(), err);
    let mut x = vec![1.0; n];
    assert_eq!(factor.solve_in_place(&mut x, 1).unwrap_err(), err);
    factor.refactor(&good).unwrap();
    factor.solve_in_place(&mut x, 1).unwrap();
    // Nearly diagonal: x ≈ (1/1, 1/2, 1/3, 1/4, 1/5).
    for (i, v) in x.iter().enumerate() {
        assert!((v - 1.0 / (i + 1) as f64).abs() < 1e-2, "x_{i} = {v}");
    }
}

#[test]
fn bad_input_errors() {
    assert_eq!(
        SpdPattern::new(3, &[(0, 0), (3, 1)]).unwrap_err(),
        SparseError::IndexOutOfRange {
            row: 3,
            col: 1,
            n: 3
        }
    );
    assert_eq!(
        SpdPattern::new(3, &[(0, 0), (0, 2)]).unwrap_err(),
        SparseError::UpperEntry { row: 0, col: 2 }
    );
    let pattern = SpdPattern::new(2, &[(0, 0), (1, 1), (1, 0)]).unwrap();
    assert_eq!(
        pattern.factor(&[1.0, 1.0]).unwrap_err(),
        SparseError::ValueCount {
            expected: 3,
            got: 2
        }
    );
    assert_eq!(
        pattern.factor(&[1.0, f64::NAN, 0.0]).unwrap_err(),
        SparseError::NonFiniteValue { entry: 1 }
    );
    let factor = pattern.factor(&[2.0, 2.0, -1.0]).unwrap();
    let mut short = vec![1.0; 3];
    assert_eq!(
        factor.solve_in_place(&mut short, 2).unwrap_err(),
        SparseError::RhsLength {
            expected: 4,
            got: 3
        }
    );
    let mut inf = vec![f64::INFINITY, 0.0];
    assert_eq!(
        factor.solve_in_place(&mut inf, 1).unwrap_err(),
        SparseError::NonFiniteSolution
    );
    // The messages say what to do.
    let msg = SparseError::UpperEntry { row: 0, col: 2 }.to_string();
    assert!(msg.contains("lower triangle"), "{msg}");
}
