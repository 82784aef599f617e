//! The least-norm step of the paper (Eq. 5–8 and, weighted, Eq. 14–16):
//!
//! A d = b with A the n_int × 3n_int Jacobian of θ at the interior vertices (boundary
//! columns dropped: boundary vertices are constants) and b = 2π − θ. The weighted
//! least-norm solution is d = G Aᵀ x with (A G Aᵀ + μ I) x = b, where G is block-diagonal
//! with one 3×3 block per interior vertex: G_c = (1 / w_c²) · (n nᵀ + t (I − n nᵀ)).
//! t = 1 gives the paper's W² = diag(1/w²) (Eq. 14–16); t < 1 penalises tangential motion
//! (robust mode's option for negatively curved pieces); μ = 0 is the paper's step, μ > 0
//! the Levenberg–Marquardt damped step of robust mode.
//!
//! [`Layout`] is built once per piece: the CSR pattern of A (row p: p itself, then its
//! interior one-ring), the lower-triangular CSC pattern of A G Aᵀ (interior vertices
//! within two rings), the list of products that fill it, and the sparse symbolic Cholesky
//! factorisation (AMD ordering; faer's supernodal analysis) with the plan of our own numeric
//! factorisation on it (`flatcut_sparse::SupernodalLltPlan`), reused for every numeric
//! factorisation of the piece. The same pattern holds Lᵀ L + D of the least-square update
//! (see `laplacian.rs`), so one symbolic factorisation serves both systems.
//!
//! All factorisations run sequentially ([`Par::Seq`]) so that a result does not depend on
//! the thread count; parallelism is across pieces.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::linalg::{SupernodalThreshold, amd};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use flatcut_mesh::{INVALID, Topology, VertexId};

use flatcut_mesh::vec3::{angle, sub};

use crate::angle_gradient::corner_gradient_next_previous;
use flatcut_sparse::{LltWorkspace, SupernodalLltPlan, solve_llt_in_place};

use crate::options::Damping;

/// ε of `Damping::GraphLaplacian`, D = (ε I + L) / (ε + mean valence). Small: the
/// interior graph Laplacian with the boundary held is already positive definite, and ε only
/// keeps the smoothest modes damped at all. Measured on the 85k-face upper back (twenty-second
/// session): ε = 1e-3 converged in 64 fine iterations, 1e-2 in 58 but 2.5× slower, 1e-1
/// not at all (docs/algorithms/flattenable.md, "A damping shaped like the graph Laplacian").
pub const GRAPH_DAMPING_EPSILON: f64 = 1e-3;

/// Per-piece sparse structure of A and A G Aᵀ with its symbolic factorisation.
pub struct Layout {
    /// Local vertex id of each interior vertex (row / column block order).
    pub interior: Vec<u32>,
    /// Interior index of each local vertex, `INVALID` for boundary vertices.
    pub index_of: Vec<u32>,
    /// CSR of A by interior row: entries `row_ptr[i]..row_ptr[i+1]`, the first being `i`.
    pub row_ptr: Vec<usize>,
    /// Interior index of each entry's column vertex.
    pub col: Vec<u32>,
    /// For every (interior vertex, outgoing halfedge): the A entry of p, a, b or `INVALID`
    /// (boundary vertex). Aligned with `corner_vertices`.
    corner_entries: Vec<[u32; 3]>,
    /// Per corner: its centre (the interior vertex), then the next and previous vertices of
    /// its face — read at every θ and A evaluation, so looked up once here.
    corner_vertices: Vec<[u32; 3]>,
    /// Start of each interior vertex's corners in `corner_entries`.
    corner_ptr: Vec<usize>,
    /// Lower CSC pattern of the normal matrix, in the factor's order.
    pattern: SymbolicSparseColMat<u32>,
    diag_slot: Vec<u32>,
    /// (slot, entry i, entry j): the products filling the normal matrix, grouped by column
    /// vertex c (`contrib_ptr`), both entries in column c.
    contrib: Vec<[u32; 3]>,
    contrib_ptr: Vec<usize>,
    /// The fill-reducing order: row k of the stored normal matrix is interior vertex
    /// `order[k]`.
    order: Vec<u32>,
    symbolic: SymbolicCholesky<u32>,
    /// What every numeric factorisation of the supernodal `symbolic` shares (our own
    /// factorisation, `flatcut_sparse::SupernodalLltPlan`); `None` only for an empty system,
    /// which faer factorises simplicially.
    plan: Option<SupernodalLltPlan>,
    /// Per interior vertex its full valence (boundary neighbours included), the diagonal of
    /// `Damping::GraphLaplacian`, and their mean.
    valence: Vec<f64>,
    mean_valence: f64,
    /// The permuted lower slots (i, j), j < i, of every pair of interior neighbours: the
    /// off-diagonal −1s of that damping (the one-ring lies within A G Aᵀ's two-ring pattern).
    ring_slots: Vec<u32>,
}

/// A lower CSC pattern symmetrically permuted (new index of old row i: `inv[i]`), in lower
/// (rows sorted) and upper form, with the new slot of every old one.
struct PermutedPattern {
    col_ptr: Vec<u32>,
    row_idx: Vec<u32>,
    upper_col_ptr: Vec<u32>,
    upper_row_idx: Vec<u32>,
    slot_of: Vec<u32>,
}

