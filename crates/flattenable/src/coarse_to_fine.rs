//! Coarse-to-fine robust processing of a large piece: a hierarchy of coarser pieces made by
//! [`crate::coarsen`] (interior half-edge collapses; the boundary is the same, bit for bit,
//! on every level), the coarsest solved from its input by robust mode, each solution
//! prolongated to the next finer level and finished there by robust mode started from it
//! ([`crate::robust::run_from`]), with displacements, fold guard and pull-backs measured
//! against that level's input.
//!
//! Why it helps: the robust iteration's cost on a large piece is the number of fine-level
//! iterations, and most of them move the surface globally (a cap's top pushed down, the
//! excess of a saddle migrating to the boundary), which a level with 4–16× fewer vertices
//! does at a fraction of the cost. The fine level then only has to remove the error
//! prolongation leaves inside each coarse face.

use std::collections::VecDeque;

use flatcut_mesh::vec3::{add, sub};
use flatcut_mesh::{Topology, TriMesh};

use crate::coarsen::{Coarsened, coarsen_with};
use crate::options::{CoarseToFine, Damping, ProcessOptions, Prolongation};
use crate::piece::{Piece, rough_median};
use crate::report::PieceReport;
use crate::{FlattenableError, robust};

/// A coarsening that removes less than this fraction of the faces ends the hierarchy
/// (nothing left to collapse cheaply: the coarse level would cost as much as the fine one).
const MIN_REDUCTION: f64 = 0.2;
/// Iterations the fine level gets from a prolongated start to reach the tolerance; then the
/// direct solve runs instead. Measured on sphere caps of 1.9k–14.5k faces (docs/algorithms/
/// flattenable.md, "Fine-level budget"): a fine level that converges does so in 11–42
/// iterations, while one that starts to crawl (θ_err ≈ 2e-7, gains of 0.1–1 % per step)
/// ran 265–500 iterations before converging or stalling, where the direct solve needs 20–40.
const FINE_LEVEL_BUDGET: usize = 60;
/// A fine level out of budget whose best θ_err is at most this (radians) was crawling near
/// θ = 2π (measured: 2e-7–1.5e-6 on the caps), and the direct solve is tried next; one that
/// ended farther (the body's saddle-like shoulder: 5.8e-3) goes on to the deeper rescue
/// hierarchies first.
const CRAWL_AT_RAD: f64 = 1e-4;
/// When every attempt has failed but one got this near θ = 2π (best θ_err, radians), the
/// displacement rescue hierarchy runs once more with `Damping::GraphLaplacian` (before the
/// continuation of a crawling fine level). The 85k-face
/// upper back ends at 3.2e-6 under the identity damping and converges so (docs/algorithms/
/// flattenable.md, "A damping shaped like the graph Laplacian"); pieces that stall farther
/// away (the saddle-like shoulder at 1.8e-3, scan pieces with darts to take out at 1e-3–1e-1)
/// were measured no better with it, and are spared its cost.
const SHAPED_RESCUE_AT_RAD: f64 = 1e-2;
/// Halvings of the prolongated displacement tried when the prolongated start folds a face
/// against the input; after them the level starts from its input.
const START_HALVINGS: usize = 8;

/// Whether `faces`-face pieces go through [`run`] under `opts`: coarse-to-fine first
/// (`min_faces..=max_faces`), or, with the rescue on, pieces smaller or larger than that but
/// big enough for a rescue hierarchy (solved directly first, the hierarchies only if that
/// fails).
pub fn applies(faces: usize, opts: &ProcessOptions) -> bool {
    let c = &opts.coarse_to_fine;
    c.levels > 0
        && c.ratio > 1.0
        && ((faces >= c.min_faces && faces <= c.max_faces)
            || (c.rescue && faces >= RESCUE_MIN_FACES * 2))
}

/// The rescue hierarchies (see [`CoarseToFine::rescue`]): levels down to pieces of about
/// this many faces (the size at which the measured body pieces converge directly in 10–20
/// iterations)…
const RESCUE_MIN_FACES: usize = 300;
/// … at most this many of them (enough for a 1M-face piece at ratio 4; the default
/// `max_faces` of 15k gives 3.8k, 940, 235)…
const RESCUE_LEVELS: usize = 8;
/// … with displacement prolongation first (the noisy scan's leg pieces converge that way and
/// not with positions), then positions (the clean body's saddle-like shoulder converges that
/// way and not with displacements; docs/algorithms/flattenable.md).
const RESCUE_PROLONGATIONS: [Prolongation; 2] =
    [Prolongation::Displacement, Prolongation::Positions];

/// Whether the first attempt for a piece of `faces` faces is the configured hierarchy (so
/// that its first coarsening is needed at once, [`Chain::first`]).
pub fn hierarchy_first(faces: usize, opts: &ProcessOptions) -> bool {
    let c = &opts.coarse_to_fine;
    applies(faces, opts) && faces >= c.min_faces && faces <= c.max_faces
}

