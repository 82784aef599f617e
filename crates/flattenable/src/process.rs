//! [`process`]: split the mesh into connected components, check each, run the chosen mode
//! on each in parallel, and put the results back together.

use std::time::Instant;

use flatcut_mesh::geometry::{face_areas, is_degenerate_face, loop_length};
use flatcut_mesh::{FaceId, Topology, TriMesh, VertexId};
use rayon::prelude::*;

use crate::coarse_to_fine::Chain;
use crate::hole_closure::{HoleClosure, Holes, least_closed};
use crate::hole_fill::{HoleFill, filled};
use crate::piece::{CREASE_NOTE, Piece, rough_median};
use crate::report::{PieceReport, ProcessReport};
use crate::{
    FlattenableError, HoleRims, Mode, ProcessOptions, Target, Update, coarse_to_fine, paper,
    pull_back,
};

/// The result of [`process`]: the mesh with new positions (same connectivity, attributes
/// and labels) and the report.
#[derive(Clone)]
pub struct Processed {
    /// Same faces as the input; interior vertices moved, everything else bit-identical.
    pub mesh: TriMesh,
    /// What happened, per piece and overall.
    pub report: ProcessReport,
}

impl std::fmt::Debug for Processed {
    // A summary: the positions of a 100k-vertex mesh do not belong in an error message.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Processed")
            .field("vertices", &self.mesh.vertex_count())
            .field("faces", &self.mesh.face_count())
            .field("converged", &self.report.converged)
            .field("final_theta_err", &self.report.final_theta_err)
            .field("iterations", &self.report.iterations)
            .finish_non_exhaustive()
    }
}

/// Makes every piece of `mesh` flattenable (θ = 2π at every interior vertex), moving the
/// interior vertices as little as possible; boundary vertices never move (but for the rims
/// of holes under `HoleRims::Free`).
///
/// Preconditions checked here (errors name the element, in input ids): finite positions,
/// indices in range, every piece open (a boundary loop), edge- and vertex-manifold,
/// consistently oriented, no degenerate face, interior valence ≥ 3. Pieces with holes keep
/// every loop fixed (`HoleRims::Fixed`), and then θ = 2π does not close a hole on a curved
/// piece: the report measures each hole and says which stay open; `HoleRims::Free` lets the
/// rims move so that they close. A piece without interior vertex comes back unchanged, with
/// a message in its report.
///
/// Errors: the checks above; paper mode's singular or diverged iterations
/// ([`FlattenableError::Singular`], [`FlattenableError::Diverged`]); robust mode's
/// [`FlattenableError::NotConverged`], which carries the whole result at the best unfolded
/// state of every piece.
pub fn process(mesh: &TriMesh, opts: &ProcessOptions) -> Result<Processed, FlattenableError> {
    let start = Instant::now();
    mesh.validate()?;
    check_options(mesh, opts)?;
    let topo = Topology::build(mesh)?;
    let comps = topo.component_count();
    check_topology(mesh, &topo)?;

    // Faces and vertices of each component.
    let mut comp_faces: Vec<Vec<u32>> = vec![Vec::new(); comps];
    for (f, &c) in topo.face_components().iter().enumerate() {
        comp_faces[c as usize].push(f as u32);
    }
    let weights = vertex_weights(mesh, &topo, opts);
    let outcomes: Vec<Result<PieceOutcome, FlattenableError>> = comp_faces
        .par_iter()
        .enumerate()
        .map(|(ci, faces)| run_piece_with_rims(mesh, ci, faces, &weights, opts))
        .collect();

    let mut out = mesh.clone();
    let mut pieces = Vec::with_capacity(comps);
    for o in outcomes {
        let (pos, map, rep) = o?;
        for (local, &global) in map.iter().enumerate() {
            out.positions[global as usize] = pos[local];
        }
        pieces.push(rep);
    }
    let report = summarise(mesh, &out, opts, pieces, start.elapsed().as_secs_f64());
    let result = Processed { mesh: out, report };
    if opts.mode == Mode::Robust
        && let Some(p) = result.report.pieces.iter().find(|p| !p.converged)
    {
        return Err(FlattenableError::NotConverged {
            piece: p.piece,
            best_theta_err: p.final_theta_err,
            best_theta_rms: p.final_theta_rms,
            input_theta_err: p.theta_err.first().copied().unwrap_or(p.final_theta_err),
            input_theta_rms: p.input_theta_rms,
            tolerance: opts.tolerance_rad,
            iterations: p.iterations,
            reason: p.stop_reason.clone(),
            partial: Box::new(result),
        });
    }
    Ok(result)
}