impl PermutedPattern {
    fn new(col_ptr: &[u32], row_idx: &[u32], inv: &[u32]) -> Self {
        let n = col_ptr.len() - 1;
        let nnz = row_idx.len();
        // (new row, new column, old slot), the new entry kept in the lower triangle.
        let mut entries = Vec::with_capacity(nnz);
        for j in 0..n {
            for s in col_ptr[j] as usize..col_ptr[j + 1] as usize {
                let (a, b) = (inv[row_idx[s] as usize], inv[j]);
                entries.push((a.max(b), a.min(b), s as u32));
            }
        }
        let mut lower_ptr = vec![0u32; n + 1];
        let mut upper_ptr = vec![0u32; n + 1];
        for &(r, c, _) in &entries {
            lower_ptr[c as usize + 1] += 1;
            upper_ptr[r as usize + 1] += 1;
        }
        for k in 0..n {
            lower_ptr[k + 1] += lower_ptr[k];
            upper_ptr[k + 1] += upper_ptr[k];
        }
        // Two counting passes instead of a sort: by row into the upper form's columns
        // (`by_row`), then, visiting those in row order, into the lower form's columns, whose
        // rows therefore come out sorted.
        let mut by_row = vec![(0u32, 0u32); nnz];
        let mut next = upper_ptr[..n].to_vec();
        for &(r, c, s) in &entries {
            by_row[next[r as usize] as usize] = (c, s);
            next[r as usize] += 1;
        }
        let mut slot_of = vec![0u32; nnz];
        let mut lower_rows = vec![0u32; nnz];
        let mut next = lower_ptr[..n].to_vec();
        for r in 0..n {
            for &(c, s) in &by_row[upper_ptr[r] as usize..upper_ptr[r + 1] as usize] {
                let k = next[c as usize] as usize;
                slot_of[s as usize] = k as u32;
                lower_rows[k] = r as u32;
                next[c as usize] += 1;
            }
        }
        // The upper form's rows (the columns c of each row r) sorted too: the same two
        // passes the other way round.
        let mut upper_rows = vec![0u32; nnz];
        let mut next = upper_ptr[..n].to_vec();
        for c in 0..n {
            for &r in &lower_rows[lower_ptr[c] as usize..lower_ptr[c + 1] as usize] {
                upper_rows[next[r as usize] as usize] = c as u32;
                next[r as usize] += 1;
            }
        }
        Self {
            col_ptr: lower_ptr,
            row_idx: lower_rows,
            upper_col_ptr: upper_ptr,
            upper_row_idx: upper_rows,
            slot_of,
        }
    }
}

/// The 3×3 metric blocks G_c = s_c (n nᵀ + t (I − n nᵀ)).
pub struct Metric<'a> {
    /// s_c = 1 / w_c², per interior vertex.
    pub scale: &'a [f64],
    /// Unit normals per interior vertex, used when `tangential < 1`.
    pub normals: Option<&'a [[f64; 3]]>,
    /// t in (0, 1]: 1 is isotropic (the paper).
    pub tangential: f64,
}

impl<'a> Metric<'a> {
    /// The paper's metric W² = diag(`scale`) (t = 1, no normals).
    pub fn isotropic(scale: &'a [f64]) -> Self {
        Self {
            scale,
            normals: None,
            tangential: 1.0,
        }
    }

    /// G applied to a field of one vector per interior vertex.
    pub fn apply_field(&self, field: &[[f64; 3]]) -> Vec<[f64; 3]> {
        field
            .iter()
            .enumerate()
            .map(|(c, &g)| self.apply(c, g))
            .collect()
    }

    #[inline]
    fn apply(&self, c: usize, g: [f64; 3]) -> [f64; 3] {
        let s = self.scale[c];
        match self.normals {
            Some(n) if self.tangential < 1.0 => {
                let n = n[c];
                let ng = n[0] * g[0] + n[1] * g[1] + n[2] * g[2];
                let t = self.tangential;
                [
                    s * (t * g[0] + (1.0 - t) * ng * n[0]),
                    s * (t * g[1] + (1.0 - t) * ng * n[1]),
                    s * (t * g[2] + (1.0 - t) * ng * n[2]),
                ]
            }
            _ => [s * g[0], s * g[1], s * g[2]],
        }
    }
}

/// A numeric Cholesky factor of one value set on the layout's pattern, with the buffers
/// that make it: refactorising into the same `Factor` ([`Layout::refactor`]) reuses them.
/// (A fresh factor of 1.9 MB at 1681 unknowns, 59 MB at 50k, costs a zeroed allocation and
/// its page faults each time, which the factorisation's own zeroing of L makes redundant.)
pub struct Factor {
    values: Vec<f64>,
    /// The lower values plus the shift (the factorisation reads the matrix from here).
    shifted: Vec<f64>,
    /// The buffers of our supernodal factorisation.
    workspace: Option<LltWorkspace>,
    /// faer's, made when faer factorises into this factor ([`Layout::refactor_with_faer`]).
    faer_scratch: Option<MemBuffer>,
}

/// Why a numeric factorisation failed.
#[derive(Debug)]
pub enum FactorError {
    /// The matrix is not (numerically) positive definite.
    NotPositiveDefinite,
    /// Out of memory or another faer failure.
    Other(String),
}

/// The angles of a block of corners from their edges (x, y, z rows of u and w): the loop of
/// [`Layout::theta`], run by `pulp` inside a function compiled for the CPU's widest vectors.
/// (A closure given to `Arch::dispatch` is not inlined there and stays at the baseline
/// width; `with_simd` is, and so is everything it calls.)
struct CornerAngles<'a, const B: usize> {
    u: &'a [[f64; B]; 3],
    w: &'a [[f64; B]; 3],
    alpha: &'a mut [f64],
}

impl<const B: usize> pulp::WithSimd for CornerAngles<'_, B> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let (u, w) = (self.u, self.w);
        for (j, a) in self.alpha.iter_mut().enumerate() {
            *a = angle([u[0][j], u[1][j], u[2][j]], [w[0][j], w[1][j], w[2][j]]);
        }
    }
}