/// The coarse levels of one piece, each made once. Every hierarchy of a run coarsens with
/// the same ratio, each level from the one above, and the coarsening is deterministic, so
/// the hierarchies (configured, rescues, shaped) all take a prefix of one chain; before, each
/// coarsened the piece again (2.3 ms of a 31 ms run at 3.5k faces, per hierarchy). Level
/// k + 1 is `levels[k]`, with its topology.
#[derive(Clone)]
pub struct Chain {
    ratio: f64,
    levels: Vec<(Coarsened, Topology)>,
    /// The coarsening after the last level removed less than `MIN_REDUCTION` of its faces:
    /// the chain ends there.
    ended: bool,
}

impl Chain {
    /// No level made yet; levels are made as hierarchies ask for them.
    pub fn new(opts: &ProcessOptions) -> Self {
        Self::with_ratio(opts.coarse_to_fine.ratio)
    }

    fn with_ratio(ratio: f64) -> Self {
        Self {
            ratio,
            levels: Vec::new(),
            ended: false,
        }
    }

    /// With its first level made from the piece (`local`, `topo`): run beside the fine
    /// piece's set-up when [`hierarchy_first`] (the two take about as long at 3.5k faces).
    pub fn first(
        local: &TriMesh,
        topo: &Topology,
        opts: &ProcessOptions,
    ) -> Result<Self, FlattenableError> {
        let mut chain = Self::new(opts);
        chain.extend(local, topo)?;
        Ok(chain)
    }

    /// Makes the next level from the last one (from the piece, `local` and `topo`, at first);
    /// false when the chain has ended.
    fn extend(&mut self, local: &TriMesh, topo: &Topology) -> Result<bool, FlattenableError> {
        if self.ended {
            return Ok(false);
        }
        let (cur, cur_topo) = self
            .levels
            .last()
            .map_or((local, topo), |(c, t)| (&c.mesh, t));
        let target = (cur.face_count() as f64 / self.ratio) as usize;
        let c = coarsen_with(cur, cur_topo, target)?;
        if (c.mesh.face_count() as f64) > (1.0 - MIN_REDUCTION) * cur.face_count() as f64 {
            self.ended = true;
            return Ok(false);
        }
        let t = Topology::build(&c.mesh)?;
        self.levels.push((c, t));
        Ok(true)
    }
}

