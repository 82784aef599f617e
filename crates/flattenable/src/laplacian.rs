//! The least-square position update (the paper's Eq. 9–12 and, weighted, Eq. 17):
//!
//! min ‖L v − g‖² + Σ_p w_p² ‖v_p − v*_p‖²  ⇔  (Lᵀ L + diag(w²)) v = Lᵀ g + diag(w²) v*
//!
//! over the interior vertices, with the boundary vertices as constants moved into g.
//! The Laplacian is one of
//! - cotan (Eq. 11): L(v_p) = 1/(2 Ā_p) Σ_q (cot α_pq + cot β_pq)(v_p − v_q), with
//!   Ā_p the mixed area normalised by its mean over the interior vertices (Eq. 12), so L
//!   has units of length and the balance with ‖v − v*‖ does not depend on the scale (Fig. 4);
//! - uniform (our reading of "the discrete graph Laplacian"): the umbrella operator
//!   L(v_p) = v_p − mean_q v_q, also scale free.
//!
//! The target is `Target::Zero` (the paper: g holds only boundary terms, the filter
//! minimises ‖L v‖, a thin-plate smoother that shrinks) or `Target::Detail` (g also holds
//! L v⁰ of the input, so the filter preserves the input's Laplacian coordinates: no
//! shrinking). L is built once per piece from the input positions (the paper: "a fixed
//! Laplacian matrix L computed at the beginning of iteration"), so Lᵀ L + diag(w²) is
//! factorised once per piece.

use flatcut_mesh::geometry::{cotan_weights, mixed_areas};
use flatcut_mesh::{INVALID, Topology, VertexId};

use crate::least_norm::{Factor, FactorError, Layout};
use crate::options::{Laplacian, Target};

/// The prepared least-square filter of one piece.
pub struct LeastSquareUpdate {
    /// Lᵀ in the layout of A: `lt[e]` = `L[col(e)][row(e)]`.
    lt: Vec<f64>,
    /// g per interior vertex (boundary terms, plus L v⁰ for `Target::Detail`).
    g: Vec<[f64; 3]>,
    /// w_p² per interior vertex.
    w2: Vec<f64>,
    factor: Factor,
}

impl LeastSquareUpdate {
    /// Builds L from `positions` (the input), the right-hand side g and the factorisation
    /// of Lᵀ L + diag(w²). `weights` is w per interior vertex.
    pub fn new(
        layout: &Layout,
        topo: &Topology,
        positions: &[[f64; 3]],
        faces: &[[u32; 3]],
        laplacian: Laplacian,
        target: Target,
        weights: &[f64],
    ) -> Result<Self, FactorError> {
        let n = layout.n();
        // Coefficients of row k of L: diagonal and off-diagonal (k, q) for every neighbour.
        let edge_w = match laplacian {
            Laplacian::Cotan => cotan_weights(positions, faces, topo),
            Laplacian::Uniform => Vec::new(),
        };
        let areas = mixed_areas(positions, faces);
        let mean_area = if n > 0 {
            layout
                .interior
                .iter()
                .map(|&p| areas[p as usize])
                .sum::<f64>()
                / n as f64
        } else {
            1.0
        };
        // lt[e] with e = (row i, col k) holds L[k][i].
        let mut lt = vec![0.0; layout.entries()];
        let mut g = vec![[0.0; 3]; n];
        for (k, &p) in layout.interior.iter().enumerate() {
            let out = topo.outgoing(VertexId(p));
            let coefs: Vec<(u32, f64)> = out
                .iter()
                .map(|&h| {
                    let q = topo.to_vertex(h).0;
                    let c = match laplacian {
                        // w_pq = (cot α + cot β)/2, so (cot α + cot β)/(2Ā) = w_pq / Ā.
                        Laplacian::Cotan => {
                            edge_w[topo.edge_of(h) as usize] / (areas[p as usize] / mean_area)
                        }
                        Laplacian::Uniform => 1.0 / out.len() as f64,
                    };
                    (q, c)
                })
                .collect();
            let diag: f64 = coefs.iter().map(|(_, c)| c).sum();
            // L v⁰ at p (for the detail target) and the boundary constants.
            let mut lv0 = [0.0; 3];
            for c in 0..3 {
                lv0[c] = diag * positions[p as usize][c];
            }
            for &(q, c) in &coefs {
                for d in 0..3 {
                    lv0[d] -= c * positions[q as usize][d];
                }
                let qi = layout.index_of[q as usize];
                if qi == INVALID {
                    for d in 0..3 {
                        g[k][d] += c * positions[q as usize][d];
                    }
                } else {
                    // L[k][qi] = −c sits in row qi, column k of Lᵀ.
                    set_entry(layout, qi as usize, k as u32, -c, &mut lt);
                }
            }
            set_entry(layout, k, k as u32, diag, &mut lt);
            if target == Target::Detail {
                for d in 0..3 {
                    g[k][d] += lv0[d];
                }
            }
        }
        let w2: Vec<f64> = weights.iter().map(|w| w * w).collect();
        let mut values = vec![0.0; layout.normal_nnz()];
        layout.gram_of_transposed(&lt, &mut values);
        let factor = layout.factor(&values, 0.0, Some(&w2))?;
        Ok(Self { lt, g, w2, factor })
    }

    /// The filtered interior positions for the targets v* (one per interior vertex).
    pub fn apply(&self, layout: &Layout, v_star: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let n = layout.n();
        let mut rhs = vec![0.0; 3 * n];
        for i in 0..n {
            for e in layout.row_ptr[i]..layout.row_ptr[i + 1] {
                let k = layout.col[e] as usize;
                for d in 0..3 {
                    rhs[d * n + i] += self.lt[e] * self.g[k][d];
                }
            }
            for d in 0..3 {
                rhs[d * n + i] += self.w2[i] * v_star[i][d];
            }
        }
        layout.solve(&self.factor, &mut rhs, 3);
        (0..n)
            .map(|i| [rhs[i], rhs[n + i], rhs[2 * n + i]])
            .collect()
    }
}

fn set_entry(layout: &Layout, row: usize, col: u32, value: f64, lt: &mut [f64]) {
    for e in layout.row_ptr[row]..layout.row_ptr[row + 1] {
        if layout.col[e] == col {
            lt[e] = value;
            return;
        }
    }
}