/// The gradients of a block of corners with respect to their next and previous points,
/// written over their edges u and w: the loop of [`Layout::gradient`], dispatched as
/// [`CornerAngles`].
struct CornerGradients<'a, const B: usize> {
    u: &'a mut [[f64; B]; 3],
    w: &'a mut [[f64; B]; 3],
    len: usize,
}

impl<const B: usize> pulp::WithSimd for CornerGradients<'_, B> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let ([ux, uy, uz], [wx, wy, wz]) = (self.u, self.w);
        for j in 0..self.len {
            let [ga, gb] =
                corner_gradient_next_previous([ux[j], uy[j], uz[j]], [wx[j], wy[j], wz[j]]);
            [ux[j], uy[j], uz[j]] = ga;
            [wx[j], wy[j], wz[j]] = gb;
        }
    }
}

/// Corners per block of the θ and A loops: their edges, coordinate by coordinate, fit the
/// stack and the L1 cache, and a block is long enough for the vectorised kernels.
const CORNER_BLOCK: usize = 256;

/// The angles and the gradients of a block of corners in one pass over their edges (the
/// loop of [`Layout::evaluate`]): the angle's |u × w| and u · w are the gradient's too, and
/// the edges are gathered once. The same operations as [`CornerAngles`] and
/// [`CornerGradients`] each, so the same bits.
struct CornerAnglesGradients<'a, const B: usize> {
    u: &'a mut [[f64; B]; 3],
    w: &'a mut [[f64; B]; 3],
    alpha: &'a mut [f64],
}

impl<const B: usize> pulp::WithSimd for CornerAnglesGradients<'_, B> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let ([ux, uy, uz], [wx, wy, wz]) = (self.u, self.w);
        for (j, a) in self.alpha.iter_mut().enumerate() {
            let (u, w) = ([ux[j], uy[j], uz[j]], [wx[j], wy[j], wz[j]]);
            *a = angle(u, w);
            let [ga, gb] = corner_gradient_next_previous(u, w);
            [ux[j], uy[j], uz[j]] = ga;
            [wx[j], wy[j], wz[j]] = gb;
        }
    }
}

/// θ summed block by block: each vertex's corners are contiguous, so their angles are
/// added run by run (the same additions in the same order as one corner at a time).
#[derive(Default)]
struct AngleSums {
    vertex: usize,
    sum: f64,
}

impl AngleSums {
    /// Adds the angles of corners `start..start + alpha.len()`.
    #[inline]
    fn add(&mut self, layout: &Layout, start: usize, alpha: &[f64], theta: &mut [f64]) {
        let end = start + alpha.len();
        let mut at = start;
        while at < end {
            let vertex_end = layout.corner_ptr[self.vertex + 1];
            let stop = vertex_end.min(end);
            for a in &alpha[at - start..stop - start] {
                self.sum += a;
            }
            at = stop;
            if stop == vertex_end {
                theta[self.vertex] = self.sum;
                self.sum = 0.0;
                self.vertex += 1;
            }
        }
    }

    /// The vertices after the last corner (without corners: θ = 0).
    fn finish(mut self, layout: &Layout, theta: &mut [f64]) {
        for t in &mut theta[self.vertex..layout.n()] {
            *t = self.sum;
            self.sum = 0.0;
        }
    }
}