/// Robust mode on `piece` (local mesh `local`, weights per local vertex `w_local`) through
/// coarse hierarchies. Fills `report` with the kept run; with a hierarchy, the prolongated
/// start counts as one iteration (`theta_err` holds the input's error, then the start's), and
/// the coarse levels are summarised in `messages`.
///
/// The attempts, each only while nothing has converged: for a piece of `min_faces` to
/// `max_faces` faces the configured hierarchy, else the direct solve (above `max_faces`, with
/// `rescue`, the configured hierarchy next); then, with `rescue`, the two rescue
/// hierarchies (deeper; displacement, then positions prolongation); last the direct solve if
/// it has not run. A fine level gets [`FINE_LEVEL_BUDGET`] iterations to reach the tolerance;
/// one cut off near θ = 2π ([`CRAWL_AT_RAD`]) moves the direct solve to the front of the
/// remaining attempts. When all of these fail, with `rescue`: the displacement rescue
/// hierarchy under `Damping::GraphLaplacian` if some attempt got within
/// [`SHAPED_RESCUE_AT_RAD`], then the continuation of a fine level cut near θ = 2π, then on
/// a rough piece (`piece::rough_median`) the direct solve under that damping. A direct
/// solve that hands the piece over (stuck far from θ = 2π under heavy damping) is followed by
/// that shaped hierarchy at once, before the identity ones, which run only if it fails. The best result by ‖θ − 2π‖² is kept, so the outcome is never worse
/// than the direct solve's; the kept run's report carries the others' messages, rejected
/// steps and factorisations (every attempt's).
pub fn run(
    (piece, local, w_local): (&Piece, &TriMesh, &[f64]),
    chain: &mut Chain,
    opts: &ProcessOptions,
    report: &mut PieceReport,
) -> Result<Vec<[f64; 3]>, FlattenableError> {
    let c2f = &opts.coarse_to_fine;
    let faces = local.face_count();
    // `run` is only called where the hierarchies apply.
    let direct_first = !hierarchy_first(faces, opts);
    let mut attempts: Vec<Option<CoarseToFine>> = Vec::new();
    attempts.push((!direct_first).then(|| c2f.clone()));
    if c2f.rescue && faces > c2f.max_faces {
        // Above `max_faces` the configured hierarchy is a rescue too: the 100×100 saddle's
        // direct solve stalls on ~1 in 6 inputs within one ulp of the grid, and that
        // hierarchy converges them (docs/algorithms/flattenable.md, "Large pieces rescued
        // by a hierarchy").
        attempts.push(Some(c2f.clone()));
    }
    if c2f.rescue {
        for prolongation in RESCUE_PROLONGATIONS {
            let h = CoarseToFine {
                min_faces: RESCUE_MIN_FACES,
                levels: RESCUE_LEVELS,
                prolongation,
                ..c2f.clone()
            };
            let same = |o: &CoarseToFine| {
                (o.min_faces, o.levels, o.prolongation) == (h.min_faces, h.levels, h.prolongation)
            };
            if !attempts.iter().flatten().any(same) {
                attempts.push(Some(h));
            }
        }
    }
    if !direct_first {
        attempts.push(None);
    }
    let mut tally = Tally::default();
    // Hierarchies abandoned at a coarse level or whose fine level failed (`Seen`).
    let mut seen = Seen::default();
    // The best state of a fine level cut by its budget near θ = 2π (its merit).
    let mut crawler: Option<(f64, Vec<[f64; 3]>)> = None;
    let merit = |p: &[[f64; 3]]| merit_at(piece, p);
    // The shaped rescue hierarchy, tried after a hand-over or after the other attempts.
    let shaped = |chain: &mut Chain, tally: &mut Tally, report: &mut PieceReport| {
        shaped_rescue((piece, local, w_local), chain, opts, &merit, tally, report)
    };
    // The lowest θ_err any attempt reached.
    let mut nearest = f64::INFINITY;
    let mut pending: VecDeque<Option<CoarseToFine>> = attempts.into();
    let mut tried = 0usize;
    // Whether the shaped rescue hierarchy has run (it runs at most once).
    let mut shaped_tried = false;
    while let Some(attempt) = pending.pop_front() {
        let k = tried;
        tried += 1;
        let mut rep = fresh(report);
        let what = if k == 0 {
            "coarse-to-fine"
        } else {
            "rescue coarse-to-fine"
        };
        // Whether this attempt was a fine level cut by its budget near θ = 2π.
        let mut crawled = false;
        // Whether this attempt was the direct solve and handed the piece over.
        let mut handed_over = false;
        let out = match &attempt {
            None => {
                if k > 0 {
                    tally.notes.push("solved again from the input".into());
                }
                // Above `max_faces` (measured there; below `min_faces` a stalled direct
                // solve costs little).
                let outcome = if faces > c2f.max_faces && pending.iter().any(Option::is_some) {
                    robust::run_before_hierarchy(piece, opts, &mut rep)
                } else {
                    robust::run(piece, opts, &mut rep)
                };
                handed_over = outcome.handed_over;
                outcome.positions
            }
            Some(h) => match pass(
                (piece, local, w_local),
                chain,
                opts,
                h,
                what,
                &mut seen,
                &mut rep,
            )? {
                Pass::NoLevels if k == 0 => {
                    return Ok(robust::run(piece, opts, report).positions);
                }
                Pass::NoLevels => continue,
                Pass::Repeated(summary) => {
                    tally.notes.push(format!(
                        "{what} not run: the same levels and prolongation as an earlier attempt ({summary})"
                    ));
                    continue;
                }
                Pass::Abandoned(summary) => {
                    tally.notes.push(format!(
                        "{what} abandoned ({summary}): a coarse level did not reach {:.0e} rad",
                        opts.tolerance_rad.max(c2f.coarse_tolerance_rad)
                    ));
                    tally.count(&rep);
                    continue;
                }
                Pass::Fine(out) => {
                    // A fine level that got near θ = 2π and crawled there until its budget
                    // ran out: that is its prolongated start's end phase, not the piece's
                    // shape, so the direct solve comes next, before any deeper hierarchy
                    // (one that ends far away, like the saddle-like shoulder's, goes on down
                    // the hierarchies, which is what converges it).
                    let near = !rep.converged && best_reached(&rep, true) <= CRAWL_AT_RAD;
                    if near
                        && let Some(i) = pending.iter().position(Option::is_none)
                        && let Some(direct) = pending.remove(i)
                    {
                        pending.push_front(direct);
                    }
                    crawled = near && rep.iterations >= FINE_LEVEL_BUDGET;
                    out
                }
            },
        };
        if rep.converged {
            *report = tally.converged(rep);
            return Ok(out);
        }
        nearest = nearest.min(best_reached(&rep, attempt.is_some()));
        tally.notes.push(match attempt {
            None => format!(
                "the direct solve did not converge (best θ_err {:.1e} in {} iterations{})",
                best_reached(&rep, false),
                rep.iterations,
                if handed_over {
                    "; handed over under heavy damping"
                } else {
                    ""
                }
            ),
            Some(_) => format!(
                "{what} did not converge (best θ_err {:.1e} in {} iterations)",
                best_reached(&rep, true),
                rep.iterations
            ),
        });
        let m = merit(&out);
        if crawled && crawler.as_ref().is_none_or(|(b, _)| m < *b) {
            crawler = Some((m, out.clone()));
        }
        tally.consider(m, out, rep);
        // A hand-over is a large piece stuck far from θ = 2π under heavy damping: a broad,
        // smooth deficit, which the shaped damping moves and the identity damping holds back
        // with the rough modes. Its hierarchy first: the 85k upper back and the 37k thigh
        // converge there 2.2× / 2.1× sooner than through the identity hierarchies
        // (docs/algorithms/flattenable.md, "A damping shaped like the graph Laplacian").
        if handed_over && shaped_allowed(opts) && !shaped_tried {
            shaped_tried = true;
            if let Some(out) = shaped(chain, &mut tally, report)? {
                return Ok(out);
            }
        }
    }
    // The shaped damping first, then the crawling fine level's continuation: on the 85k upper
    // back the continuation ran 388 iterations (~60 s) without converging before the shaped
    // rescue converged it; on the scan's leg at 10 mm, which the continuation converged, the
    // shaped rescue converges it too, nearer the input (docs/algorithms/flattenable.md, "A
    // damping shaped like the graph Laplacian").
    if !shaped_tried
        && shaped_allowed(opts)
        && nearest <= SHAPED_RESCUE_AT_RAD
        && let Some(out) = shaped(chain, &mut tally, report)?
    {
        return Ok(out);
    }
    // Every attempt failed, the shaped one too. A fine level cut by its budget near θ = 2π was still converging:
    // the budget is there so that the direct solve, faster where a cap's fine level crawls,
    // runs first; when the direct solve and the deeper hierarchies did not converge either
    // (rough scan pieces), that fine level's best state goes on, once, without a budget.
    if let Some((_, start)) = crawler {
        let mut rep = fresh(report);
        push_input_theta_err(piece, &mut rep);
        let out = robust::run_from(piece, &start, opts, None, &mut rep).positions;
        let summary = format!(
            "a fine level cut by its budget near θ = 2π went on from its best state (θ_err {:.1e}) without a budget: {} in {} iterations",
            rep.theta_err.get(1).copied().unwrap_or(f64::NAN),
            if rep.converged {
                "converged".to_string()
            } else {
                format!("best θ_err {:.1e}", best_reached(&rep, true))
            },
            rep.iterations
        );
        tally.notes.push(summary);
        if rep.converged {
            *report = tally.converged(rep);
            return Ok(out);
        }
        // Kept only if nearer θ = 2π than every attempt (its start was one of them).
        tally.consider(merit(&out), out, rep);
    }
    // Last, on a rough piece, the direct solve under the shaped damping (`shaped_direct`).
    if shaped_direct_applies(piece, opts)
        && let Some(out) = shaped_direct(piece, opts, &merit, &mut tally, report)
    {
        return Ok(out);
    }
    let Some((out, kept)) = tally.best() else {
        // Every hierarchy was abandoned and the direct solve already ran first: impossible
        // (the direct solve always leaves a best state), but answer with a plain run.
        return Ok(robust::run(piece, opts, report).positions);
    };
    *report = kept;
    Ok(out)
}

