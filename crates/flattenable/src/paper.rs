//! `Mode::Paper`: Algorithm 1 of the paper as printed.
//!
//! repeat: A and b = 2π − θ at the current positions (Eq. 5); (A W² Aᵀ) x = b (Eq. 8/16);
//! d = W² Aᵀ x; update the interior positions directly (v ← v + d) or by the least-square
//! filter (Eq. 9/17) until the hybrid switch (θ_err < 1e-3, or a decrease of θ_err below
//! 0.01 in one step after 20 steps) hands over to the direct update; until ‖d‖² < ε with
//! ε = max(n_int·1e-8, 1e-5) or 50 steps.
//!
//! Decisions where the text is open (docs/algorithms/flattenable.md): the terminal test is
//! made on the d of the step just applied; the switch is tested after each step on the
//! θ_err it produced; the symbolic factorisation is made once per piece; an input already
//! within `tolerance_rad` is returned unchanged (no step is computed from a vanishing
//! Jacobian). The paper has no fold guard: folded faces are counted and flagged in the
//! report; a non-finite position is an error ([`FlattenableError::Diverged`]).

use std::f64::consts::TAU;

use crate::FlattenableError;
use crate::laplacian::LeastSquareUpdate;
use crate::least_norm::{FactorError, Metric, least_norm_step};
use crate::options::{ProcessOptions, Update};
use crate::piece::Piece;
use crate::report::PieceReport;

/// Runs paper mode on one piece; returns the final local positions.
pub fn run(
    piece: &Piece,
    opts: &ProcessOptions,
    report: &mut PieceReport,
) -> Result<Vec<[f64; 3]>, FlattenableError> {
    let layout = &piece.layout;
    let n = layout.n();
    let mut pos = piece.pos0.clone();
    let mut theta = vec![0.0; n];
    let mut grad = vec![[0.0; 3]; layout.entries()];
    let mut normal = vec![0.0; layout.normal_nnz()];
    layout.evaluate(&pos, &mut theta, &mut grad);
    let (mut err, _) = Piece::errors(&theta);
    report.theta_err.push(err);
    opts.progress.notify(piece, 0, err);
    let scale: Vec<f64> = piece.weights.iter().map(|w| 1.0 / (w * w)).collect();
    let metric = Metric {
        scale: &scale,
        normals: None,
        tangential: 1.0,
    };
    let singular = |iteration: usize, e: FactorError| FlattenableError::Singular {
        piece: piece.index,
        iteration,
        detail: format!("{e:?}"),
    };
    let mut ls = match opts.update {
        Update::LeastSquare => Some(
            LeastSquareUpdate::new(
                layout,
                &piece.topo,
                &piece.pos0,
                &piece.faces,
                opts.laplacian,
                opts.target,
                &piece.weights,
            )
            .map_err(|e| singular(0, e))?,
        ),
        Update::Direct => None,
    };
    let eps = (n as f64 * opts.stop_d2_per_vertex).max(opts.stop_d2_min);
    report.stop_reason = "iteration limit".into();
    for it in 0..opts.iteration_limit() {
        if err <= opts.tolerance_rad {
            report.converged = true;
            report.stop_reason = format!("θ_err ≤ {:.1e} rad", opts.tolerance_rad);
            break;
        }
        layout.normal_matrix(&grad, &metric, &mut normal);
        let b: Vec<f64> = theta.iter().map(|t| TAU - t).collect();
        let d = least_norm_step(layout, &grad, &metric, &normal, &b, 0.0)
            .map_err(|e| singular(it, e))?;
        let interior = piece.interior_of(&pos);
        let v_star: Vec<[f64; 3]> = interior
            .iter()
            .zip(&d)
            .map(|(v, d)| [v[0] + d[0], v[1] + d[1], v[2] + d[2]])
            .collect();
        let next = match &ls {
            Some(f) => f.apply(layout, &v_star),
            None => v_star,
        };
        pos = piece.with_interior(&pos, &next);
        layout.evaluate(&pos, &mut theta, &mut grad);
        let prev = err;
        (err, _) = Piece::errors(&theta);
        report.iterations = it + 1;
        report.theta_err.push(err);
        opts.progress.notify(piece, it + 1, err);
        if !err.is_finite() || pos.iter().flatten().any(|c| !c.is_finite()) {
            return Err(FlattenableError::Diverged {
                piece: piece.index,
                iteration: it + 1,
                theta_err: err,
                folded_faces: piece.faces.len(),
            });
        }
        if ls.is_some()
            && (err < opts.switch_theta_err
                || (it + 1 >= opts.switch_after && prev - err < opts.switch_decrease))
        {
            ls = None;
            report.messages.push(format!(
                "switched to the direct update after iteration {}",
                it + 1
            ));
        }
        let d2: f64 = d
            .iter()
            .map(|v| v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            .sum();
        if d2 < eps {
            report.converged = true;
            report.stop_reason = format!("terminal condition ‖d‖² = {d2:.3e} < {eps:.3e}");
            break;
        }
    }
    let folded = piece.folded_faces(&pos);
    if folded > 0 {
        // The paper has no fold guard; its result is returned as it is, flagged.
        report.messages.push(format!(
            "{folded} faces folded (normal flipped against the input or a corner newly below {} deg): the paper's method has no fold guard; use the robust mode",
            opts.min_angle_deg
        ));
    }
    Ok(pos)
}
