//! The numeric L Lᵀ factorisation of our own on a faer supernodal symbolic factor, for
//! patterns with many narrow supernodes that are factorised again and again.
//!
//! faer's `factorize_supernodal_numeric_llt` is left-looking: for every supernode s it
//! finds, for each descendant d that updates s, where d's rows sit in s (a global-to-local
//! map), and calls its generic matrix product with row and column index lists. On the
//! two-ring patterns of flatcut_flattenable's A G Aᵀ most supernodes are a few columns wide
//! and that per-update work costs more than the arithmetic. The pattern never changes
//! between factorisations, so [`SupernodalLltPlan`] works all of it out once: where every
//! entry of A lands in L, which descendants update each supernode, and the local row of
//! every row they update. A factorisation is then the same left-looking algorithm with only
//! arithmetic left: per update, the lower part of a product X Xᵀ subtracted through the
//! precomputed rows; per supernode, a left-looking dense Cholesky of its panel.
//!
//! Where the arithmetic is large enough for faer's dense kernels to pay for their dispatch,
//! they run: an update from a descendant at least [`GEMM_MIN_DEPTH`] columns wide is one
//! faer matrix product into a buffer, and a supernode at least [`DENSE_MIN_COLUMNS`] wide
//! is factorised by faer's dense Cholesky and triangular solve. Below those, the products
//! are tiles of `TILE_ROWS` × `TILE_COLS` entries kept in registers while the descendant's
//! (or the panel's earlier) columns stream past once, written in plain loops that `pulp`
//! compiles at the machine's vector width; every entry of a tile is summed in increasing
//! column order whatever the width, so these paths round alike on every machine (faer's
//! kernels choose their blocking by CPU, as they did when faer factorised alone).
//!
//! The layout read and written is the one of [`crate::solve_llt_in_place`] (faer's
//! documented `SymbolicSupernodalCholesky` accessors), so faer's solves and ours read the
//! result. Measured against faer's numeric factorisation of the same A G Aᵀ (docs/
//! benchmarks.md, seventeenth session): 1.5× faster at 100 unknowns, 1.5–1.7× at 484 and
//! 1 681, 1.4× at 4 900, 1.1× at 49 729.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::{Accum, MatMut, MatRef, Par};

use crate::SparseError;
use crate::supernodes::Supernodes;

/// A descendant this many columns wide or wider updates a supernode through one faer
/// matrix product (below, the register tiles win: faer's dispatch costs more than a few
/// columns of arithmetic). Chosen over 4, 8 and 12 on the bench caps of 242–100k faces.
pub const GEMM_MIN_DEPTH: usize = 8;
/// A supernode this many columns wide or wider is factorised by faer's dense Cholesky and
/// triangular solve (chosen over 8, 16 and 32 likewise).
pub const DENSE_MIN_COLUMNS: usize = 16;

/// One descendant's update of a supernode: the rows of descendant `d` from pattern position
/// `first` on, of which the first `own` fall in the updated supernode's own columns; their
/// local rows in it are `rel[rel_start..]`.
#[derive(Debug, Clone, Copy)]
struct Update {
    d: u32,
    first: u32,
    own: u32,
    rel_start: u32,
}

/// What a pattern's numeric factorisations share: where A's entries land in L and every
/// supernode's updates with their local rows. Built once per pattern by
/// [`SupernodalLltPlan::new`].
#[derive(Debug, Clone)]
pub struct SupernodalLltPlan {
    /// Per stored entry of A (lower CSC, the factor's order): its position in L's values.
    a_dst: Vec<u32>,
    /// A's entries that land in supernode s: `a_dst[a_ptr[s]..a_ptr[s + 1]]` (CSC order
    /// visits the supernodes' columns in turn).
    a_ptr: Vec<usize>,
    /// Updates of supernode s: `updates[update_ptr[s]..update_ptr[s + 1]]`, descendants in
    /// increasing order (a fixed order, so every factorisation rounds alike).
    updates: Vec<Update>,
    update_ptr: Vec<usize>,
    rel: Vec<u32>,
    /// Largest product buffer of an update through faer's matrix product.
    max_products: usize,
    /// Widest supernode factorised by faer's dense Cholesky (its workspace).
    max_dense: usize,
    dimension: usize,
    len_val: usize,
}

/// The buffers of [`SupernodalLltPlan::factorize`], made once by
/// [`SupernodalLltPlan::workspace`] and reused by every factorisation.
pub struct LltWorkspace {
    products: Vec<f64>,
    dense: MemBuffer,
}