/// ‖θ − 2π‖² of `piece` at `positions`: what the attempts are compared by.
fn merit_at(piece: &Piece, positions: &[[f64; 3]]) -> f64 {
    let mut theta = vec![0.0; piece.layout.n()];
    piece.layout.theta(positions, &mut theta);
    Piece::errors(&theta).1
}

/// A piece the hierarchies do not apply to (`applies`): the direct solve, then on a rough
/// piece, if it did not converge, the direct solve under the shaped damping
/// ([`shaped_direct`]; the rough 12×12 grid of `tests/process.rs` converges so in 17
/// iterations where the direct solve stalls at 6.3e-2). A piece that converges, or is not
/// rough, gets the direct solve alone, as before.
pub fn run_direct(piece: &Piece, opts: &ProcessOptions, report: &mut PieceReport) -> Vec<[f64; 3]> {
    let start = report.clone();
    let out = robust::run(piece, opts, report).positions;
    if report.converged || !shaped_direct_applies(piece, opts) {
        return out;
    }
    let merit = |p: &[[f64; 3]]| merit_at(piece, p);
    let mut tally = Tally::default();
    let direct = std::mem::replace(report, start);
    tally.notes.push(format!(
        "the direct solve did not converge (best θ_err {:.1e} in {} iterations)",
        best_reached(&direct, false),
        direct.iterations
    ));
    tally.consider(merit(&out), out, direct);
    if let Some(out) = shaped_direct(piece, opts, &merit, &mut tally, report) {
        return out;
    }
    let (out, kept) = tally
        .best()
        .unwrap_or_else(|| unreachable!("the direct solve was considered"));
    *report = kept;
    out
}

/// Whether [`shaped_direct`] runs for `piece` under `opts`: with the rescue on, the shaped
/// damping not the run's own already, and a rough piece (`piece::rough_median`).
fn shaped_direct_applies(piece: &Piece, opts: &ProcessOptions) -> bool {
    shaped_allowed(opts) && rough_median(&piece.input_theta()).is_some()
}

