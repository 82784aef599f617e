//! Options of [`crate::process`], read straight from the pipeline TOML (serde); every
//! field has a documented default.

use serde::{Deserialize, Serialize};

use crate::progress::ProgressHook;

/// Which algorithm runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// The paper as printed: undamped least-norm steps, the chosen position update, the
    /// hybrid switch and the terminal condition ‖d‖² < max(n_int·1e-8, 1e-5) or 50 steps.
    Paper,
    /// Levenberg–Marquardt-damped least-norm steps with a trust-region test on
    /// ‖θ − 2π‖², fold guards, scale-free thresholds, polish to `tolerance_rad`.
    #[default]
    Robust,
}

/// How the positions follow the least-norm step d.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Update {
    /// v ← v + d.
    #[default]
    Direct,
    /// v ← argmin ‖L v − g‖² + ‖W⁻¹(v − (v + d))‖² (Eq. 9 / 17), switching to the direct
    /// update by the hybrid rule.
    LeastSquare,
}

/// The Laplacian of the least-square update.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Laplacian {
    /// Eq. 11 with the normalised mixed area of Eq. 12.
    #[default]
    Cotan,
    /// The umbrella operator v_p − mean of the one-ring.
    Uniform,
}

/// What the result should stay close to: the target of the least-square update and, in
/// robust mode, whether the converged surface is pulled back towards the input.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Target {
    /// 0, the paper (thin-plate smoothing; shrinks). Robust mode: memoryless least-norm
    /// steps only (fewer iterations).
    Zero,
    /// L v⁰ of the input: keeps the input's detail, does not shrink. Robust mode also pulls
    /// the surface back towards the input along the constraint set (least total
    /// displacement, the paper's Eq. 1) while holding the area, so that the result is never
    /// farther from the input nor of larger area change than `Zero`'s (with the least-square
    /// update, `Zero` runs beside it and is returned when it is not). Measured: up to 6.6 %
    /// less RMS displacement on real pieces (1.3 % on average), 10–40 % on saddles, at
    /// 1.2–2.5× the factorisations of `Zero` on the bench caps (1.39× over 19 sizes, 1.13× on
    /// random mixed pieces; twice the CPU with the least-square update); `Zero` is the fast choice.
    #[default]
    Detail,
}

/// Shape of the Levenberg–Marquardt damping of robust mode's step (A G Aᵀ + μ m D) x = b.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Damping {
    /// D = I: the large-μ limit is the steepest-descent step of ‖θ − 2π‖². Measured the
    /// better default on every input but the largest body piece (docs/algorithms/
    /// flattenable.md, "A damping shaped like the graph Laplacian").
    #[default]
    Identity,
    /// D = (ε I + L) / (ε + mean valence), L the graph Laplacian of the interior vertices
    /// (valence on the diagonal, −1 per interior neighbour; ε =
    /// `least_norm::GRAPH_DAMPING_EPSILON`): smooth parts of the residual are damped up to
    /// ~1/ε times less than rough ones. Converges the 85k-face upper back that `Identity`
    /// does not; stalls some saddles that `Identity` converges. The coarse-to-fine rescue
    /// tries it right after a large piece's direct solve hands the piece over, when every
    /// other attempt has failed near θ = 2π, and on a rough piece as a last direct solve
    /// (`CoarseToFine::rescue`). The levels of
    /// its hierarchies measure ‖θ − 2π‖ in the D⁻¹ norm, in which its heavily damped steps
    /// descend; a direct solve keeps the plain norm.
    GraphLaplacian,
}

/// How a coarse solution is carried to the next finer level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Prolongation {
    /// v_fine = v⁰_fine + interp(v_coarse − v⁰_coarse): keeps the fine detail, which the
    /// fine level then only has to flatten locally.
    #[default]
    Displacement,
    /// v_fine = interp(v_coarse): the fine vertices start on the flattenable coarse surface
    /// (fine detail lost; the detail target must pull it back).
    Positions,
}