fn check_options(mesh: &TriMesh, opts: &ProcessOptions) -> Result<(), FlattenableError> {
    let bad = |name, reason: String| Err(FlattenableError::InvalidOption { name, reason });
    if let Some(w) = &opts.weights {
        if w.len() != mesh.vertex_count() {
            return bad(
                "weights",
                format!("{} weights for {} vertices", w.len(), mesh.vertex_count()),
            );
        }
        if let Some((i, v)) = w
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v > 0.0))
        {
            return bad(
                "weights",
                format!("vertex {i} has weight {v}; weights must be finite and > 0"),
            );
        }
    }
    for (name, v) in [
        ("boundary_ring_weight", opts.boundary_ring_weight),
        ("feature_weight", opts.feature_weight),
        ("tolerance_rad", opts.tolerance_rad),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return bad(name, format!("{v} must be finite and > 0"));
        }
    }
    if !(opts.tangential_penalty.is_finite() && opts.tangential_penalty >= 1.0) {
        return bad(
            "tangential_penalty",
            format!("{} must be ≥ 1", opts.tangential_penalty),
        );
    }
    let c2f = &opts.coarse_to_fine;
    if c2f.levels > 0 && !(c2f.ratio.is_finite() && c2f.ratio > 1.0) {
        return bad(
            "coarse_to_fine.ratio",
            format!("{} must be finite and > 1", c2f.ratio),
        );
    }
    if c2f.levels > 0 && !(c2f.coarse_tolerance_rad.is_finite() && c2f.coarse_tolerance_rad > 0.0) {
        return bad(
            "coarse_to_fine.coarse_tolerance_rad",
            format!("{} must be finite and > 0", c2f.coarse_tolerance_rad),
        );
    }
    if !(0.0..60.0).contains(&opts.min_angle_deg) {
        return bad(
            "min_angle_deg",
            format!("{} must be in [0, 60)", opts.min_angle_deg),
        );
    }
    for (c, curve) in opts.feature_curves.iter().enumerate() {
        if let Some(v) = curve.iter().find(|&&v| v as usize >= mesh.vertex_count()) {
            return bad(
                "feature_curves",
                format!("curve {c} names vertex {v}, which does not exist"),
            );
        }
    }
    Ok(())
}

fn check_topology(mesh: &TriMesh, topo: &Topology) -> Result<(), FlattenableError> {
    let vc = topo.vertex_components();
    if let Some([a, b]) = topo.non_manifold_edges().first().copied() {
        return Err(FlattenableError::NonManifoldEdge {
            piece: vc[a as usize] as usize,
            a,
            b,
        });
    }
    if let Some(v) = topo.non_manifold_vertices().first().copied() {
        return Err(FlattenableError::NonManifoldVertex {
            piece: vc[v.idx()] as usize,
            vertex: v,
        });
    }
    if let Some([a, b]) = topo.inconsistent_edges().first().copied() {
        return Err(FlattenableError::InconsistentOrientation {
            piece: vc[a as usize] as usize,
            a,
            b,
        });
    }
    let summaries = topo.component_summaries();
    if let Some(c) = summaries.iter().position(|s| s.closed) {
        return Err(FlattenableError::ClosedPiece { piece: c });
    }
    let fc = topo.face_components();
    check_extents(mesh, fc, summaries.len())?;
    let diag = mesh.diagonal();
    for (f, face) in mesh.faces.iter().enumerate() {
        if is_degenerate_face(*face, mesh.triangle(FaceId(f as u32)), diag) {
            return Err(FlattenableError::DegenerateFace {
                piece: fc[f] as usize,
                face: FaceId(f as u32),
            });
        }
    }
    for v in 0..mesh.vertex_count() as u32 {
        let v = VertexId(v);
        if topo.is_interior_vertex(v) {
            let valence = topo.one_ring(v).map_or(0, <[u32]>::len);
            if valence < 3 {
                return Err(FlattenableError::LowValence {
                    piece: vc[v.idx()] as usize,
                    vertex: v,
                    valence,
                });
            }
        }
    }
    Ok(())
}