impl SupernodalLltPlan {
    /// The plan of `symbolic` for matrices with the lower pattern `a_lower` (rows sorted in
    /// each column, every row ≥ its column, in the factor's order: the pattern `symbolic`
    /// was analysed from, with the identity ordering).
    pub fn new(
        symbolic: &SymbolicSupernodalCholesky<u32>,
        a_lower: SymbolicSparseColMatRef<'_, u32>,
    ) -> Result<Self, SparseError> {
        let n = symbolic.nrows();
        if a_lower.nrows() != n || a_lower.ncols() != n {
            return Err(SparseError::PatternMismatch {
                reason: format!(
                    "pattern {}×{} against a factor of dimension {n}",
                    a_lower.nrows(),
                    a_lower.ncols()
                ),
            });
        }
        let supernodes = Supernodes::of(symbolic);
        let (begin, end, val_ptr) = (supernodes.begin, supernodes.end, supernodes.val_ptr);
        let ns = symbolic.n_supernodes();
        let pattern = |s: usize| supernodes.pattern(s);
        let mut super_of = vec![0u32; n];
        for s in 0..ns {
            for c in begin[s]..end[s] {
                super_of[c as usize] = s as u32;
            }
        }
        // Local row of every global row in supernode s (own columns first, then its
        // pattern), filled for one s at a time.
        let mut local = vec![u32::MAX; n];
        let set_local = |local: &mut [u32], s: usize| {
            let (start, size) = (begin[s] as usize, (end[s] - begin[s]) as usize);
            for (i, l) in local[start..start + size].iter_mut().enumerate() {
                *l = i as u32;
            }
            for (i, &r) in pattern(s).iter().enumerate() {
                local[r as usize] = (size + i) as u32;
            }
        };
        let clear_local = |local: &mut [u32], s: usize| {
            let (start, size) = (begin[s] as usize, (end[s] - begin[s]) as usize);
            local[start..start + size].fill(u32::MAX);
            for &r in pattern(s) {
                local[r as usize] = u32::MAX;
            }
        };

        // A's entries.
        let mut a_dst = Vec::with_capacity(a_lower.compute_nnz());
        let mut a_ptr = Vec::with_capacity(ns + 1);
        for s in 0..ns {
            a_ptr.push(a_dst.len());
            set_local(&mut local, s);
            let rows = (end[s] - begin[s]) as usize + pattern(s).len();
            for j in begin[s]..end[s] {
                let cj = (j - begin[s]) as usize;
                for i in a_lower.row_idx_of_col(j as usize) {
                    let li = local[i];
                    if i < j as usize || li == u32::MAX {
                        return Err(SparseError::PatternMismatch {
                            reason: format!(
                                "entry ({i}, {j}) is above the diagonal or outside the factor's pattern"
                            ),
                        });
                    }
                    a_dst.push(val_ptr[s] + (cj * rows) as u32 + li);
                }
            }
            clear_local(&mut local, s);
        }
        a_ptr.push(a_dst.len());

        // Updates: descendant d updates every supernode that owns one of its pattern rows;
        // the rows owned by one supernode are contiguous in d's (sorted) pattern.
        let mut pairs: Vec<(u32, Update)> = Vec::new();
        for d in 0..ns {
            let p = pattern(d);
            let mut first = 0;
            while first < p.len() {
                let s = super_of[p[first] as usize];
                let own = p[first..]
                    .iter()
                    .take_while(|&&r| super_of[r as usize] == s)
                    .count();
                pairs.push((
                    s,
                    Update {
                        d: d as u32,
                        first: first as u32,
                        own: own as u32,
                        rel_start: 0,
                    },
                ));
                first += own;
            }
        }
        // Stable: descendants stay in increasing order within each supernode.
        pairs.sort_by_key(|&(s, _)| s);
        let mut update_ptr = vec![0usize; ns + 1];
        for &(s, _) in &pairs {
            update_ptr[s as usize + 1] += 1;
        }
        for s in 0..ns {
            update_ptr[s + 1] += update_ptr[s];
        }
        let mut updates: Vec<Update> = pairs.into_iter().map(|(_, u)| u).collect();
        let mut rel = Vec::new();
        let mut max_products = 0;
        for s in 0..ns {
            set_local(&mut local, s);
            for u in &mut updates[update_ptr[s]..update_ptr[s + 1]] {
                u.rel_start =
                    u32::try_from(rel.len()).map_err(|_| SparseError::OutOfMemory { n })?;
                let rows = &pattern(u.d as usize)[u.first as usize..];
                if (end[u.d as usize] - begin[u.d as usize]) as usize >= GEMM_MIN_DEPTH {
                    max_products = max_products.max(rows.len() * u.own as usize);
                }
                for &r in rows {
                    let l = local[r as usize];
                    if l == u32::MAX {
                        return Err(SparseError::PatternMismatch {
                            reason: format!("row {r} of supernode {} is not in supernode {s}", u.d),
                        });
                    }
                    rel.push(l);
                }
            }
            clear_local(&mut local, s);
        }
        Ok(Self {
            a_dst,
            a_ptr,
            updates,
            update_ptr,
            rel,
            max_products,
            max_dense: (0..ns)
                .map(|s| (end[s] - begin[s]) as usize)
                .filter(|&size| size >= DENSE_MIN_COLUMNS)
                .max()
                .unwrap_or(0),
            dimension: n,
            len_val: symbolic.len_val(),
        })
    }