/// Coarse-to-fine for large pieces (robust mode): coarsen the piece by interior
/// half-edge collapses (boundary kept bit-identical), solve the coarsest level from the
/// input, prolongate, finish on each finer level. See docs/algorithms/flattenable.md.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CoarseToFine {
    /// A level with at least this many faces gets a coarser level below it; pieces with
    /// fewer faces are solved directly. Default 2 000 (measured in
    /// docs/algorithms/flattenable.md: below that the fine solve is already fast).
    pub min_faces: usize,
    /// Pieces with more faces than this are solved directly first (with `rescue`, the
    /// hierarchies follow if that does not converge). Default 15 000: measured to help
    /// from 2k to 10k faces (body pieces, grids); above, mixed — a 100k-face cap went from 283
    /// to 109 fine iterations, another 100k cap and the 19.6k one stalled from the
    /// prolongated start and fell back to the direct solve at twice its time
    /// (docs/algorithms/flattenable.md). Raise it to try coarse-to-fine on larger pieces.
    pub max_faces: usize,
    /// Face-count ratio between consecutive levels (> 1). Default 4.
    pub ratio: f64,
    /// Largest number of coarse levels; 0 disables coarse-to-fine. Default 3.
    pub levels: usize,
    /// How a coarse solution is carried to the finer level. Default `Displacement`.
    pub prolongation: Prolongation,
    /// θ_err (radians) at which a coarse level is solved enough; one that stops above it
    /// abandons the hierarchy. Default 3e-4, below the error prolongation leaves on the finer
    /// level (~1e-3–1e-2). Tighter is slower, not better: solved to 1e-6, a cap's coarse
    /// level ends flat at its centre, the fine level inherits a small excess angle there and
    /// crawls (19 caps of 1.9k–14.5k faces, both targets: 2 102 factorisations at 1e-6,
    /// 1 268 at 3e-4, 1 179 solved directly); looser is a lottery (1e-3: 1 149 on the caps
    /// but 48 instead of 20 iterations on igl_inspired_mesh; 3e-3 lost a saddle's
    /// hierarchy). docs/algorithms/flattenable.md, "Coarse levels solved loosely". Never
    /// below the piece's `tolerance_rad`.
    pub coarse_tolerance_rad: f64,
    /// When a piece does not converge, try two deeper hierarchies (levels down to ~300
    /// faces; displacement, then positions prolongation) before giving up, also for pieces
    /// below `min_faces` (from 600 faces, after their direct solve) and above `max_faces`
    /// (after their direct solve, the configured hierarchy first). Default true: measured
    /// to make the saddle-like shoulder of mh_body_subdiv2 converge (30 fine iterations where
    /// the default hierarchy and the direct solve stall at 4–8e-3) and 14 instead of 11 of the
    /// 16 pieces of the noisy scan's wetsuit at 10 mm (docs/algorithms/flattenable.md).
    /// Last, on a rough piece (scan noise: a median |2π − θ| above 0.1 rad at the input), the
    /// direct solve under `Damping::GraphLaplacian`, for pieces of any size: the noisy scan's
    /// wetsuit converges on every piece at 10 mm on scans perturbed by 1e-12 (5 of 8 such
    /// scans left a leg unconverged before), 13 instead of 10 at 6 mm (docs/algorithms/
    /// flattenable.md, "Rough scan pieces: the shaped direct solve").
    /// Pieces that converge on the first attempt are unaffected. (Independently of this
    /// flag, a fine level that crawls near θ = 2π is cut after 60 iterations and the direct
    /// solve runs next: docs/algorithms/flattenable.md, "Fine-level budget".)
    pub rescue: bool,
}

impl Default for CoarseToFine {
    fn default() -> Self {
        Self {
            min_faces: 2_000,
            max_faces: 15_000,
            ratio: 4.0,
            levels: 3,
            prolongation: Prolongation::Displacement,
            coarse_tolerance_rad: 3e-4,
            rescue: true,
        }
    }
}

/// What happens at the rims of a piece's holes: its boundary loops other than the outline
/// (the longest loop).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum HoleRims {
    /// Fixed like the outline: boundary vertices never move. θ = 2π then flattens the piece
    /// without stretch only where its holes already close in the plane (a flat or
    /// developable piece): on a curved one each hole keeps the Gaussian curvature it
    /// encloses, and the pattern stretches around it. The report measures every hole
    /// ([`crate::PieceReport::holes`]) and a message says which do not close.
    #[default]
    Fixed,
    /// Each hole filled for the processing (by ears of its rim's polygon, or where that
    /// filled piece does not converge by a fan whose centre continues the surface; removed
    /// afterwards): the rims move like interior vertices, every hole closes, and the
    /// piece flattens without stretch. The outline stays fixed; the report says how far the
    /// rims moved and how much their lengths changed: a rim that is a seam (a patch sewn
    /// into the hole) then no longer matches its mate, so this is for cut-outs; a seam from
    /// the hole to the outline keeps every seam's length. Where the filled piece does not
    /// converge, the run with the rims fixed is returned instead, and a message says so.
    Free,
}

