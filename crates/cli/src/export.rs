//! `flatcut export PIECES... --out DIR`: flattened pieces to what the cutting room uses —
//! SVG (per piece and a sheet), DXF (AAMA), PNG and EXR distortion maps, a tiled print PDF
//! and GLB colour maps of the 3D pieces.
//!
//! Each PIECE is `FLAT` or `FLAT=3D`: FLAT is a flattened piece as `flatcut flatten` writes it
//! (`v x y 0` in mm, the 3D piece's faces in its order); 3D is the piece it was flattened from,
//! which gives the distortion maps (without it the piece is taken as flat and its maps are
//! refused). The piece is named after 3D's file stem (FLAT's when alone), as the seam ledger
//! names it. Every file is written atomically; on an error nothing is left under a final name.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use flatcut_export::{
    DxfOptions, DxfVersion, ExrOptions, Field, Paper, PdfOptions, PngOptions, SvgOptions,
};
use flatcut_io::Units;
use flatcut_mesh::{SeamLedger, TriMesh};
use flatcut_pattern::{LayoutOptions, PatternOptions, PatternPiece, PieceInput, PieceMeta};
use serde::Serialize;

/// The formats `--formats` accepts.
const FORMATS: [&str; 6] = ["svg", "png", "exr", "dxf", "pdf", "glb"];
/// A flattened piece's z may differ from 0 by this much (mm) and still be flat: OBJ decimals.
const FLAT_Z_MM: f64 = 1e-6;

/// Arguments of `flatcut export`.
#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// Pieces: `FLAT` or `FLAT=3D` (the flattened OBJ and the 3D piece it came from).
    #[arg(required = true)]
    pub pieces: Vec<String>,
    /// Output directory (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// The seam ledger (seams.json) of these pieces: notches on mates, darts, per-seam widths.
    #[arg(long)]
    pub seams: Option<PathBuf>,
    /// Per-piece metadata as JSON: `{"NAME": {"size": "38", "quantity": 2, "mirror": true,
    /// "fabric": "neoprene", "grain_3d": [0, 1, 0], "shrink_along_grain": 0,
    /// "shrink_across_grain": -0.05}}` (every field optional).
    #[arg(long)]
    pub meta: Option<PathBuf>,
    /// Pattern options as JSON (the fields of `flatcut_pattern::PatternOptions`: seam_overrides,
    /// free_edge_allowance_mm, corner, dart_corner, hem_corner, notch_spacing_mm, ...).
    #[arg(long)]
    pub pattern_options: Option<PathBuf>,
    /// Seam allowance, mm (overrides the options file; default 10).
    #[arg(long, allow_negative_numbers = true)]
    pub seam_allowance_mm: Option<f64>,
    /// Comma-separated formats: svg, png, exr, dxf, pdf, glb (png, exr and glb need FLAT=3D).
    #[arg(long, default_value = "svg,dxf,pdf")]
    pub formats: String,
    /// Units of the 3D pieces (default: mm, m for glTF). Flattened pieces are always mm.
    #[arg(long, value_parser = crate::util::parse_units)]
    pub units: Option<Units>,
    /// Sheet (fabric) width for the layout, mm.
    #[arg(long, default_value_t = 1500.0)]
    pub sheet_width_mm: f64,
    /// PNG resolution, pixels per mm.
    #[arg(long, default_value_t = 2.0)]
    pub px_per_mm: f64,
    /// Paper of the tiled PDF: a4 or letter.
    #[arg(long, default_value = "a4", value_parser = parse_paper)]
    pub paper: Paper,
    /// DXF version: r12 (AAMA strict) or r13.
    #[arg(long, default_value = "r12", value_parser = parse_dxf)]
    pub dxf_version: DxfVersion,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

fn parse_paper(s: &str) -> Result<Paper, String> {
    match s.to_ascii_lowercase().as_str() {
        "a4" => Ok(Paper::A4),
        "letter" => Ok(Paper::Letter),
        _ => Err(format!("unknown paper '{s}': use a4 or letter")),
    }
}

