//! `flatcut run [PIPELINE.toml ...]`: run pipeline recipes end to end into their output
//! folders (crates/pipeline), or the bundled wetsuit demo when none is given.

use std::path::{Path, PathBuf};

use flatcut_pipeline::{Pipeline, Report, RunOptions, WETSUIT_DEMO_TOML};

/// Arguments of `flatcut run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Pipeline files (TOML, schema 1). None: the bundled demo (pipelines/wetsuit-demo.toml on
    /// a generated dress form), written to out/wetsuit-demo in the current folder.
    pub pipelines: Vec<PathBuf>,
    /// Output folder (default: the pipeline's `output`, relative to its file). With several
    /// pipelines, each goes to DIR/<name>.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the results as JSON (the reports) instead of text.
    #[arg(long)]
    pub json: bool,
    /// No progress bars.
    #[arg(long, short)]
    pub quiet: bool,
    /// Write into an output folder that belongs to another pipeline (or is not flatcut's).
    #[arg(long)]
    pub force: bool,
    /// Worker threads (default: all cores, or RAYON_NUM_THREADS). Results are identical for
    /// any count.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// The outcome of one pipeline of the batch.
struct Outcome {
    source: String,
    name: String,
    out_dir: Option<PathBuf>,
    seconds: f64,
    result: Result<Report, String>,
}

fn load(args: &RunArgs) -> Vec<(String, Result<Pipeline, String>)> {
    if args.pipelines.is_empty() {
        let src = Path::new("pipelines/wetsuit-demo.toml (bundled)");
        return vec![(
            src.display().to_string(),
            Pipeline::parse(WETSUIT_DEMO_TOML, src, Path::new(".")).map_err(|e| e.to_string()),
        )];
    }
    args.pipelines
        .iter()
        .map(|p| {
            (
                p.display().to_string(),
                Pipeline::read(p).map_err(|e| e.to_string()),
            )
        })
        .collect()
}

fn piece_line(o: &mut String, r: &Report) {
    for p in &r.pieces {
        outln!(
            o,
            "  {:<16} {:>7} faces  θ_err {:.2e} → {:.2e} rad ({} it{})  max strain {:.2e}  E_h p95 {:.2e}  {:.1} × {:.1} mm{}{}",
            p.name,
            p.faces,
            p.process.theta_err_before,
            p.process.theta_err_after,
            p.process.iterations,
            if p.process.converged {
                ""
            } else {
                ", NOT converged"
            },
            p.flatten.max_edge_strain,
            p.flatten.e_h.p95,
            p.flatten.size_mm[0],
            p.flatten.size_mm[1],
            if p.flatten.flipped_faces > 0 {
                format!("  {} FLIPPED faces", p.flatten.flipped_faces)
            } else {
                String::new()
            },
            crease_note(&p.process)
        );
    }
}

/// "  creased up to N° (kind there: what helps)" for a piece whose processed surface creases.
fn crease_note(p: &flatcut_pipeline::report::ProcessSummary) -> String {
    if p.creased_edges == 0 {
        return String::new();
    }
    let kind = flatcut_flattenable::CreaseKind::of(p.creased_defect_rad)
        .map_or(String::new(), |k| format!(" ({})", k.advice()));
    format!("  creased up to {:.0}°{kind}", p.max_crease_deg)
}