/// The last attempt on a rough piece (scan noise, `piece::rough_median`) whose other attempts
/// all failed: the direct solve from the input under `Damping::GraphLaplacian`. Where the
/// identity damping's attempts and the shaped hierarchy stall (the 10 mm scan wetsuit's
/// front-right leg at 7e-4–1.6e-2 on scans perturbed by 1e-12), it converges. It runs only
/// after every other attempt has failed, so a piece that converges keeps its path bit for
/// bit; on smooth pieces that fail it was measured no better (the real meshes, the body
/// patches) and costs a direct solve (docs/algorithms/flattenable.md, "Rough scan pieces: the
/// shaped direct solve"). For the pieces of [`shaped_direct_applies`]. Its positions when it
/// converges (`report` then set), else `None` (the attempt considered in `tally`).
fn shaped_direct(
    piece: &Piece,
    opts: &ProcessOptions,
    merit: &dyn Fn(&[[f64; 3]]) -> f64,
    tally: &mut Tally,
    report: &mut PieceReport,
) -> Option<Vec<[f64; 3]>> {
    let shaped = ProcessOptions {
        damping: Damping::GraphLaplacian,
        ..opts.clone()
    };
    tally
        .notes
        .push("solved again from the input with graph-Laplacian damping".into());
    let mut rep = fresh(report);
    let out = robust::run(piece, &shaped, &mut rep).positions;
    if rep.converged {
        *report = std::mem::take(tally).converged(rep);
        return Some(out);
    }
    tally.notes.push(format!(
        "the direct solve with graph-Laplacian damping did not converge (best θ_err {:.1e} in {} iterations)",
        best_reached(&rep, false),
        rep.iterations
    ));
    tally.consider(merit(&out), out, rep);
    None
}

/// Whether [`shaped_rescue`] may run under `opts`: with the rescue on, and not when the
/// shaped damping is the run's own already.
fn shaped_allowed(opts: &ProcessOptions) -> bool {
    opts.coarse_to_fine.rescue && opts.damping == Damping::Identity
}

/// After a hand-over, or after the other attempts for a piece that got within
/// [`SHAPED_RESCUE_AT_RAD`] of θ = 2π: the deeper hierarchy with the damping shaped like the graph Laplacian, which damps the smooth
/// part of the residual less than the rough part (what such a piece has left after the other
/// attempts is a broad, smooth deficit that the identity damping takes away together with
/// the rough modes it must hold back). Its positions when it converges (`report` then set),
/// else `None` (the attempt considered in `tally`).
fn shaped_rescue(
    (piece, local, w_local): (&Piece, &TriMesh, &[f64]),
    chain: &mut Chain,
    opts: &ProcessOptions,
    merit: &dyn Fn(&[[f64; 3]]) -> f64,
    tally: &mut Tally,
    report: &mut PieceReport,
) -> Result<Option<Vec<[f64; 3]>>, FlattenableError> {
    let c2f = &opts.coarse_to_fine;
    let shaped = ProcessOptions {
        damping: Damping::GraphLaplacian,
        ..opts.clone()
    };
    let h = CoarseToFine {
        min_faces: RESCUE_MIN_FACES,
        levels: RESCUE_LEVELS,
        prolongation: RESCUE_PROLONGATIONS[0],
        ..c2f.clone()
    };
    let what = "rescue coarse-to-fine with graph-Laplacian damping";
    let mut rep = fresh(report);
    // Its levels are solved under the other damping: nothing the other attempts did is known.
    match pass(
        (piece, local, w_local),
        chain,
        &shaped,
        &h,
        what,
        &mut Seen::default(),
        &mut rep,
    )? {
        Pass::NoLevels | Pass::Repeated(_) => {}
        Pass::Abandoned(summary) => {
            tally.notes.push(format!(
                "{what} abandoned ({summary}): a coarse level did not reach {:.0e} rad",
                opts.tolerance_rad.max(c2f.coarse_tolerance_rad)
            ));
            tally.count(&rep);
        }
        Pass::Fine(out) => {
            if rep.converged {
                *report = std::mem::take(tally).converged(rep);
                return Ok(Some(out));
            }
            tally.notes.push(format!(
                "{what} did not converge (best θ_err {:.1e} in {} iterations)",
                best_reached(&rep, true),
                rep.iterations
            ));
            tally.consider(merit(&out), out, rep);
        }
    }
    Ok(None)
}

/// The attempts of [`run`] so far: the best unconverged one (its merit ‖θ − 2π‖², positions
/// and report), the work of the others, and the notes for the final report.
#[derive(Default)]
struct Tally {
    notes: Vec<String>,
    best: Option<(f64, Vec<[f64; 3]>, PieceReport)>,
    rejected: usize,
    factorizations: usize,
    corrections: usize,
    smoothed_steps: usize,
}

impl Tally {
    /// Counts the work of an attempt that is not kept.
    fn count(&mut self, rep: &PieceReport) {
        self.rejected += rep.rejected_steps;
        self.factorizations += rep.factorizations;
        self.corrections += rep.corrections;
        self.smoothed_steps += rep.smoothed_steps;
    }