    /// The buffers [`SupernodalLltPlan::factorize`] works in.
    pub fn workspace(&self) -> Result<LltWorkspace, SparseError> {
        let oom = |_| SparseError::OutOfMemory { n: self.dimension };
        let mut products = Vec::new();
        products.try_reserve_exact(self.max_products).map_err(oom)?;
        products.resize(self.max_products, 0.0);
        let dense = MemBuffer::try_new(cholesky_in_place_scratch::<f64>(
            self.max_dense,
            Par::Seq,
            Default::default(),
        ))
        .map_err(|_| SparseError::OutOfMemory { n: self.dimension })?;
        Ok(LltWorkspace { products, dense })
    }

    /// Factorises the matrix with lower values `a_values` (the stored entries of the
    /// pattern given to [`SupernodalLltPlan::new`], in its order) into `l_values`, laid out
    /// as faer's supernodal factor of `symbolic`, in `workspace` (from
    /// [`SupernodalLltPlan::workspace`] of this plan). After an error `l_values` holds no
    /// valid factor.
    ///
    /// # Panics
    /// If `symbolic` is not the plan's or a length does not match it.
    pub fn factorize(
        &self,
        symbolic: &SymbolicSupernodalCholesky<u32>,
        a_values: &[f64],
        l_values: &mut [f64],
        workspace: &mut LltWorkspace,
    ) -> Result<(), SparseError> {
        assert_eq!(symbolic.nrows(), self.dimension, "symbolic factor");
        assert_eq!(symbolic.len_val(), self.len_val, "symbolic factor");
        assert_eq!(a_values.len(), self.a_dst.len(), "matrix values");
        assert!(l_values.len() >= self.len_val, "factor values");
        assert!(workspace.products.len() >= self.max_products, "workspace");
        pulp::Arch::new()
            .dispatch(Factorize {
                plan: self,
                symbolic,
                a_values,
                l_values,
                workspace,
            })
            .map_err(|_| SparseError::NotPositiveDefinite { n: self.dimension })
    }
}

/// The first column whose pivot was not positive.
struct NotPositiveDefinite;

struct Factorize<'a> {
    plan: &'a SupernodalLltPlan,
    symbolic: &'a SymbolicSupernodalCholesky<u32>,
    a_values: &'a [f64],
    l_values: &'a mut [f64],
    workspace: &'a mut LltWorkspace,
}

impl pulp::WithSimd for Factorize<'_> {
    type Output = Result<(), NotPositiveDefinite>;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        factorize(
            self.plan,
            self.symbolic,
            self.a_values,
            self.l_values,
            &mut self.workspace.products,
            &mut self.workspace.dense,
        )
    }
}

/// Rows of a product tile: one 512-bit vector (two 256-bit ones), the accumulators of
/// [`tile`] four such.
const TILE_ROWS: usize = 8;
/// Columns of a product tile.
const TILE_COLS: usize = 4;

/// `acc[c][i] = Σ_k x_k[row0 + i] · x_k[cols[c]]` over the columns x_k = `block[k · ld..][..len]`,
/// k < `depth`: a tile of X Xᵀ kept in registers while the k loop streams X once. Every entry
/// is summed in increasing k, whatever the vector width.
#[inline(always)]
fn tile<const M: usize>(
    block: &[f64],
    ld: usize,
    depth: usize,
    len: usize,
    row0: usize,
    cols: [usize; TILE_COLS],
) -> [[f64; M]; TILE_COLS] {
    let mut acc = [[0.0; M]; TILE_COLS];
    for k in 0..depth {
        let column = &block[k * ld..k * ld + len];
        let x: &[f64; M] = column[row0..row0 + M]
            .try_into()
            .unwrap_or_else(|_| unreachable!("a slice of M values"));
        for (a, &col) in acc.iter_mut().zip(&cols) {
            let c = column[col];
            for (t, &xi) in a.iter_mut().zip(x) {
                *t += xi * c;
            }
        }
    }
    acc
}

