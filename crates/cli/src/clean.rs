//! `flatcut clean IN OUT`: repair a scan and say what was repaired.

use std::path::PathBuf;

use anyhow::{Context, bail};
use flatcut_io::Units;
use flatcut_mesh::clean::{CleanOptions, Keep, clean};

/// Which components `flatcut clean` keeps.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum KeepArg {
    /// Only the component with the most faces (drops scan debris).
    Largest,
    /// Every component.
    All,
}

/// Arguments of `flatcut clean`.
#[derive(clap::Args, Debug)]
pub struct CleanArgs {
    /// Input mesh file (.obj, .ply, .stl, .gltf, .glb); never modified.
    pub input: PathBuf,
    /// Output mesh file; its extension picks the format. Must differ from the input.
    pub output: PathBuf,
    /// Units of the input: mm, cm, dm, m or in (default: m for .gltf/.glb, as glTF fixes, else mm). The output is in mm.
    #[arg(long, value_parser = crate::util::parse_units)]
    pub units: Option<Units>,
    /// Weld vertices closer than this distance in mm (0: only exactly coincident ones).
    #[arg(long, default_value_t = 0.0)]
    pub weld_mm: f64,
    /// Keep the largest component or all of them.
    #[arg(long, value_enum, default_value = "all")]
    pub keep: KeepArg,
    /// Write the JSON report to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print the report as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `flatcut clean`.
pub fn run(args: &CleanArgs) -> anyhow::Result<()> {
    if !(args.weld_mm.is_finite() && args.weld_mm >= 0.0) {
        bail!(
            "--weld-mm must be a finite distance ≥ 0 in mm, got {}",
            args.weld_mm
        );
    }
    let mut outputs = vec![("OUT", args.output.as_path())];
    outputs.extend(args.report.as_deref().map(|r| ("--report", r)));
    crate::util::refuse_overwrite(&[("IN", &args.input)], &outputs)?;
    let loaded =
        flatcut_io::read_mesh(&args.input, crate::util::units_for(&args.input, args.units))?;
    let opts = CleanOptions {
        weld_tolerance_mm: args.weld_mm,
        keep: match args.keep {
            KeepArg::Largest => Keep::Largest,
            KeepArg::All => Keep::All,
        },
        ..CleanOptions::default()
    };
    let (cleaned, report, _map) =
        clean(&loaded.mesh, &opts).with_context(|| format!("cleaning {}", args.input.display()))?;
    flatcut_io::write_mesh(&args.output, &cleaned, &flatcut_io::WriteOptions::default())?;
    let json = serde_json::to_string_pretty(&report)?;
    if let Some(path) = &args.report {
        crate::util::write_text_atomic(path, &json)?;
    }
    let mut o = String::new();
    if args.json {
        outln!(o, "{json}");
    } else {
        outln!(
            o,
            "{}: {} vertices, {} faces",
            args.output.display(),
            cleaned.positions.len(),
            cleaned.faces.len()
        );
        let r = &report;
        outln!(o, "  welded vertices        {}", r.welded_vertices);
        outln!(o, "  welds refused (pinch)  {}", r.refused_welds);
        outln!(o, "  degenerate faces       {}", r.degenerate_faces);
        outln!(o, "  duplicate faces        {}", r.duplicate_faces);
        outln!(o, "  flipped faces          {}", r.flipped_faces);
        outln!(o, "  unorientable parts     {}", r.unorientable_components);
        outln!(
            o,
            "  dropped components     {} ({} faces)",
            r.dropped_components,
            r.dropped_component_faces
        );
        outln!(o, "  unreferenced vertices  {}", r.unreferenced_vertices);
        outln!(o, "  faces dropped in all   {}", r.dropped_faces);
    }
    crate::util::emit(&o)
}