/// The extents (bounding-box diagonals, in the mesh's units) a piece may have. Measured on a
/// 37-vertex disk: scaled by a power of two it gives its result scaled, bit for bit, from
/// 2^-200 to 2^200 (6e-61 to 2e60); at 2^300 its angles overflowed to π and the run reported
/// θ_err 3.1 without a word on why, at 2^-300 its areas underflowed to zero and it was refused
/// as degenerate, and a 1e300-wide cone came back "already flattenable", its angles NaN. The
/// bounds sit ~1e10 inside the measured ones, for pieces whose edges are far shorter than
/// their extent (a million faces: ~1e-3 of it). Real pieces span 1e-1 to 1e5 mm.
const EXTENT_RANGE: (f64, f64) = (1e-50, 1e50);

/// Every piece's extent within [`EXTENT_RANGE`].
fn check_extents(
    mesh: &TriMesh,
    face_components: &[u32],
    pieces: usize,
) -> Result<(), FlattenableError> {
    let (min, max) = EXTENT_RANGE;
    let extents = flatcut_mesh::geometry::component_extents(mesh, face_components, pieces);
    match extents.iter().position(|e| !(min..=max).contains(e)) {
        Some(piece) => Err(FlattenableError::ExtentOutOfRange {
            piece,
            extent: extents[piece],
            min,
            max,
        }),
        None => Ok(()),
    }
}

/// w per input vertex: caller's weight × boundary-ring weight × feature weight.
fn vertex_weights(mesh: &TriMesh, topo: &Topology, opts: &ProcessOptions) -> Vec<f64> {
    let mut w = opts
        .weights
        .clone()
        .unwrap_or_else(|| vec![1.0; mesh.vertex_count()]);
    if opts.boundary_ring_weight != 1.0 {
        for (v, wv) in w.iter_mut().enumerate() {
            let v = VertexId(v as u32);
            if topo.is_interior_vertex(v)
                && topo
                    .one_ring(v)
                    .is_some_and(|r| r.iter().any(|&q| topo.is_boundary_vertex(VertexId(q))))
            {
                *wv *= opts.boundary_ring_weight;
            }
        }
    }
    let mut on_feature = vec![false; mesh.vertex_count()];
    for curve in &opts.feature_curves {
        for &v in curve {
            on_feature[v as usize] = true;
        }
    }
    for (wv, f) in w.iter_mut().zip(on_feature) {
        if f {
            *wv *= opts.feature_weight;
        }
    }
    w
}

/// Total angle defect (rad) above which a piece that does not converge is called cup-like
/// in its error: π is half a hemisphere's Gaussian curvature; the 60° cap, which
/// converges, carries about 1 rad.
const LARGE_TOTAL_DEFECT_RAD: f64 = std::f64::consts::PI;

/// Gaussian curvature a hole encloses (rad, its development's turning residual with the rims
/// fixed) above which a failed `HoleRims::Free` run is explained by it: a quarter of a
/// hemisphere's 2π. On 72 body patches with a hole every hole enclosing less closed with
/// free rims and none enclosing 1.8 rad or more did (docs/algorithms/flattenable.md, "Holes").
const LARGE_ENCLOSED_CURVATURE_RAD: f64 = std::f64::consts::FRAC_PI_2;

type PieceOutcome = (Vec<[f64; 3]>, Vec<u32>, PieceReport);

