//! `flatcut process IN OUT`: make every piece flattenable (θ = 2π at every interior vertex)
//! by the least-norm method (crates/flattenable), moving interior vertices as little as
//! possible and never the boundary.
//!
//! OUT is written in `--units` when given, else in its format's convention (m for .glb, mm
//! otherwise), any format flatcut_io writes; as .glb
//! its vertices are coloured by |θ − 2π| (0 on the boundary). The report gives every number
//! in millimetres.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Context;
use flatcut_flattenable::{
    Damping, FlattenableError, HoleRims, IterationDone, Laplacian, Mode, ProcessOptions,
    ProcessReport, Processed, ProgressHook, Target, Update,
};
use flatcut_io::{Units, WriteOptions};
use flatcut_mesh::{Topology, TriMesh};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Arguments of `flatcut process`.
#[derive(clap::Args, Debug)]
pub struct ProcessArgs {
    /// Input mesh (.obj, .ply, .stl, .gltf, .glb): open pieces, each component processed.
    pub input: PathBuf,
    /// Output mesh (.obj, .ply, .stl, .glb; .glb carries |θ − 2π| as vertex colours).
    pub output: PathBuf,
    /// Units of the input: mm, cm, dm, m or in (default: m for .gltf/.glb, else mm); OUT is written in --units when given, else in its own format's convention (m for .glb, mm otherwise).
    #[arg(long, value_parser = crate::util::parse_units)]
    pub units: Option<Units>,
    /// `robust` (damped steps, fold guards, polish to --tolerance) or `paper` (as printed).
    #[arg(long, default_value = "robust", value_parser = parse_mode)]
    pub mode: Mode,
    /// Position update: `direct` or `least-square` (the paper's Laplacian filter).
    #[arg(long, default_value = "direct", value_parser = parse_update)]
    pub update: Update,
    /// Laplacian of the least-square update: `cotan` or `uniform`.
    #[arg(long, default_value = "cotan", value_parser = parse_laplacian)]
    pub laplacian: Laplacian,
    /// Target of the least-square update: `detail` (keeps the input's shape; in robust mode
    /// also pulls the result back towards the input at the same area change: never farther
    /// from the input nor more shrunk than `zero`) or `zero` (the paper's; shrinks; fewer
    /// iterations). Default: detail in robust mode, zero in paper mode.
    #[arg(long, value_parser = parse_target)]
    pub target: Option<Target>,
    /// Iteration limit per piece (default 500 robust, 50 paper).
    #[arg(long)]
    pub max_iterations: Option<usize>,
    /// Per-vertex weights file: one number per input vertex (whitespace separated, `#`
    /// comments); larger moves less.
    #[arg(long)]
    pub weights: Option<PathBuf>,
    /// Weight of the interior vertices next to the boundary (soft G1; the paper uses 10).
    #[arg(long, default_value_t = 1.0)]
    pub boundary_ring_weight: f64,
    /// Robust mode's success threshold on max |θ − 2π| (radians).
    #[arg(long, default_value_t = 1e-9)]
    pub tolerance: f64,
    /// Write OUT with the best unfolded state even when a piece does not converge (the
    /// command still fails with exit code 1).
    #[arg(long)]
    pub keep_best: bool,
    /// Robust mode: end every piece with global steps, without the local polish (by default
    /// a large piece's last steps are solved on the region still above --tolerance).
    #[arg(long)]
    pub no_local_polish: bool,
    /// Robust mode's step damping: `identity` (the default; measured best on all but the
    /// largest pieces) or `graph-laplacian` (damps smooth corrections less than rough ones:
    /// converges the 85k-face body piece that `identity` leaves at θ_err 3e-6; the default
    /// also tries it right after a large piece's direct solve stalls far from θ = 2π, and as
    /// a last rescue). docs/algorithms/flattenable.md.
    #[arg(long, default_value = "identity", value_parser = parse_damping)]
    pub damping: Damping,
    /// The rims of a piece's holes (its boundary loops but the longest): `fixed` (never move,
    /// like the outline; on a curved piece θ = 2π then leaves each hole open in the plane,
    /// and the report says by how much) or `free` (they move, and every hole closes, so the
    /// piece flattens without stretch).
    #[arg(long, default_value = "fixed", value_parser = parse_hole_rims)]
    pub hole_rims: HoleRims,
    /// Also write the report as JSON to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print the report as JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// No progress spinner (it is drawn on standard error, and only when that is a terminal).
    #[arg(long, short)]
    pub quiet: bool,
}

fn parse_mode(s: &str) -> Result<Mode, String> {
    match s {
        "robust" => Ok(Mode::Robust),
        "paper" => Ok(Mode::Paper),
        _ => Err(format!("unknown mode '{s}': use robust or paper")),
    }
}

