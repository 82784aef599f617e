//! `Mode::Robust` (the default): the paper's least-norm step under Levenberg–Marquardt
//! damping with a trust-region ratio test on the merit f = ‖θ − 2π‖².
//!
//! At every accepted point: A, b = 2π − θ, the step d = G Aᵀ (A G Aᵀ + μ m I)⁻¹ b where
//! m is the mean diagonal of A G Aᵀ (so μ is scale free), the trial point v + d (or its
//! least-square filter while that phase lasts), and the ratio ρ of actual to predicted
//! decrease of f (predicted by the linear model: ‖b‖² − ‖b − A d‖²). A trial that
//! folds a face (normal flip against the input or a corner newly below the floor), is
//! not finite, or does not decrease f is rejected and μ raised; an accepted one lowers μ
//! when the model was good. As μ → 0 the step is the paper's (Gauss–Newton on the
//! constraints), so the end game converges quadratically where A has full rank.
//!
//! The least-square phase (`Update::LeastSquare`) lasts while each filtered step still
//! reduces f by at least 10 %; then the plain damped step finishes (the filter's fixed
//! point is not θ = 2π, as the paper notes).
//!
//! `Target::Detail` adds pull-backs ([`crate::pull_back`]): near θ = 2π, a move along the
//! constraint set towards the input, after which the plain steps restore θ = 2π; one that
//! does not end nearer the input at no larger area change is undone (the whole iteration
//! state), and the run goes on as the zero target's would. From the first pull-back on,
//! every step also holds the area (`AreaRow`).
//!
//! Double roots: after `LIFT_AFTER` iterations without gain, nearly flat vertices with excess
//! angle (whose rows of A nearly vanish) get a second-order step along their normal
//! (`lift_flat_excess`); negatively curved pieces otherwise stall there depending on round-off.
//!
//! Local polish (`ProcessOptions::local_polish`): once at most 1/`LOCAL_ACTIVE_DIVISOR` of
//! the interior vertices of a large piece are above the tolerance, the run goes on on the
//! region around them alone ([`crate::local_polish`]), whose factorisations are those of a
//! small matrix.
//!
//! Near θ = 2π (θ_err ≤ `DEAD_ZONE_FROM_RAD`) the merit ignores residuals within half the
//! tolerance (`Piece::merit`): they need not go, and on large pieces chasing them cost most
//! of the end game.
//!
//! Stops: θ_err ≤ tolerance (converged); the iteration limit; μ beyond `MU_MAX` (no
//! decreasing unfolded step exists at any damping); or no 10 % gain of the merit
//! ‖θ − 2π‖² in `STALL_WINDOW` iterations. The best unfolded state (lowest merit) is
//! returned when not converged.

use std::f64::consts::TAU;

use crate::laplacian::LeastSquareUpdate;
use crate::least_norm::{Layout, Metric};
use crate::options::{Damping, ProcessOptions, Target, Update};
use crate::piece::{Piece, beyond};
use crate::pull_back::{
    self, AreaRow, PULL_BACK_AT_RAD, PULL_BACK_MAX_ERR_RAD, PULL_BACK_REFUSALS,
    PULL_BACK_SHORT_MAX_ERR_RAD, PULL_BACKS, Projection, Restoring, Snapshot, displacement2,
};
use crate::report::PieceReport;
use crate::smoothed_step::{self, Filters};

/// Initial damping relative to the mean diagonal of A G Aᵀ (the prototype's value).
const MU_START: f64 = 1e-3;
/// Smallest relative damping: keeps the factorisation defined when rows of A vanish at
/// flat vertices, ~1e3 above f64 round-off of the diagonal.
pub(crate) const MU_MIN: f64 = 1e-13;
/// Largest relative damping before giving up: the step is then ~1e-8 of the steepest
/// descent step and no longer moves anything measurable.
const MU_MAX: f64 = 1e8;
/// Iterations without a 10 % gain of the best merit ‖θ − 2π‖² that count as a stall. Long:
/// negatively curved pieces spend a hundred or more iterations at a slow, steady decrease
/// while the excess angle migrates to the boundary (the 100×100 saddle: f from 1.1e-4 to
/// 3e-5 in 200 iterations, then quadratic convergence in 80; a window of 60 at 19 % cut it
/// off at 1.9e-4).
const STALL_WINDOW: usize = 100;
/// The best merit must fall below this fraction of the previous best to count as a gain.
const STALL_GAIN: f64 = 0.9;
/// …nor in this many factorisations (rejected trials included). Every converging run
/// measured went at most 23 factorisations from one such gain to the next (19 caps of
/// 1.9k–14.5k faces: 13; 37 one-ulp saddles: 23; the converging patches, real meshes and
/// body pieces: ≤ 10), while every stalled run spent 570–600 in its last 100 iterations —
/// about five rejected trials per accepted step, 85 % of the scan-like body's 136 s
/// (docs/algorithms/flattenable.md, "Stalls counted in factorisations").
const STALL_FACTORIZATIONS: usize = 100;
/// Factor by which a vertex of a face that would fold is stiffened, the largest stiffness,
/// and how many stiffening rounds one iteration may try before raising the damping.
const STIFFEN: f64 = 10.0;
const STIFF_MAX: f64 = 1e4;
const MAX_STIFFEN: usize = 6;
/// Second-order corrections tried per trial step.
const MAX_CORRECTIONS: usize = 3;
/// A correction is kept when it at least halves the merit (`CORRECTION_KEEP`), or, within
/// `CORRECTION_RELAXED_BELOW_RAD` of θ = 2π, when it cuts the merit by a fifth
/// (`CORRECTION_RELAXED_KEEP`) and the linear model predicted that cut (ρ of the correction at
/// least `CORRECTION_RELAXED_RHO`). On large pieces the damped steps of the global phase each
/// leave most of the residual (f_trial / f 0.3–0.96 on the 100k cap), and a correction then
/// gains what another damped step would (its own ratio 0.54–0.99), for one solve and one θ
/// instead of a factorisation: the 100k cap 43 → 36 factorisations, its seven one-ulp inputs
/// 327 → 275, the 33k cap 47 → 21 (docs/algorithms/flattenable.md, "Corrections kept at a
/// fifth"). Not farther from θ = 2π: a rough scan piece (the wetsuit scan's front-right side,
/// θ_err 1.1 rad) kept one at its second iteration and then stalled at 2.2e-4. Not on pieces
/// below `CORRECTION_RELAXED_MIN_FACES`, whose global phase coarse-to-fine's coarse levels run
/// (the default range ends at 15 000 faces) or which are small: there it only moved paths by
/// a few factorisations either way (the 3.5k cap's zero target 16 → 17, 29.3 → 32.6 ms).
const CORRECTION_KEEP: f64 = 0.5;
const CORRECTION_RELAXED_KEEP: f64 = 0.8;
const CORRECTION_RELAXED_RHO: f64 = 0.25;
const CORRECTION_RELAXED_BELOW_RAD: f64 = 1e-3;
const CORRECTION_RELAXED_MIN_FACES: usize = 15_000;
/// No correction is tried after a trial step that raised the merit more than this many
/// times: the step went far beyond its linearisation, and a correction linearised at the
/// trial point has never brought one back. Traced (twentieth session): on the 100k cap
/// (detail target) all 17 corrections tried after f_trial / f of 4 to 2e9 were refused, 11
/// of them above 1e3; on the seven one-ulp 100×100 saddles (detail) the kept corrections
/// followed trials of f_trial / f ≤ 18.7, pull-back restores that the corrections rescue.
/// So results are the same, bit for bit, and each skipped correction saves a solve and a θ
/// (~25 ms at 100k faces). Where the relaxed rule applies (pieces of at least
/// `CORRECTION_RELAXED_MIN_FACES`, θ_err ≤ `CORRECTION_RELAXED_BELOW_RAD`) and no pull-back is
/// being restored, none after a trial that raised the merit at all: on the 100k cap (zero
/// target, twenty-eighth session) the six tried after f_trial / f of 4 to 243 were refused
/// (f_cand / f_trial 8e5 to 1e9), and skipping them left every result the same to the printed
/// digit (the 19.6k–50k caps, the seven one-ulp 100×100 saddles with both targets, three
/// one-ulp 100k caps, the body pieces, the 85k upper back) for 2–4 % of the 100k cap's and
/// the 85k piece's time.
const CORRECTION_SKIP_ABOVE: f64 = 1e3;
/// Pieces below this many faces, solved directly from their input, take no corrections:
/// there a factorisation is so cheap (8 µs at 250 faces) that a correction's solve, θ and
/// fold check cost ~40 % of the iteration it may save. Measured (release, `STEP_RATIO=1
/// SIZES=8,…,30 … measure -- speed`, twenty-eighth session): the caps of 98–1 058 faces ran
/// 5–40 % faster without them (detail target 242 faces 0.63 → 0.57 ms, 882 faces 6.4 →
/// 4.1 ms), the 1 250 and 1 682 ones 15–22 % slower; of 60 random pieces of 100–1.9k faces
/// (in about the same time) and 60 body patches of 108–1.8k faces the same ones converged,
/// most to the same surface, and the five bundled pipelines' files were unchanged. Coarse levels keep them:
/// without, the 3.5k cap's level of 882 faces led to a fine level 31 → 39 ms.
const CORRECTION_MIN_FACES: usize = 1_000;
/// Accept a trial when ρ exceeds this (any real decrease of the merit).
const RHO_ACCEPT: f64 = 1e-4;
/// θ_err from which the merit has a dead zone (radians), and its half-width as a fraction of
/// the tolerance: residuals within it count zero in f and in the right-hand side. Near the end
/// of a large piece most of ‖θ − 2π‖² sat at vertices already within the tolerance (the
/// 100k cap's nearly flat top: ~19 000 at −9e-10, rows of A of norm·h ~1e-4), and steps that
/// chased them blew up at every damping. With the zone the 100k cap takes 46–50
/// factorisations over seven inputs within one ulp of the grid, where it took 56–161
/// (docs/algorithms/flattenable.md, "A dead zone in the merit"). Not from the start: far from
/// θ = 2π it only perturbs paths (one of the seven one-ulp saddles stalled). 1e-6 and 1e-8,
/// and zones of 0.25 and 0.75 of the tolerance, measured no better. With a tolerance looser
/// than 1e-7 the run ends before the zone would act.
const DEAD_ZONE_FROM_RAD: f64 = 1e-7;
const DEAD_ZONE_FRACTION: f64 = 0.5;
/// Largest damping divisor after a very good step (ρ > 0.75); smaller when the step was
/// within a factor 10 of the step cap (the divisor then aims the next step at the cap).
/// 10 rather than the textbook 3: the end phase needs μ down near 1e-9 before the slow
/// modes of A G Aᵀ (rows that nearly vanish at nearly flat vertices) are solved, and with 3
/// the linear phase lasted longer than the stall window (cap 100×100 stalled at 1.1e-5, now
/// converges in ~100 iterations).
const MU_DOWN: f64 = 10.0;
/// A smoothed step (`smoothed_step.rs`) is tried after this many accepted steps in a row each
/// gained less than `SMOOTH_STAGNANT_GAIN` of the merit, within `SMOOTH_BELOW_RAD` of θ = 2π
/// (and after twice as many again each time a try found nothing to take or its jump was
/// undone). On the shallow paraboloids (`SHAPE=para`, A = 0.01–0.3 at 130–225
/// vertices a side) the damped steps there gained 0.001–0.01 % each, a smoothed step 5–40 %:
/// 19 of 20 converged where 12 had, and with the jumps (`SmoothedMove::Jump`) all 20
/// (docs/algorithms/flattenable.md, "Shallow pieces: a smoothed step" and "Irregular shallow
/// pieces: a smoothed jump"). The gate keeps every path that gains ≥ 1 % per step as it was:
/// the caps, saddles, random pieces, body pieces and the bundled pipelines gave the same
/// results to the printed digit (one 71k-face cap tries: 66 → 68 factorisations, the same
/// surface).
/// Not farther from θ = 2π: the 100×100 saddle's slow phase and the scan-resolution body
/// pieces at 2e-4–8e-4 gained ≤ 11 % per smoothed step and took longer paths.
const SMOOTH_AFTER: usize = 5;
const SMOOTH_STAGNANT_GAIN: f64 = 1e-2;
const SMOOTH_BELOW_RAD: f64 = 1e-5;
/// A smoothed jump is kept when the plain steps after it have brought the merit this
/// fraction below where it left from (a try cost a factorisation, as a damped step that
/// would have gained < `SMOOTH_STAGNANT_GAIN` does).
const SMOOTH_MIN_GAIN: f64 = 1e-2;
/// A filtered step is taken when it gains at least this fraction of the merit; below it the
/// try takes the jump instead. With 1 % (the twenty-ninth session's gate for the steps) the
/// regular paraboloid z = 0.1 (x² + y²) at 200×200 took filtered steps gaining 1–10 % for
/// 500 iterations and ended unconverged at 4.6e-8 (1 241 factorisations); with 10 % it jumps
/// there and converges in 212. The regular battery (20 paraboloids) then converges
/// entirely: the other A = 0.1 sizes 692 → 732 factorisations, A = 0.01, 0.03, 0.3
/// unchanged; the twelve jittered ones 1 051 → 1 007 (docs/algorithms/flattenable.md,
/// "Irregular shallow pieces: a smoothed jump").
const SMOOTH_STEP_MIN_GAIN: f64 = 0.1;
/// Relative damping of the step that is filtered: the Gauss–Newton step, damped only enough
/// to keep the factorisation defined (1e-11 measured the same on the paraboloid).
const SMOOTH_MU: f64 = 1e-9;
/// Factorisations the plain steps after a smoothed jump may take to bring the merit below
/// `1 − SMOOTH_MIN_GAIN` of where the jump left from; then the jump is undone (the state
/// before it restored, the factorisations excused from the stall budget, the next try
/// waiting twice as long). On the jittered paraboloids every jump was kept, the longest
/// restore taking 15 factorisations (the jump's own included); twice that bounds what an
/// undone one costs.
const JUMP_RESTORE_FACTORIZATIONS: usize = 30;
/// The fraction of the smooth-part scale a smoothed jump takes. The whole of it removes the
/// model's smooth residual but leaves a rough one ~1e3 times the merit, and the restores
/// from there ended on other surfaces, some creased (the jittered paraboloids, `JITTER=0.3
/// and 0.15 SHAPE=para A=0.1, 0.03 N=130, 160, 200 … measure -- saddles`: largest crease
/// 18.9° against 1.2° before); a quarter removes ~44 % of the smooth part for 1/16 of the
/// rough one. Fractions 1, ½, ¼, ⅛ measured: 1 122, 1 233, 1 051 and 1 120 factorisations
/// over the twelve (2 444 before, one not converged), largest crease 18.9°, 14.7°, 2.7°,
/// 2.4° (2.0° before).
const JUMP_FRACTION: f64 = 0.25;
/// Halvings of a smoothed jump that folds before it is given up.
const JUMP_HALVINGS: usize = 10;