/// [`run_piece`], under `HoleRims::Free` on the piece with its holes filled
/// (`hole_fill::filled`: ears, then a fan), the fills then dropped and the result measured
/// on the piece itself (its θ, its holes, its displacement and folds).
fn run_piece_with_rims(
    mesh: &TriMesh,
    index: usize,
    faces: &[u32],
    weights: &[f64],
    opts: &ProcessOptions,
) -> Result<PieceOutcome, FlattenableError> {
    if opts.hole_rims == HoleRims::Fixed {
        return run_piece(mesh, index, faces, weights, opts);
    }
    let start = Instant::now();
    let (local, map) = flatcut_mesh::submesh(mesh, faces);
    let topo = Topology::build(&local)?;
    let holes = Holes::of(&topo, &local.positions);
    if holes.is_empty() {
        return run_piece(mesh, index, faces, weights, opts);
    }
    let w_local: Vec<f64> = map.iter().map(|&g| weights[g as usize]).collect();
    // Ears first (no vertex added; fewest iterations over the body patches measured), then
    // the fan where the ears' filled piece does not converge: each closes some holes the
    // other does not (docs/algorithms/flattenable.md, "Holes").
    let mut tried: Vec<(HoleFill, TriMesh, String)> = Vec::new();
    let mut done = None;
    for fill in [HoleFill::Ears, HoleFill::Fan] {
        let mesh_filled = filled(&local, &holes, fill);
        if tried.iter().any(|(_, m, _)| *m == mesh_filled) {
            continue;
        }
        let mut w_filled = w_local.clone();
        w_filled.resize(mesh_filled.vertex_count(), 1.0);
        let all: Vec<u32> = (0..mesh_filled.face_count() as u32).collect();
        match run_piece(&mesh_filled, index, &all, &w_filled, opts) {
            Ok(run) if run.2.converged => {
                done = Some((fill, run));
                break;
            }
            other => {
                let outcome = match &other {
                    Ok((_, _, run)) => {
                        format!("stopped at θ_err {:.1e} rad", run.final_theta_err)
                    }
                    Err(e) => format!("could not be processed ({e})"),
                };
                tried.push((fill, mesh_filled, outcome));
            }
        }
    }
    let fill_outcomes = tried
        .iter()
        .map(|(fill, _, outcome)| format!("by {}: {outcome}", fill_name(*fill)))
        .collect::<Vec<_>>()
        .join("; ");
    let Some((fill, (pos, filled_map, mut report))) = done else {
        // Filled, the piece did not become flat (or could not be processed): the run with
        // the rims fixed, which holds the boundary and meets θ = 2π more often
        // (docs/algorithms/flattenable.md, "Holes"), is the better result to return.
        let (positions, vertex_map, mut report) = run_piece(mesh, index, faces, weights, opts)?;
        // A hole over much curvature closes only if its rim moves far: the likely cause.
        let why = report
            .holes
            .iter()
            .filter(|h| h.turning_residual_rad.abs() > LARGE_ENCLOSED_CURVATURE_RAD)
            .max_by(|a, b| {
                a.turning_residual_rad
                    .abs()
                    .total_cmp(&b.turning_residual_rad.abs())
            })
            .map_or_else(String::new, |h| {
                format!(
                    "; its hole on boundary loop {} encloses {:.2} rad of Gaussian curvature, more than a quarter of a hemisphere's 2π, and such a hole closes only if its rim moves far: a seam from the hole to the outline (a `[[cut]]` line of a pipeline) is the cut that lets the piece flatten",
                    h.loop_index,
                    h.turning_residual_rad.abs()
                )
            });
        report.messages.push(format!(
            "hole rims free: the piece with its {} holes filled did not converge ({fill_outcomes}); the run with the rims fixed is returned{}{why}",
            holes.len(),
            if report.converged {
                " (θ = 2π, its holes as they stay)"
            } else {
                ""
            }
        ));
        report.seconds = start.elapsed().as_secs_f64();
        return Ok((positions, vertex_map, report));
    };
    let mut positions = local.positions.clone();
    for (p, &v) in pos.iter().zip(&filled_map) {
        if let Some(slot) = positions.get_mut(v as usize) {
            *slot = *p;
        }
    }
    let piece =
        Piece::new(index, map, &local, topo, &w_local, opts.min_angle_deg).map_err(|e| {
            FlattenableError::Singular {
                piece: index,
                iteration: 0,
                detail: format!("{e:?}"),
            }
        })?;
    let theta0 = piece.input_theta();
    // The filled copy's note on creases names its own vertices and counts the fill's edges:
    // the piece's own measure below writes the note again.
    report.messages.retain(|m| !m.starts_with(CREASE_NOTE));
    report.vertices = local.vertex_count();
    report.faces = local.face_count();
    report.interior_vertices = piece.layout.n();
    report.boundary_loops = piece.topo.boundary_loops().len();
    piece.measure(&positions, &theta0, &mut report);
    let rim_moved_mm = holes
        .rims()
        .flatten()
        .map(|v| flatcut_mesh::vec3::dist(positions[v.idx()], local.positions[v.idx()]))
        .fold(0.0, f64::max);
    // A rim's length is a seam's length when another piece is sewn into the hole.
    let rim_length_change_percent = holes
        .rims()
        .map(|rim| {
            let before = loop_length(&local.positions, rim);
            100.0 * (loop_length(&positions, rim) - before) / before
        })
        .fold(0.0f64, |m, c| if c.abs() > m.abs() { c } else { m });
    report.messages.push(format!(
        "hole rims free: {} holes filled by {} for the processing and the fills dropped{}; the rims moved by up to {rim_moved_mm:.4} mm and their lengths changed by up to {rim_length_change_percent:+.3} % (the outline is fixed; a piece sewn into a hole no longer matches its rim by that much)",
        holes.len(),
        fill_name(fill),
        if tried.is_empty() {
            String::new()
        } else {
            format!(" (filled {fill_outcomes})")
        }
    ));
    if report.converged && report.holes.iter().any(|h| !h.closes(opts.tolerance_rad)) {
        report.messages.push(holes_open(
            &report.holes,
            opts.tolerance_rad,
            opts.hole_rims,
        ));
    }
    report.seconds = start.elapsed().as_secs_f64();
    Ok((positions, piece.vertex_map, report))
}

