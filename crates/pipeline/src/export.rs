//! The pattern and export stages: flattened pieces (+ the seam ledger) become pattern pieces
//! (crates/pattern: seam allowance, notches, grain, label, shrink), laid out on a sheet, and
//! written in the formats `[export].formats` asks for (crates/export), all as bytes.

use std::collections::BTreeMap;

use flatcut_export::{
    DxfOptions, ExrOptions, PdfOptions, PngOptions, SvgOptions, dxf_aama, piece_exr, piece_png,
    piece_svg, sheet_png, sheet_svg, tiled_pdf,
};
use flatcut_mesh::SeamLedger;
use flatcut_pattern::{
    Layout, LayoutOptions, PatternOptions, PatternPiece, PieceInput, build_pieces, layout,
};
use serde::{Deserialize, Serialize};

use crate::PipelineError;

/// An output format of `[export].formats`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ExportFormat {
    /// `pieces/<name>.svg` and `sheet.svg` (true scale, layers).
    Svg,
    /// `pieces/<name>.png` (distortion map) and `sheet.png`.
    Png,
    /// `pieces/<name>.exr` (float E_h and E_r rasters).
    Exr,
    /// `pieces/<name>.dxf` and `pattern.dxf` (AAMA/ASTM D6673 style).
    Dxf,
    /// `sheet.pdf`, tiled for a home printer.
    Pdf,
    /// `processed.glb`: the processed 3D pieces coloured by |θ − 2π|.
    Glb,
}

/// `[export]`: which files, and each writer's options (`[export.svg]`, `[export.png]`, …).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExportSpec {
    /// Formats to write (default: all of svg, png, exr, dxf, pdf, glb).
    pub formats: Vec<ExportFormat>,
    /// [`flatcut_export::SvgOptions`].
    pub svg: SvgOptions,
    /// [`flatcut_export::PngOptions`].
    pub png: PngOptions,
    /// [`flatcut_export::ExrOptions`].
    pub exr: ExrOptions,
    /// [`flatcut_export::DxfOptions`].
    pub dxf: DxfOptions,
    /// [`flatcut_export::PdfOptions`].
    pub pdf: PdfOptions,
}

impl Default for ExportSpec {
    fn default() -> Self {
        Self {
            // Every format; the EXR writer is byte-identical from run to run (see
            // flatcut_export::piece_exr), like the others.
            formats: vec![
                ExportFormat::Svg,
                ExportFormat::Png,
                ExportFormat::Exr,
                ExportFormat::Dxf,
                ExportFormat::Pdf,
                ExportFormat::Glb,
            ],
            svg: SvgOptions::default(),
            png: PngOptions::default(),
            exr: ExrOptions::default(),
            dxf: DxfOptions::default(),
            pdf: PdfOptions::default(),
        }
    }
}

impl ExportSpec {
    /// Whether `f` is asked for.
    pub fn wants(&self, f: ExportFormat) -> bool {
        self.formats.contains(&f)
    }
}

/// The pattern pieces, their layout, and the files.
pub struct Exported {
    /// Pattern pieces in piece order.
    pub pieces: Vec<PatternPiece>,
    /// The sheet.
    pub layout: Layout,
    /// Files by name inside the output folder.
    pub files: BTreeMap<String, Vec<u8>>,
}

fn export_err(what: &str, source: flatcut_export::ExportError) -> PipelineError {
    PipelineError::Export {
        file: what.to_string(),
        source: Box::new(source),
    }
}

/// Builds the pattern pieces and writes the files.
pub fn export(
    inputs: &[PieceInput],
    ledger: &SeamLedger,
    pattern: &PatternOptions,
    layout_opts: &LayoutOptions,
    spec: &ExportSpec,
) -> Result<Exported, PipelineError> {
    let ledger = (!ledger.seams.is_empty()).then_some(ledger);
    let pieces =
        build_pieces(inputs, ledger, pattern).map_err(|source| PipelineError::Pattern {
            source: Box::new(source),
        })?;
    let sheet = layout(&pieces, layout_opts).map_err(|source| PipelineError::Pattern {
        source: Box::new(source),
    })?;
    let mut files = BTreeMap::new();
    for p in &pieces {
        let stem = format!("pieces/{}", p.name);
        if spec.wants(ExportFormat::Svg) {
            files.insert(format!("{stem}.svg"), piece_svg(p, &spec.svg));
        }
        if spec.wants(ExportFormat::Png) {
            let name = format!("{stem}.png");
            let bytes = piece_png(p, &spec.png).map_err(|e| export_err(&name, e))?;
            files.insert(name, bytes);
        }
        if spec.wants(ExportFormat::Exr) {
            let name = format!("{stem}.exr");
            let bytes = piece_exr(p, &spec.exr).map_err(|e| export_err(&name, e))?;
            files.insert(name, bytes);
        }
        if spec.wants(ExportFormat::Dxf) {
            let name = format!("{stem}.dxf");
            let one = std::slice::from_ref(p);
            let l = layout(one, layout_opts).map_err(|source| PipelineError::Pattern {
                source: Box::new(source),
            })?;
            let bytes = dxf_aama(one, &l, &spec.dxf).map_err(|e| export_err(&name, e))?;
            files.insert(name, bytes);
        }
    }
    if spec.wants(ExportFormat::Svg) {
        files.insert("sheet.svg".into(), sheet_svg(&pieces, &sheet, &spec.svg));
    }
    if spec.wants(ExportFormat::Png) {
        let bytes =
            sheet_png(&pieces, &sheet, &spec.png).map_err(|e| export_err("sheet.png", e))?;
        files.insert("sheet.png".into(), bytes);
    }
    if spec.wants(ExportFormat::Dxf) {
        let bytes =
            dxf_aama(&pieces, &sheet, &spec.dxf).map_err(|e| export_err("pattern.dxf", e))?;
        files.insert("pattern.dxf".into(), bytes);
    }
    if spec.wants(ExportFormat::Pdf) {
        let bytes =
            tiled_pdf(&pieces, &sheet, &spec.pdf).map_err(|e| export_err("sheet.pdf", e))?;
        files.insert("sheet.pdf".into(), bytes);
    }
    Ok(Exported {
        pieces,
        layout: sheet,
        files,
    })
}