/// Options of [`crate::process`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ProcessOptions {
    /// Algorithm. Default `Robust`.
    pub mode: Mode,
    /// Position update. Default `Direct`.
    pub update: Update,
    /// Laplacian of the least-square update. Default `Cotan`.
    pub laplacian: Laplacian,
    /// Target of the least-square update and, in robust mode, pull-backs towards the input
    /// (`Detail`). Default `Detail` (`Zero` is the paper's).
    pub target: Target,
    /// Iteration limit per piece (accepted steps). Default 50 in paper mode (the paper's
    /// terminal condition) and 500 in robust mode when `None`.
    pub max_iterations: Option<usize>,
    /// Per-vertex weights w ≥ 0 (finite, > 0), one per vertex of the input mesh; a larger w
    /// moves the vertex less (Eq. 14–17). Default `None` (all 1).
    pub weights: Option<Vec<f64>>,
    /// Weight of the interior vertices next to the boundary (soft G1 continuity across
    /// seams, the paper's §4.2). Default 1 (off); the paper suggests 10.
    pub boundary_ring_weight: f64,
    /// Feature curves as lists of input vertex indices; their vertices get
    /// `feature_weight`. Default none.
    pub feature_curves: Vec<Vec<u32>>,
    /// Weight of vertices on feature curves. Default 10 (the paper's value).
    pub feature_weight: f64,
    /// Robust mode stops successfully when θ_err = max |θ − 2π| ≤ this (radians).
    /// Paper mode stops immediately if the input already satisfies it. Default 1e-9.
    pub tolerance_rad: f64,
    /// Paper mode: switch from the least-square to the direct update when θ_err < this
    /// (radians). Default 1e-3 (the paper).
    pub switch_theta_err: f64,
    /// Paper mode: … or when θ_err decreased by less than this in one step after
    /// `switch_after` steps. Default 0.01 (the paper).
    pub switch_decrease: f64,
    /// Paper mode: see `switch_decrease`. Default 20 (the paper).
    pub switch_after: usize,
    /// Paper mode: terminal condition ‖d‖² < max(n_int · this, `stop_d2_min`) (absolute,
    /// squared model units, as printed). Default 1e-8. Set 0 to disable.
    pub stop_d2_per_vertex: f64,
    /// Paper mode: see `stop_d2_per_vertex`. Default 1e-5.
    pub stop_d2_min: f64,
    /// Robust mode: weight of tangential motion relative to normal motion in the metric of
    /// the least-norm step: G = nnᵀ + (I − nnᵀ)/τ² (n the current vertex normal). 1 is
    /// isotropic (the paper's metric); larger prefers motion along the normal, which keeps
    /// triangles shaped and is what lets saddle-like pieces converge (measured in
    /// docs/algorithms/flattenable.md). Default 10. Paper mode ignores it.
    pub tangential_penalty: f64,
    /// Smallest corner angle (degrees) a step may create: a corner that ends below it and
    /// below its input angle rejects the step. Default 0.5.
    pub min_angle_deg: f64,
    /// Robust mode: coarse-to-fine for large pieces. Default on for pieces of 2 000 to 15 000 faces.
    pub coarse_to_fine: CoarseToFine,
    /// Robust mode: once at most 5 % of a piece's interior vertices (pieces of at least
    /// 1 000) are above `tolerance_rad`, solve them with a few rings around them alone, their
    /// outer neighbours held, instead of factorising the whole piece for them. Default true:
    /// measured on sphere caps of 19.6k–100k faces, 15 % less CPU in all (the 100k cap 13.0
    /// → 10.0 s) for the same surface (docs/algorithms/flattenable.md, "Local polish").
    pub local_polish: bool,
    /// The rims of a piece's holes: `Fixed` (the default: boundary vertices never move, and
    /// θ = 2π does not close a hole on a curved piece) or `Free` (they move so that every
    /// hole closes). See [`HoleRims`].
    pub hole_rims: HoleRims,
    /// Robust mode: shape of the step's damping. Default `Identity`; the coarse-to-fine
    /// rescue runs one more hierarchy with `GraphLaplacian` when all else failed (see
    /// [`Damping`]).
    pub damping: Damping,
    /// Called after every iteration of every run (pieces, coarse levels, polish regions),
    /// from the thread running it; it only observes. Not part of a configuration file.
    /// Default none.
    #[serde(skip)]
    pub progress: ProgressHook,
}

impl Default for ProcessOptions {
    fn default() -> Self {
        Self {
            mode: Mode::Robust,
            update: Update::Direct,
            laplacian: Laplacian::Cotan,
            target: Target::Detail,
            max_iterations: None,
            weights: None,
            boundary_ring_weight: 1.0,
            feature_curves: Vec::new(),
            feature_weight: 10.0,
            tolerance_rad: 1e-9,
            switch_theta_err: 1e-3,
            switch_decrease: 0.01,
            switch_after: 20,
            stop_d2_per_vertex: 1e-8,
            stop_d2_min: 1e-5,
            tangential_penalty: 10.0,
            min_angle_deg: 0.5,
            coarse_to_fine: CoarseToFine::default(),
            local_polish: true,
            hole_rims: HoleRims::Fixed,
            damping: Damping::Identity,
            progress: ProgressHook::default(),
        }
    }
}

impl ProcessOptions {
    /// The paper's settings: `Mode::Paper`, the given update, uniform-or-cotan Laplacian
    /// with the zero target, 50 iterations.
    pub fn paper(update: Update) -> Self {
        Self {
            mode: Mode::Paper,
            update,
            target: Target::Zero,
            ..Self::default()
        }
    }

    /// The iteration limit actually used.
    pub fn iteration_limit(&self) -> usize {
        self.max_iterations.unwrap_or(match self.mode {
            Mode::Paper => 50,
            Mode::Robust => 500,
        })
    }
}