/// A fill as the messages name it.
fn fill_name(fill: HoleFill) -> &'static str {
    match fill {
        HoleFill::Ears => "ears",
        HoleFill::Fan => "fans",
    }
}

fn run_piece(
    mesh: &TriMesh,
    index: usize,
    faces: &[u32],
    weights: &[f64],
    opts: &ProcessOptions,
) -> Result<PieceOutcome, FlattenableError> {
    let start = Instant::now();
    // Local numbering in order of first use, so the piece is the same whatever the rest.
    let (local, map) = flatcut_mesh::submesh(mesh, faces);
    let topo = Topology::build(&local)?;
    let w_local: Vec<f64> = map.iter().map(|&g| weights[g as usize]).collect();
    let new_piece = |topo: Topology| {
        Piece::new(index, map, &local, topo, &w_local, opts.min_angle_deg).map_err(|e| {
            FlattenableError::Singular {
                piece: index,
                iteration: 0,
                detail: format!("{e:?}"),
            }
        })
    };
    // A piece whose first attempt is a hierarchy has its first coarse level made beside its
    // own set-up (the symbolic factorisation and the rest of `Piece::new`), on the other core
    // when that is free: the same levels, only sooner. A failed coarsening is left to the
    // hierarchy to meet again, where it did before. (A piece found already flattenable below
    // does not use it: one coarsening made for nothing, ~2 ms at 3.5k faces.)
    let robust_hierarchy =
        opts.mode == Mode::Robust && coarse_to_fine::hierarchy_first(local.face_count(), opts);
    let (piece, chain) = if robust_hierarchy {
        let (piece, chain) = beside(
            || new_piece(topo.clone()),
            || Chain::first(&local, &topo, opts),
        );
        (
            piece?,
            chain
                .and_then(Result::ok)
                .unwrap_or_else(|| Chain::new(opts)),
        )
    } else {
        (new_piece(topo)?, Chain::new(opts))
    };
    let mut report = PieceReport {
        piece: index,
        vertices: local.vertex_count(),
        faces: local.face_count(),
        interior_vertices: piece.layout.n(),
        boundary_loops: piece.topo.boundary_loops().len(),
        ..Default::default()
    };
    // θ of the input, once: the already-flattenable test, the report and the roughness
    // diagnosis all read it.
    let theta0 = piece.input_theta();
    let input_theta_err =
        (opts.mode == Mode::Robust && piece.layout.n() > 0).then(|| Piece::errors(&theta0).0);
    let positions = if piece.layout.n() == 0 {
        report.converged = true;
        report.theta_err.push(0.0);
        report.stop_reason = "no interior vertex: returned unchanged".into();
        report.messages.push(report.stop_reason.clone());
        local.positions.clone()
    } else if let Some(err) = input_theta_err.filter(|&e| e <= opts.tolerance_rad) {
        // Nothing to do, and nothing a run could improve: any move adds displacement.
        // (Before, a flat sheet went through a coarse-to-fine hierarchy and a pull-back that
        // was undone, and its report said so.)
        report.converged = true;
        report.theta_err.push(err);
        report.stop_reason = format!(
            "already flattenable (θ_err {err:.1e} ≤ {:.1e} rad): returned unchanged",
            opts.tolerance_rad
        );
        report.messages.push(report.stop_reason.clone());
        local.positions.clone()
    } else {
        let run_robust = |opts: &ProcessOptions, mut chain: Chain, report: &mut PieceReport| {
            if coarse_to_fine::applies(local.face_count(), opts) {
                coarse_to_fine::run((&piece, &local, &w_local), &mut chain, opts, report)
            } else {
                Ok(coarse_to_fine::run_direct(&piece, opts, report))
            }
        };
        match opts.mode {
            Mode::Paper => paper::run(&piece, opts, &mut report)?,
            Mode::Robust if opts.update == Update::LeastSquare && opts.target == Target::Detail => {
                // The detail filter keeps L v⁰ where the paper's smooths towards L v = 0, so
                // the two least-square paths end on different surfaces: on the grids of
                // docs/algorithms/flattenable.md the detail one nearer the input but with a
                // larger area change on three of six. The detail target must be no worse than
                // the paper's on either, so the paper's runs beside it (on the other core when
                // it is free) and is returned when the detail path's result is not.
                let zero_opts = ProcessOptions {
                    target: Target::Zero,
                    progress: Default::default(),
                    ..opts.clone()
                };
                let mut zero_report = report.clone();
                let zero_chain = chain.clone();
                let (detail, zero) = beside(
                    || run_robust(opts, chain, &mut report),
                    || run_robust(&zero_opts, zero_chain, &mut zero_report),
                );
                let detail = detail?;
                let measured = |positions: &[[f64; 3]], run: &PieceReport| {
                    let mut m = run.clone();
                    piece.measure(positions, &theta0, &mut m);
                    m
                };
                match zero {
                    Some(Ok(zero)) => {
                        let (d, z) = (measured(&detail, &report), measured(&zero, &zero_report));
                        if at_least_as_good(&d, &z) {
                            detail
                        } else {
                            zero_report.messages.push(format!(
                                "the detail target's least-square path ended at RMS displacement {:.4} mm and area change {:+.4} % ({}), the paper's zero target at {:.4} mm and {:+.4} %: the paper's result is returned, as the detail target must neither move farther nor change the area more",
                                d.rms_displacement_mm,
                                d.area_change_percent,
                                if d.converged { "converged" } else { "not converged" },
                                z.rms_displacement_mm,
                                z.area_change_percent
                            ));
                            report = zero_report;
                            zero
                        }
                    }
                    Some(Err(_)) | None => detail,
                }
            }
            Mode::Robust => run_robust(opts, chain, &mut report)?,
        }
    };
    piece.measure(&positions, &theta0, &mut report);
    if report.converged && report.holes.iter().any(|h| !h.closes(opts.tolerance_rad)) {
        report.messages.push(holes_open(
            &report.holes,
            opts.tolerance_rad,
            opts.hole_rims,
        ));
    }
    if opts.mode == Mode::Robust
        && opts.target == Target::Detail
        && !pull_back::allowed(piece.faces.len())
    {
        // With the least-square update the detail target also filters towards L v⁰, so only
        // the direct update's result is the zero target's.
        report.messages.push(format!(
            "detail target: no pull-backs towards the input on a piece of {} faces (above {}, every one measured was undone after a long restore){}",
            piece.faces.len(),
            pull_back::PULL_BACK_MAX_FACES,
            if opts.update == Update::Direct {
                ", so the result is the zero target's"
            } else {
                ""
            }
        ));
    }
    let roughness = (!report.converged).then(|| rough_median(&theta0)).flatten();
    if let Some(median) = roughness {
        let hint = format!(
            "the surface is rough: the median |2π − θ| of its interior vertices is {median:.3} rad (smooth surfaces at a working resolution: below 0.05), i.e. scan noise, and its total angle defect ({:.3} rad) is mostly the noise's; smooth the scan or remesh it coarser before processing",
            report.input_total_defect_rad
        );
        report.stop_reason = format!("{}; {hint}", report.stop_reason);
        report.messages.push(hint);
    } else if report.input_total_defect_rad < 0.0 && !report.converged {
        // Discrete Gauss–Bonnet: the interior's angle excess has to end up in the boundary
        // angles; with the boundary fixed that needs wrinkles along it. Say so in the error
        // (stop_reason is part of NotConverged's message), not only in the report.
        let hint = format!(
            "the piece has a negative total angle defect ({:.3} rad, saddle-like): with its boundary fixed it can only become flat by wrinkling near the boundary; it has more surface than a flat sheet spans, so a seam or gusset where it resists, or a different cut, helps, and a dart (which takes surface out) does not",
            report.input_total_defect_rad
        );
        report.stop_reason = format!("{}; {hint}", report.stop_reason);
        report.messages.push(hint);
    } else if report.input_total_defect_rad > LARGE_TOTAL_DEFECT_RAD && !report.converged {
        let hint = format!(
            "the piece carries a total angle defect of {:.3} rad (a hemisphere carries 2π): a cup- or cap-like piece whose fixed boundary is short for its area can only become flat by crumpling; cut it into smaller pieces or add darts in its dome-like parts",
            report.input_total_defect_rad
        );
        report.stop_reason = format!("{}; {hint}", report.stop_reason);
        report.messages.push(hint);
    }
    report.seconds = start.elapsed().as_secs_f64();
    Ok((positions, piece.vertex_map, report))
}