impl Layout {
    /// Builds the pattern for a piece. `topo` must be the piece's topology with every
    /// interior vertex manifold (checked by the caller).
    pub fn build(topo: &Topology, faces: &[[u32; 3]]) -> Result<Self, FactorError> {
        let nv = topo.vertex_count();
        let mut index_of = vec![INVALID; nv];
        let mut interior = Vec::new();
        for v in 0..nv as u32 {
            if topo.is_interior_vertex(VertexId(v)) {
                index_of[v as usize] = interior.len() as u32;
                interior.push(v);
            }
        }
        let n = interior.len();
        let mut row_ptr = Vec::with_capacity(n + 1);
        let mut col = Vec::new();
        let mut corner_entries = Vec::new();
        let mut corner_vertices = Vec::new();
        let mut corner_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0);
        corner_ptr.push(0);
        for (i, &p) in interior.iter().enumerate() {
            let start = col.len();
            col.push(i as u32);
            for &q in topo.one_ring(VertexId(p)).unwrap_or(&[]) {
                let qi = index_of[q as usize];
                if qi != INVALID {
                    col.push(qi);
                }
            }
            let entry = |v: u32, col: &[u32]| -> u32 {
                let vi = index_of[v as usize];
                if vi == INVALID {
                    return INVALID;
                }
                col[start..]
                    .iter()
                    .position(|&c| c == vi)
                    .map_or(INVALID, |k| (start + k) as u32)
            };
            for &h in topo.outgoing(VertexId(p)) {
                let f = faces[Topology::face(h).idx()];
                let k = (h % 3) as usize;
                corner_entries.push([
                    start as u32,
                    entry(f[(k + 1) % 3], &col),
                    entry(f[(k + 2) % 3], &col),
                ]);
                corner_vertices.push([f[k], f[(k + 1) % 3], f[(k + 2) % 3]]);
            }
            row_ptr.push(col.len());
            corner_ptr.push(corner_entries.len());
        }
        // Column lists of A: entries per column vertex.
        let mut ccount = vec![0usize; n + 1];
        for &c in &col {
            ccount[c as usize + 1] += 1;
        }
        for c in 0..n {
            ccount[c + 1] += ccount[c];
        }
        let contrib_ptr_cols = ccount.clone();
        let mut fill = ccount.clone();
        let mut by_col = vec![(0u32, 0u32); col.len()];
        for i in 0..n {
            for e in row_ptr[i]..row_ptr[i + 1] {
                let c = col[e] as usize;
                by_col[fill[c]] = (i as u32, e as u32);
                fill[c] += 1;
            }
        }
        // Lower pattern: for each row i the rows j ≤ i that share a column of A with it,
        // deduplicated by a marker; rows are visited in increasing order, so each column's row
        // list comes out sorted (no sort of all the pairs: that was most of this function's
        // time at 1.7k unknowns).
        let mut m_col_ptr = vec![0u32; n + 1];
        let mut mark = vec![u32::MAX; n];
        let mut lower_ptr = vec![0usize; n + 1];
        let mut lower_cols: Vec<u32> = Vec::new();
        for i in 0..n {
            for &c in &col[row_ptr[i]..row_ptr[i + 1]] {
                let c = c as usize;
                for &(j, _) in &by_col[contrib_ptr_cols[c]..contrib_ptr_cols[c + 1]] {
                    if j as usize <= i && mark[j as usize] != i as u32 {
                        mark[j as usize] = i as u32;
                        lower_cols.push(j);
                        m_col_ptr[j as usize + 1] += 1;
                    }
                }
            }
            lower_ptr[i + 1] = lower_cols.len();
        }
        for j in 0..n {
            m_col_ptr[j + 1] += m_col_ptr[j];
        }
        let mut m_row_idx = vec![0u32; m_col_ptr[n] as usize];
        let mut next: Vec<u32> = m_col_ptr[..n].to_vec();
        for i in 0..n {
            for &j in &lower_cols[lower_ptr[i]..lower_ptr[i + 1]] {
                m_row_idx[next[j as usize] as usize] = i as u32;
                next[j as usize] += 1;
            }
        }
        let slot = |i: u32, j: u32| -> u32 {
            let (s, e) = (
                m_col_ptr[j as usize] as usize,
                m_col_ptr[j as usize + 1] as usize,
            );
            // Present by construction.
            s as u32 + m_row_idx[s..e].binary_search(&i).unwrap_or(0) as u32
        };
        let diag_slot: Vec<u32> = (0..n as u32).map(|j| slot(j, j)).collect();
        let valence: Vec<f64> = interior
            .iter()
            .map(|&p| topo.one_ring(VertexId(p)).map_or(0, <[u32]>::len) as f64)
            .collect();
        let mean_valence = valence.iter().sum::<f64>() / n.max(1) as f64;
        // Row i of A holds i first, then its interior one-ring (the pattern's columns).
        let mut ring_slots = Vec::new();
        for i in 0..n {
            for &j in &col[row_ptr[i] + 1..row_ptr[i + 1]] {
                if (j as usize) < i {
                    ring_slots.push(slot(i as u32, j));
                }
            }
        }
        let mut contrib = Vec::new();
        let mut contrib_ptr = Vec::with_capacity(n + 1);
        contrib_ptr.push(0);
        for c in 0..n {
            let list = &by_col[contrib_ptr_cols[c]..contrib_ptr_cols[c + 1]];
            for &(i, ei) in list {
                for &(j, ej) in list {
                    if i >= j {
                        contrib.push([slot(i, j), ei, ej]);
                    }
                }
            }
            contrib_ptr.push(contrib.len());
        }
        // The fill-reducing order faer's symbolic factorisation would choose (AMD with its
        // default control), applied here once: the pattern, the slots of the products and
        // the diagonal are stored in that order, and the factorisation is told the order is
        // the identity. faer would otherwise permute the whole matrix at every numeric
        // factorisation (3 % of a 3.5k-face run); the factors are the same bit for bit.
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &m_col_ptr, None, &m_row_idx);
        let mut fwd = vec![0u32; n];
        let mut inv = vec![0u32; n];
        let mut amd_mem =
            MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<u32>(n, m_row_idx.len()))
                .map_err(|e| FactorError::Other(format!("{e:?}")))?;
        amd::order_maybe_unsorted(
            &mut fwd,
            &mut inv,
            sym,
            amd::Control::default(),
            MemStack::new(&mut amd_mem),
        )
        .map_err(|e| FactorError::Other(format!("{e:?}")))?;
        let permuted = PermutedPattern::new(&m_col_ptr, &m_row_idx, &inv);
        let diag_slot = diag_slot
            .iter()
            .map(|&s| permuted.slot_of[s as usize])
            .collect();
        for c in &mut contrib {
            c[0] = permuted.slot_of[c[0] as usize];
        }
        for s in &mut ring_slots {
            *s = permuted.slot_of[*s as usize];
        }
        let upper = SymbolicSparseColMatRef::new_checked(
            n,
            n,
            &permuted.upper_col_ptr,
            None,
            &permuted.upper_row_idx,
        );
        // Always supernodal: faer's automatic choice (a flop-ratio threshold) picks the
        // simplicial factorisation for these two-ring patterns up to a few thousand unknowns,
        // where the supernodal one was measured 2–3× faster (1681 unknowns: 0.70 vs 1.9 ms;
        // 484: 0.12 vs 0.25 ms; `measure -- speed`), and never slower on the bench pieces.
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        // faer reads the pattern of an identity-ordered symbolic factorisation as the upper
        // triangle whatever the side, so it is given the upper one.
        let symbolic =
            factorize_symbolic_cholesky(upper, Side::Upper, SymmetricOrdering::Identity, params)
                .map_err(|e| FactorError::Other(format!("{e:?}")))?;
        let PermutedPattern {
            col_ptr: m_col_ptr,
            row_idx: m_row_idx,
            ..
        } = permuted;
        // Checked once here; every numeric factorisation reads it through `as_ref`, which
        // does not check again (faer's checked view of the pattern was ~2 % of a
        // factorisation at 3.5k faces).
        let pattern = SymbolicSparseColMat::new_checked(n, n, m_col_ptr, None, m_row_idx);
        let plan = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(supernodal) => Some(
                SupernodalLltPlan::new(supernodal, pattern.as_ref())
                    .map_err(|e| FactorError::Other(e.to_string()))?,
            ),
            SymbolicCholeskyRaw::Simplicial(_) => None,
        };
        Ok(Self {
            interior,
            index_of,
            row_ptr,
            col,
            corner_entries,
            corner_vertices,
            corner_ptr,
            pattern,
            diag_slot,
            contrib,
            contrib_ptr,
            order: fwd,
            symbolic,
            plan,
            valence,
            mean_valence,
            ring_slots,
        })
    }

    /// Number of interior vertices (rows of A).
    pub fn n(&self) -> usize {
        self.interior.len()
    }

    /// Number of stored entries of A (each a 3-vector).
    pub fn entries(&self) -> usize {
        self.col.len()
    }

    /// Number of stored entries of the lower normal matrix.
    pub fn normal_nnz(&self) -> usize {
        self.pattern.row_idx().len()
    }

    /// θ at every interior vertex and the entries of A (∂θ_i / ∂v_col).
    pub fn evaluate(&self, positions: &[[f64; 3]], theta: &mut [f64], grad: &mut [[f64; 3]]) {
        let mut alpha = [0.0f64; CORNER_BLOCK];
        let arch = pulp::Arch::new();
        let mut sums = AngleSums::default();
        grad.iter_mut().for_each(|g| *g = [0.0; 3]);
        self.corner_blocks(positions, |start, len, u, w| {
            arch.dispatch(CornerAnglesGradients {
                u,
                w,
                alpha: &mut alpha[..len],
            });
            sums.add(self, start, &alpha[..len], theta);
            self.scatter_block(start, len, u, w, grad);
        });
        sums.finish(self, theta);
    }

    /// The corners in blocks of [`CORNER_BLOCK`]: each block's edges u = a − p and
    /// w = b − p gathered (x, y, z rows), then `block(start, len, u, w)` — the loop of
    /// [`Layout::theta`], [`Layout::gradient`] and [`Layout::evaluate`].
    #[inline]
    fn corner_blocks(
        &self,
        positions: &[[f64; 3]],
        mut block: impl FnMut(
            usize,
            usize,
            &mut [[f64; CORNER_BLOCK]; 3],
            &mut [[f64; CORNER_BLOCK]; 3],
        ),
    ) {
        let mut u = [[0.0f64; CORNER_BLOCK]; 3];
        let mut w = [[0.0f64; CORNER_BLOCK]; 3];
        let corners = self.corner_vertices.len();
        for start in (0..corners).step_by(CORNER_BLOCK) {
            let len = CORNER_BLOCK.min(corners - start);
            self.gather_edges(start, len, positions, &mut u, &mut w);
            block(start, len, &mut u, &mut w);
        }
    }

    /// Corner `k`'s points: its centre (the interior vertex), then the next and previous
    /// points of its face.
    #[inline]
    fn corner_points(&self, k: usize, positions: &[[f64; 3]]) -> [[f64; 3]; 3] {
        self.corner_vertices[k].map(|v| positions[v as usize])
    }

    /// Adds corner `k`'s gradients (centre, next, previous) to their entries of A.
    #[inline]
    fn scatter(&self, k: usize, g: [[f64; 3]; 3], grad: &mut [[f64; 3]]) {
        for (slot, gk) in self.corner_entries[k].iter().zip(g) {
            if *slot != INVALID {
                let e = &mut grad[*slot as usize];
                e[0] += gk[0];
                e[1] += gk[1];
                e[2] += gk[2];
            }
        }
    }

    /// Adds the gradients of corners `start..start + len` (with respect to their next and
    /// previous points in `u` and `w`, their centre's being minus the sum) to A, in corner
    /// order.
    #[inline]
    fn scatter_block<const B: usize>(
        &self,
        start: usize,
        len: usize,
        u: &[[f64; B]; 3],
        w: &[[f64; B]; 3],
        grad: &mut [[f64; 3]],
    ) {
        for j in 0..len {
            let ga = [u[0][j], u[1][j], u[2][j]];
            let gb = [w[0][j], w[1][j], w[2][j]];
            let gp = [-(ga[0] + gb[0]), -(ga[1] + gb[1]), -(ga[2] + gb[2])];
            self.scatter(start + j, [gp, ga, gb], grad);
        }
    }

    /// The entries of A alone, for positions whose θ is already known (an accepted trial).
    /// The corners go in blocks, as in [`Layout::theta`]: their edges first, then the
    /// arithmetic of [`crate::angle_gradient::corner_gradient`] in a loop without branches,
    /// which vectorises (one corner at a time it was 7 % of a 3.5k-face run), then the scatter in corner
    /// order — the same operations in the same order as one `corner_gradient` per corner,
    /// so the same bits (tested against `angle_sum_gradient`).
    pub fn gradient(&self, positions: &[[f64; 3]], grad: &mut [[f64; 3]]) {
        grad.iter_mut().for_each(|g| *g = [0.0; 3]);
        let arch = pulp::Arch::new();
        // The edges u, w of a block are overwritten by the gradients with respect to the
        // corner's next and previous points.
        self.corner_blocks(positions, |start, len, u, w| {
            arch.dispatch(CornerGradients { u, w, len });
            self.scatter_block(start, len, u, w, grad);
        });
    }

    /// θ at every interior vertex only (for trial points). The corners go in blocks: their
    /// edges u, w from the centre first, then their angles `vec3::angle(u, w)` in a loop
    /// without branches, which vectorises (atan2 one corner at a time was a fifth of a
    /// 3.5k-face run), then the sums in corner order: the same sums as
    /// [`Layout::theta_at`], bit for bit.
    pub fn theta(&self, positions: &[[f64; 3]], theta: &mut [f64]) {
        let mut alpha = [0.0f64; CORNER_BLOCK];
        let arch = pulp::Arch::new();
        let mut sums = AngleSums::default();
        self.corner_blocks(positions, |start, len, u, w| {
            // Compiled for the widest vectors the CPU has (4 lanes with AVX2 where the
            // baseline x86-64 build has 2): the same operations, so the same bits.
            arch.dispatch(CornerAngles {
                u,
                w,
                alpha: &mut alpha[..len],
            });
            sums.add(self, start, &alpha[..len], theta);
        });
        sums.finish(self, theta);
    }

    /// The edges u = a − p and w = b − p of corners `start..start + len`, coordinate by
    /// coordinate (the gather ahead of [`Layout::theta`]'s and [`Layout::gradient`]'s block
    /// loops).
    #[inline]
    fn gather_edges<const B: usize>(
        &self,
        start: usize,
        len: usize,
        positions: &[[f64; 3]],
        u: &mut [[f64; B]; 3],
        w: &mut [[f64; B]; 3],
    ) {
        for j in 0..len {
            let [p, a, b] = self.corner_points(start + j, positions);
            let (uj, wj) = (sub(a, p), sub(b, p));
            for c in 0..3 {
                u[c][j] = uj[c];
                w[c][j] = wj[c];
            }
        }
    }

    /// θ at interior vertex `i` only (its star's corners).
    pub fn theta_at(&self, i: usize, positions: &[[f64; 3]]) -> f64 {
        let mut t = 0.0;
        for k in self.corner_ptr[i]..self.corner_ptr[i + 1] {
            let [p, a, b] = self.corner_points(k, positions);
            t += angle(sub(a, p), sub(b, p));
        }
        t
    }

    /// Lower values of A G Aᵀ (without shift) into `values` (length [`Layout::normal_nnz`]).
    pub fn normal_matrix(&self, grad: &[[f64; 3]], metric: &Metric<'_>, values: &mut [f64]) {
        let dot = |gi: [f64; 3], gj: [f64; 3]| gi[0] * gj[0] + gi[1] * gj[1] + gi[2] * gj[2];
        match metric.normals {
            Some(normals) if metric.tangential < 1.0 => {
                // n_c · g_e once per entry of A rather than once per pair of entries that
                // share column c, packed beside the entry so that a pair reads two
                // 32-byte rows (the same products, so the same values bit for bit).
                let packed: Vec<[f64; 4]> = grad
                    .iter()
                    .zip(&self.col)
                    .map(|(g, &c)| [g[0], g[1], g[2], dot(normals[c as usize], *g)])
                    .collect();
                let t = metric.tangential;
                self.accumulate_pairs(values, |c, ei, ej| {
                    let (pi, pj) = (packed[ei], packed[ej]);
                    let dij = pi[0] * pj[0] + pi[1] * pj[1] + pi[2] * pj[2];
                    metric.scale[c] * (t * dij + (1.0 - t) * pi[3] * pj[3])
                });
            }
            _ => self.accumulate_pairs(values, |c, ei, ej| {
                metric.scale[c] * dot(grad[ei], grad[ej])
            }),
        }
    }

    /// Lower values of Lᵀ L into `values`, where `lt[e]` holds `L[col(e)][row(e)]` (Lᵀ in the
    /// layout of A).
    pub fn gram_of_transposed(&self, lt: &[f64], values: &mut [f64]) {
        self.accumulate_pairs(values, |_, ei, ej| lt[ei] * lt[ej]);
    }

    /// `values[s] = Σ term(c, e_i, e_j)` over the products (s, e_i, e_j) of entries of A that
    /// share column c, column by column in the layout's order (the one sum both normal
    /// matrices are made of).
    #[inline]
    fn accumulate_pairs(
        &self,
        values: &mut [f64],
        mut term: impl FnMut(usize, usize, usize) -> f64,
    ) {
        values.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..self.n() {
            for &[s, ei, ej] in &self.contrib[self.contrib_ptr[c]..self.contrib_ptr[c + 1]] {
                values[s as usize] += term(c, ei as usize, ej as usize);
            }
        }
    }

    /// Mean of the diagonal of a value set (the scale damping is measured against).
    pub fn mean_diagonal(&self, values: &[f64]) -> f64 {
        if self.n() == 0 {
            return 0.0;
        }
        self.diag_slot
            .iter()
            .map(|&s| values[s as usize])
            .sum::<f64>()
            / self.n() as f64
    }

    /// Numeric Cholesky of `values + shift · I` (or `+ diag(shift_diag)`), reusing the
    /// symbolic factorisation.
    pub fn factor(
        &self,
        values: &[f64],
        shift: f64,
        shift_diag: Option<&[f64]>,
    ) -> Result<Factor, FactorError> {
        let mut factor = self.new_factor()?;
        self.refactor(&mut factor, values, shift, shift_diag)?;
        Ok(factor)
    }

    /// The buffers of a factor on this layout, for [`Layout::refactor`] (not yet a valid
    /// factor).
    pub fn new_factor(&self) -> Result<Factor, FactorError> {
        let workspace = self
            .plan
            .as_ref()
            .map(SupernodalLltPlan::workspace)
            .transpose()
            .map_err(|e| FactorError::Other(e.to_string()))?;
        Ok(Factor {
            values: vec![0.0; self.symbolic.len_val()],
            shifted: vec![0.0; self.normal_nnz()],
            workspace,
            faer_scratch: None,
        })
    }

    /// [`Layout::factor`] into the buffers of `factor` (made by [`Layout::new_factor`] or
    /// [`Layout::factor`] on this layout). After an error `factor` is not a valid factor
    /// until the next successful call.
    ///
    /// The numbers come from `flatcut_sparse::SupernodalLltPlan` (the pattern's updates
    /// worked out once, faer's dense kernels where the supernodes are wide): the same
    /// factor as faer's numeric factorisation to round-off, 1.1–1.7× faster on these
    /// patterns (docs/benchmarks.md, seventeenth session).
    pub fn refactor(
        &self,
        factor: &mut Factor,
        values: &[f64],
        shift: f64,
        shift_diag: Option<&[f64]>,
    ) -> Result<(), FactorError> {
        self.shift_into(factor, values, shift, shift_diag)?;
        self.factorize_shifted(factor)
    }

    /// `scale` · D for `Damping::GraphLaplacian`, D = (ε I + L) / (ε + mean valence): the
    /// magnitude of its off-diagonal entries (−that per pair of interior neighbours) and
    /// its diagonal, per interior vertex. The damped step and the shaped merit's norm
    /// ([`Layout::graph_damping_triplets`]) take their D from here.
    fn graph_damping(&self, scale: f64) -> (f64, Vec<f64>) {
        let unit = scale / (GRAPH_DAMPING_EPSILON + self.mean_valence);
        let diag = self
            .valence
            .iter()
            .map(|d| unit * (GRAPH_DAMPING_EPSILON + d))
            .collect();
        (unit, diag)
    }

    /// The graph-Laplacian damping's matrix D as triplets (interior indices): the metric of
    /// the shaped damping's merit ‖θ − 2π‖²_{D⁻¹}.
    pub fn graph_damping_triplets(&self) -> flatcut_sparse::Triplets {
        let (unit, _) = self.graph_damping(1.0);
        self.graph_triplets(|valence| unit * (GRAPH_DAMPING_EPSILON + valence), -unit)
    }

    /// A matrix on the graph of the interior vertices as lower triplets (interior indices):
    /// `diagonal(full valence)` on the diagonal (boundary neighbours counted, as in a graph
    /// Laplacian with the boundary held at zero), `off` for every pair of interior
    /// neighbours; row by row, the diagonal first. With `|k| 1 + t k` and `−t` it is I + t L.
    pub fn graph_triplets(
        &self,
        diagonal: impl Fn(f64) -> f64,
        off: f64,
    ) -> flatcut_sparse::Triplets {
        let n = self.n();
        let mut t = flatcut_sparse::Triplets::with_capacity(n, self.col.len());
        for (i, &k) in self.valence.iter().enumerate() {
            t.push(i, i, diagonal(k));
            for &j in &self.col[self.row_ptr[i] + 1..self.row_ptr[i + 1]] {
                if (j as usize) < i {
                    t.push(i, j as usize, off);
                }
            }
        }
        t
    }

    /// [`Layout::refactor`] of `values + shift · D`, D shaped as `damping` says (robust
    /// mode's damped step).
    pub fn refactor_damped(
        &self,
        factor: &mut Factor,
        values: &[f64],
        shift: f64,
        damping: Damping,
    ) -> Result<(), FactorError> {
        match damping {
            Damping::Identity => self.shift_into(factor, values, shift, None)?,
            Damping::GraphLaplacian => {
                let (unit, diag) = self.graph_damping(shift);
                self.shift_into(factor, values, 0.0, Some(&diag))?;
                for &s in &self.ring_slots {
                    factor.shifted[s as usize] -= unit;
                }
            }
        }
        self.factorize_shifted(factor)
    }

    /// The numeric factorisation of `factor.shifted`.
    fn factorize_shifted(&self, factor: &mut Factor) -> Result<(), FactorError> {
        match (&self.plan, &mut factor.workspace, self.symbolic.raw()) {
            (Some(plan), Some(workspace), SymbolicCholeskyRaw::Supernodal(supernodal)) => plan
                .factorize(supernodal, &factor.shifted, &mut factor.values, workspace)
                .map_err(|_| FactorError::NotPositiveDefinite),
            _ => self.faer_factorize(factor),
        }
    }

    /// [`Layout::refactor`] by faer's own numeric factorisation: the reference "one sparse
    /// Cholesky" of the issue's speed targets (`measure -- speed`, the step-kernel benchmark).
    pub fn refactor_with_faer(
        &self,
        factor: &mut Factor,
        values: &[f64],
        shift: f64,
        shift_diag: Option<&[f64]>,
    ) -> Result<(), FactorError> {
        self.shift_into(factor, values, shift, shift_diag)?;
        self.faer_factorize(factor)
    }

    /// `values + shift · I (+ diag(shift_diag))` into `factor.shifted`, checked finite.
    fn shift_into(
        &self,
        factor: &mut Factor,
        values: &[f64],
        shift: f64,
        shift_diag: Option<&[f64]>,
    ) -> Result<(), FactorError> {
        let v = &mut factor.shifted;
        v.copy_from_slice(values);
        for (j, &s) in self.diag_slot.iter().enumerate() {
            v[s as usize] += shift + shift_diag.map_or(0.0, |d| d[j]);
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(FactorError::NotPositiveDefinite);
        }
        Ok(())
    }

    fn faer_factorize(&self, factor: &mut Factor) -> Result<(), FactorError> {
        let scratch = match &mut factor.faer_scratch {
            Some(scratch) => scratch,
            None => factor.faer_scratch.insert(
                MemBuffer::try_new(
                    self.symbolic
                        .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
                )
                .map_err(|e| FactorError::Other(format!("{e:?}")))?,
            ),
        };
        let mat = SparseColMatRef::new(self.pattern.as_ref(), &factor.shifted);
        // faer zeroes L itself before filling it.
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut factor.values,
                mat,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(scratch),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|_| FactorError::NotPositiveDefinite)
    }

    /// Solves in place for `k` right-hand sides stored column-major in `rhs` (n × k).
    pub fn solve(&self, factor: &Factor, rhs: &mut [f64], k: usize) {
        let n = self.n();
        // Into the factor's order and back (what faer does itself when it holds the order).
        let mut permuted = vec![0.0; n * k];
        for col in 0..k {
            for (kk, &o) in self.order.iter().enumerate() {
                permuted[col * n + kk] = rhs[col * n + o as usize];
            }
        }
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(supernodal) => {
                for column in permuted.chunks_exact_mut(n) {
                    solve_llt_in_place(supernodal, &factor.values, column);
                }
            }
            // Only an empty system (faer makes its factor simplicial even when supernodal is
            // forced; pieces without interior vertices never get here).
            SymbolicCholeskyRaw::Simplicial(_) => {
                let par = Par::Seq;
                let mut buf = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, par));
                let mat = MatMut::from_column_major_slice_mut(&mut permuted, n, k);
                LltRef::<'_, u32, f64>::new(&self.symbolic, &factor.values)
                    .solve_in_place_with_conj(Conj::No, mat, par, MemStack::new(&mut buf));
            }
        }
        for col in 0..k {
            for (kk, &o) in self.order.iter().enumerate() {
                rhs[col * n + o as usize] = permuted[col * n + kk];
            }
        }
    }

    /// d = G Aᵀ x, one 3-vector per interior vertex.
    pub fn step_from_multipliers(
        &self,
        grad: &[[f64; 3]],
        metric: &Metric<'_>,
        x: &[f64],
    ) -> Vec<[f64; 3]> {
        let mut at = vec![[0.0; 3]; self.n()];
        for (i, &xi) in x.iter().enumerate() {
            for e in self.row_ptr[i]..self.row_ptr[i + 1] {
                let c = self.col[e] as usize;
                let g = grad[e];
                at[c][0] += g[0] * xi;
                at[c][1] += g[1] * xi;
                at[c][2] += g[2] * xi;
            }
        }
        metric.apply_field(&at)
    }

    /// A d, one value per interior vertex.
    pub fn apply(&self, grad: &[[f64; 3]], d: &[[f64; 3]]) -> Vec<f64> {
        (0..self.n())
            .map(|i| {
                (self.row_ptr[i]..self.row_ptr[i + 1])
                    .map(|e| {
                        let (g, v) = (grad[e], d[self.col[e] as usize]);
                        g[0] * v[0] + g[1] * v[1] + g[2] * v[2]
                    })
                    .sum()
            })
            .collect()
    }
}