/// Runs `flatcut run`.
pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let loaded = load(args);
    let batch = loaded.len() > 1;
    let mut outcomes: Vec<Outcome> = Vec::new();
    let mut used: Vec<PathBuf> = Vec::new();
    for (source, pipeline) in loaded {
        let start = std::time::Instant::now();
        let mut outcome = Outcome {
            source: source.clone(),
            name: String::new(),
            out_dir: None,
            seconds: 0.0,
            result: Err(String::new()),
        };
        outcome.result = (|| {
            let p = pipeline?;
            outcome.name = p.name().to_string();
            let out = match &args.out {
                Some(d) if batch => d.join(p.name()),
                Some(d) => d.clone(),
                None => p.default_output(),
            };
            if used.contains(&out) {
                return Err(format!(
                    "{source}: its output folder {} is used by an earlier pipeline of this batch; give each pipeline its own `output`",
                    out.display()
                ));
            }
            used.push(out.clone());
            outcome.out_dir = Some(out.clone());
            let opts = RunOptions {
                out: Some(out),
                force: args.force,
                threads: args.threads,
                quiet: args.quiet,
            };
            flatcut_pipeline::run(&p, &opts)
                .map(|r| r.report)
                .map_err(|e| e.to_string())
        })();
        outcome.seconds = start.elapsed().as_secs_f64();
        outcomes.push(outcome);
    }

    let failed = outcomes.iter().filter(|o| o.result.is_err()).count();
    let mut o = String::new();
    if args.json {
        let runs: Vec<serde_json::Value> = outcomes
            .iter()
            .map(|oc| {
                serde_json::json!({
                    "pipeline": oc.name,
                    "source": oc.source,
                    "output": oc.out_dir.as_ref().map(|d| d.display().to_string()),
                    "ok": oc.result.is_ok(),
                    "error": oc.result.as_ref().err(),
                    "report": oc.result.as_ref().ok(),
                })
            })
            .collect();
        let json = flatcut_pipeline::report::to_json(&serde_json::json!({ "runs": runs }));
        o.push_str(&String::from_utf8_lossy(&json));
    } else {
        for oc in &outcomes {
            match &oc.result {
                Ok(r) => {
                    outln!(
                        o,
                        "{}: {} piece(s) → {} ({:.1} s)",
                        oc.name,
                        r.pieces.len(),
                        oc.out_dir
                            .as_ref()
                            .map_or(String::new(), |d| d.display().to_string()),
                        oc.seconds
                    );
                    piece_line(&mut o, r);
                    if let Some(d) = &oc.out_dir {
                        outln!(o, "  open {}", d.join("report.html").display());
                    }
                    for w in &r.warnings {
                        outln!(o, "  warning: {w}");
                    }
                }
                // A single failure is the command's error message (standard error).
                Err(e) if batch => outln!(o, "{}: FAILED: {e}", oc.source),
                Err(_) => {}
            }
        }
        if batch {
            outln!(o, "");
            outln!(
                o,
                "{:<24} {:>6} {:>8} {:>11} {:>11} {:>7}  status",
                "pipeline",
                "pieces",
                "faces",
                "θ_err max",
                "strain max",
                "s"
            );
            for oc in &outcomes {
                let label = if oc.name.is_empty() {
                    &oc.source
                } else {
                    &oc.name
                };
                match &oc.result {
                    Ok(r) => {
                        let faces: usize = r.pieces.iter().map(|p| p.faces).sum();
                        let th = r
                            .pieces
                            .iter()
                            .map(|p| p.process.theta_err_after)
                            .fold(0.0, f64::max);
                        let st = r
                            .pieces
                            .iter()
                            .map(|p| p.flatten.max_edge_strain)
                            .fold(0.0, f64::max);
                        let ok = r.warnings.is_empty();
                        outln!(
                            o,
                            "{label:<24} {:>6} {faces:>8} {th:>11.2e} {st:>11.2e} {:>7.1}  {}",
                            r.pieces.len(),
                            oc.seconds,
                            if ok { "ok" } else { "ok, with warnings" }
                        );
                    }
                    Err(_) => outln!(
                        o,
                        "{label:<24} {:>6} {:>8} {:>11} {:>11} {:>7.1}  FAILED",
                        "-",
                        "-",
                        "-",
                        "-",
                        oc.seconds
                    ),
                }
            }
        }
    }
    crate::util::emit(&o)?;
    if failed > 0 {
        let first = outcomes
            .iter()
            .find_map(|oc| oc.result.as_ref().err())
            .cloned()
            .unwrap_or_default();
        if batch {
            anyhow::bail!(
                "{failed} of {} pipelines failed; first: {first}",
                outcomes.len()
            );
        }
        anyhow::bail!("{first}");
    }
    Ok(())
}