/// The metric's per-vertex scale 1/w² with the stiffness k a vertex of a would-be folded
/// face earned: 1/(w k)² (Eq. 14 with w k for w).
fn stiffened_scale(scale: &[f64], stiff: &[f64]) -> Vec<f64> {
    scale.iter().zip(stiff).map(|(s, k)| s / (k * k)).collect()
}

/// The fold guard's face normals ((f1 − f0) × (f2 − f0)) at an accepted trial, with its
/// positions: the key under which the next step's metric may sum them.
struct FaceNormalsAt {
    positions: Vec<[f64; 3]>,
    face_normals: Vec<[f64; 3]>,
}

/// Whether two position arrays are the same bits (a cache's key).
fn same_bits(a: &[[f64; 3]], b: &[[f64; 3]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The right-hand side of a step: 2π − θ beyond the merit's dead zone, per interior vertex.
fn residual_beyond(theta: &[f64], dead_zone: f64) -> Vec<f64> {
    theta.iter().map(|t| beyond(TAU - t, dead_zone)).collect()
}

/// The best state of a run by the merit f = ‖θ − 2π‖² (what the steps decrease; θ_err, the
/// max, can rise meanwhile), and what the stall and lift tests count from.
#[derive(Clone)]
pub(crate) struct Best {
    merit: f64,
    pos: Vec<[f64; 3]>,
    /// The iteration of the last counted gain (or restart).
    pub(crate) at: usize,
    /// The merit at the last counted gain: a slow steady decrease counts once it adds up to
    /// a 10 % gain (comparing with the previous best would never count it).
    gain_ref: f64,
    /// The report's factorisation count at the last counted gain (or restart).
    pub(crate) factorizations_at: usize,
}

impl Best {
    fn new(merit: f64, pos: &[[f64; 3]], factorizations: usize) -> Self {
        Self {
            merit,
            pos: pos.to_vec(),
            at: 0,
            gain_ref: merit,
            factorizations_at: factorizations,
        }
    }

    /// An accepted state at `iteration` (after `factorizations` in all): kept if it beats
    /// the best, counted as a gain if it beats `STALL_GAIN` of the last counted one.
    fn record(&mut self, merit: f64, pos: &[[f64; 3]], iteration: usize, factorizations: usize) {
        if merit < self.merit {
            if merit < STALL_GAIN * self.gain_ref {
                self.at = iteration;
                self.gain_ref = merit;
                self.factorizations_at = factorizations;
            }
            self.merit = merit;
            self.pos = pos.to_vec();
        }
    }

    /// The stall count starts again at `iteration` from `merit` (after a pull-back or a
    /// lift); the best state stays.
    fn restart(&mut self, merit: f64, iteration: usize, factorizations: usize) {
        self.at = iteration;
        self.gain_ref = merit;
        self.factorizations_at = factorizations;
    }

    /// Whether the run has gone `STALL_WINDOW` iterations or `STALL_FACTORIZATIONS`
    /// factorisations without a counted gain.
    fn stalled(&self, iteration: usize, factorizations: usize) -> bool {
        iteration >= self.at + STALL_WINDOW
            || factorizations >= self.factorizations_at + STALL_FACTORIZATIONS
    }
}

/// Outcome of a robust run on one piece.
pub struct RobustOutcome {
    /// Best (lowest θ_err) unfolded local positions reached.
    pub positions: Vec<[f64; 3]>,
    /// Whether the run stopped to hand the piece over to coarse-to-fine
    /// ([`run_before_hierarchy`]).
    pub handed_over: bool,
}

/// Runs robust mode on one piece; fills `report` (converged or not).
pub fn run(piece: &Piece, opts: &ProcessOptions, report: &mut PieceReport) -> RobustOutcome {
    run_direct(piece, opts, Kind::DIRECT, report)
}

/// A direct solve of the piece from its input, of `kind`.
fn run_direct(
    piece: &Piece,
    opts: &ProcessOptions,
    kind: Kind,
    report: &mut PieceReport,
) -> RobustOutcome {
    run_inner(
        piece,
        &piece.pos0,
        opts,
        None,
        Polish::of(opts),
        kind,
        report,
    )
}

/// [`run`] started from `start` (same boundary as the input) instead of the input; the
/// fold guard, the pull-backs and every displacement still refer to the input `piece.pos0`
/// (coarse-to-fine starts the fine level from a prolongated solution). With `budget`, the
/// run gives up after that many iterations unless it has reached the tolerance by then
/// (coarse-to-fine then tries the direct solve instead of crawling on). Under
/// `Damping::GraphLaplacian` its merit is measured in that damping's norm ([`MeritNorm`]).
pub fn run_from(
    piece: &Piece,
    start: &[[f64; 3]],
    opts: &ProcessOptions,
    budget: Option<usize>,
    report: &mut PieceReport,
) -> RobustOutcome {
    run_inner(
        piece,
        start,
        opts,
        budget,
        Polish::of(opts),
        Kind::in_hierarchy(opts),
        report,
    )
}

/// [`run`] as the direct solve of a piece above `CoarseToFine::max_faces` that
/// coarse-to-fine hierarchies follow if it does not converge: it also stops, handing the
/// piece over, when it is stuck far from θ = 2π under heavy damping ([`HAND_OVER_MU`]),
/// where the hierarchies' coarse levels make the global moves it cannot.
pub fn run_before_hierarchy(
    piece: &Piece,
    opts: &ProcessOptions,
    report: &mut PieceReport,
) -> RobustOutcome {
    run_direct(
        piece,
        opts,
        Kind {
            hand_over: true,
            ..Kind::DIRECT
        },
        report,
    )
}

/// [`run_from`] for a coarse level of coarse-to-fine: no local polish (the level stops at
/// its loose tolerance, far from the end phase the polish is for, and its result only
/// starts the next level).
pub fn run_coarse_level(
    piece: &Piece,
    start: &[[f64; 3]],
    opts: &ProcessOptions,
    report: &mut PieceReport,
) -> RobustOutcome {
    run_inner(
        piece,
        start,
        opts,
        None,
        Polish::Coarse,
        Kind::in_hierarchy(opts),
        report,
    )
}

/// What kind of run [`run_inner`] is.
#[derive(Clone, Copy)]
struct Kind {
    /// The direct solve before coarse-to-fine hierarchies: it may hand the piece over.
    hand_over: bool,
    /// The merit in the shaped damping's norm ([`MeritNorm`]): for the levels of a
    /// hierarchy under `Damping::GraphLaplacian`, not for a direct solve from the input.
    shaped_merit: bool,
}

impl Kind {
    /// A direct solve from the input.
    const DIRECT: Kind = Kind {
        hand_over: false,
        shaped_merit: false,
    };

    /// A level of a coarse-to-fine hierarchy under `opts`.
    fn in_hierarchy(opts: &ProcessOptions) -> Self {
        Kind {
            hand_over: false,
            shaped_merit: opts.damping == Damping::GraphLaplacian,
        }
    }
}

/// How a run ends.
#[derive(Clone, Copy)]
enum Polish {
    /// Global steps to the end.
    Global,
    /// Near the end, regions ([`crate::local_polish`]).
    Local,
    /// This is a region's run, started at the parent's damping (where the parent's steps
    /// were good); it does not split again.
    Region { mu: f64 },
    /// A coarse level of coarse-to-fine: global steps, and no pull-backs (the level's result
    /// only starts the next one, and a pull-back there would send the detail target's fine
    /// level down another path than the zero target's).
    Coarse,
}

impl Polish {
    /// How a piece's own run ends under `opts` (`local_polish`).
    fn of(opts: &ProcessOptions) -> Self {
        if opts.local_polish {
            Polish::Local
        } else {
            Polish::Global
        }
    }
}

/// [`run_from`], ending as `polish` says.
fn run_inner(
    piece: &Piece,
    start: &[[f64; 3]],
    opts: &ProcessOptions,
    budget: Option<usize>,
    polish: Polish,
    kind: Kind,
    report: &mut PieceReport,
) -> RobustOutcome {
    let hand_over = kind.hand_over;
    let smoothed_before = report.smoothed_steps;
    let local = matches!(polish, Polish::Local);
    // Second-order corrections, except on a small piece's own run (`CORRECTION_MIN_FACES`).
    let corrections_pay = piece.faces.len() >= CORRECTION_MIN_FACES
        || !matches!(polish, Polish::Global | Polish::Local);
    let layout = &piece.layout;
    let n = layout.n();
    let mut pos = start.to_vec();
    let mut theta = vec![0.0; n];
    let mut trial_theta = vec![0.0; n];
    let mut grad = vec![[0.0; 3]; layout.entries()];
    // A at the trial point, where no correction can follow (`trial_grad_fresh`).
    let mut trial_grad = vec![[0.0; 3]; layout.entries()];
    let mut trial_grad_fresh = false;
    // The fold guard's face normals at the trial, and those of the last accepted trial with
    // its positions: the next step's metric sums them instead of forming them again
    // (`Piece::interior_normals_from_faces`), where the positions are still those.
    let mut trial_face_normals = vec![[0.0; 3]; piece.faces.len()];
    let mut trial_normals_fresh = false;
    let mut accepted_face_normals: Option<FaceNormalsAt> = None;
    let mut normal = vec![0.0; layout.normal_nnz()];
    layout.evaluate(&pos, &mut theta, &mut grad);
    // The shaped damping's norm for the merit (its matrix factorised once per run); the
    // plain merit if that factorisation fails (it is positive definite: ε > 0).
    let shaped_triplets = kind.shaped_merit.then(|| layout.graph_damping_triplets());
    let shaped_pattern = shaped_triplets.as_ref().and_then(|t| t.pattern().ok());
    let norm = match (&shaped_pattern, &shaped_triplets) {
        (Some(p), Some(t)) => MeritNorm::shaped(p, t.values()).unwrap_or_else(MeritNorm::plain),
        _ => MeritNorm::plain(),
    };
    // The merit's dead zone: 0 until θ_err is within `DEAD_ZONE_FROM_RAD`, then
    // `DEAD_ZONE_FRACTION` of the tolerance.
    let mut dead_zone = 0.0;
    let (mut err, mut f) = norm.merit(&theta, dead_zone);
    report.theta_err.push(err);
    // One set of factorisation buffers for every step of the run (only an allocation
    // failure stops here: the start is returned, unconverged, with the reason).
    let mut factor = match layout.new_factor() {
        Ok(f) => f,
        Err(e) => {
            report.stop_reason = format!("factorisation buffers: {e:?}");
            return RobustOutcome {
                positions: start.to_vec(),
                handed_over: false,
            };
        }
    };
    let mut best = Best::new(f, &pos, report.factorizations);
    let scale: Vec<f64> = piece.weights.iter().map(|w| 1.0 / (w * w)).collect();
    let tangential = 1.0 / (opts.tangential_penalty * opts.tangential_penalty);
    let mut ls = match opts.update {
        Update::LeastSquare => {
            match LeastSquareUpdate::new(
                layout,
                &piece.topo,
                &piece.pos0,
                &piece.faces,
                opts.laplacian,
                opts.target,
                &piece.weights,
            ) {
                Ok(u) => Some(u),
                Err(e) => {
                    report.messages.push(format!(
                        "least-square filter unavailable ({e:?}); direct update"
                    ));
                    None
                }
            }
        }
        Update::Direct => None,
    };
    // Target::Detail: the input the pull-backs move towards, and how many remain.
    let anchor = piece.interior_of(&piece.pos0);
    let input = pull_back::Input {
        piece,
        anchor: &anchor,
        area0: piece.total_area(&piece.pos0),
        damping: opts.damping,
    };
    // From the first pull-back on, every step holds the area where the path before it ended
    // (the direct update's is the zero target's), so that the pull-backs trade no area
    // change for their shorter displacement.
    let mut area_goal: Option<f64> = None;
    let detail = opts.target == Target::Detail && !matches!(polish, Polish::Coarse);
    let mut pull_backs = if detail && pull_back::allowed(piece.faces.len()) {
        PULL_BACKS
    } else {
        0
    };
    // The iteration of the last pull-back, the merit right after it (what its restoring steps
    // are judged by) and the state before it, until the plain steps have restored θ = 2π
    // again and the pull-back is kept or undone.
    let mut restoring: Option<Restoring> = None;
    // θ_err a pull-back may leave (long ones first, short ones after one is undone).
    let mut pull_back_max_err = PULL_BACK_MAX_ERR_RAD;
    // Set when a restore's trials are refused more than `PULL_BACK_REFUSALS` times.
    let mut restore_refused = false;
    // The projection of a long pull-back just undone, for the short one that follows.
    let mut undone_projection: Option<Projection> = None;
    // Extra per-vertex stiffness (≥ 1) earned by vertices of faces that would fold.
    let mut stiff = vec![1.0f64; n];
    let mut mu = match polish {
        Polish::Region { mu } => mu,
        _ => MU_START,
    };
    // Per interior vertex: the mean length of its input edges, the scale of its steps.
    let reach = piece.interior_edge_lengths();
    let limit = opts.iteration_limit();
    let mut last_lift = 0usize;
    let mut lifts = 0usize;
    // Smoothed steps: accepted steps in a row that gained < `SMOOTH_STAGNANT_GAIN`, how many
    // a try waits for (doubled after a try without gain), and the filters, built at the
    // first try (L depends on the connectivity only: one factorisation per stiffness).
    let mut stagnant = 0usize;
    let mut smooth_wait = SMOOTH_AFTER;
    let filters: std::cell::OnceCell<Option<Filters>> = std::cell::OnceCell::new();
    let filter_factors = std::cell::OnceCell::new();
    // A smoothed jump being restored by the plain steps, and how many were kept and undone.
    let mut jump: Option<Jump> = None;
    let (mut jumps_kept, mut jumps_undone) = (0usize, 0usize);
    // The most factorisations a kept jump's restore took (its own included).
    let mut longest_restore = 0usize;
    // Whether θ_err has been within the tolerance or a pull-back taken (the detail target's
    // pull-backs start at 1e-7 and go on past the tolerance: the budget must not cut them).
    let mut reached = false;
    report.stop_reason = "iteration limit".into();
    // Local polish: the iteration before which no region is tried (after a region that did
    // not finish), the wait after the next one that does not, and what the regions did.
    let mut local_retry_at = 0usize;
    let mut local_wait = LOCAL_RETRY_AFTER;
    let mut polished = PolishTally::default();
    let mut notified = None;
    let mut handed_over = false;
    loop {
        if notified != Some(report.iterations) {
            notified = Some(report.iterations);
            opts.progress.notify(piece, report.iterations, err);
        }
        // Near θ = 2π the merit stops counting residuals well within the tolerance: on a
        // large piece they are many (the nearly flat top of a cap, ~1e-9 below 2π at
        // tens of thousands of vertices), they lie where rows of A nearly vanish, and chasing
        // them blew up every step (docs/algorithms/flattenable.md, "A dead zone in the merit").
        // From here the merit has one definition, so the best state restarts from this one.
        if dead_zone == 0.0 && err <= DEAD_ZONE_FROM_RAD {
            dead_zone = DEAD_ZONE_FRACTION * opts.tolerance_rad;
            f = norm.merit(&theta, dead_zone).1;
            best = Best::new(f, &pos, report.factorizations);
            best.at = report.iterations;
        }
        reached |= err <= opts.tolerance_rad || report.pull_backs > 0;
        // A pull-back under way: `None` while its restoring steps go on, then `Some(None)`
        // to keep it or `Some(Some(reason))` to undo it.
        let refused = std::mem::take(&mut restore_refused);
        let decided = restoring.as_ref().and_then(|r| {
            // θ_err two iterations ago (the history's last entry is `err`).
            let err_two_back = report
                .theta_err
                .iter()
                .rev()
                .nth(2)
                .copied()
                .unwrap_or(f64::INFINITY);
            pull_back::verdict(
                r,
                &input,
                (&pos, err, err_two_back, f, report.iterations),
                area_goal,
                refused,
            )
        });
        // The state to go back to when a pull-back or a smoothed jump is undone below.
        let mut undone: Option<Snapshot> = None;
        if let Some(undo) = decided
            && let Some(Restoring {
                before,
                projection,
                pulled_err,
                ..
            }) = restoring.take()
            && let Some(why) = undo
        {
            // Undo it: back to the state before, damping, stiffness and best state included,
            // and no more pull-backs, so that the detail target from here follows the zero
            // target's path bit for bit (its stall and lift counts shifted by the iterations
            // spent).
            let spent = report.iterations - before.iterations;
            // After a long pull-back, one more chance with short ones; after a short one, no
            // more (the detail target then ends where it stood before it). A long one that
            // already left θ_err within the short bound is the short one too (the same state,
            // projection and fraction): its restore would repeat and be undone again.
            if pull_back_max_err > PULL_BACK_SHORT_MAX_ERR_RAD
                && pulled_err > PULL_BACK_SHORT_MAX_ERR_RAD
            {
                pull_back_max_err = PULL_BACK_SHORT_MAX_ERR_RAD;
                // The short one starts from this same state: the same projection.
                undone_projection = Some(projection);
            } else {
                pull_backs = 0;
            }
            report
                .messages
                .push(format!("pull-back undone after {spent} iterations: {why}"));
            undone = Some(before);
        }
        // A smoothed jump under way (never during a pull-back's restore): kept once the plain
        // steps have brought the merit below where it left from, undone when they have not
        // within their budget.
        if let Some(j) = &jump {
            let merit_before = norm.merit(&j.theta, dead_zone).1;
            if f <= (1.0 - SMOOTH_MIN_GAIN) * merit_before {
                longest_restore =
                    longest_restore.max(report.factorizations - j.before.factorizations);
                jump = None;
                jumps_kept += 1;
                report.smoothed_steps += 1;
                smooth_wait = SMOOTH_AFTER;
            } else if report.factorizations >= j.before.factorizations + JUMP_RESTORE_FACTORIZATIONS
                && let Some(Jump { before, .. }) = jump.take()
            {
                jumps_undone += 1;
                smooth_wait *= 2;
                undone = Some(before);
            }
        }
        if let Some(before) = undone {
            Snapshot {
                pos,
                mu,
                stiff,
                best,
                last_lift,
                dead_zone,
                area_goal,
                ..
            } = before.resumed(report.iterations, report.factorizations);
            layout.evaluate(&pos, &mut theta, &mut grad);
            (err, f) = norm.merit(&theta, dead_zone);
        }
        // The first pull-back waits for the tolerance: the state before it is then the zero
        // target's result (the same path bit for bit), so holding its area and undoing what
        // does not beat it compares with that result itself, not with a point on its way.
        let pull_back_at = if report.pull_backs == 0 {
            opts.tolerance_rad.min(PULL_BACK_AT_RAD)
        } else {
            PULL_BACK_AT_RAD
        };
        if pull_backs > 0 && ls.is_none() && jump.is_none() && err <= pull_back_at {
            let interior = piece.interior_of(&pos);
            // Σ ‖v⁰ − v‖² now: what the pull-back must shorten, and what it is judged against
            // once θ = 2π is restored.
            let z2 = displacement2(&anchor, &interior);
            let before = Snapshot {
                iterations: report.iterations,
                factorizations: report.factorizations,
                moved: z2,
                area_goal,
                pos: pos.clone(),
                mu,
                stiff: stiff.clone(),
                best: best.clone(),
                last_lift,
                dead_zone,
            };
            let normals = (tangential < 1.0).then(|| piece.interior_normals(&pos));
            pull_backs -= 1;
            let eff = stiffened_scale(&scale, &stiff);
            let metric = Metric {
                scale: &eff,
                normals: normals.as_deref(),
                tangential,
            };
            // The area stays where the path before the first pull-back ended.
            let goal = *area_goal.get_or_insert(piece.total_area(&pos));
            // Right after a long pull-back was undone the state is the one it was projected
            // from (positions, damping, stiffness and area goal restored), so its projection
            // is this one's, bit for bit, and its factorisation is saved.
            let projection = match undone_projection.take() {
                Some(p) => Some(p),
                None => pull_back::project(
                    &input,
                    (&pos, &interior),
                    (&grad, &metric),
                    (&mut normal, &mut factor),
                    mu,
                    goal,
                    report,
                )
                .map(|direction| Projection {
                    direction,
                    fraction: 1.0,
                }),
            };
            let Some((pulled, projection)) = projection.and_then(|p| {
                pull_back::shorten(&input, (&pos, &interior, z2), p, pull_back_max_err)
            }) else {
                pull_backs = 0;
                area_goal = before.area_goal;
                continue;
            };
            pos = pulled;
            layout.evaluate(&pos, &mut theta, &mut grad);
            (err, f) = norm.merit(&theta, dead_zone);
            report.iterations += 1;
            report.pull_backs += 1;
            report.theta_err.push(err);
            // The stall test restarts from the pulled-back point; the best state stays the
            // restored one before it until the plain steps beat it.
            best.restart(f, report.iterations, report.factorizations);
            restoring = Some(Restoring {
                at: report.iterations,
                factorizations_at: report.factorizations,
                projection,
                pulled_merit: f,
                pulled_err: err,
                before,
            });
            continue;
        }
        // Stuck far from θ = 2π under heavy damping, with a hierarchy to follow: hand over.
        if hand_over
            && ls.is_none()
            && restoring.is_none()
            && jump.is_none()
            && err > HAND_OVER_ABOVE_RAD
            && report.iterations >= best.at + HAND_OVER_AFTER
            && mu >= HAND_OVER_MU
        {
            report.stop_reason = format!(
                "handed over to coarse-to-fine: no 10 % gain of ‖θ − 2π‖² in {} iterations at damping {mu:.1e}",
                report.iterations - best.at
            );
            handed_over = true;
            break;
        }
        // A plateau of a shallow piece: the damped steps gain nothing while the residual is
        // smooth; a filtered Gauss–Newton step removes its smooth part (`smoothed_step.rs`).
        if stagnant >= smooth_wait
            && ls.is_none()
            && restoring.is_none()
            && jump.is_none()
            && area_goal.is_none()
            && matches!(polish, Polish::Global | Polish::Local)
            && err > opts.tolerance_rad
            && err <= SMOOTH_BELOW_RAD
        {
            stagnant = 0;
            let factorizations_before = report.factorizations;
            let eff = stiffened_scale(&scale, &stiff);
            let normals = (tangential < 1.0).then(|| piece.interior_normals(&pos));
            let metric = Metric {
                scale: &eff,
                normals: normals.as_deref(),
                tangential,
            };
            let factors = filters
                .get_or_init(|| Filters::new(layout))
                .as_ref()
                .and_then(|f| filter_factors.get_or_init(|| f.factors(layout)).as_ref());
            let smoothed = factors.and_then(|factors| {
                smoothed_trial(
                    piece,
                    (&pos, &theta, f, dead_zone),
                    (&grad, &metric, &mut normal, &mut factor),
                    factors,
                    opts,
                    &norm,
                    report,
                )
            });
            match smoothed {
                Some(SmoothedMove::Step(next, next_theta)) => {
                    smooth_wait = SMOOTH_AFTER;
                    pos = next;
                    theta = next_theta;
                    layout.gradient(&pos, &mut grad);
                    (err, f) = norm.merit(&theta, dead_zone);
                    report.iterations += 1;
                    report.smoothed_steps += 1;
                    report.theta_err.push(err);
                    best.record(f, &pos, report.iterations, report.factorizations);
                    continue;
                }
                Some(SmoothedMove::Jump(next, next_theta)) => {
                    let before = Snapshot {
                        iterations: report.iterations,
                        // Before the try's own factorisation: an undone jump excuses it too,
                        // as a try without gain does.
                        factorizations: factorizations_before,
                        moved: displacement2(&anchor, &piece.interior_of(&pos)),
                        area_goal,
                        pos: std::mem::replace(&mut pos, next),
                        mu,
                        stiff: stiff.clone(),
                        best: best.clone(),
                        last_lift,
                        dead_zone,
                    };
                    jump = Some(Jump {
                        before,
                        theta: std::mem::replace(&mut theta, next_theta),
                    });
                    layout.gradient(&pos, &mut grad);
                    (err, f) = norm.merit(&theta, dead_zone);
                    report.iterations += 1;
                    report.theta_err.push(err);
                    // The best state stays the one before it until the plain steps beat it,
                    // and the stall test goes on counting from there: the restore's descent
                    // from the raised merit is not a gain, only getting below the state
                    // before the jump is (jumps gaining 1 % each kept a crawl alive).
                    continue;
                }
                None => {
                    // Not counted against the stall budget: the damped steps go on as if
                    // it had not been tried.
                    smooth_wait *= 2;
                    best.factorizations_at += report.factorizations - factorizations_before;
                }
            }
        }
        // A long run without gain, with nearly flat stars left at excess angle: give them
        // their second-order step (`lift_flat_excess`), then restart the stall count.
        if ls.is_none()
            && restoring.is_none()
            && jump.is_none()
            && err > opts.tolerance_rad
            && report.iterations >= best.at + LIFT_AFTER
            && report.iterations >= last_lift + LIFT_AFTER
            && lifts < MAX_LIFTS
        {
            last_lift = report.iterations;
            if let Some(lifted) = lift_flat_excess(piece, layout, &pos, &theta, err, &reach) {
                pos = lifted;
                layout.evaluate(&pos, &mut theta, &mut grad);
                (err, f) = norm.merit(&theta, dead_zone);
                report.iterations += 1;
                report.theta_err.push(err);
                best.restart(f, report.iterations, report.factorizations);
                lifts += 1;
                continue;
            }
        }
        if err <= opts.tolerance_rad {
            if let Some(j) = jump.take() {
                longest_restore =
                    longest_restore.max(report.factorizations - j.before.factorizations);
                jumps_kept += 1;
                report.smoothed_steps += 1;
            }
            best.merit = f;
            best.pos.clone_from(&pos);
            report.converged = true;
            report.stop_reason = format!("θ_err ≤ {:.1e} rad", opts.tolerance_rad);
            break;
        }
        if report.iterations >= limit {
            break;
        }
        if let Some(budget) = budget
            && !reached
            && report.iterations >= budget
        {
            report.stop_reason =
                format!("not converged within the {budget} iterations allowed from this start");
            break;
        }
        if best.stalled(report.iterations, report.factorizations) {
            report.stop_reason = format!(
                "stalled: no 10 % gain of ‖θ − 2π‖² in {} iterations ({} factorisations)",
                report.iterations - best.at,
                report.factorizations - best.factorizations_at
            );
            break;
        }
        // Near the end only a few vertices are above the tolerance: solve their region alone
        // (local_polish.rs) instead of factorising the whole piece for them.
        if local
            && ls.is_none()
            && restoring.is_none()
            && jump.is_none()
            && (pull_backs == 0 || report.pull_backs == 0)
            && n >= LOCAL_MIN_INTERIOR
            && report.iterations >= local_retry_at
            && let Some(done) =
                polish_region(piece, &pos, (&theta, f, dead_zone), mu, opts, &norm, report)
        {
            match done {
                RegionRun::Gained {
                    positions,
                    theta: polished_theta,
                    steps,
                    finished,
                    interior,
                } => {
                    polished.runs += 1;
                    polished.steps += steps;
                    polished.largest = polished.largest.max(interior);
                    pos = positions;
                    theta = polished_theta;
                    layout.gradient(&pos, &mut grad);
                    let before = f;
                    (err, f) = norm.merit(&theta, dead_zone);
                    best.record(f, &pos, report.iterations, report.factorizations);
                    // A region that did not finish but gained goes on at once, around what
                    // is left; one that gained little gives the global steps a turn.
                    if !finished && f >= LOCAL_GAIN * before {
                        local_retry_at = report.iterations + local_wait;
                        local_wait *= 2;
                    }
                    continue;
                }
                RegionRun::Failed => {
                    // Where regions do not gain (a piece stuck at the angle floor with a few
                    // vertices above the tolerance), try them ever more rarely.
                    polished.runs += 1;
                    polished.failed += 1;
                    local_retry_at = report.iterations + local_wait;
                    local_wait *= 2;
                }
            }
        }
        let normals = (tangential < 1.0).then(|| match &accepted_face_normals {
            Some(cached) if same_bits(&cached.positions, &pos) => {
                piece.interior_normals_from_faces(&cached.face_normals)
            }
            _ => piece.interior_normals(&pos),
        });
        let b = residual_beyond(&theta, dead_zone);
        let interior = piece.interior_of(&pos);
        let area_row = area_goal.map(|goal| AreaRow::at(piece, &pos, goal));
        let mut accepted = None;
        let mut stiffened = 0usize;
        let mut assembled = false;
        let mut mean_diag = 0.0;
        while mu <= MU_MAX {
            // A restore that finishes takes one factorisation per iteration; one that keeps
            // being refused is blowing up at the near-flat modes and is undone at once.
            if let Some(Restoring {
                at,
                factorizations_at,
                ..
            }) = &restoring
                && report.factorizations
                    >= factorizations_at + (report.iterations - at) + PULL_BACK_REFUSALS
            {
                restore_refused = true;
                break;
            }
            let eff = stiffened_scale(&scale, &stiff);
            let metric = Metric {
                scale: &eff,
                normals: normals.as_deref(),
                tangential,
            };
            if !assembled {
                layout.normal_matrix(&grad, &metric, &mut normal);
                // μ scales the mean diagonal: a uniform shift keeps the large-μ limit the
                // steepest-descent step of ‖b − A d‖² (Marquardt's per-row scaling does not,
                // and was measured to stall at once on the 100×100 cap).
                mean_diag = layout.mean_diagonal(&normal).max(f64::MIN_POSITIVE);
                assembled = true;
            }
            report.factorizations += 1;
            if layout
                .refactor_damped(&mut factor, &normal, mu * mean_diag, opts.damping)
                .is_err()
            {
                mu = (mu * 10.0).max(MU_MIN);
                report.rejected_steps += 1;
                continue;
            }
            let factor = &factor;
            // d = G Aᵀ (A G Aᵀ + μ m I)⁻¹ rhs with this factor.
            let solve = |rhs: &[f64]| -> Option<Vec<[f64; 3]>> {
                let mut x = rhs.to_vec();
                layout.solve(factor, &mut x, 1);
                x.iter()
                    .all(|v| v.is_finite())
                    .then(|| layout.step_from_multipliers(&grad, &metric, &x))
            };
            let Some(d) = solve(&b) else {
                mu = (mu * 10.0).max(MU_MIN);
                report.rejected_steps += 1;
                continue;
            };
            // After a pull-back (`Target::Detail`) the step also holds the area.
            let held = area_row.as_ref().and_then(|row| {
                row.direction(layout, factor, &grad, &metric)
                    .map(|dir| (row, dir))
            });
            let d = match &held {
                Some((row, dir)) => row.correct(dir, d, row.off, mu),
                None => d,
            };
            // No vertex moves farther than the linearisation reaches (`STEP_CAP_EDGES`): a
            // step a little longer is shortened to the cap (`STEP_SHORTEN_MAX`), a longer one
            // refused and the damping raised, which bounds it by damping the nearly singular
            // directions that make it long (a much shortened step keeps them).
            let longest = d
                .iter()
                .zip(&reach)
                .map(|(v, l)| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() / l)
                .fold(0.0f64, f64::max);
            if ls.is_none() && longest > STEP_SHORTEN_MAX * STEP_CAP_EDGES {
                mu *= 4.0;
                report.rejected_steps += 1;
                continue;
            }
            let d: Vec<[f64; 3]> = if ls.is_none() && longest > STEP_CAP_EDGES {
                let s = STEP_CAP_EDGES / longest;
                d.iter().map(|v| [v[0] * s, v[1] * s, v[2] * s]).collect()
            } else {
                d
            };
            let v_star: Vec<[f64; 3]> = interior
                .iter()
                .zip(&d)
                .map(|(v, d)| [v[0] + d[0], v[1] + d[1], v[2] + d[2]])
                .collect();
            let filtered = ls.as_ref().map(|u| u.apply(layout, &v_star));
            let next = filtered.as_ref().unwrap_or(&v_star);
            let mut trial = piece.with_interior(&pos, next);
            let offending = piece.offending_faces_with_normals(
                &trial,
                (tangential < 1.0).then_some(&mut trial_face_normals[..]),
            );
            let folded = offending.len();
            // Corrections move the trial: then its guard's normals are no longer its own.
            trial_normals_fresh = folded == 0 && tangential < 1.0;
            if folded > 0 && ls.is_none() && stiffened < MAX_STIFFEN {
                // A face would fold: its corners and normal depend only on its three
                // vertices, so stiffen those (a larger weight in the metric, Eq. 14) and
                // re-solve at the same damping rather than shrinking the whole step.
                for &f in &offending {
                    for &v in &piece.faces[f] {
                        let i = layout.index_of[v as usize];
                        if i != flatcut_mesh::INVALID {
                            stiff[i as usize] = (stiff[i as usize] * STIFFEN).min(STIFF_MAX);
                        }
                    }
                }
                stiffened += 1;
                assembled = false;
                report.rejected_steps += 1;
                continue;
            }
            // Where no correction can follow, A at the trial comes with its θ (one pass over
            // the corners, and the accepted step needs it); otherwise θ alone.
            trial_grad_fresh = folded == 0 && !(ls.is_none() && corrections_pay);
            let mut f_trial = if folded == 0 {
                if trial_grad_fresh {
                    layout.evaluate(&trial, &mut trial_theta, &mut trial_grad);
                } else {
                    layout.theta(&trial, &mut trial_theta);
                }
                norm.merit(&trial_theta, dead_zone).1
            } else {
                f64::INFINITY
            };
            // Second-order corrections (as in SQP against the Maratos effect): the residual
            // left at the trial point, solved with the same factor (a solve costs a small
            // fraction of a factorisation), pulls the point back onto the curved constraint
            // set θ = 2π. Kept while each one at least halves the merit, or on a large piece
            // near θ = 2π cuts it by a fifth as predicted (`keep_correction`); none is tried
            // after a trial that raised the merit more than `CORRECTION_SKIP_ABOVE`-fold.
            // Corrections kept on this trial, counted if it is accepted.
            let mut trial_corrections = 0;
            if folded == 0 && ls.is_none() {
                let relaxed = err <= CORRECTION_RELAXED_BELOW_RAD
                    && piece.faces.len() >= CORRECTION_RELAXED_MIN_FACES;
                // On a large piece near θ = 2π, outside a restore, a trial that raised the
                // merit at all gets none (`CORRECTION_SKIP_ABOVE`).
                let raised = relaxed && restoring.is_none() && f_trial >= f;
                let corrections =
                    if f_trial > CORRECTION_SKIP_ABOVE * f || raised || !corrections_pay {
                        0
                    } else {
                        MAX_CORRECTIONS
                    };
                for _ in 0..corrections {
                    let r = residual_beyond(&trial_theta, dead_zone);
                    let Some(dc) = solve(&r) else { break };
                    let dc = match &held {
                        Some((row, dir)) => {
                            row.correct(dir, dc, row.goal - piece.total_area(&trial), mu)
                        }
                        None => dc,
                    };
                    let mut cand = trial.clone();
                    for (i, &p) in layout.interior.iter().enumerate() {
                        for k in 0..3 {
                            cand[p as usize][k] += dc[i][k];
                        }
                    }
                    let mut cand_theta = vec![0.0; n];
                    layout.theta(&cand, &mut cand_theta);
                    let f_cand = norm.merit(&cand_theta, dead_zone).1;
                    // The fold guard only for a correction the merit would keep (about half
                    // of them are not).
                    let kept = keep_correction(f_trial, f_cand, relaxed, || {
                        norm.model(&r, &layout.apply(&grad, &dc), 1.0)
                    });
                    if !kept || piece.folded_faces(&cand) > 0 {
                        break;
                    }
                    trial = cand;
                    trial_normals_fresh = false;
                    trial_theta = cand_theta;
                    f_trial = f_cand;
                    trial_corrections += 1;
                }
            }
            if ls.is_some() {
                if f_trial.is_finite() && f_trial < 0.9 * f {
                    accepted = Some((trial, None));
                    break;
                }
                ls = None;
                report.messages.push(format!(
                    "least-square phase ended after {} iterations; direct damped steps finish",
                    report.iterations
                ));
                continue;
            }
            // Predicted decrease of the linear model.
            let ad = layout.apply(&grad, &d);
            let pred = f - norm.model(&b, &ad, 1.0);
            let rho = if pred > 0.0 {
                (f - f_trial) / pred
            } else {
                -1.0
            };
            if f_trial.is_finite() && f_trial < f && rho > RHO_ACCEPT {
                if rho > 0.75 {
                    // Down by 10, but not so far that the next step is predicted past the
                    // step cap (where the damping dominates, a step's length goes as 1/μ):
                    // a step beyond 1.5 caps is refused, and each refusal is a factorisation.
                    let down = MU_DOWN.min(STEP_CAP_EDGES / longest);
                    mu = (mu / down).max(MU_MIN);
                } else if rho < 0.25 {
                    mu *= 2.0;
                }
                report.corrections += trial_corrections;
                accepted = Some((trial, None));
                break;
            }
            report.rejected_steps += 1;
            // Before paying for a new factorisation at a larger damping, try fractions of
            // the same step: the linear model is exact to first order, so a short enough
            // step along d achieves its predicted decrease f − ‖b − α A d‖². A try costs a θ
            // evaluation and a fold check. The damping then doubles (as after a step with
            // ρ < 1/4): ×4 as after a plain rejection stalled the 100k-face cap at 1.4e-6,
            // ×2 converged it in 111 iterations instead of 283.
            // Near θ = 2π a rejected step is the near-flat modes answering at second order
            // (the rest of the step is right), so it is followed much further down
            // (`DEEP_BACKTRACKS`) before the damping is raised; so is a blow-up a little
            // farther from θ = 2π (`BLOWUP_RHO`), or while a pull-back is being restored.
            let blow_up =
                rho < BLOWUP_RHO && (err <= BLOWUP_BACKTRACK_AT_RAD || restoring.is_some());
            let tries = if err <= DEEP_BACKTRACK_AT_RAD || blow_up {
                DEEP_BACKTRACKS
            } else {
                BACKTRACKS
            };
            if ls.is_none()
                && let Some((short, short_theta)) = backtrack(
                    piece, layout, &pos, &interior, &d, &b, &ad, f, f_trial, dead_zone, n, tries,
                    &norm,
                )
            {
                report.backtracked_steps += 1;
                mu *= 2.0;
                accepted = Some((short, Some(short_theta)));
                break;
            }
            mu *= 4.0;
        }
        // `accepted`: the new positions and their θ when it is not in `trial_theta`
        // (a backtracked step brings its own).
        if restore_refused {
            continue;
        }
        let Some((trial, trial_theta_owned)) = accepted else {
            report.stop_reason =
                "no decreasing unfolded step at any damping (μ above its limit)".into();
            break;
        };
        pos = trial;
        // Stiffness relaxes again so that it does not freeze a region for good.
        for k in &mut stiff {
            *k = (*k / STIFFEN.sqrt()).max(1.0);
        }
        // θ at the accepted point was computed for its test (the same sums, bit for bit),
        // and A too where no correction could follow.
        match trial_theta_owned {
            Some(t) => {
                theta = t;
                layout.gradient(&pos, &mut grad);
            }
            None => {
                if trial_normals_fresh {
                    let cached = accepted_face_normals.get_or_insert_with(|| FaceNormalsAt {
                        positions: Vec::new(),
                        face_normals: vec![[0.0; 3]; piece.faces.len()],
                    });
                    cached.positions.clone_from(&pos);
                    std::mem::swap(&mut cached.face_normals, &mut trial_face_normals);
                }
                std::mem::swap(&mut theta, &mut trial_theta);
                if trial_grad_fresh {
                    std::mem::swap(&mut grad, &mut trial_grad);
                } else {
                    layout.gradient(&pos, &mut grad);
                }
            }
        }
        let f_before = f;
        (err, f) = norm.merit(&theta, dead_zone);
        if f < (1.0 - SMOOTH_STAGNANT_GAIN) * f_before {
            stagnant = 0;
        } else {
            stagnant += 1;
        }
        report.iterations += 1;
        report.theta_err.push(err);
        best.record(f, &pos, report.iterations, report.factorizations);
    }
    // After a pull-back was kept the run can end (iteration limit, stall) short of the
    // tolerance while its best state, by the merit, is still the converged one before the
    // pull-backs (the zero target's result): that is what is returned, and it converged.
    if !report.converged && report.pull_backs > 0 {
        layout.theta(&best.pos, &mut theta);
        if Piece::errors(&theta).0 <= opts.tolerance_rad {
            report.converged = true;
            report.messages.push(format!(
                "the pull-backs did not finish ({}): the converged state before them is returned",
                report.stop_reason
            ));
            report.stop_reason = format!("θ_err ≤ {:.1e} rad", opts.tolerance_rad);
        }
    }
    if polished.runs > 0 {
        report.messages.push(format!(
            "local polish: {} region runs ({} without gain), {} iterations, regions of up to {} of {n} interior vertices",
            polished.runs, polished.failed, polished.steps, polished.largest
        ));
    }
    if report.smoothed_steps > smoothed_before {
        report.messages.push(format!(
            "{} smoothed steps (filtered Gauss–Newton steps on a plateau of a shallow piece; kept jumps included)",
            report.smoothed_steps - smoothed_before
        ));
    }
    // A jump still being restored when the run ended: its state is not the result (the best
    // state before it is), so it counts as undone.
    jumps_undone += usize::from(jump.is_some());
    if jumps_kept + jumps_undone > 0 {
        report.messages.push(format!(
            "smoothed jumps (the smooth part of the residual removed, the rough part left to the plain steps): {jumps_kept} kept (restored within {longest_restore} factorisations), {jumps_undone} undone"
        ));
    }
    if lifts > 0 {
        report.messages.push(format!(
            "{lifts} lifts of nearly flat vertices with excess angle (second-order steps after {LIFT_AFTER} iterations without gain)"
        ));
    }
    RobustOutcome {
        positions: best.pos,
        handed_over,
    }
}

/// Local polish (`local_polish.rs`): pieces with at least this many interior vertices
/// (below, a factorisation of the whole piece costs little more than building a region)…
const LOCAL_MIN_INTERIOR: usize = 1000;
/// … go to a region once at most 1/`LOCAL_ACTIVE_DIVISOR` of their interior vertices are
/// above the tolerance…
const LOCAL_ACTIVE_DIVISOR: usize = 20;
/// … and the region holds at most 1/`LOCAL_REGION_DIVISOR` of them.
const LOCAL_REGION_DIVISOR: usize = 4;
/// Iterations a region's run gets, and how long the piece goes on with global steps after a
/// region run that did not finish before it tries another (doubled after each such run).
const LOCAL_BUDGET: usize = 30;
const LOCAL_RETRY_AFTER: usize = 3;
/// A region run that leaves at most this fraction of the merit is followed by another at once.
const LOCAL_GAIN: f64 = 0.5;

/// What the region runs of a piece did (for its message).
#[derive(Default)]
struct PolishTally {
    runs: usize,
    /// Runs whose result was not kept.
    failed: usize,
    /// Accepted steps of the kept runs.
    steps: usize,
    /// Interior vertices of the largest kept region.
    largest: usize,
}

/// What a region run ([`polish_region`]) did.
enum RegionRun {
    /// It lowered the merit ‖θ − 2π‖² of the piece without folding a face: the piece's new
    /// positions and θ, the region's accepted steps (already counted in the report), whether
    /// the region reached the tolerance, and its interior vertex count.
    Gained {
        positions: Vec<[f64; 3]>,
        theta: Vec<f64>,
        steps: usize,
        finished: bool,
        interior: usize,
    },
    /// It did not.
    Failed,
}

/// The local polish step of a run at `pos` (θ `theta` and its merit, damping `mu`): when at most
/// 1/`LOCAL_ACTIVE_DIVISOR` of the interior vertices are above the tolerance and their region
/// ([`crate::local_polish::region`]) holds at most 1/`LOCAL_REGION_DIVISOR` of them, robust
/// mode on the region alone. `None` when no region is tried. The region's work (iterations,
/// θ_err of the piece along the way, factorisations) goes into `report`.
fn polish_region(
    piece: &Piece,
    pos: &[[f64; 3]],
    (theta, merit, dead_zone): (&[f64], f64, f64),
    mu: f64,
    opts: &ProcessOptions,
    norm: &MeritNorm<'_>,
    report: &mut PieceReport,
) -> Option<RegionRun> {
    let layout = &piece.layout;
    let n = layout.n();
    let active: Vec<usize> = (0..n)
        .filter(|&i| (theta[i] - TAU).abs() > opts.tolerance_rad)
        .collect();
    if active.len() * LOCAL_ACTIVE_DIVISOR > n {
        return None;
    }
    let region = crate::local_polish::region(
        piece,
        &active,
        theta,
        opts.tolerance_rad,
        n / LOCAL_REGION_DIVISOR,
        opts.min_angle_deg,
    )?;
    let mut sub = PieceReport::default();
    let out = run_inner(
        &region.piece,
        &crate::local_polish::restrict(&region, pos),
        &crate::local_polish::region_options(opts),
        Some(LOCAL_BUDGET),
        Polish::Region { mu },
        Kind {
            hand_over: false,
            shaped_merit: norm.is_shaped(),
        },
        &mut sub,
    )
    .positions;
    crate::local_polish::account(report, &sub);
    let positions = crate::local_polish::extend(&region, pos, &out);
    let mut new_theta = vec![0.0; n];
    layout.theta(&positions, &mut new_theta);
    let (err, f) = norm.merit(&new_theta, dead_zone);
    if f >= merit || piece.folded_faces(&positions) > 0 {
        return Some(RegionRun::Failed);
    }
    // θ_err of the piece along the region's run: the region's, or the unchanged rest's where
    // that is larger.
    let mut in_region = vec![false; n];
    for &v in &region.piece.layout.interior {
        let p = region.parent_of[v as usize];
        in_region[layout.index_of[p as usize] as usize] = true;
    }
    let rest = (0..n)
        .filter(|&i| !in_region[i])
        .map(|i| (theta[i] - TAU).abs())
        .fold(0.0f64, f64::max);
    let steps = sub.theta_err.len().saturating_sub(1).max(1);
    for e in sub.theta_err.iter().skip(1).take(steps - 1) {
        report.theta_err.push(e.max(rest));
    }
    report.theta_err.push(err);
    report.iterations += steps;
    Some(RegionRun::Gained {
        positions,
        theta: new_theta,
        steps,
        finished: sub.converged,
        interior: region.piece.layout.n(),
    })
}

/// The direct solve of a large piece that coarse-to-fine hierarchies follow
/// ([`run_before_hierarchy`]) hands the piece over after `HAND_OVER_AFTER` iterations without
/// a 10 % gain while its relative damping is at least `HAND_OVER_MU` and θ_err above
/// `HAND_OVER_ABOVE_RAD` (instead of lifting, and stalling only after up to 8 × 20 + 100
/// iterations). Measured (twenty-first session, docs/algorithms/flattenable.md, "Body pieces
/// at scan resolution"): the Loop-subdivided upper back and thigh of mh_body_subdiv2 (21k,
/// 37k, 85k faces) sit at damping 0.02–0.2 from their 20th iteration on with θ_err
/// 6e-4–8e-4, and spent ~300 iterations there before their hierarchy converged them; the
/// 100×100 saddle's slow phase, which does converge directly, stays below 6.1e-3.
const HAND_OVER_MU: f64 = 3e-2;
const HAND_OVER_ABOVE_RAD: f64 = 1e-4;
/// Ten rather than `LIFT_AFTER` (twenty-fourth session): each iteration there is a
/// factorisation of the whole piece, while the hierarchy that follows starts from the input
/// and its coarse levels are cheap. The 85k upper back 8.6 → 8.0 s, the 37k thigh 3.4 → 2.7 s,
/// the 88k shoulder 7.1 → 5.0 s (the same results; the shoulder's unconverged best 1.91e-3 →
/// 1.90e-3); the real meshes above 15k faces that stall (whole objects and reliefs) now hand
/// over before the stall test and end 0.2–5.6 s sooner at best states within 0.7 % of before;
/// the saddles, caps, patches and random pieces the same (docs/algorithms/flattenable.md,
/// "A damping shaped like the graph Laplacian").
const HAND_OVER_AFTER: usize = 10;

/// Iterations without a 10 % gain of the merit after which nearly flat vertices with excess
/// angle are lifted, and the most lifts per piece (each restarts the stall count, so the cap
/// bounds the extra iterations of a piece that stalls for other reasons: 8 × 20).
const LIFT_AFTER: usize = 20;
const MAX_LIFTS: usize = 8;
/// Vertices whose excess is at least this fraction of the current θ_err are lifted.
const LIFT_FRACTION: f64 = 0.5;
/// Normal offset of the two probes that measure θ's slope and curvature, in mean input edge
/// lengths: small against the lift (~0.01–0.1 edge), large against round-off.
const LIFT_PROBE_EDGES: f64 = 1e-3;
/// A lift longer than this (mean input edge lengths) is not taken: the quadratic model of θ
/// is not trusted that far.
const LIFT_MAX_EDGES: f64 = 0.5;

/// The second-order step for the double roots that stall negatively curved pieces: an
/// interior vertex with excess angle (θ > 2π) whose star is nearly flat sits near the maximum
/// of θ over its centre's normal offset h, so its row of A nearly vanishes and the least-norm
/// step asks for long moves that the ratio test refuses. Modelled as
/// θ(h) ≈ θ + g h − c h²/2 (g, c from two probes at ±`LIFT_PROBE_EDGES`), the root of
/// θ(h) = 2π nearer to 0 removes its excess to second order. Every vertex with excess at
/// least `LIFT_FRACTION` of θ_err is lifted at once; `None` when none qualifies or the lifted
/// surface folds a face. Measured on the 100×100 saddle (docs/algorithms/flattenable.md):
/// without lifts one of four inputs within an ulp of the grid stalled at 2.1e-4, with them
/// seven of seven converged.
fn lift_flat_excess(
    piece: &Piece,
    layout: &Layout,
    pos: &[[f64; 3]],
    theta: &[f64],
    err: f64,
    reach: &[f64],
) -> Option<Vec<[f64; 3]>> {
    let normals = piece.interior_normals(pos);
    let mut out = pos.to_vec();
    let mut moved = 0;
    // Probes move one vertex of this copy and put it back: θ at that vertex is all they need.
    let mut probe = pos.to_vec();
    for (i, &p) in layout.interior.iter().enumerate() {
        let r = theta[i] - TAU;
        if r <= LIFT_FRACTION * err {
            continue;
        }
        let n = normals[i];
        let delta = LIFT_PROBE_EDGES * reach[i];
        let v = pos[p as usize];
        let mut at = |h: f64| {
            probe[p as usize] = [v[0] + h * n[0], v[1] + h * n[1], v[2] + h * n[2]];
            let t = layout.theta_at(i, &probe);
            probe[p as usize] = v;
            t
        };
        let (tp, tm) = (at(delta), at(-delta));
        let g = (tp - tm) / (2.0 * delta);
        let c = -(tp + tm - 2.0 * theta[i]) / (delta * delta);
        // θ must curve down (a maximum near h = 0); NaN probes are skipped too.
        if c.is_nan() || c <= 0.0 {
            continue;
        }
        // θ(h) ≈ θ + g h − c h²/2 = 2π: c h²/2 − g h − r = 0.
        let disc = (g * g + 2.0 * c * r).sqrt();
        let (h1, h2) = ((g + disc) / c, (g - disc) / c);
        let h = if h1.abs() < h2.abs() { h1 } else { h2 };
        if !h.is_finite() || h.abs() > LIFT_MAX_EDGES * reach[i] {
            continue;
        }
        for k in 0..3 {
            out[p as usize][k] += h * n[k];
        }
        moved += 1;
    }
    (moved > 0 && piece.folded_faces(&out) == 0).then_some(out)
}

/// A smoothed jump being restored: the state before it and its θ (its merit is taken
/// again under the dead zone the run has when the jump is judged).
struct Jump {
    before: Snapshot,
    theta: Vec<f64>,
}

/// What a smoothed try found (`smoothed_trial`): the positions and their θ.
enum SmoothedMove {
    /// A filtered step that gained at least `SMOOTH_STEP_MIN_GAIN` of the merit: taken as a
    /// step.
    Step(Vec<[f64; 3]>, Vec<f64>),
    /// No filtered step gained: the smoothed jump, which removes the residual's smooth part
    /// and leaves a rough one in its place (the merit rises); kept only if the plain steps
    /// after it bring the merit below where it left from.
    Jump(Vec<[f64; 3]>, Vec<f64>),
}

/// The smoothed try at `pos` (`smoothed_step.rs`): the Gauss–Newton step (damping
/// `SMOOTH_MU`, one factorisation) filtered at every stiffness of `factors`, each scaled to
/// its linear model's optimum; the unfolded one with the least merit if it gains
/// `SMOOTH_STEP_MIN_GAIN`. Otherwise the jump: `JUMP_FRACTION` of the step filtered by
/// `JUMP_FILTER` and scaled to take out the residual's smooth part
/// ([`smoothed_step::smooth_part_scale`]), halved while it folds. On a regular grid of a
/// smooth surface the filtered steps gain; on an irregular one (or a rough relief) the angle
/// sums answer a smooth move with a rough residual as large as the smooth one removed, so
/// only the jump, restored by the plain steps (which remove rough residuals well), gets off
/// the plateau (docs/algorithms/flattenable.md, "Irregular shallow pieces: a smoothed jump").
/// `None` when the factorisation or every filter fails or folds.
fn smoothed_trial(
    piece: &Piece,
    (pos, theta, f, dead_zone): (&[[f64; 3]], &[f64], f64, f64),
    (grad, metric, normal, factor): (
        &[[f64; 3]],
        &Metric<'_>,
        &mut [f64],
        &mut crate::least_norm::Factor,
    ),
    factors: &[flatcut_sparse::SpdFactor<'_>],
    opts: &ProcessOptions,
    norm: &MeritNorm<'_>,
    report: &mut PieceReport,
) -> Option<SmoothedMove> {
    let layout = &piece.layout;
    layout.normal_matrix(grad, metric, normal);
    let mean_diag = layout.mean_diagonal(normal).max(f64::MIN_POSITIVE);
    report.factorizations += 1;
    layout
        .refactor_damped(factor, normal, SMOOTH_MU * mean_diag, opts.damping)
        .ok()?;
    let b = residual_beyond(theta, dead_zone);
    let mut x = b.clone();
    layout.solve(factor, &mut x, 1);
    if !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    let d = layout.step_from_multipliers(grad, metric, &x);
    let interior = piece.interior_of(pos);
    let moved = |step: &[[f64; 3]], s: f64| -> Vec<[f64; 3]> {
        let next: Vec<[f64; 3]> = interior
            .iter()
            .zip(step)
            .map(|(v, d)| [v[0] + s * d[0], v[1] + s * d[1], v[2] + s * d[2]])
            .collect();
        piece.with_interior(pos, &next)
    };
    let mut trial_theta = vec![0.0; layout.n()];
    let mut best: Option<(Vec<[f64; 3]>, Vec<f64>, f64)> = None;
    // The jump's filtered step and its image under A, kept from the loop.
    let mut jump_step = None;
    for (k, filter) in factors.iter().enumerate() {
        let Some(smooth) = smoothed_step::filtered(filter, &d) else {
            continue;
        };
        let ad = layout.apply(grad, &smooth);
        let s = smoothed_step::model_scale(&b, &ad);
        let trial = moved(&smooth, s);
        if k == smoothed_step::JUMP_FILTER {
            jump_step = Some((smooth, ad));
        }
        if piece.folded_faces(&trial) > 0 {
            continue;
        }
        layout.theta(&trial, &mut trial_theta);
        let f_trial = norm.merit(&trial_theta, dead_zone).1;
        if f_trial.is_finite()
            && f_trial < f
            && best.as_ref().is_none_or(|(_, _, fb)| f_trial < *fb)
        {
            best = Some((trial, trial_theta.clone(), f_trial));
        }
    }
    if let Some((trial, trial_theta, f_trial)) = best
        && f_trial <= (1.0 - SMOOTH_STEP_MIN_GAIN) * f
    {
        return Some(SmoothedMove::Step(trial, trial_theta));
    }
    let (smooth, ad) = jump_step?;
    let filter = factors.get(smoothed_step::JUMP_FILTER)?;
    let mut s = JUMP_FRACTION * smoothed_step::smooth_part_scale(filter, &b, &ad)?;
    for _ in 0..JUMP_HALVINGS {
        let trial = moved(&smooth, s);
        if piece.folded_faces(&trial) == 0 {
            layout.theta(&trial, &mut trial_theta);
            let f_trial = norm.merit(&trial_theta, dead_zone).1;
            return f_trial
                .is_finite()
                .then_some(SmoothedMove::Jump(trial, trial_theta));
        }
        s *= 0.5;
    }
    None
}

/// Step fractions tried along a rejected direction before the damping is raised (1/2, 1/4,
/// 1/8).
const BACKTRACKS: usize = 3;
/// Within `DEEP_BACKTRACK_AT_RAD` of θ = 2π, fractions down to 2⁻¹⁰ are tried. There a
/// rejected step is a group of nearly flat vertices (rows of A near zero, nearly dependent)
/// that the least-norm step moves far, answering at second order: on the 50k-face cap a step
/// of 0.15 edge lengths took f = ‖θ − 2π‖² from 5.6e-11 to 2.4e-4, and 1/8 of it was still
/// worse, so each such step cost 5–8 factorisations at rising damping before one was
/// accepted. A θ evaluation is a tenth of a factorisation. Measured (docs/algorithms/
/// flattenable.md, "Deep backtracking near θ = 2π" and "Long steps refused"): zero target,
/// 130×130 cap 95 → 62 factorisations, eight caps of 7k–100k faces 910 → 543 (and the 225
/// cap no longer stalls at 1.7e-9); 1k–10k unchanged.
const DEEP_BACKTRACKS: usize = 10;
/// θ_err below which backtracking goes deep (radians). Not earlier: in the 100×100 saddle's
/// long phase at ~1e-4 deeper backtracking changed which paths reach the final quadratic
/// phase (two of the seven one-ulp inputs stalled).
const DEEP_BACKTRACK_AT_RAD: f64 = 1e-6;
/// A trial that made f worse by this many times the decrease the linear model promised
/// (ρ below it; a folded trial's ρ is −∞) is that near-flat blow-up too, and below
/// `BLOWUP_BACKTRACK_AT_RAD` it is backtracked deep as well. The 100k-face cap's trace shows
/// them from θ_err 2e-6 (ρ = −7e5 at 1.6e-6, nine factorisations for one step). Measured
/// (docs/algorithms/flattenable.md, "Blow-ups backtracked deep"): caps of 14k–100k faces,
/// zero target 855 → 771 factorisations (100k 107 → 88), detail 1 030 → 986; the saddle
/// harness, the caps up to 10k, the body pieces, patches, pipelines and real meshes follow
/// the same paths. Without the θ_err gate (any θ_err) two of the seven saddles stall.
const BLOWUP_RHO: f64 = -1e3;
/// θ_err below which a blow-up (`BLOWUP_RHO`) is backtracked deep (radians): above the
/// saddle's long phase at ~1e-4. While a pull-back is being restored a blow-up is backtracked
/// deep at any θ_err (at most `PULL_BACK_MAX_ERR_RAD` there): the pull-back leaves the surface
/// near θ = 2π with the tiny damping of the converged phase, and its first restoring step blew
/// up (ρ ≈ −7e4 on the 3.5k cap) at nine dampings, ×4 each, before one was accepted. Measured
/// (docs/algorithms/flattenable.md, "Blow-ups while restoring a pull-back"): 3.5k cap, detail
/// target, 54 → 34 factorisations; 21 caps of 1.9k–14.5k faces 805 → 767, none worse.
const BLOWUP_BACKTRACK_AT_RAD: f64 = 1e-5;

/// The longest step any interior vertex may take in one iteration, in its mean input edge
/// lengths. The linearisation of θ is good for about one edge length; at small damping the
/// least-norm step can be several (4 edge lengths on the 160×160 cap), and such a step, even
/// when the linear model rates it well (ρ = 0.84 there), can leave the surface where A Aᵀ is
/// nearly singular in the direction of the residual, so that no small step reduces it (that
/// cap then stalled at θ_err 1.7e-5). A longer step is refused and the damping raised ×4,
/// unless it is at most `STEP_SHORTEN_MAX` times longer: then it is shortened to this length.
/// (Until 2026-11-26 it was shortened to this length along its direction instead: that keeps
/// the nearly singular directions that made it long, and on the 175×175, 190×190 and 205×205
/// caps a shortened step of 7.7 edge lengths, rated ρ = 2.7, left the surface where no step
/// reduces f — stalled at 1.5e-5. Refused, all fourteen caps of 7k–100k faces converge;
/// docs/algorithms/flattenable.md, "Long steps refused".) 2 edge lengths: 0.5 and 1 also
/// unstalled the 160×160 cap but cost more iterations on the 100×100 and 130×130 caps
/// (docs/algorithms/flattenable.md, "Step length cap").
const STEP_CAP_EDGES: f64 = 2.0;

/// A step at most this many times longer than `STEP_CAP_EDGES` is shortened to the cap along
/// its direction instead of refused (its predicted decrease and backtracking then refer to
/// the shortened step). Refusing costs a factorisation, and at large damping the next step
/// is often only just over the cap (2.1–3.3 edge lengths after a ×4 on the 100k cap), so
/// most refusals bought a slightly different direction for the price of a factorisation.
/// Shortening is what stalled the 175–205 caps when a step of 7.7 edge lengths (3.9× the
/// cap) was cut down; up to 1.5× the direction is the damped one's nearly. Measured on the
/// fourteen caps of 7k–100k faces, zero target: 819 → 702 factorisations, 47.4 → 40.0 s
/// CPU, all converged (docs/algorithms/flattenable.md, "Slightly long steps shortened").
const STEP_SHORTEN_MAX: f64 = 1.5;

/// The first halving `k` (α = 2⁻ᵏ, 1 ≤ k ≤ `tries`) worth evaluating after the full step
/// (or the full step with its second-order corrections) took the merit from `f` to
/// `full_merit`. A near-flat blow-up is the second-order terms of θ, squared: B α⁴ with
/// B ≈ `full_merit` (16× less per halving, as traced on the 33k-face cap: 1.3e7, 8.1e5,
/// 5.1e4, … × f). The merit can only fall where B α⁴ is below the linear decrease, about
/// 2 α f, i.e. for α < (2 f / B)^⅓, which lies below (f / B)^¼ whenever B ≥ 16 f; so the
/// fractions above (f / B)^¼ are skipped, keeping one halving as a margin. A blow-up growing
/// more slowly (as α² or α³) can only be accepted deeper still.
fn first_fraction(f: f64, full_merit: f64, tries: usize) -> usize {
    if !(full_merit.is_finite() && f > 0.0 && full_merit > f) {
        return 1;
    }
    let quartic = ((full_merit / f).log2() / 4.0).ceil() as usize;
    quartic.saturating_sub(1).clamp(1, tries.max(1))
}

/// How a run measures its merit: ‖r‖², r = θ − 2π beyond the dead zone, or rᵀ D⁻¹ r with the
/// D of `Damping::GraphLaplacian` (factorised once per run). The damped step with that D
/// minimises ‖d‖²_{G⁻¹} + ‖A d − b‖²_{D⁻¹} / μm: its large-μ limit, G Aᵀ D⁻¹ b / μm, descends
/// on the D⁻¹ merit but not always on the plain one, whose ratio test then judged the step
/// by what it does not decrease (tested: `graph_damping_norm_is_the_damped_systems_and_
/// heavy_damping_descends_in_it`). Measured (twenty-fourth session): the 85k upper back's
/// shaped fine level 63 → 35 iterations, the same surface. Only for hierarchy levels
/// ([`Kind::in_hierarchy`]): from a raw input the D⁻¹ merit, which weighs rough residuals
/// ~1/(1000 · valence) of smooth ones, let the 37k thigh's direct solve crease (109°)
/// (docs/algorithms/flattenable.md, "A damping shaped like the graph Laplacian").
struct MeritNorm<'a> {
    shaped: Option<flatcut_sparse::SpdFactor<'a>>,
}

impl<'a> MeritNorm<'a> {
    fn plain() -> Self {
        Self { shaped: None }
    }

    fn is_shaped(&self) -> bool {
        self.shaped.is_some()
    }

    fn shaped(pattern: &'a flatcut_sparse::SpdPattern, values: &[f64]) -> Option<Self> {
        pattern
            .factor(values)
            .ok()
            .map(|f| Self { shaped: Some(f) })
    }

    /// rᵀ M r with M = I or D⁻¹.
    fn quadratic(&self, r: &[f64]) -> f64 {
        match &self.shaped {
            None => r.iter().map(|x| x * x).sum(),
            Some(f) => {
                let mut y = r.to_vec();
                if f.solve_in_place(&mut y, 1).is_err() {
                    return f64::INFINITY;
                }
                r.iter().zip(&y).map(|(a, b)| a * b).sum()
            }
        }
    }

    /// θ_err and the merit.
    fn merit(&self, theta: &[f64], dead_zone: f64) -> (f64, f64) {
        match &self.shaped {
            None => Piece::merit(theta, dead_zone),
            Some(_) => {
                let (err, _) = Piece::merit(theta, dead_zone);
                (err, self.quadratic(&residual_beyond(theta, dead_zone)))
            }
        }
    }

    /// The model's merit after α d: ‖b − α A d‖² in this norm.
    fn model(&self, b: &[f64], ad: &[f64], alpha: f64) -> f64 {
        self.along(b, ad).at(alpha)
    }

    /// The model's merit along a step, for several fractions α (backtracking): in the
    /// shaped norm the quadratic in α from two solves with D, not one per α.
    fn along<'s>(&'s self, b: &'s [f64], ad: &'s [f64]) -> Along<'s> {
        match &self.shaped {
            None => Along::Plain { b, ad },
            Some(f) => {
                let mut y = [b.to_vec(), ad.to_vec()].concat();
                if f.solve_in_place(&mut y, 2).is_err() {
                    return Along::Shaped([f64::INFINITY, 0.0, 0.0]);
                }
                let (yb, yad) = y.split_at(b.len());
                let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
                Along::Shaped([dot(b, yb), dot(b, yad), dot(ad, yad)])
            }
        }
    }
}