/// What is open about a piece's holes, for its messages: how many of them do not close within
/// `tolerance_rad` and the worst one's turning residual and gap.
fn holes_open(holes: &[HoleClosure], tolerance_rad: f64, rims: HoleRims) -> String {
    let open: Vec<&HoleClosure> = holes.iter().filter(|h| !h.closes(tolerance_rad)).collect();
    let Some(w) = least_closed(open.iter().copied()) else {
        return "every hole closes in the plane".into();
    };
    let what = format!(
        "{} of its {} holes do not close in the plane, though θ = 2π (the worst, boundary loop {} of {} vertices and {:.1} mm: its development turns {:+.3e} rad from once around, the Gaussian curvature it encloses, and ends {:.3} mm from its start)",
        open.len(),
        holes.len(),
        w.loop_index,
        w.vertices,
        w.length_mm,
        w.turning_residual_rad,
        w.gap_mm
    );
    // Half a turn or more short: the piece wraps around the hole (a sleeve, a leg, a skirt).
    if w.turning_residual_rad.abs() > std::f64::consts::PI {
        format!(
            "{what}: the piece wraps around that hole like a band or tube, and with the rim held it cannot be laid flat; a seam from the hole to the outline (a `[[cut]]` line of a pipeline) can{}",
            if rims == HoleRims::Fixed {
                ", and `hole_rims = \"free\"` only by moving the rim far"
            } else {
                ""
            }
        )
    } else if rims == HoleRims::Fixed {
        format!(
            "{what}, so its pattern stretches around them; with `hole_rims = \"free\"` (`--hole-rims free`) the rims move so that every hole closes, or a seam from each hole to the outline (a `[[cut]]` line of a pipeline from its rim to the outline; its two sides become a seam of the piece with itself) makes the piece a disk"
        )
    } else {
        format!(
            "{what}, so its pattern stretches around them; a seam from each hole to the outline (a `[[cut]]` line of a pipeline from its rim to the outline; its two sides become a seam of the piece with itself) makes the piece a disk"
        )
    }
}