/// `f(i, c, value)` for every entry of the lower part (i ≥ `cols[c]`'s position `j0 + c`) of
/// X Xᵀ restricted to rows `j0..end` and columns `j0..j0 + TILE_COLS` (those below `j_end`),
/// X being the first `depth` columns of `block` (leading dimension `ld`).
#[inline(always)]
fn lower_product_columns(
    block: &[f64],
    ld: usize,
    depth: usize,
    j0: usize,
    j_end: usize,
    end: usize,
    sink: &mut impl Sink,
) {
    let last = j_end - 1;
    let cols = [
        j0,
        (j0 + 1).min(last),
        (j0 + 2).min(last),
        (j0 + 3).min(last),
    ];
    let width = (j_end - j0).min(TILE_COLS);
    let mut i0 = j0;
    while i0 + TILE_ROWS <= end {
        let acc = tile::<TILE_ROWS>(block, ld, depth, end, i0, cols);
        for (c, a) in acc.iter().enumerate().take(width) {
            if i0 >= j0 + c {
                sink.run(i0, c, a);
            } else {
                for (ii, &v) in a.iter().enumerate() {
                    if i0 + ii >= j0 + c {
                        sink.entry(i0 + ii, c, v);
                    }
                }
            }
        }
        i0 += TILE_ROWS;
    }
    while i0 < end {
        let acc = tile::<1>(block, ld, depth, end, i0, cols);
        for (c, a) in acc.iter().enumerate().take(width) {
            if i0 >= j0 + c {
                sink.entry(i0, c, a[0]);
            }
        }
        i0 += 1;
    }
}

/// Where [`lower_product_columns`] subtracts its entries: entry (i, c), or a run of
/// `TILE_ROWS` entries (i0.., c).
trait Sink {
    fn entry(&mut self, i: usize, c: usize, v: f64);
    fn run(&mut self, i0: usize, c: usize, v: &[f64; TILE_ROWS]);
}

/// A descendant's update of a supernode's panel, through the local rows `rel`; columns
/// from `j0`.
struct Scatter<'a> {
    panel: &'a mut [f64],
    rows: usize,
    rel: &'a [u32],
    j0: usize,
}

impl Sink for Scatter<'_> {
    #[inline(always)]
    fn entry(&mut self, i: usize, c: usize, v: f64) {
        self.panel[self.rel[self.j0 + c] as usize * self.rows + self.rel[i] as usize] -= v;
    }

    #[inline(always)]
    fn run(&mut self, i0: usize, c: usize, v: &[f64; TILE_ROWS]) {
        let base = self.rel[self.j0 + c] as usize * self.rows;
        let rel = &self.rel[i0..i0 + TILE_ROWS];
        let first = rel[0] as usize;
        // Local rows strictly increase, so these are contiguous when the last is 7 on.
        if rel[TILE_ROWS - 1] as usize == first + TILE_ROWS - 1 {
            for (t, &x) in self.panel[base + first..base + first + TILE_ROWS]
                .iter_mut()
                .zip(v)
            {
                *t -= x;
            }
        } else {
            for (&r, &x) in rel.iter().zip(v) {
                self.panel[base + r as usize] -= x;
            }
        }
    }
}

/// A panel block's update from the panel's columns before it: columns `c` of `block`.
struct Block<'a> {
    block: &'a mut [f64],
    rows: usize,
}

impl Sink for Block<'_> {
    #[inline(always)]
    fn entry(&mut self, i: usize, c: usize, v: f64) {
        self.block[c * self.rows + i] -= v;
    }

    #[inline(always)]
    fn run(&mut self, i0: usize, c: usize, v: &[f64; TILE_ROWS]) {
        let at = c * self.rows + i0;
        for (t, &x) in self.block[at..at + TILE_ROWS].iter_mut().zip(v) {
            *t -= x;
        }
    }
}