/// [`MeritNorm::along`]: the model's merit at α.
enum Along<'s> {
    /// ‖b − α A d‖², summed as [`model_merit`] does (the same bits as before the shaped norm).
    Plain { b: &'s [f64], ad: &'s [f64] },
    /// bᵀD⁻¹b, bᵀD⁻¹(A d), (A d)ᵀD⁻¹(A d).
    Shaped([f64; 3]),
}

impl Along<'_> {
    fn at(&self, alpha: f64) -> f64 {
        match self {
            Along::Plain { b, ad } => model_merit(b, ad, alpha),
            Along::Shaped([bb, bad, adad]) => bb - 2.0 * alpha * bad + alpha * alpha * adad,
        }
    }
}

/// The merit the linear model predicts after a step α d from a point with residual `b`:
/// ‖b − α A d‖², given `ad` = A d. (With α = 1 the products α·(A d)ᵢ are exact, so the value
/// is the same to the bit as ‖b − A d‖².)
fn model_merit(b: &[f64], ad: &[f64], alpha: f64) -> f64 {
    b.iter()
        .zip(ad)
        .map(|(b, a)| (b - alpha * a) * (b - alpha * a))
        .sum()
}

/// Whether a second-order correction that took the merit from `f_trial` to `f_cand` is kept;
/// `relaxed`: whether a cut by a fifth may do (a large piece near θ = 2π, see
/// `CORRECTION_RELAXED_KEEP`). `predicted_residual` gives ‖r − A dc‖², the merit the linear
/// model (A at the step's base point) predicts after it, and is only evaluated for a relaxed
/// correction that cuts the merit by less than half.
fn keep_correction(
    f_trial: f64,
    f_cand: f64,
    relaxed: bool,
    predicted_residual: impl FnOnce() -> f64,
) -> bool {
    if f_cand.is_nan() {
        return false;
    }
    if f_cand < CORRECTION_KEEP * f_trial {
        return true;
    }
    if !relaxed || f_cand >= CORRECTION_RELAXED_KEEP * f_trial {
        return false;
    }
    let predicted_gain = f_trial - predicted_residual();
    predicted_gain > 0.0 && (f_trial - f_cand) >= CORRECTION_RELAXED_RHO * predicted_gain
}