fn parse_dxf(s: &str) -> Result<DxfVersion, String> {
    match s.to_ascii_lowercase().as_str() {
        "r12" => Ok(DxfVersion::R12),
        "r13" => Ok(DxfVersion::R13),
        _ => Err(format!("unknown DXF version '{s}': use r12 or r13")),
    }
}

/// The formats asked for, checked.
fn formats(s: &str) -> anyhow::Result<BTreeSet<&'static str>> {
    let mut out = BTreeSet::new();
    for f in s.split(',').map(str::trim).filter(|f| !f.is_empty()) {
        let known = FORMATS
            .iter()
            .find(|k| k.eq_ignore_ascii_case(f))
            .with_context(|| {
                format!(
                    "unknown format '{f}' in --formats: use some of {}",
                    FORMATS.join(",")
                )
            })?;
        out.insert(*known);
    }
    if out.is_empty() {
        bail!("--formats is empty: use some of {}", FORMATS.join(","));
    }
    Ok(out)
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "piece".into())
}

/// Reads one PIECE argument.
fn read_piece(arg: &str, units: Option<Units>) -> anyhow::Result<PieceInput> {
    let (flat_path, solid_path) = match arg.split_once('=') {
        Some((f, s)) => (PathBuf::from(f), Some(PathBuf::from(s))),
        None => (PathBuf::from(arg), None),
    };
    let flat = flatcut_io::read_mesh(&flat_path, Units::Mm)
        .with_context(|| format!("cannot read the flattened piece {}", flat_path.display()))?
        .mesh;
    if let Some(v) = flat.positions.iter().position(|p| p[2].abs() > FLAT_Z_MM) {
        bail!(
            "{}: vertex {v} has z = {} — not a flattened piece (give the file `flatcut flatten` writes, then `=` and the 3D piece)",
            flat_path.display(),
            flat.positions[v][2]
        );
    }
    let uv: Vec<[f64; 2]> = flat.positions.iter().map(|p| [p[0], p[1]]).collect();
    let (name, mesh) = match &solid_path {
        Some(s) => {
            let solid = flatcut_io::read_mesh(s, crate::util::units_for(s, units))
                .with_context(|| format!("cannot read the 3D piece {}", s.display()))?
                .mesh;
            if solid.positions.len() != flat.positions.len() || solid.faces != flat.faces {
                bail!(
                    "{} ({} vertices, {} faces) and {} ({} vertices, {} faces) are not the same piece: give the 3D file that was flattened",
                    flat_path.display(),
                    flat.positions.len(),
                    flat.faces.len(),
                    s.display(),
                    solid.positions.len(),
                    solid.faces.len()
                );
            }
            (stem(s), solid)
        }
        None => (stem(&flat_path), flat.clone()),
    };
    let (mut e_h, mut e_r, mut strain) = (Vec::new(), Vec::new(), Vec::new());
    if solid_path.is_some() {
        for f in &mesh.faces {
            let p = f.map(|v| mesh.positions[v as usize]);
            let q = f.map(|v| uv[v as usize]);
            let d = flatcut_lscm::metrics::face_distortion(p, q);
            e_h.push(d.e_h);
            e_r.push(d.e_r);
            strain.push(d.edge_strain);
        }
    }
    Ok(PieceInput {
        name,
        mesh,
        uv,
        meta: PieceMeta::default(),
        internal_lines: Vec::new(),
        e_h,
        e_r,
        edge_strain: strain,
    })
}

#[derive(Serialize)]
struct SeamReport {
    id: String,
    side: &'static str,
    length_2d_mm: f64,
    mate_length_2d_mm: f64,
    allowance_mm: f64,
}

#[derive(Serialize)]
struct PieceReport {
    name: String,
    sew_length_mm: f64,
    area_mm2: f64,
    shrink: flatcut_pattern::ShrinkReport,
    notches: usize,
    darts: usize,
    seams: Vec<SeamReport>,
}

#[derive(Serialize)]
struct Report {
    out: String,
    seam_allowance_mm: f64,
    sheet_width_mm: f64,
    sheet_height_mm: f64,
    pieces: Vec<PieceReport>,
    files: Vec<String>,
}