/// `a` on this thread and `b` at the same time on the thread pool, like `rayon::join`, and
/// both results. Unlike `rayon::join`, called from outside the pool (a caller's own thread,
/// which is where a single piece runs) it keeps `a` on this thread: `rayon::join` sends both
/// halves to one worker, and the second worker, asleep, took `b` in one call of five at the
/// 3.5k-face bench cap (0.4–1.5 ms late when it did), so the halves mostly ran one after the
/// other (docs/algorithms/flattenable.md, "The set-up on the caller's thread, the first
/// coarse level on the pool"). Called on a worker it behaves as `rayon::join`: the worker
/// runs `b` itself when no other has taken it by the time `a` is done. The second result is
/// always `Some` (the scope waits for `b`; a panic in `b` is passed on); it is an option
/// only so that no caller needs an unwrap. With a pool of one thread (`RAYON_NUM_THREADS=1`)
/// the caller runs both, one after the other, so that no more than one thread works, as
/// under `rayon::join`.
fn beside<RA, RB: Send>(a: impl FnOnce() -> RA, b: impl FnOnce() -> RB + Send) -> (RA, Option<RB>) {
    if rayon::current_num_threads() < 2 {
        return (a(), Some(b()));
    }
    let mut rb = None;
    let ra = rayon::in_place_scope(|s| {
        s.spawn(|_| rb = Some(b()));
        a()
    });
    (ra, rb)
}