    /// Keeps an unconverged attempt if its merit `m` is the lowest so far.
    fn consider(&mut self, m: f64, out: Vec<[f64; 3]>, rep: PieceReport) {
        if self.best.as_ref().is_none_or(|(b, _, _)| m < *b) {
            if let Some((_, _, old)) = self.best.take() {
                self.count(&old);
            }
            self.best = Some((m, out, rep));
        } else {
            self.count(&rep);
        }
    }

    /// The report of `rep`, which converged, with the notes and the work of every earlier
    /// attempt (the best unconverged one's too).
    fn converged(mut self, rep: PieceReport) -> PieceReport {
        if let Some((_, _, old)) = self.best.take() {
            self.count(&old);
        }
        self.finish(rep)
    }

    /// The best unconverged attempt's positions and report, with the notes and the others'
    /// work.
    fn best(mut self) -> Option<(Vec<[f64; 3]>, PieceReport)> {
        let (_, out, kept) = self.best.take()?;
        Some((out, self.finish(kept)))
    }

    fn finish(mut self, mut rep: PieceReport) -> PieceReport {
        self.notes.append(&mut rep.messages);
        rep.messages = self.notes;
        rep.rejected_steps += self.rejected;
        rep.factorizations += self.factorizations;
        rep.corrections += self.corrections;
        rep.smoothed_steps += self.smoothed_steps;
        rep
    }
}

/// The lowest θ_err an attempt reached. For a hierarchy `theta_err[0]` is the piece's input,
/// which its fine level starts away from (at the prolongated start, `theta_err[1]`) and does
/// not return to, so it does not count.
fn best_reached(rep: &PieceReport, hierarchy: bool) -> f64 {
    rep.theta_err
        .iter()
        .skip(usize::from(hierarchy))
        .fold(f64::INFINITY, |m, &e| m.min(e))
}

/// A fine level's report starts with the input's θ_err, then its run pushes its start's.
fn push_input_theta_err(piece: &Piece, report: &mut PieceReport) {
    report.theta_err.push(Piece::errors(&piece.input_theta()).0);
}

/// A report for a new attempt: the piece's fields kept, the run's fields reset.
fn fresh(report: &PieceReport) -> PieceReport {
    PieceReport {
        iterations: 0,
        converged: false,
        theta_err: Vec::new(),
        rejected_steps: 0,
        backtracked_steps: 0,
        corrections: 0,
        smoothed_steps: 0,
        pull_backs: 0,
        factorizations: 0,
        stop_reason: String::new(),
        messages: Vec::new(),
        ..report.clone()
    }
}

/// How one pass through a hierarchy ended.
enum Pass {
    /// No coarser level could be made.
    NoLevels,
    /// A coarse level did not reach [`CoarseToFine::coarse_tolerance_rad`] (its levels'
    /// summary).
    Abandoned(String),
    /// The fine level ran from the prolongated start; the report says whether it converged.
    Fine(Vec<[f64; 3]>),
    /// The same levels and prolongation as a hierarchy whose fine level already ran and did not
    /// converge (its summary): not run again.
    Repeated(String),
}

/// The hierarchies of one piece's attempts so far, by their levels' face counts. The
/// coarsening is deterministic and each level is made from the one above with the same
/// ratio, so equal face counts are equal levels: a hierarchy with different parameters
/// (`min_faces`, `levels`) can still build the same ones (the 85k upper back's configured
/// hierarchy and its displacement rescue hierarchy both stop at 1 664 faces) and would
/// repeat their solves and their result.
#[derive(Default)]
struct Seen {
    /// Abandoned at a coarse level: the face counts from the coarsest level to that one, the
    /// prolongation (`None` at the coarsest level, which is solved from its own input
    /// whatever the prolongation), summary. Any hierarchy that starts with those levels
    /// solves them the same way and is abandoned there too (the 88k shoulder's configured
    /// and displacement rescue hierarchies each spent 276 iterations on their 5.5k level).
    abandoned: Vec<(Vec<usize>, Option<Prolongation>, String)>,
    /// Their fine level ran and did not converge (prolongation, summary).
    finished: Vec<(Vec<usize>, Prolongation, String)>,
}