/// The first of α = 2⁻ᵏ, k from [`first_fraction`] (1 unless the full step blew up) to
/// `tries`, for which `pos + α d` has no folded face and a real decrease of the merit against
/// the linear model's prediction (ρ above `RHO_ACCEPT`, as for full steps); the new positions
/// and their θ.
#[allow(clippy::too_many_arguments)]
fn backtrack(
    piece: &Piece,
    layout: &Layout,
    pos: &[[f64; 3]],
    interior: &[[f64; 3]],
    d: &[[f64; 3]],
    b: &[f64],
    ad: &[f64],
    f: f64,
    full_merit: f64,
    dead_zone: f64,
    n: usize,
    tries: usize,
    norm: &MeritNorm<'_>,
) -> Option<(Vec<[f64; 3]>, Vec<f64>)> {
    let first = first_fraction(f, full_merit, tries);
    let model = norm.along(b, ad);
    let mut alpha = 0.5f64.powi(first as i32);
    let mut theta = vec![0.0; n];
    for _ in first..=tries {
        let next: Vec<[f64; 3]> = interior
            .iter()
            .zip(d)
            .map(|(v, d)| {
                [
                    v[0] + alpha * d[0],
                    v[1] + alpha * d[1],
                    v[2] + alpha * d[2],
                ]
            })
            .collect();
        let cand = piece.with_interior(pos, &next);
        if piece.folded_faces(&cand) == 0 {
            layout.theta(&cand, &mut theta);
            let f_cand = norm.merit(&theta, dead_zone).1;
            let pred = f - model.at(alpha);
            if f_cand.is_finite() && f_cand < f && pred > 0.0 && (f - f_cand) / pred > RHO_ACCEPT {
                return Some((cand, theta));
            }
        }
        alpha *= 0.5;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::{CORRECTION_RELAXED_RHO, first_fraction, keep_correction};

    /// Along a step the merit is the linear model's f (1 − α)² plus a blow-up B αᵖ
    /// (second-order terms: p = 4 for a near-flat star, 2 or 3 for milder ones). No
    /// fraction α = 2⁻ᵏ that `first_fraction` skips may lower the merit, for full-step
    /// merits from 1 to 1e12 times f; and a large blow-up does skip.
    #[test]
    fn skipped_fractions_could_not_lower_the_merit() {
        let f = 3.7e-12;
        for p in [2, 3, 4] {
            for e in 0..=48 {
                let full = 10f64.powf(e as f64 / 4.0) * f;
                let merit = |alpha: f64| f * (1.0 - alpha).powi(2) + full * alpha.powi(p);
                let first = first_fraction(f, full, 10);
                for k in 1..first {
                    let alpha = 0.5f64.powi(k as i32);
                    assert!(
                        merit(alpha) >= f,
                        "p = {p}, full / f = {:e}: α = 2^-{k} skipped but lowers the merit",
                        full / f
                    );
                }
            }
        }
        // 1e7 f: (1e7)^¼ ≈ 2^5.8, so 2⁻¹ … 2⁻⁴ are skipped (2⁻⁵ kept as the margin).
        assert_eq!(first_fraction(f, 1e7 * f, 10), 5);
        assert_eq!(first_fraction(f, 1e7 * f, 3), 3);
    }

    #[test]
    fn no_skip_without_a_blow_up() {
        let f = 1e-9;
        for full in [0.5 * f, f, 15.9 * f, f64::INFINITY, f64::NAN] {
            assert_eq!(first_fraction(f, full, 10), 1, "full = {full:e}");
        }
        assert_eq!(first_fraction(0.0, 1.0, 10), 1);
    }

    /// A correction that halves the merit is kept anywhere, without asking the linear model;
    /// a smaller cut only where relaxed (a large piece near θ = 2π), by at least a fifth, and
    /// when the model predicted it (ρ ≥ 1/4); a NaN merit never.
    #[test]
    fn corrections_kept_at_half_anywhere_and_at_a_fifth_where_relaxed() {
        let never = || -> f64 { panic!("the linear model was asked") };
        let (near, far) = (true, false);
        let f = 4.0e-9;
        for relaxed in [near, far] {
            assert!(keep_correction(f, 0.49 * f, relaxed, never));
            assert!(!keep_correction(f, f64::NAN, relaxed, never));
        }
        // A cut of 30 %: kept near θ = 2π when the model predicted a gain of at most 1/ρ_min = 4×
        // it.
        let cut = 0.3 * f;
        let predicted = |gain: f64| move || f - gain;
        assert!(keep_correction(f, f - cut, near, predicted(cut)));
        assert!(keep_correction(
            f,
            f - cut,
            near,
            predicted(0.99 * cut / CORRECTION_RELAXED_RHO)
        ));
        assert!(!keep_correction(
            f,
            f - cut,
            near,
            predicted(1.01 * cut / CORRECTION_RELAXED_RHO)
        ));
        // …not when the model predicted an increase, nor where not relaxed.
        assert!(!keep_correction(f, f - cut, near, predicted(-cut)));
        assert!(!keep_correction(f, f - cut, far, never));
        // A cut of less than a fifth is not kept at all.
        assert!(!keep_correction(f, 0.81 * f, near, never));
    }
}