fn parse_update(s: &str) -> Result<Update, String> {
    match s {
        "direct" => Ok(Update::Direct),
        "least-square" | "least-squares" => Ok(Update::LeastSquare),
        _ => Err(format!("unknown update '{s}': use direct or least-square")),
    }
}

fn parse_laplacian(s: &str) -> Result<Laplacian, String> {
    match s {
        "cotan" => Ok(Laplacian::Cotan),
        "uniform" => Ok(Laplacian::Uniform),
        _ => Err(format!("unknown laplacian '{s}': use cotan or uniform")),
    }
}

fn parse_damping(s: &str) -> Result<Damping, String> {
    match s {
        "identity" => Ok(Damping::Identity),
        "graph-laplacian" => Ok(Damping::GraphLaplacian),
        _ => Err(format!(
            "unknown damping '{s}': use identity or graph-laplacian"
        )),
    }
}

fn parse_hole_rims(s: &str) -> Result<HoleRims, String> {
    match s {
        "fixed" => Ok(HoleRims::Fixed),
        "free" => Ok(HoleRims::Free),
        _ => Err(format!("unknown hole rims '{s}': use fixed or free")),
    }
}

fn parse_target(s: &str) -> Result<Target, String> {
    match s {
        "zero" => Ok(Target::Zero),
        "detail" => Ok(Target::Detail),
        _ => Err(format!("unknown target '{s}': use zero or detail")),
    }
}

fn read_weights(path: &std::path::Path, vertices: usize) -> anyhow::Result<Vec<f64>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read weights file {}", path.display()))?;
    let mut w = Vec::with_capacity(vertices);
    for (line_no, line) in text.lines().enumerate() {
        let data = line.split('#').next().unwrap_or("");
        for tok in data.split_whitespace() {
            let v: f64 = tok.parse().map_err(|_| {
                anyhow::anyhow!(
                    "{}:{}: '{tok}' is not a number (one weight per vertex expected)",
                    path.display(),
                    line_no + 1
                )
            })?;
            if !(v.is_finite() && v > 0.0) {
                anyhow::bail!(
                    "{}:{}: weight {v} must be finite and > 0",
                    path.display(),
                    line_no + 1
                );
            }
            w.push(v);
        }
    }
    if w.len() != vertices {
        anyhow::bail!(
            "{}: {} weights for {} vertices; give one weight per vertex of the input",
            path.display(),
            w.len(),
            vertices
        );
    }
    Ok(w)
}

/// |θ − 2π| per vertex (0 on the boundary and for unused vertices), for the GLB colours.
fn defect_field(mesh: &TriMesh) -> Vec<f64> {
    match Topology::build(mesh) {
        Ok(topo) => flatcut_mesh::geometry::angle_defects(&mesh.positions, &mesh.faces, &topo)
            .iter()
            .map(|d| d.map_or(0.0, f64::abs))
            .collect(),
        Err(_) => vec![0.0; mesh.vertex_count()],
    }
}

fn write_output(args: &ProcessArgs, processed: &Processed) -> anyhow::Result<()> {
    let mut mesh = processed.mesh.clone();
    mesh.attributes.scalar = Some(defect_field(&mesh));
    mesh.attributes.colors = None;
    let opts = WriteOptions {
        units: args.units,
        ..Default::default()
    };
    flatcut_io::write_mesh(&args.output, &mesh, &opts)
        .with_context(|| format!("cannot write {}", args.output.display()))
}

fn text_report(r: &ProcessReport) -> String {
    let mut o = String::new();
    outln!(
        o,
        "mode {}: {} piece(s), {} iteration(s), {}",
        r.mode,
        r.pieces.len(),
        r.iterations,
        if r.converged {
            "converged"
        } else {
            "NOT converged"
        }
    );
    outln!(
        o,
        "θ_err (max |θ − 2π|): {:.3e} → {:.3e} rad (RMS {:.3e} → {:.3e})",
        r.theta_err.first().copied().unwrap_or(0.0),
        r.final_theta_err,
        r.input_theta_rms,
        r.final_theta_rms
    );
    outln!(
        o,
        "displacement: max {:.4} mm, RMS {:.4} mm; area change {:+.3} %; folded faces {}; normals turned by up to {:.1}°; creases {} edges (bend grown by > {:.0}°, up to {:.1}°); {:.3} s",
        r.max_displacement_mm,
        r.rms_displacement_mm,
        r.area_change_percent,
        r.folded_faces,
        r.max_normal_turn_deg,
        r.creased_edges,
        flatcut_flattenable::CREASE_DEG,
        r.max_crease_deg,
        r.seconds
    );
    // Holes: θ = 2π alone does not close them (docs/algorithms/flattenable.md, "Holes").
    let holes = r.pieces.iter().flat_map(|p| &p.holes);
    if let Some(worst) = flatcut_flattenable::hole_closure::least_closed(holes.clone()) {
        outln!(
            o,
            "holes: {}; the least closed turns {:+.3e} rad from once around and leaves a {:.3e} mm gap in the plane",
            holes.count(),
            worst.turning_residual_rad,
            worst.gap_mm
        );
    }
    if r.pieces.len() > 1 {
        for p in &r.pieces {
            outln!(
                o,
                "  piece {}: {} faces, {} interior, {} it, θ_err {:.3e}, max disp {:.4} mm, area {:+.3} %: {}",
                p.piece,
                p.faces,
                p.interior_vertices,
                p.iterations,
                p.final_theta_err,
                p.max_displacement_mm,
                p.area_change_percent,
                p.stop_reason
            );
        }
    }
    for m in &r.messages {
        outln!(o, "note: {m}");
    }
    o
}