/// One pass: the hierarchy `c2f` (its levels taken from `chain`, made there when missing),
/// solved coarsest first, the fine level run from its prolongation into `report` (its
/// message starts with `label`). Hierarchies in `seen` are not solved again; this one is
/// added to it.
#[allow(clippy::too_many_arguments)]
fn pass(
    (piece, local, w_local): (&Piece, &TriMesh, &[f64]),
    chain: &mut Chain,
    opts: &ProcessOptions,
    c2f: &CoarseToFine,
    label: &str,
    seen: &mut Seen,
    report: &mut PieceReport,
) -> Result<Pass, FlattenableError> {
    // The levels are those of one ratio: a hierarchy with another (none is made so) starts
    // the chain again.
    if chain.ratio != c2f.ratio {
        *chain = Chain::with_ratio(c2f.ratio);
    }
    // The levels below the piece this hierarchy takes: levels[k] maps level k (k = 0 the
    // piece) to level k + 1.
    let mut depth = 0;
    loop {
        let faces = match depth {
            0 => local.face_count(),
            d => chain.levels[d - 1].0.mesh.face_count(),
        };
        if depth >= c2f.levels || faces < c2f.min_faces {
            break;
        }
        if chain.levels.len() == depth && !chain.extend(local, &piece.topo)? {
            break;
        }
        depth += 1;
    }
    let levels: Vec<&Coarsened> = chain.levels[..depth].iter().map(|(c, _)| c).collect();
    let mut weights: Vec<Vec<f64>> = vec![w_local.to_vec()];
    for c in &levels {
        let w = weights.last().map_or_else(Vec::new, |w| {
            c.fine_of_coarse.iter().map(|&v| w[v as usize]).collect()
        });
        weights.push(w);
    }
    // The topology of each coarse level, for its piece.
    let topos: Vec<Topology> = chain.levels[..depth]
        .iter()
        .map(|(_, t)| t.clone())
        .collect();
    if levels.is_empty() {
        return Ok(Pass::NoLevels);
    }
    let coarse_opts = ProcessOptions {
        tolerance_rad: opts.tolerance_rad.max(c2f.coarse_tolerance_rad),
        ..opts.clone()
    };
    // A hierarchy whose coarsest levels are those of one already abandoned (same face
    // counts: the coarsening is deterministic; the same prolongation, except at the coarsest
    // level, which starts from its own input) would repeat those solves and that failure.
    let key: Vec<usize> = levels.iter().map(|l| l.mesh.face_count()).collect();
    let coarsest_first: Vec<usize> = key.iter().rev().copied().collect();
    if let Some((_, _, summary)) = seen.abandoned.iter().find(|(solved, how, _)| {
        coarsest_first.starts_with(solved) && how.is_none_or(|h| h == c2f.prolongation)
    }) {
        return Ok(Pass::Abandoned(format!(
            "{summary}; the same levels as an earlier attempt, not solved again"
        )));
    }
    if let Some((_, _, summary)) = seen
        .finished
        .iter()
        .find(|(k, how, _)| *k == key && *how == c2f.prolongation)
    {
        return Ok(Pass::Repeated(summary.clone()));
    }
    // Solve from the coarsest level up to level 1.
    let mut solution: Option<Vec<[f64; 3]>> = None;
    let mut summary = Vec::new();
    // Level k's topology is topos[k − 1]: taken coarsest first, each moved into its piece.
    for (k, topo) in (1..=levels.len()).rev().zip(topos.into_iter().rev()) {
        let mesh = &levels[k - 1].mesh;
        let n = mesh.vertex_count();
        let lp = Piece::new(
            piece.index,
            (0..n as u32).collect(),
            mesh,
            topo,
            &weights[k],
            opts.min_angle_deg,
        )
        .map_err(|e| FlattenableError::Singular {
            piece: piece.index,
            iteration: 0,
            detail: format!("coarse level {k}: {e:?}"),
        })?;
        let mut rep = PieceReport::default();
        let pos = if lp.layout.n() == 0 {
            lp.pos0.clone()
        } else {
            let start = match &solution {
                None => lp.pos0.clone(),
                Some(coarser) => start_from(&lp, levels[k], coarser, c2f.prolongation),
            };
            robust::run_coarse_level(&lp, &start, &coarse_opts, &mut rep).positions
        };
        report.rejected_steps += rep.rejected_steps;
        report.factorizations += rep.factorizations;
        report.corrections += rep.corrections;
        report.smoothed_steps += rep.smoothed_steps;
        let mut theta = vec![0.0; lp.layout.n()];
        lp.layout.theta(&pos, &mut theta);
        let err = Piece::errors(&theta).0;
        summary.push(format!(
            "level {k}: {} faces, {} iterations (+{} rejected), θ_err {err:.1e}",
            mesh.face_count(),
            rep.iterations,
            rep.rejected_steps,
        ));
        if err > coarse_opts.tolerance_rad {
            // A coarse level that does not become flattenable gives a start that is not
            // near the fine solution (measured: the 100×100 saddle's coarse level stalls at
            // 1e-3 and the fine level from its prolongation stalls at 2e-4, while the fine
            // level from its input converges).
            let how = (k < levels.len()).then_some(c2f.prolongation);
            seen.abandoned.push((
                coarsest_first[..=levels.len() - k].to_vec(),
                how,
                summary.join("; "),
            ));
            return Ok(Pass::Abandoned(summary.join("; ")));
        }
        solution = Some(pos);
    }
    let coarse = solution.unwrap_or_else(|| levels[0].mesh.positions.clone());
    let start = start_from(piece, levels[0], &coarse, c2f.prolongation);
    push_input_theta_err(piece, report);
    let coarse_rejected = report.rejected_steps;
    report.rejected_steps = 0;
    let out = robust::run_from(piece, &start, opts, Some(FINE_LEVEL_BUDGET), report).positions;
    report.iterations += 1;
    report.messages.insert(
        0,
        format!(
            "{label} ({:?} prolongation): {}; fine level ({} faces): {} iterations (+{} rejected)",
            c2f.prolongation,
            summary.join("; "),
            local.face_count(),
            report.iterations - 1,
            report.rejected_steps,
        ),
    );
    report.rejected_steps += coarse_rejected;
    if !report.converged {
        seen.finished
            .push((key, c2f.prolongation, summary.join("; ")));
    }
    Ok(Pass::Fine(out))
}