/// One least-norm step: d = G Aᵀ (A G Aᵀ + μ I)⁻¹ b. `normal` holds the lower values of
/// A G Aᵀ for this `grad` and `metric`.
pub fn least_norm_step(
    layout: &Layout,
    grad: &[[f64; 3]],
    metric: &Metric<'_>,
    normal: &[f64],
    b: &[f64],
    mu: f64,
) -> Result<Vec<[f64; 3]>, FactorError> {
    let factor = layout.factor(normal, mu, None)?;
    let mut x = b.to_vec();
    layout.solve(&factor, &mut x, 1);
    if x.iter().any(|v| !v.is_finite()) {
        return Err(FactorError::NotPositiveDefinite);
    }
    Ok(layout.step_from_multipliers(grad, metric, &x))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use flatcut_mesh::shapes;

    /// The lower pattern of A G Aᵀ by its definition: every pair (j ≤ i) of rows of A that
    /// share a column, sorted by column then row, duplicates removed.
    fn pattern_by_definition(layout: &Layout) -> (Vec<u32>, Vec<u32>) {
        let n = layout.n();
        let mut rows_of_col = vec![Vec::new(); n];
        for i in 0..n {
            for &c in &layout.col[layout.row_ptr[i]..layout.row_ptr[i + 1]] {
                rows_of_col[c as usize].push(i as u32);
            }
        }
        let mut pairs = Vec::new();
        for rows in &rows_of_col {
            for &i in rows {
                for &j in rows {
                    if j <= i {
                        pairs.push((j, i));
                    }
                }
            }
        }
        csc_of_pairs(n, pairs)
    }

    /// A lower CSC pattern from its (column, row) pairs: sorted, duplicates removed.
    fn csc_of_pairs(n: usize, mut pairs: Vec<(u32, u32)>) -> (Vec<u32>, Vec<u32>) {
        pairs.sort_unstable();
        pairs.dedup();
        let mut col_ptr = vec![0u32; n + 1];
        for &(j, _) in &pairs {
            col_ptr[j as usize + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        (col_ptr, pairs.iter().map(|&(_, i)| i).collect())
    }

    #[test]
    fn normal_pattern_equals_its_definition() {
        for mesh in [
            shapes::saddle_grid(9),
            shapes::sphere_cap(10.0, 1.0, 6),
            shapes::patch_with_holes(10.0, 12),
        ] {
            let topo = Topology::build(&mesh).unwrap();
            let layout = Layout::build(&topo, &mesh.faces).unwrap();
            let (col_ptr, row_idx) = pattern_by_definition(&layout);
            assert!(layout.n() > 10);
            // Stored in the fill-reducing order: back to interior indices, lower, sorted.
            let mut pairs = Vec::new();
            for k in 0..layout.n() {
                let col_ptr = layout.pattern.col_ptr();
                let range = col_ptr[k] as usize..col_ptr[k + 1] as usize;
                for &r in &layout.pattern.row_idx()[range] {
                    let (a, b) = (layout.order[r as usize], layout.order[k]);
                    pairs.push((a.min(b), a.max(b)));
                }
            }
            let stored_len = pairs.len();
            let (stored_ptr, stored_rows) = csc_of_pairs(layout.n(), pairs);
            // No entry stored twice.
            assert_eq!(stored_rows.len(), stored_len);
            assert_eq!(stored_ptr, col_ptr);
            assert_eq!(stored_rows, row_idx);
        }
    }
}
