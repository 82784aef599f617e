//! What [`crate::process`] reports, per piece and for the whole mesh (serialised to JSON
//! by the CLI's `--report`).
//!
//! θ_err is the paper's Eq. 13, max_p |θ(v_p) − 2π| over interior vertices (radians); the
//! RMS over interior vertices is reported beside it because a maximum hides how much of a
//! piece is already flat.

use serde::Serialize;

use crate::hole_closure::HoleClosure;

/// An interior edge whose bend (the angle between its two faces' normals) grew by more than
/// this over the input's (degrees) counts as creased: see docs/algorithms/flattenable.md,
/// "Creases", for the values measured on smooth and pleated results.
pub const CREASE_DEG: f64 = 30.0;

/// A crease whose vertices' input angle defects sum to less than this in magnitude (rad)
/// lies in nearly developable surface: at a working resolution of 5–10 mm the per-vertex
/// defect of a smooth body is a few 1e-3 rad, so a crease of tens of edges there sums to
/// a few hundredths of its noise.
pub const CREASE_DEFECT_NEUTRAL_RAD: f64 = 0.05;

/// The surface a crease lies in, read from the sign of the input's angle defect Σ (2π − θ)
/// over the interior vertices of the creased edges ([`PieceReport::creased_defect_rad`]);
/// it says which cut takes the crease away.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CreaseKind {
    /// Angle excess (θ > 2π): the piece has more surface there than a flat sheet spans
    /// around those vertices. A dart takes surface out and makes it worse; a seam there (or
    /// a gusset let into a slit) gives the excess its own piece.
    SaddleLike,
    /// Angle deficit (θ < 2π): the sheet has too much; a dart takes it out.
    DomeLike,
    /// |Σ| below [`CREASE_DEFECT_NEUTRAL_RAD`]: the crease comes from the fixed boundary, not
    /// from the curvature under it.
    NearlyDevelopable,
}

impl CreaseKind {
    /// The kind of a crease whose interior vertices sum to `creased_defect_rad`; `None` for
    /// NaN (no input to read it from).
    pub fn of(creased_defect_rad: f64) -> Option<Self> {
        if creased_defect_rad.is_nan() {
            None
        } else if creased_defect_rad.abs() < CREASE_DEFECT_NEUTRAL_RAD {
            Some(Self::NearlyDevelopable)
        } else if creased_defect_rad < 0.0 {
            Some(Self::SaddleLike)
        } else {
            Some(Self::DomeLike)
        }
    }

    /// What a pattern engineer can do there, in a few words. Local to the crease: a piece
    /// that is cup-like as a whole (its total defect's hint asks for darts) can crease in a
    /// saddle-like part of it, where a dart does not help.
    pub fn advice(self) -> &'static str {
        match self {
            Self::SaddleLike => "saddle-like under the crease: a seam or gusset there, not a dart",
            Self::DomeLike => "dome-like under the crease: a dart there",
            Self::NearlyDevelopable => {
                "nearly developable under the crease: the fixed seam forces it; move that seam"
            }
        }
    }
}