/// Runs `flatcut process`.
pub fn run(args: &ProcessArgs) -> anyhow::Result<()> {
    let mut inputs = vec![("IN", args.input.as_path())];
    inputs.extend(args.weights.as_deref().map(|w| ("--weights", w)));
    let mut outputs = vec![("OUT", args.output.as_path())];
    outputs.extend(args.report.as_deref().map(|r| ("--report", r)));
    crate::util::refuse_overwrite(&inputs, &outputs)?;
    let loaded =
        flatcut_io::read_mesh(&args.input, crate::util::units_for(&args.input, args.units))
            .with_context(|| format!("cannot read {}", args.input.display()))?;
    let mesh = loaded.mesh;
    let weights = match &args.weights {
        Some(p) => Some(read_weights(p, mesh.vertex_count())?),
        None => None,
    };
    // Pieces of scan resolution take seconds to minutes: say what is happening (on
    // standard error; indicatif draws nothing when it is not a terminal).
    let spinner = (!args.quiet).then(|| {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template("{spinner} {elapsed} {msg}") {
            bar.set_style(style);
        }
        bar.set_message(format!("processing {}", args.input.display()));
        bar.enable_steady_tick(Duration::from_millis(120));
        bar
    });
    let target = args.target.unwrap_or(match args.mode {
        Mode::Paper => Target::Zero,
        Mode::Robust => Target::Detail,
    });
    let opts = ProcessOptions {
        mode: args.mode,
        update: args.update,
        laplacian: args.laplacian,
        target,
        max_iterations: args.max_iterations,
        weights,
        boundary_ring_weight: args.boundary_ring_weight,
        tolerance_rad: args.tolerance,
        local_polish: !args.no_local_polish,
        hole_rims: args.hole_rims,
        damping: args.damping,
        progress: spinner.as_ref().map_or_else(ProgressHook::default, |bar| {
            let bar = bar.clone();
            ProgressHook::new(move |e: &IterationDone| {
                bar.set_message(format!(
                    "piece {}: {} faces, iteration {}, θ_err {:.1e} rad",
                    e.piece, e.faces, e.iteration, e.theta_err
                ));
            })
        }),
        ..Default::default()
    };
    let outcome = flatcut_flattenable::process(&mesh, &opts);
    if let Some(bar) = &spinner {
        bar.finish_and_clear();
    }
    let (processed, failure) = match outcome {
        Ok(p) => (p, None),
        Err(e) => {
            // Not converging is a result (the library's message: best and input θ_err and
            // RMS, the reason; then what was written); anything else is an error.
            let message = e.to_string();
            match e {
                FlattenableError::NotConverged { partial, .. } => {
                    let written = if args.keep_best {
                        "; the best unfolded state was written"
                    } else {
                        "; nothing written (use --keep-best to write the best unfolded state)"
                    };
                    let msg = format!("{}: {message}{written}", args.input.display());
                    (*partial, Some(msg))
                }
                e => {
                    return Err(e)
                        .with_context(|| format!("cannot process {}", args.input.display()));
                }
            }
        }
    };
    let json = serde_json::to_string_pretty(&processed.report)?;
    if let Some(p) = &args.report {
        crate::util::write_text_atomic(p, &(json.clone() + "\n"))?;
    }
    if failure.is_none() || args.keep_best {
        write_output(args, &processed)?;
    }
    if args.json {
        crate::util::emit(&(json + "\n"))?;
    } else {
        crate::util::emit(&text_report(&processed.report))?;
    }
    match failure {
        Some(msg) => Err(anyhow::anyhow!(msg)),
        None => Ok(()),
    }
}