/// The start of a finer level from the solution `coarse` of the level below: prolongated,
/// boundary taken from the input bit for bit, and shortened towards the input (halving the
/// move) while it folds a face against the input; the input itself if nothing else is
/// unfolded.
fn start_from(
    piece: &Piece,
    map: &Coarsened,
    coarse: &[[f64; 3]],
    how: Prolongation,
) -> Vec<[f64; 3]> {
    let prolongated = match how {
        Prolongation::Positions => map.prolongate(coarse),
        Prolongation::Displacement => {
            let d: Vec<[f64; 3]> = coarse
                .iter()
                .zip(&map.mesh.positions)
                .map(|(v, v0)| sub(*v, *v0))
                .collect();
            map.prolongate(&d)
                .iter()
                .zip(&piece.pos0)
                .map(|(d, v0)| add(*v0, *d))
                .collect()
        }
    };
    let target = piece.interior_of(&prolongated);
    let base = piece.interior_of(&piece.pos0);
    let mut beta = 1.0;
    for _ in 0..=START_HALVINGS {
        let moved: Vec<[f64; 3]> = base
            .iter()
            .zip(&target)
            .map(|(a, b)| {
                [
                    a[0] + beta * (b[0] - a[0]),
                    a[1] + beta * (b[1] - a[1]),
                    a[2] + beta * (b[2] - a[2]),
                ]
            })
            .collect();
        let cand = piece.with_interior(&piece.pos0, &moved);
        if piece.folded_faces(&cand) == 0 {
            return cand;
        }
        beta *= 0.5;
    }
    piece.pos0.clone()
}

#[cfg(test)]
mod tests {
    use super::{Chain, hierarchy_first, run};
    use crate::options::ProcessOptions;
    use crate::piece::Piece;
    use crate::report::PieceReport;
    use flatcut_mesh::Topology;

    /// A 40×40 dome (3 042 faces, so its first attempt is the configured hierarchy): the
    /// chain made ahead (`Chain::first`, as `process` makes it beside the piece's set-up)
    /// and the one made on demand give the same run, bit for bit; and with the iterations
    /// cut to none, so that the configured hierarchy and the rescue ones all run, the
    /// chain ends with the deepest hierarchy's levels, each level made once and shared.
    #[test]
    fn a_chain_made_ahead_gives_the_run_of_one_made_on_demand() {
        let mesh = flatcut_mesh::shapes::grid_patch(40, 40, 1.0, |x, y| {
            (1.0 - 0.5 * (x * x + y * y)).sqrt()
        });
        let n = mesh.vertex_count();
        let weights = vec![1.0; n];
        let topo = Topology::build(&mesh).unwrap();
        let piece = Piece::new(0, (0..n as u32).collect(), &mesh, topo, &weights, 0.5).unwrap();
        let opts = ProcessOptions::default();
        assert!(hierarchy_first(mesh.face_count(), &opts));
        let solve = |chain: &mut Chain, opts: &ProcessOptions| {
            let mut report = PieceReport::default();
            let out = run((&piece, &mesh, &weights), chain, opts, &mut report).unwrap();
            (out, report)
        };
        let mut ahead = Chain::first(&mesh, &piece.topo, &opts).unwrap();
        assert_eq!(ahead.levels.len(), 1);
        let (a, ra) = solve(&mut ahead, &opts);
        let (b, rb) = solve(&mut Chain::new(&opts), &opts);
        assert!(ra.converged);
        assert_eq!(a, b);
        assert_eq!(
            (ra.iterations, ra.factorizations, &ra.messages),
            (rb.iterations, rb.factorizations, &rb.messages)
        );

        let none = ProcessOptions {
            max_iterations: Some(0),
            ..Default::default()
        };
        let mut shared = Chain::new(&none);
        let (_, report) = solve(&mut shared, &none);
        let hierarchies = report
            .messages
            .iter()
            .filter(|m| m.contains("coarse-to-fine"))
            .count();
        assert!(hierarchies >= 2, "{:?}", report.messages);
        // The deepest level any hierarchy reached, from their summaries ("level K: …").
        let deepest = report
            .messages
            .iter()
            .flat_map(|m| m.split("level ").skip(1))
            .filter_map(|s| s.split(':').next()?.trim().parse::<usize>().ok())
            .max()
            .unwrap();
        assert_eq!(shared.levels.len(), deepest, "{:?}", report.messages);
    }
}