#[inline(always)]
fn factorize(
    plan: &SupernodalLltPlan,
    symbolic: &SymbolicSupernodalCholesky<u32>,
    a_values: &[f64],
    l: &mut [f64],
    products: &mut [f64],
    dense: &mut MemBuffer,
) -> Result<(), NotPositiveDefinite> {
    let Supernodes {
        begin,
        end,
        val_ptr,
        pattern_len,
        ..
    } = Supernodes::of(symbolic);
    let l = &mut l[..plan.len_val];
    for s in 0..symbolic.n_supernodes() {
        let size = (end[s] - begin[s]) as usize;
        let rows = size + pattern_len[s] as usize;
        let (head, tail) = l.split_at_mut(val_ptr[s] as usize);
        let panel = &mut tail[..size * rows];
        // The panel's entries of A, written just before its updates read and write it (one
        // pass over L fewer than zeroing it all first, and the panel is in cache after).
        panel.fill(0.0);
        let entries = plan.a_ptr[s]..plan.a_ptr[s + 1];
        for (&dst, &a) in plan.a_dst[entries.clone()].iter().zip(&a_values[entries]) {
            panel[(dst - val_ptr[s]) as usize] += a;
        }
        // Updates from the descendants, left-looking: the lower part of X Xᵀ, X being the
        // descendant's rows from the first that falls in s's own columns, subtracted from s
        // through the precomputed local rows.
        for u in &plan.updates[plan.update_ptr[s]..plan.update_ptr[s + 1]] {
            let d = u.d as usize;
            let d_size = (end[d] - begin[d]) as usize;
            let d_rows = d_size + pattern_len[d] as usize;
            let block = &head[val_ptr[d] as usize..val_ptr[d + 1] as usize];
            let first = d_size + u.first as usize;
            let rel = &plan.rel[u.rel_start as usize..][..d_rows - first];
            let own = u.own as usize;
            let count = d_rows - first;
            if d_size >= GEMM_MIN_DEPTH {
                // X Xᵀ's first `own` columns (the upper corner is computed and not read).
                let x = MatRef::from_column_major_slice_with_stride(
                    &block[first..],
                    count,
                    d_size,
                    d_rows,
                );
                let t = &mut products[..count * own];
                matmul(
                    MatMut::from_column_major_slice_mut(t, count, own),
                    Accum::Replace,
                    x,
                    x.subrows(0, own).transpose(),
                    1.0,
                    Par::Seq,
                );
                for j in 0..own {
                    let base = rel[j] as usize * rows;
                    for i in j..count {
                        panel[base + rel[i] as usize] -= t[j * count + i];
                    }
                }
                continue;
            }
            for j0 in (0..own).step_by(TILE_COLS) {
                lower_product_columns(
                    &block[first..],
                    d_rows,
                    d_size,
                    j0,
                    own,
                    d_rows - first,
                    &mut Scatter {
                        panel,
                        rows,
                        rel,
                        j0,
                    },
                );
            }
        }
        if size >= DENSE_MIN_COLUMNS {
            let panel = MatMut::from_column_major_slice_mut(panel, rows, size);
            let (mut top, bottom) = panel.split_at_row_mut(size);
            cholesky_in_place(
                top.as_mut(),
                Default::default(),
                Par::Seq,
                MemStack::new(dense),
                Default::default(),
            )
            .map_err(|_| NotPositiveDefinite)?;
            solve_lower_triangular_in_place(top.as_ref(), bottom.transpose_mut(), Par::Seq);
            continue;
        }
        // Dense Cholesky of the panel (its own columns and the rows below), left-looking by
        // blocks of TILE_COLS columns: the block's update from the columns before it as
        // product tiles, then the block's own columns one by one.
        for j0 in (0..size).step_by(TILE_COLS) {
            let j_end = (j0 + TILE_COLS).min(size);
            let (done, rest) = panel.split_at_mut(j0 * rows);
            if j0 > 0 {
                lower_product_columns(
                    done,
                    rows,
                    j0,
                    j0,
                    j_end,
                    rows,
                    &mut Block { block: rest, rows },
                );
            }
            for j in j0..j_end {
                let (block_done, column) = rest.split_at_mut((j - j0) * rows);
                let column = &mut column[j..rows];
                for k in j0..j {
                    let previous = &block_done[(k - j0) * rows + j..(k - j0 + 1) * rows];
                    let c = previous[0];
                    for (t, &x) in column.iter_mut().zip(previous) {
                        *t -= x * c;
                    }
                }
                let pivot = column[0];
                if !(pivot > 0.0 && pivot.is_finite()) {
                    return Err(NotPositiveDefinite);
                }
                let root = pivot.sqrt();
                column[0] = root;
                for t in &mut column[1..] {
                    *t /= root;
                }
            }
        }
    }
    Ok(())
}