/// A piece's per-vertex E_h (area-weighted mean of its faces), for the GLB colour map.
fn vertex_e_h(p: &PatternPiece) -> Vec<f64> {
    let mut sum = vec![0.0; p.mesh.positions.len()];
    let mut w = vec![0.0; p.mesh.positions.len()];
    for (f, face) in p.mesh.faces.iter().enumerate() {
        let [a, b, c] = face.map(|v| p.mesh.positions[v as usize]);
        let area = 0.5
            * flatcut_mesh::vec3::norm(flatcut_mesh::vec3::cross(
                flatcut_mesh::vec3::sub(b, a),
                flatcut_mesh::vec3::sub(c, a),
            ));
        for &v in face {
            sum[v as usize] += area * p.e_h[f];
            w[v as usize] += area;
        }
    }
    sum.iter()
        .zip(&w)
        .map(|(s, w)| if *w > 0.0 { s / w } else { 0.0 })
        .collect()
}

/// Runs `flatcut export`.
pub fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let fmts = formats(&args.formats)?;
    let mut inputs: Vec<PieceInput> = args
        .pieces
        .iter()
        .map(|a| read_piece(a, args.units))
        .collect::<anyhow::Result<_>>()?;
    let mut names = BTreeSet::new();
    for p in &inputs {
        if !names.insert(p.name.as_str()) {
            bail!(
                "two pieces are named '{}' (from their file names): rename one",
                p.name
            );
        }
    }
    if let Some(path) = &args.meta {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let mut meta: std::collections::BTreeMap<String, PieceMeta> = serde_json::from_str(&text)
            .with_context(|| {
            format!(
                "{}: not a piece-metadata JSON object (name → fields)",
                path.display()
            )
        })?;
        for p in &mut inputs {
            if let Some(m) = meta.remove(&p.name) {
                p.meta = m;
            }
        }
        if let Some(name) = meta.keys().next() {
            bail!(
                "{}: piece '{name}' is not among the pieces given (they are named after their files)",
                path.display()
            );
        }
    }
    let ledger: Option<SeamLedger> =
        match &args.seams {
            Some(path) => {
                let text = std::fs::read_to_string(path)
                    .with_context(|| format!("cannot read {}", path.display()))?;
                Some(serde_json::from_str(&text).with_context(|| {
                    format!("{} is not a seam ledger (seams.json)", path.display())
                })?)
            }
            None => None,
        };
    if fmts.contains("png") || fmts.contains("exr") || fmts.contains("glb") {
        if let Some((arg, _)) = args
            .pieces
            .iter()
            .zip(&inputs)
            .find(|(_, p)| p.e_h.is_empty())
        {
            bail!(
                "piece '{arg}': png, exr and glb show the distortion, which needs the 3D piece: give FLAT=3D, or leave those formats out"
            );
        }
    }
    let mut opts: PatternOptions = match &args.pattern_options {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            serde_json::from_str(&text)
                .with_context(|| format!("{}: not valid pattern options", path.display()))?
        }
        None => PatternOptions::default(),
    };
    if let Some(w) = args.seam_allowance_mm {
        opts.seam_allowance_mm = w;
    }
    let pieces = flatcut_pattern::build_pieces(&inputs, ledger.as_ref(), &opts)?;
    let layout = flatcut_pattern::layout(
        &pieces,
        &LayoutOptions {
            sheet_width_mm: args.sheet_width_mm,
            ..Default::default()
        },
    )?;

    // Make every file in memory first, so a failure leaves nothing behind.
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    let out = &args.out;
    let svg = SvgOptions::default();
    let png = PngOptions {
        px_per_mm: args.px_per_mm,
        ..Default::default()
    };
    for p in &pieces {
        let base = flatcut_export::text::ident(&p.name);
        if fmts.contains("svg") {
            files.push((
                out.join(format!("{base}.svg")),
                flatcut_export::piece_svg(p, &svg),
            ));
        }
        if fmts.contains("png") {
            for field in [Field::EH, Field::ER, Field::EdgeStrain] {
                let bytes = flatcut_export::piece_png(
                    p,
                    &PngOptions {
                        field,
                        ..png.clone()
                    },
                )?;
                files.push((out.join(format!("{base}-{}.png", field.name())), bytes));
            }
        }
        if fmts.contains("exr") {
            let bytes = flatcut_export::piece_exr(
                p,
                &ExrOptions {
                    pixel_mm: 1.0 / args.px_per_mm,
                },
            )?;
            files.push((out.join(format!("{base}.exr")), bytes));
        }
    }
    if fmts.contains("svg") {
        files.push((
            out.join("sheet.svg"),
            flatcut_export::sheet_svg(&pieces, &layout, &svg),
        ));
    }
    if fmts.contains("png") {
        files.push((
            out.join("sheet.png"),
            flatcut_export::sheet_png(&pieces, &layout, &png)?,
        ));
    }
    if fmts.contains("dxf") {
        let bytes = flatcut_export::dxf_aama(
            &pieces,
            &layout,
            &DxfOptions {
                version: args.dxf_version,
            },
        )?;
        files.push((out.join("pattern.dxf"), bytes));
    }
    if fmts.contains("pdf") {
        let opts = PdfOptions {
            paper: args.paper,
            ..Default::default()
        };
        files.push((
            out.join("sheet-tiled.pdf"),
            flatcut_export::tiled_pdf(&pieces, &layout, &opts)?,
        ));
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut written = Vec::new();
    for (path, bytes) in &files {
        crate::util::write_bytes_atomic(path, bytes)?;
        written.push(path.display().to_string());
    }
    if fmts.contains("glb") {
        for p in &pieces {
            let mesh = TriMesh {
                attributes: flatcut_mesh::VertexAttributes {
                    scalar: Some(vertex_e_h(p)),
                    ..Default::default()
                },
                ..p.mesh.clone()
            };
            let path = out.join(format!("{}-e_h.glb", flatcut_export::text::ident(&p.name)));
            flatcut_io::write_mesh(&path, &mesh, &flatcut_io::WriteOptions::default())?;
            written.push(path.display().to_string());
        }
    }

    let report = Report {
        out: out.display().to_string(),
        seam_allowance_mm: opts.seam_allowance_mm,
        sheet_width_mm: layout.width_mm,
        sheet_height_mm: layout.height_mm,
        pieces: pieces
            .iter()
            .map(|p| PieceReport {
                name: p.name.clone(),
                sew_length_mm: flatcut_pattern::geom::polyline_length(&p.sew_line)
                    + p.sew_line
                        .first()
                        .zip(p.sew_line.last())
                        .map_or(0.0, |(a, b)| flatcut_pattern::geom::dist(*a, *b)),
                area_mm2: p.shrink.area_after_mm2,
                shrink: p.shrink,
                notches: p.notches.len(),
                darts: p.darts.len(),
                seams: p
                    .seams
                    .iter()
                    .map(|s| SeamReport {
                        id: s.id.clone(),
                        side: s.side,
                        length_2d_mm: s.length_2d_mm,
                        mate_length_2d_mm: s.mate_length_2d_mm,
                        allowance_mm: s.allowance_mm,
                    })
                    .collect(),
            })
            .collect(),
        files: written,
    };
    let mut o = String::new();
    if args.json {
        outln!(o, "{}", serde_json::to_string_pretty(&report)?);
        return crate::util::emit(&o);
    }
    outln!(
        o,
        "sheet                {:.1} × {:.1} mm",
        report.sheet_width_mm,
        report.sheet_height_mm
    );
    for p in &report.pieces {
        outln!(
            o,
            "piece {:<14} sew line {:.1} mm, area {:.0} mm2, {} notches, {} darts",
            p.name,
            p.sew_length_mm,
            p.area_mm2,
            p.notches,
            p.darts
        );
        for s in &p.seams {
            outln!(
                o,
                "  seam {:<16} side {} {:.2} mm, mate {:.2} mm (difference {:+.2} mm)",
                s.id,
                s.side,
                s.length_2d_mm,
                s.mate_length_2d_mm,
                s.length_2d_mm - s.mate_length_2d_mm
            );
        }
    }
    for f in &report.files {
        outln!(o, "wrote {f}");
    }
    crate::util::emit(&o)
}
