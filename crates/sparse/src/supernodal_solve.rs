//! L Lᵀ x = b on a faer supernodal Cholesky factor, one right-hand side at a time.
//!
//! faer's own solve (`LltRef::solve_in_place_with_conj`) runs, per supernode, its generic
//! dense triangular solve and matrix product. On the two-ring patterns of A G Aᵀ most
//! supernodes are a few columns wide, and that dispatch costs more than the arithmetic:
//! at 1k faces one of faer's solves took a sixth of the instructions of a numeric
//! factorisation, and a step solves about three times per factorisation, so the solves
//! cost half as much as the factorisation itself. Here each supernode column is one
//! contiguous slice of L, swept once forward (an axpy into the rows below) and once
//! backward (a dot product with them).
//!
//! The layout read is faer's documented one (`crate::supernodes`).

use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;

use crate::supernodes::Supernodes;

/// Solves L Lᵀ x = b in place (`x` holds b on entry), L being the numeric supernodal
/// factor `values` on `symbolic`, in the factor's own (permuted) order.
///
/// # Panics
/// If `x.len()` is not the factor's dimension or `values` is shorter than the factor.
pub fn solve_llt_in_place(
    symbolic: &SymbolicSupernodalCholesky<u32>,
    values: &[f64],
    x: &mut [f64],
) {
    assert_eq!(x.len(), symbolic.nrows(), "right-hand side length");
    assert!(values.len() >= symbolic.len_val(), "factor values");
    // The loops below are plain slices; compiled inside `with_simd` they vectorise at the
    // machine's width. Rust does not fuse a * b + c, so every width rounds alike.
    pulp::Arch::new().dispatch(Solve {
        symbolic,
        values,
        x,
    });
}

struct Solve<'a> {
    symbolic: &'a SymbolicSupernodalCholesky<u32>,
    values: &'a [f64],
    x: &'a mut [f64],
}

impl pulp::WithSimd for Solve<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        solve(self.symbolic, self.values, self.x);
    }
}

#[inline(always)]
fn solve(symbolic: &SymbolicSupernodalCholesky<u32>, values: &[f64], x: &mut [f64]) {
    let supernodes = Supernodes::of(symbolic);
    let supernode = |s: usize| {
        let start = supernodes.begin[s] as usize;
        let size = supernodes.end[s] as usize - start;
        let block = &values[supernodes.val_ptr[s] as usize..supernodes.val_ptr[s + 1] as usize];
        (start, size, supernodes.pattern(s), block)
    };

    // The rows below a supernode's own columns, gathered once per supernode (instead of
    // once per column), so the inner loops run over contiguous slices.
    let mut below = vec![
        0.0;
        supernodes
            .pattern_len
            .iter()
            .map(|&l| l as usize)
            .max()
            .unwrap_or(0)
    ];

    // Forward: L y = b.
    for s in 0..symbolic.n_supernodes() {
        let (start, size, pattern, block) = supernode(s);
        let rows = size + pattern.len();
        let below = &mut below[..pattern.len()];
        below.fill(0.0);
        for j in 0..size {
            let column = &block[j * rows..(j + 1) * rows];
            let xj = x[start + j] / column[j];
            x[start + j] = xj;
            for (xi, l) in x[start + j + 1..start + size]
                .iter_mut()
                .zip(&column[j + 1..size])
            {
                *xi -= l * xj;
            }
            for (t, l) in below.iter_mut().zip(&column[size..]) {
                *t += l * xj;
            }
        }
        for (&i, t) in pattern.iter().zip(below.iter()) {
            x[i as usize] -= t;
        }
    }
    // Backward: Lᵀ x = y, supernodes and columns in reverse.
    for s in (0..symbolic.n_supernodes()).rev() {
        let (start, size, pattern, block) = supernode(s);
        let rows = size + pattern.len();
        let below = &mut below[..pattern.len()];
        for (t, &i) in below.iter_mut().zip(pattern) {
            *t = x[i as usize];
        }
        for j in (0..size).rev() {
            let column = &block[j * rows..(j + 1) * rows];
            let (top, bottom) = x[start + j..start + size].split_at(1);
            let acc = top[0] - dot(&column[j + 1..size], bottom) - dot(&column[size..], below);
            x[start + j] = acc / column[j];
        }
    }
}

/// Σ a_i b_i in four interleaved partial sums, so that the loop vectorises (a fixed,
/// deterministic order).
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut partial = [0.0; 4];
    let (a4, a_rest) = a.split_at(n - n % 4);
    let (b4, b_rest) = b.split_at(n - n % 4);
    for (ca, cb) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for k in 0..4 {
            partial[k] += ca[k] * cb[k];
        }
    }
    let mut sum = (partial[0] + partial[2]) + (partial[1] + partial[3]);
    for (x, y) in a_rest.iter().zip(b_rest) {
        sum += x * y;
    }
    sum
}
