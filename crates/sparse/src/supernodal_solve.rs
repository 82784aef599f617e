//! L Lᵀ x = b on a faer supernodal Cholesky factor, one right-hand side at a time.
//!
//! faer's own solve (`LltRef::solve_in_place_with_conj`) runs, per supernode, its generic
//! dense triangular solve and matrix product. On the two-ring patterns of A G Aᵀ most
//! supernodes are a few columns wide, and that dispatch costs more than the arithmetic:
//! at 1k faces one of faer's solves took a sixth of the instructions of a numeric
//! factorisation, and a step solves about three times per factorisation, so the solves
//! cost half as much as the factorisation itself. Here each supernode column is one
//! contiguous slice of L, swept once forward (an axpy into the rows below) and once
//! backward (a dot product with them). Supernodes at least [`GROUP_COLUMNS`] wide with at
//! least [`GROUP_MIN_ROWS`] rows below sweep those rows [`GROUP_COLUMNS`] columns at a time,
//! every sum still taken in the same order as column by column, so the result is the same
//! to the bit either way.
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
    let mut below_dots = [0.0; GROUP_COLUMNS];

    // Forward: L y = b, each supernode's own triangle first, then the rows below it. Where
    // there are enough of those (`grouped_columns`) they take GROUP_COLUMNS columns'
    // products per pass: each entry of `below` still receives its products one column after
    // another, in increasing order (the same sums, bit for bit), but is loaded and stored
    // once per group instead of once per column.
    for s in 0..symbolic.n_supernodes() {
        let (start, size, pattern, block) = supernode(s);
        let rows = size + pattern.len();
        for j in 0..size {
            let column = &block[j * rows..j * rows + size];
            let xj = x[start + j] / column[j];
            x[start + j] = xj;
            for (xi, l) in x[start + j + 1..start + size]
                .iter_mut()
                .zip(&column[j + 1..size])
            {
                *xi -= l * xj;
            }
        }
        let below = &mut below[..pattern.len()];
        below.fill(0.0);
        let own = &x[start..start + size];
        let grouped = grouped_columns(size, below.len());
        for j in (0..grouped).step_by(GROUP_COLUMNS) {
            let c = |k: usize| &block[(j + k) * rows + size..(j + k + 1) * rows];
            let [x0, x1, x2, x3] = [own[j], own[j + 1], own[j + 2], own[j + 3]];
            for ((((t, l0), l1), l2), l3) in
                below.iter_mut().zip(c(0)).zip(c(1)).zip(c(2)).zip(c(3))
            {
                *t = (((*t + l0 * x0) + l1 * x1) + l2 * x2) + l3 * x3;
            }
        }
        for (j, &xj) in own.iter().enumerate().skip(grouped) {
            for (t, l) in below
                .iter_mut()
                .zip(&block[j * rows + size..(j + 1) * rows])
            {
                *t += l * xj;
            }
        }
        for (&i, t) in pattern.iter().zip(below.iter()) {
            x[i as usize] -= t;
        }
    }
    // Backward: Lᵀ x = y, supernodes and columns in reverse. A column's product with the
    // rows below does not depend on the supernode's own unknowns, so where there are enough
    // such rows (`GROUP_MIN_ROWS`) the products of GROUP_COLUMNS columns are summed side by
    // side: independent chains of additions instead of one (each summed exactly as its own
    // [`dot`], so the same bits).
    for s in (0..symbolic.n_supernodes()).rev() {
        let (start, size, pattern, block) = supernode(s);
        let rows = size + pattern.len();
        let below = &mut below[..pattern.len()];
        for (t, &i) in below.iter_mut().zip(pattern) {
            *t = x[i as usize];
        }
        let blocked = grouped_columns(size, below.len());
        for j in (0..size).rev() {
            let column = &block[j * rows..(j + 1) * rows];
            let below_dot = if j < blocked {
                if j % GROUP_COLUMNS == GROUP_COLUMNS - 1 {
                    let j0 = j + 1 - GROUP_COLUMNS;
                    below_dots = dots(
                        std::array::from_fn(|k| {
                            &block[(j0 + k) * rows + size..(j0 + k + 1) * rows]
                        }),
                        below,
                    );
                }
                below_dots[j % GROUP_COLUMNS]
            } else {
                dot(&column[size..], below)
            };
            let (top, bottom) = x[start + j..start + size].split_at(1);
            let acc = top[0] - dot(&column[j + 1..size], bottom) - below_dot;
            x[start + j] = acc / column[j];
        }
    }
}

/// Columns of a supernode swept together below its triangle, forward and backward.
pub const GROUP_COLUMNS: usize = 4;
/// Rows below a supernode from which that pays: applied to every supernode, the grouped
/// sweeps made the solve slower at 3.5k faces (most supernodes are narrow and short there);
/// from 16 rows on they made it 10 % faster at 10k and 50k faces.
pub const GROUP_MIN_ROWS: usize = 16;

/// How many of a supernode's `size` columns sweep its `rows_below` in groups of
/// [`GROUP_COLUMNS`] (the first ones; the rest go one by one): none unless there are at
/// least [`GROUP_MIN_ROWS`] rows below.
#[inline(always)]
fn grouped_columns(size: usize, rows_below: usize) -> usize {
    if rows_below >= GROUP_MIN_ROWS {
        size - size % GROUP_COLUMNS
    } else {
        0
    }
}

/// [`dot`] of each of `columns` with `b`, summed side by side: each result is the same
/// value, bit for bit, as its own [`dot`].
#[inline(always)]
fn dots(columns: [&[f64]; GROUP_COLUMNS], b: &[f64]) -> [f64; GROUP_COLUMNS] {
    let n = b.len();
    let n4 = n - n % 4;
    let [c0, c1, c2, c3] = columns.map(|c| &c[..n]);
    let four = |c: &[f64]| -> [f64; 4] { [c[0], c[1], c[2], c[3]] };
    let mut partial = [[0.0; 4]; GROUP_COLUMNS];
    for ((((y, a0), a1), a2), a3) in b[..n4]
        .chunks_exact(4)
        .zip(c0.chunks_exact(4))
        .zip(c1.chunks_exact(4))
        .zip(c2.chunks_exact(4))
        .zip(c3.chunks_exact(4))
    {
        let y = four(y);
        for (p, a) in partial
            .iter_mut()
            .zip([four(a0), four(a1), four(a2), four(a3)])
        {
            for k in 0..4 {
                p[k] += a[k] * y[k];
            }
        }
    }
    std::array::from_fn(|c| {
        let p = &partial[c];
        let mut sum = (p[0] + p[2]) + (p[1] + p[3]);
        for (x, y) in columns[c][n4..n].iter().zip(&b[n4..n]) {
            sum += x * y;
        }
        sum
    })
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
