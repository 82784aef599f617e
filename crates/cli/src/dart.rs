//! `flatcut dart IN OUT --from X,Y,Z --tip X,Y,Z [...]`: cut darts into a piece (slits from
//! its boundary to a tip inside, opened so the piece can flatten with less deformation),
//! writing the darted piece and a seam ledger with one dart seam each.
//! `flatcut dart IN --suggest N`: propose where darts would help (concentrated curvature);
//! with OUT as well, the proposed darts are cut.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use flatcut_dart::{DartOptions, DartSpec, SuggestOptions, append_dart_seams, dart, suggest};
use flatcut_io::Units;
use flatcut_mesh::SeamLedger;

/// Arguments of `flatcut dart`.
#[derive(clap::Args, Debug)]
pub struct DartArgs {
    /// Input piece (.obj, .ply, .stl, .gltf, .glb): an open surface; never modified.
    pub input: PathBuf,
    /// Output: the darted piece (format by extension, coordinates in --units, else the
    /// format's convention). Optional with --suggest.
    pub output: Option<PathBuf>,
    /// Start of a dart on (within --boundary-tolerance of) the piece's boundary, `X,Y,Z` in
    /// --units. Repeat for several darts, each with its --tip.
    #[arg(long = "from", value_parser = parse_point, allow_hyphen_values = true)]
    pub from: Vec<[f64; 3]>,
    /// Tip of a dart inside the piece, `X,Y,Z` in --units (one per --from, in order).
    #[arg(long = "tip", value_parser = parse_point, allow_hyphen_values = true)]
    pub tip: Vec<[f64; 3]>,
    /// Propose N darts where the angle defect is concentrated, best first.
    #[arg(long, value_name = "N")]
    pub suggest: Option<usize>,
    /// Units of the input and of the points: mm, cm, dm, m or in (default: m for .gltf/.glb,
    /// else mm).
    #[arg(long, value_parser = crate::util::parse_units)]
    pub units: Option<Units>,
    /// Largest distance of a start from the boundary (and smallest of a tip), mm.
    #[arg(long, default_value_t = flatcut_dart::DEFAULT_BOUNDARY_TOLERANCE_MM)]
    pub boundary_tolerance_mm: f64,
    /// Where to write the seam ledger (JSON, mm). Default: `<OUT without extension>.seams.json`.
    #[arg(long)]
    pub seams: Option<PathBuf>,
    /// An existing seam ledger (e.g. flatcut trim's seams.json) to add the darts to: seams of
    /// the piece are renumbered onto the darted piece, seams through a dart's start split.
    #[arg(long)]
    pub ledger: Option<PathBuf>,
    /// Name of the piece in the ledger. Default: the input's file stem.
    #[arg(long)]
    pub piece: Option<String>,
    /// Print the summary as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Parses `X,Y,Z`.
fn parse_point(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected X,Y,Z (three numbers), got {s:?}"));
    }
    let mut p = [0.0; 3];
    for (k, t) in parts.iter().enumerate() {
        p[k] = t
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{t:?} in {s:?} is not a finite number"))?;
    }
    Ok(p)
}

fn scaled(p: [f64; 3], f: f64) -> [f64; 3] {
    [p[0] * f, p[1] * f, p[2] * f]
}

/// Where the seam ledger goes: `--seams`, else beside OUT.
fn seams_path(args: &DartArgs, out: &std::path::Path) -> PathBuf {
    args.seams
        .clone()
        .unwrap_or_else(|| out.with_extension("seams.json"))
}