/// Whether a measured result is at least as good as another for the detail target's bar:
/// converged if the other converged, and then no larger RMS displacement and no larger
/// |area change| (to `AREA_TIE_PERCENT`).
fn at_least_as_good(report: &PieceReport, other: &PieceReport) -> bool {
    if !other.converged {
        return true;
    }
    report.converged
        && report.rms_displacement_mm <= other.rms_displacement_mm
        && report.area_change_percent.abs() <= other.area_change_percent.abs() + AREA_TIE_PERCENT
}

/// Area changes (`PieceReport::area_change_percent`) this close count as equal when two
/// results are compared: the detail target's own slack for the area it holds (1e-9 of the
/// input area, `AREA_HOLD_SLACK` in src/pull_back.rs), far below the 0.001 % any report prints.
/// The detail target's |area change| is never above the zero target's by more.
pub const AREA_TIE_PERCENT: f64 = 100.0 * pull_back::AREA_HOLD_SLACK;

fn summarise(
    input: &TriMesh,
    out: &TriMesh,
    opts: &ProcessOptions,
    pieces: Vec<PieceReport>,
    seconds: f64,
) -> ProcessReport {
    let iterations = pieces.iter().map(|p| p.iterations).max().unwrap_or(0);
    let theta_err = (0..=iterations)
        .map(|i| {
            pieces
                .iter()
                .filter_map(|p| p.theta_err.get(i.min(p.theta_err.len().saturating_sub(1))))
                .fold(0.0f64, |m, &e| m.max(e))
        })
        .collect();
    let n_int: usize = pieces.iter().map(|p| p.interior_vertices).sum();
    let rms = |f: fn(&PieceReport) -> f64| {
        if n_int == 0 {
            return 0.0;
        }
        (pieces
            .iter()
            .map(|p| f(p).powi(2) * p.interior_vertices as f64)
            .sum::<f64>()
            / n_int as f64)
            .sqrt()
    };
    let a0: f64 = face_areas(&input.positions, &input.faces).iter().sum();
    let a1: f64 = face_areas(&out.positions, &out.faces).iter().sum();
    ProcessReport {
        mode: match opts.mode {
            Mode::Paper => "paper".into(),
            Mode::Robust => "robust".into(),
        },
        iterations,
        converged: pieces.iter().all(|p| p.converged),
        theta_err,
        final_theta_err: pieces.iter().fold(0.0, |m, p| m.max(p.final_theta_err)),
        final_theta_rms: rms(|p| p.final_theta_rms),
        input_theta_rms: rms(|p| p.input_theta_rms),
        max_displacement_mm: pieces.iter().fold(0.0, |m, p| m.max(p.max_displacement_mm)),
        rms_displacement_mm: rms(|p| p.rms_displacement_mm),
        area_change_percent: if a0 > 0.0 {
            100.0 * (a1 - a0) / a0
        } else {
            0.0
        },
        folded_faces: pieces.iter().map(|p| p.folded_faces).sum(),
        max_normal_turn_deg: pieces.iter().fold(0.0, |m, p| m.max(p.max_normal_turn_deg)),
        max_crease_deg: pieces.iter().fold(0.0, |m, p| m.max(p.max_crease_deg)),
        creased_edges: pieces.iter().map(|p| p.creased_edges).sum(),
        seconds,
        messages: pieces
            .iter()
            .flat_map(|p| {
                p.messages
                    .iter()
                    .map(move |m| format!("piece {}: {m}", p.piece))
            })
            .collect(),
        pieces,
    }
}

#[cfg(test)]
mod tests {
    use super::beside;

    /// From outside the pool (a test's own thread, as a caller's main thread) the first half
    /// runs on the calling thread — `rayon::join` would send it to a worker, and this fails —
    /// and on a worker of a one-thread pool, where nobody can take the second half, that
    /// worker runs both: no deadlock, both results.
    #[test]
    fn beside_keeps_the_first_half_on_a_caller_outside_the_pool() {
        let (a, b) = beside(rayon::current_thread_index, || 2 + 2);
        assert_eq!(a, None);
        assert_eq!(b, Some(4));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let (a, b) = pool.install(|| {
            beside(
                || (rayon::current_thread_index(), 1),
                || (rayon::current_thread_index(), 2),
            )
        });
        assert_eq!(a, (Some(0), 1));
        assert_eq!(b, Some((Some(0), 2)));
    }
}
