//! `flatcut trim IN --cuts CUTS.toml --out DIR`: cut a surface along lines drawn on it into
//! named pieces, one `<name>.obj` each (mm), with the seam ledger `seams.json` and the full
//! report `trim_report.json` (every face's fate).

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use flatcut_io::Units;
use flatcut_trim::{Cuts, trim};

/// Arguments of `flatcut trim`.
#[derive(clap::Args, Debug)]
pub struct TrimArgs {
    /// Input mesh file (.obj, .ply, .stl, .gltf, .glb); never modified.
    pub input: PathBuf,
    /// The cut description (TOML): `units`, `[[cut]]` lines, `[[piece]]` seeds, `[options]`.
    #[arg(long)]
    pub cuts: PathBuf,
    /// Output folder (created if missing): `<piece>.obj` per kept piece, `seams.json`,
    /// `trim_report.json`.
    #[arg(long)]
    pub out: PathBuf,
    /// Print the summary as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Line and column (1-based) of a byte offset in `text`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Reads and parses CUTS.toml, errors with file, line and column.
pub fn read_cuts(path: &Path) -> anyhow::Result<Cuts> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the cut description {}", path.display()))?;
    toml::from_str::<Cuts>(&text).map_err(|e| {
        let at = e.span().map(|s| line_col(&text, s.start));
        match at {
            Some((l, c)) => {
                anyhow::anyhow!("{}:{l}:{c}: {}", path.display(), e.message().trim_end())
            }
            None => anyhow::anyhow!("{}: {}", path.display(), e.message().trim_end()),
        }
    })
}

/// A piece name must be usable as a file name.
fn check_piece_name(name: &str, cuts: &Path) -> anyhow::Result<()> {
    let ok = !name.is_empty()
        && name != "."
        && name != ".."
        && name != "seams"
        && name != "trim_report"
        && name
            .chars()
            .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '.' | ' '));
    if !ok {
        bail!(
            "{}: piece name {name:?} cannot be a file name; use letters, digits, '-', '_' or '.' (and not \"seams\" or \"trim_report\")",
            cuts.display()
        );
    }
    Ok(())
}

/// Runs `flatcut trim`.
pub fn run(args: &TrimArgs) -> anyhow::Result<()> {
    let mut cuts = read_cuts(&args.cuts)?;
    let units = match &cuts.units {
        Some(u) => u
            .parse::<Units>()
            .map_err(|e| anyhow::anyhow!("{}: key `units`: {e}", args.cuts.display()))?,
        None => crate::util::units_for(&args.input, None),
    };
    for p in &cuts.pieces {
        check_piece_name(&p.name, &args.cuts)?;
    }
    let files: Vec<(String, PathBuf)> = cuts
        .pieces
        .iter()
        .map(|p| {
            (
                format!("piece {:?}", p.name),
                args.out.join(format!("{}.obj", p.name)),
            )
        })
        .chain(["seams.json", "trim_report.json"].map(|f| (f.to_string(), args.out.join(f))))
        .collect();
    let outputs: Vec<(&str, &Path)> = files
        .iter()
        .map(|(w, p)| (w.as_str(), p.as_path()))
        .collect();
    crate::util::refuse_overwrite(&[("IN", &args.input), ("CUTS", &args.cuts)], &outputs)?;
    let loaded = flatcut_io::read_mesh(&args.input, units)?;
    cuts.scale(units.factor_to_mm());
    let t = trim(&loaded.mesh, &cuts).with_context(|| {
        format!(
            "cutting {} along {}",
            args.input.display(),
            args.cuts.display()
        )
    })?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the output folder {}", args.out.display()))?;
    let wopts = flatcut_io::WriteOptions {
        units: Some(Units::Mm),
        ..Default::default()
    };
    for p in &t.pieces {
        let path = args.out.join(format!("{}.obj", p.name));
        flatcut_io::write_mesh(&path, &p.mesh, &wopts)?;
    }
    let seams = serde_json::to_string_pretty(&t.ledger)?;
    crate::util::write_text_atomic(&args.out.join("seams.json"), &seams)?;
    let report = serde_json::to_string(&t.report)?;
    crate::util::write_text_atomic(&args.out.join("trim_report.json"), &report)?;

    let r = &t.report;
    let split_faces = r.face_fates.iter().filter(|f| f.len() > 1).count();
    let mut o = String::new();
    if args.json {
        let summary = serde_json::json!({
            "output": args.out,
            "source_faces": r.source_faces,
            "source_area_mm2": r.source_area_mm2,
            "split_faces": split_faces,
            "pieces": r.pieces,
            "lines": r.lines,
            "seams": t.ledger.seams.iter().map(|s| serde_json::json!({
                "id": s.id, "a": s.a.piece, "b": s.b.piece, "length_3d_mm": s.length_3d_mm,
            })).collect::<Vec<_>>(),
            "unsewn_edges": r.unsewn_edges,
        });
        outln!(o, "{}", serde_json::to_string_pretty(&summary)?);
    } else {
        outln!(
            o,
            "{}: {} faces cut by {} lines ({} faces split) into {} pieces ({} kept)",
            args.input.display(),
            r.source_faces,
            r.lines.len(),
            split_faces,
            r.pieces.len(),
            t.pieces.len()
        );
        for l in &r.lines {
            outln!(
                o,
                "  line  {:<20} {:>10.1} mm  {}",
                l.name,
                l.length_mm,
                if l.closed { "closed" } else { "open" }
            );
        }
        for p in &r.pieces {
            outln!(
                o,
                "  piece {:<20} {:>7} faces {:>12.0} mm²  loops {} genus {}{}{}",
                p.name,
                p.faces,
                p.area_mm2,
                p.boundary_loops,
                p.genus,
                if p.disk { "" } else { "  NOT A DISK" },
                if p.kept {
                    ""
                } else {
                    "  (dropped: no seed names it)"
                }
            );
        }
        outln!(
            o,
            "  {} seams in {}",
            t.ledger.seams.len(),
            args.out.join("seams.json").display()
        );
        if r.unsewn_edges > 0 {
            outln!(
                o,
                "  {} cut edges are on the boundary or beside a dropped piece (in no seam)",
                r.unsewn_edges
            );
        }
    }
    crate::util::emit(&o)
}