/// Runs `flatcut dart`.
pub fn run(args: &DartArgs) -> anyhow::Result<()> {
    if args.from.len() != args.tip.len() {
        bail!(
            "{} --from and {} --tip given; give one --tip per --from, in the same order",
            args.from.len(),
            args.tip.len()
        );
    }
    if args.suggest.is_none() && args.from.is_empty() {
        bail!("give darts with --from X,Y,Z --tip X,Y,Z, or ask for proposals with --suggest N");
    }
    if args.suggest.is_some() && !args.from.is_empty() {
        bail!("give either --from/--tip darts or --suggest N, not both");
    }
    if args.suggest.is_none() && args.output.is_none() {
        bail!("give the output file OUT for the darted piece");
    }
    if !(args.boundary_tolerance_mm.is_finite() && args.boundary_tolerance_mm >= 0.0) {
        bail!("--boundary-tolerance-mm must be a non-negative number");
    }
    if let Some(out) = &args.output {
        let seams = seams_path(args, out);
        let mut inputs = vec![("IN", args.input.as_path())];
        inputs.extend(args.ledger.as_deref().map(|l| ("--ledger", l)));
        crate::util::refuse_overwrite(&inputs, &[("OUT", out), ("--seams", &seams)])?;
    }
    let units = crate::util::units_for(&args.input, args.units);
    let f = units.factor_to_mm();
    let loaded = flatcut_io::read_mesh(&args.input, units)?;
    let piece = loaded.mesh;
    let dopts = DartOptions {
        boundary_tolerance_mm: args.boundary_tolerance_mm,
        ..Default::default()
    };

    let mut o = String::new();
    let mut summary = serde_json::Map::new();
    summary.insert("input".into(), serde_json::json!(args.input));
    summary.insert("units".into(), serde_json::json!(units.to_string()));
    let specs: Vec<DartSpec> = if let Some(n) = args.suggest {
        let sopts = SuggestOptions {
            dart: dopts.clone(),
            ..Default::default()
        };
        let s = suggest(&piece, n, &sopts)
            .with_context(|| format!("proposing darts for {}", args.input.display()))?;
        let rows: Vec<serde_json::Value> = s
            .iter()
            .map(|x| {
                serde_json::json!({
                    "name": x.spec.name,
                    "from": scaled(x.spec.from, 1.0 / f),
                    "tip": scaled(x.spec.tip.unwrap_or_default(), 1.0 / f),
                    "start_vertex": x.start_vertex,
                    "tip_vertex": x.tip_vertex,
                    "length_mm": x.length_mm,
                    "concentrated_defect_rad": x.concentrated_defect_rad,
                    "abs_defect_before_rad": x.abs_defect_before_rad,
                    "abs_defect_after_rad": x.abs_defect_after_rad,
                })
            })
            .collect();
        summary.insert("suggestions".into(), serde_json::Value::Array(rows));
        outln!(
            o,
            "{}: {} dart{} proposed (asked {n}); Σ|2π − θ| inside {:.4} rad",
            args.input.display(),
            s.len(),
            if s.len() == 1 { "" } else { "s" },
            s.first().map_or(0.0, |x| x.abs_defect_before_rad)
        );
        for x in &s {
            let (a, b) = (
                scaled(x.spec.from, 1.0 / f),
                scaled(x.spec.tip.unwrap_or_default(), 1.0 / f),
            );
            outln!(
                o,
                "  {}: --from {},{},{} --tip {},{},{}  ({:.1} mm, curvature {:.4} rad there, Σ|2π − θ| after {:.4} rad)",
                x.spec.name,
                a[0],
                a[1],
                a[2],
                b[0],
                b[1],
                b[2],
                x.length_mm,
                x.concentrated_defect_rad,
                x.abs_defect_after_rad
            );
        }
        s.into_iter().map(|x| x.spec).collect()
    } else {
        args.from
            .iter()
            .zip(&args.tip)
            .enumerate()
            .map(|(i, (a, b))| {
                DartSpec::to_tip(&format!("dart-{}", i + 1), scaled(*a, f), scaled(*b, f))
            })
            .collect()
    };

    if let Some(out) = &args.output {
        if specs.is_empty() {
            bail!(
                "no dart to cut: {} has no place with enough concentrated curvature; nothing written",
                args.input.display()
            );
        }
        let darted = dart(&piece, &specs, &dopts)
            .with_context(|| format!("cutting darts into {}", args.input.display()))?;
        let name = match &args.piece {
            Some(n) => n.clone(),
            None => args
                .input
                .file_stem()
                .map_or("piece".into(), |s| s.to_string_lossy().into_owned()),
        };
        let mut ledger = match &args.ledger {
            Some(p) => read_ledger(p)?,
            None => SeamLedger::new(vec![name.clone()]),
        };
        append_dart_seams(&mut ledger, &name, &darted).with_context(|| {
            format!(
                "adding the darts of piece {name:?} to {}",
                args.ledger
                    .as_deref()
                    .map_or("a new ledger".into(), |p| p.display().to_string())
            )
        })?;
        let seams_path = seams_path(args, out);
        let wopts = flatcut_io::WriteOptions {
            units: args.units,
            ..Default::default()
        };
        flatcut_io::write_mesh(out, &darted.mesh, &wopts)
            .with_context(|| format!("cannot write {}", out.display()))?;
        crate::util::write_text_atomic(&seams_path, &serde_json::to_string_pretty(&ledger)?)?;
        let rows: Vec<serde_json::Value> = darted
            .darts
            .iter()
            .map(|d| {
                serde_json::json!({
                    "name": d.name,
                    "length_mm": d.length_mm,
                    "tip_vertex": d.tip,
                    "leg_a": d.leg_a,
                    "leg_b": d.leg_b,
                    "start_mm": d.start_mm,
                    "tip_mm": d.tip_mm,
                })
            })
            .collect();
        summary.insert("output".into(), serde_json::json!(out));
        summary.insert("seams".into(), serde_json::json!(seams_path));
        summary.insert(
            "vertices".into(),
            serde_json::json!(darted.mesh.positions.len()),
        );
        summary.insert("faces".into(), serde_json::json!(darted.mesh.faces.len()));
        summary.insert("darts".into(), serde_json::Value::Array(rows));
        outln!(
            o,
            "{}: {} dart{} cut → {} ({} vertices, {} faces); seams in {}",
            args.input.display(),
            darted.darts.len(),
            if darted.darts.len() == 1 { "" } else { "s" },
            out.display(),
            darted.mesh.positions.len(),
            darted.mesh.faces.len(),
            seams_path.display()
        );
        for d in &darted.darts {
            outln!(
                o,
                "  {:<14} {:>9.2} mm  tip vertex {}, legs of {} vertices",
                d.name,
                d.length_mm,
                d.tip,
                d.leg_a.len()
            );
        }
    }
    if args.json {
        o.clear();
        outln!(
            o,
            "{}",
            serde_json::to_string_pretty(&serde_json::Value::Object(summary))?
        );
    }
    crate::util::emit(&o)
}

fn read_ledger(path: &Path) -> anyhow::Result<SeamLedger> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the seam ledger {}", path.display()))?;
    let l: SeamLedger = serde_json::from_str(&text)
        .with_context(|| format!("{} is not a seam ledger (seams.json)", path.display()))?;
    l.check()
        .with_context(|| format!("the seam ledger {} is inconsistent", path.display()))?;
    Ok(l)
}