/// The outcome of one connected component.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PieceReport {
    /// Component number (order of first appearance of its faces).
    pub piece: usize,
    /// Vertices of the piece.
    pub vertices: usize,
    /// Faces of the piece.
    pub faces: usize,
    /// Interior vertices (the constraints θ = 2π and the vertices that move).
    pub interior_vertices: usize,
    /// Boundary loops (1 for a disk; more for a piece with holes, all fixed).
    pub boundary_loops: usize,
    /// Per hole (every boundary loop but the longest) of the returned positions: how it
    /// develops in the plane. θ = 2π alone does not close a hole; one that does not close
    /// stretches the pattern around it ([`crate::hole_closure`]). Under `HoleRims::Free` the
    /// run's own numbers (`iterations`, `theta_err`, `factorizations`, …) are those of the
    /// piece with its holes filled, the measures of the result (θ, holes, displacement,
    /// area, folds, creases) the piece's own.
    pub holes: Vec<HoleClosure>,
    /// The largest [`HoleClosure::error_rad`] over the holes (rad; 0 without holes).
    pub final_hole_err: f64,
    /// Accepted iterations.
    pub iterations: usize,
    /// Robust mode: θ_err ≤ tolerance. Paper mode: the paper's terminal condition held.
    pub converged: bool,
    /// θ_err (max |θ − 2π|, rad) of the input and after every accepted iteration.
    pub theta_err: Vec<f64>,
    /// θ_err of the returned positions (rad).
    pub final_theta_err: f64,
    /// RMS of θ − 2π over interior vertices of the returned positions (rad).
    pub final_theta_rms: f64,
    /// RMS of θ − 2π over interior vertices of the input (rad): what `final_theta_rms` is
    /// compared with (an unconverged piece is returned at its least ‖θ − 2π‖², whose max can
    /// be above the input's on rough pieces).
    pub input_theta_rms: f64,
    /// Σ (2π − θ) over interior vertices of the input (rad): the total Gaussian curvature
    /// the fixed boundary has to absorb. Negative (saddle-like) pieces are hard.
    pub input_total_defect_rad: f64,
    /// Largest vertex displacement (model units, mm).
    pub max_displacement_mm: f64,
    /// RMS displacement over interior vertices (mm).
    pub rms_displacement_mm: f64,
    /// Relative change of the total area, in percent.
    pub area_change_percent: f64,
    /// Faces whose normal flipped against the input or with a corner newly below the
    /// angle floor (0 in every returned result of robust mode).
    pub folded_faces: usize,
    /// Smallest corner angle of the result (degrees).
    pub min_angle_deg: f64,
    /// Largest angle between a face's normal in the result and in the input (degrees;
    /// below 90 in robust mode, whose fold guard rejects more).
    pub max_normal_turn_deg: f64,
    /// Largest growth of an interior edge's bend over the input's (degrees): how sharply
    /// the result creases where the input did not.
    pub max_crease_deg: f64,
    /// Interior edges whose bend grew by more than [`CREASE_DEG`]: where the flattenable
    /// surface creases (the one nearest a saddle is pleated) and the flattened piece folds.
    pub creased_edges: usize,
    /// Σ (2π − θ) of the input over the interior vertices of the creased edges (rad; 0
    /// without crease): negative where the crease lies in saddle-like surface. See
    /// [`CreaseKind::of`].
    pub creased_defect_rad: f64,
    /// Input position (mm) of an end of the edge whose bend grew most, when an edge creased.
    pub sharpest_crease_position_mm: Option<[f64; 3]>,
    /// The interior vertex of largest |θ − 2π| in the returned positions (input numbering;
    /// `None` without interior vertex): where an unconverged piece is least flat.
    pub worst_vertex: Option<u32>,
    /// Its input position (mm).
    pub worst_vertex_position_mm: Option<[f64; 3]>,
    /// The fewest interior vertices that hold half of the remaining ‖θ − 2π‖² (0 when it is
    /// 0): a few means one spot resists, a large share of `interior_vertices` means the
    /// residual is spread over the piece.
    pub vertices_holding_half_residual: usize,
    /// The largest input distance (mm) from the worst vertex to one of those vertices: whether
    /// the spot that resists is small enough for one cut or dart.
    pub half_residual_radius_mm: f64,
    /// Trial steps rejected by the merit test or the fold guards (robust mode).
    pub rejected_steps: usize,
    /// Rejected trials rescued by a fraction of the same step (no new factorisation;
    /// robust mode, counted in `rejected_steps` too).
    pub backtracked_steps: usize,
    /// Second-order corrections kept (robust mode): each moved the trial point for one solve
    /// and one θ evaluation with the step's factorisation, where another step would have
    /// cost a factorisation. None on a piece below 1 000 faces solved directly, where a
    /// factorisation is too cheap for them to pay.
    pub corrections: usize,
    /// Smoothed steps taken (robust mode, every attempt; each also counts as an iteration of
    /// its attempt): low-pass filtered Gauss–Newton steps on a plateau near θ = 2π, where the
    /// damped steps of a shallow piece gain < 1 % each, and the smoothed jumps kept (where no
    /// filtered step gains: a part of the smooth step, then plain steps; the messages say
    /// how many were kept and undone).
    pub smoothed_steps: usize,
    /// Pull-backs towards the input taken by `Target::Detail` (robust mode; counted in
    /// `iterations`).
    pub pull_backs: usize,
    /// Numeric Cholesky factorisations of A G Aᵀ (+ μ m I) done (robust mode): the unit of
    /// cost an iteration is measured against.
    pub factorizations: usize,
    /// Wall time of the piece (seconds).
    pub seconds: f64,
    /// Why the iteration stopped.
    pub stop_reason: String,
    /// Diagnostics worth reading (switches, warnings, unchanged pieces).
    pub messages: Vec<String>,
}

/// The outcome of [`crate::process`].
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ProcessReport {
    /// "paper" or "robust".
    pub mode: String,
    /// Largest iteration count over the pieces.
    pub iterations: usize,
    /// Every piece converged.
    pub converged: bool,
    /// Per iteration, the largest θ_err over the pieces (a finished piece keeps its last).
    pub theta_err: Vec<f64>,
    /// Largest θ_err over the pieces (rad).
    pub final_theta_err: f64,
    /// RMS of θ − 2π over all interior vertices (rad).
    pub final_theta_rms: f64,
    /// The same of the input (rad).
    pub input_theta_rms: f64,
    /// Largest vertex displacement (mm).
    pub max_displacement_mm: f64,
    /// RMS displacement over all interior vertices (mm).
    pub rms_displacement_mm: f64,
    /// Relative change of the total area (percent).
    pub area_change_percent: f64,
    /// Folded faces over all pieces.
    pub folded_faces: usize,
    /// Largest normal turn against the input over the pieces (degrees).
    pub max_normal_turn_deg: f64,
    /// Largest crease over the pieces (see [`PieceReport::max_crease_deg`]).
    pub max_crease_deg: f64,
    /// Creased edges over all pieces (see [`PieceReport::creased_edges`]).
    pub creased_edges: usize,
    /// Wall time of the whole call (seconds).
    pub seconds: f64,
    /// One entry per connected component.
    pub pieces: Vec<PieceReport>,
    /// Diagnostics of the whole call.
    pub messages: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crease_kind_follows_the_sign_beyond_the_neutral_band() {
        let band = CREASE_DEFECT_NEUTRAL_RAD;
        assert_eq!(CreaseKind::of(-0.61), Some(CreaseKind::SaddleLike));
        assert_eq!(CreaseKind::of(-band), Some(CreaseKind::SaddleLike));
        assert_eq!(
            CreaseKind::of(-band * (1.0 - 1e-12)),
            Some(CreaseKind::NearlyDevelopable)
        );
        assert_eq!(CreaseKind::of(0.0), Some(CreaseKind::NearlyDevelopable));
        assert_eq!(
            CreaseKind::of(band * (1.0 - 1e-12)),
            Some(CreaseKind::NearlyDevelopable)
        );
        assert_eq!(CreaseKind::of(band), Some(CreaseKind::DomeLike));
        assert_eq!(CreaseKind::of(0.94), Some(CreaseKind::DomeLike));
        assert_eq!(CreaseKind::of(f64::NAN), None);
        assert!(CreaseKind::SaddleLike.advice().contains("not a dart"));
        assert!(CreaseKind::DomeLike.advice().contains("a dart"));
    }
}
