//! `flatcut surface WIRE.toml OUT`: a triangulated surface patch spanning a wire-frame of 3D
//! boundary curves (and optional interior guide curves), written in mm.
//!
//! WIRE.toml: top-level `units` (mm, cm, dm, m, in; default mm) for the points,
//! `target_edge_mm`, `[[curve]]` tables with `name` and `points = [[x, y, z], …]` (one closed
//! curve, or open curves that join end to end into one loop), optional `[[guide]]` tables of
//! the same shape, and an optional `[options]` table (see `flatcut_trim::WireframeOptions`).

use std::path::PathBuf;

use anyhow::Context;
use flatcut_io::{Units, WriteOptions};
use flatcut_trim::wireframe::{WireFrame, WireframeReport, wireframe_surface};
use serde::Serialize;

/// Arguments of `flatcut surface`.
#[derive(clap::Args, Debug)]
pub struct SurfaceArgs {
    /// The wire-frame (TOML): `units`, `target_edge_mm`, `[[curve]]`, optional `[[guide]]`, `[options]`.
    pub wire: PathBuf,
    /// Output mesh (.obj, .ply, .stl, .glb), in mm (.glb: metres, as glTF fixes).
    pub output: PathBuf,
    /// Also write the report as JSON to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print the report as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// The report: what was read, what was written, and the patch's measurements.
#[derive(Serialize)]
struct Report<'a> {
    input: String,
    output: String,
    units: String,
    target_edge_mm: f64,
    curves: usize,
    guides: usize,
    #[serde(flatten)]
    patch: &'a WireframeReport,
}

/// Reads and parses WIRE.toml; TOML errors carry their line and column.
fn read_wire(path: &std::path::Path) -> anyhow::Result<WireFrame> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the wire-frame {}", path.display()))?;
    toml::from_str(&text).map_err(|e| {
        let at = e
            .span()
            .map(|s| {
                let before = &text[..s.start.min(text.len())];
                let line = before.matches('\n').count() + 1;
                let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
                format!(" at line {line}, column {col}")
            })
            .unwrap_or_default();
        anyhow::anyhow!("{}{at}: {}", path.display(), e.message().trim_end())
    })
}

/// Runs `flatcut surface`.
pub fn run(args: &SurfaceArgs) -> anyhow::Result<()> {
    let mut outputs = vec![("OUT", args.output.as_path())];
    outputs.extend(args.report.as_deref().map(|r| ("--report", r)));
    crate::util::refuse_overwrite(&[("WIRE", &args.wire)], &outputs)?;
    let input = args.wire.display().to_string();
    let wire = read_wire(&args.wire)?;
    let units: Units = wire
        .units
        .parse()
        .with_context(|| format!("{input}: units = \"{}\"", wire.units))?;
    let wire_mm = wire.scaled(units.factor_to_mm());
    let patch = wireframe_surface(&wire_mm, &wire.options)
        .with_context(|| format!("cannot make a surface from {input}"))?;
    flatcut_io::write_mesh(&args.output, &patch.mesh, &WriteOptions::default())?;

    let report = Report {
        input,
        output: args.output.display().to_string(),
        units: units.name().to_string(),
        target_edge_mm: wire.target_edge_mm,
        curves: wire.curve.len(),
        guides: wire.guide.len(),
        patch: &patch.report,
    };
    let json = serde_json::to_string_pretty(&report)?;
    if let Some(path) = &args.report {
        crate::util::write_text_atomic(path, &(json.clone() + "\n"))?;
    }
    let mut o = String::new();
    if args.json {
        outln!(o, "{json}");
        return crate::util::emit(&o);
    }
    let r = &patch.report;
    let domain = match r.domain {
        flatcut_trim::wireframe::DomainKind::Plane => "best-fit plane",
        flatcut_trim::wireframe::DomainKind::Circle => "circle (arc length)",
    };
    outln!(o, "input                    {}", report.input);
    outln!(o, "output                   {}", report.output);
    outln!(
        o,
        "curves / guides          {} / {}",
        report.curves,
        report.guides
    );
    outln!(o, "domain                   {domain}");
    outln!(o, "faces / vertices         {} / {}", r.faces, r.vertices);
    outln!(o, "boundary vertices        {}", r.boundary_vertices);
    outln!(o, "loop length (mm)         {:.3}", r.loop_length_mm);
    outln!(o, "area (mm2)               {:.3}", r.area_mm2);
    outln!(
        o,
        "min angle domain/3D      {:.2}° / {:.2}° (first lift {:.2}°, {} re-parametrisation passes{})",
        r.min_angle_domain_deg,
        r.min_angle_3d_deg,
        r.min_angle_lifted_deg,
        r.reparam_passes,
        if r.conformal_domain {
            ", conformal domain kept"
        } else {
            ""
        }
    );
    outln!(
        o,
        "max boundary deviation   {:.3e} mm",
        r.max_boundary_deviation_mm
    );
    for w in &r.warnings {
        outln!(o, "warning: {w}");
    }
    crate::util::emit(&o)
}
