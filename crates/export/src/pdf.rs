//! A tiled print PDF of the sheet for a home printer: pages of A4 or Letter overlapping by a
//! set amount, registration marks at the corners of every tile, a page label ("row 1 col 2,
//! page 2 of 6"), and the sheet's 50 mm test square to check the print scale. A small
//! hand-written PDF 1.4 (uncompressed content, the standard Helvetica font).

use std::fmt::Write as _;

use flatcut_pattern::{Layout, PatternPiece, TEST_SQUARE_MM};
use serde::{Deserialize, Serialize};

use crate::ExportError;
use crate::text::ascii7;

/// Points per mm.
const PT_PER_MM: f64 = 72.0 / 25.4;
/// Mean advance of a Helvetica character, as a fraction of the font size.
const HELVETICA_ADVANCE: f64 = 0.55;
/// Radius of the registration circles, mm.
const MARK_MM: f64 = 4.0;

/// Paper size.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Paper {
    /// 210 × 297 mm (default).
    #[default]
    A4,
    /// 8.5 × 11 in.
    Letter,
}

impl Paper {
    /// Width and height, mm.
    pub fn size_mm(self) -> [f64; 2] {
        match self {
            Paper::A4 => [210.0, 297.0],
            Paper::Letter => [215.9, 279.4],
        }
    }
}

/// Options of [`tiled_pdf`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PdfOptions {
    /// Paper (default A4).
    pub paper: Paper,
    /// Unprintable margin kept blank on every side, mm (default 10).
    pub margin_mm: f64,
    /// Overlap of neighbouring tiles, mm (default 15).
    pub overlap_mm: f64,
}

impl Default for PdfOptions {
    fn default() -> Self {
        Self {
            paper: Paper::A4,
            margin_mm: 10.0,
            overlap_mm: 15.0,
        }
    }
}

/// The tiles: how many columns and rows, and the sheet origin (mm) of tile (row, col)'s
/// printable area lower-left corner.
pub fn tiles(layout: &Layout, opts: &PdfOptions) -> Result<(usize, usize, f64, f64), ExportError> {
    let [pw, ph] = opts.paper.size_mm();
    let (aw, ah) = (pw - 2.0 * opts.margin_mm, ph - 2.0 * opts.margin_mm);
    if !(opts.margin_mm.is_finite() && opts.margin_mm >= 0.0 && aw > 50.0 && ah > 50.0) {
        return Err(ExportError::BadOption {
            what: "margin_mm",
            value: opts.margin_mm,
            hint: "use a margin ≥ 0 mm leaving more than 50 mm printable",
        });
    }
    if !(opts.overlap_mm.is_finite()
        && opts.overlap_mm >= 0.0
        && opts.overlap_mm < 0.5 * aw.min(ah))
    {
        return Err(ExportError::BadOption {
            what: "overlap_mm",
            value: opts.overlap_mm,
            hint: "use an overlap ≥ 0 mm and under half the printable area",
        });
    }
    let (sx, sy) = (aw - opts.overlap_mm, ah - opts.overlap_mm);
    let count = |len: f64, a: f64, s: f64| (((len - a) / s).ceil().max(0.0) as usize) + 1;
    Ok((
        count(layout.width_mm, aw, sx),
        count(layout.height_mm, ah, sy),
        sx,
        sy,
    ))
}

fn pdf_string(s: &str) -> String {
    ascii7(s)
        .replace('\\', "\\\\")
        .replace('(', "\\(")
        .replace(')', "\\)")
}

fn poly(o: &mut String, pts: &[[f64; 2]], closed: bool) {
    for (i, p) in pts.iter().enumerate() {
        let _ = write!(
            o,
            "{:.3} {:.3} {} ",
            p[0],
            p[1],
            if i == 0 { "m" } else { "l" }
        );
    }
    o.push_str(if closed { "h S\n" } else { "S\n" });
}

/// The sheet, drawn in sheet mm (y up) — shared by every page, which only moves and clips it.
fn sheet_drawing(pieces: &[PatternPiece], layout: &Layout) -> String {
    let mut o = String::new();
    let ts = layout.test_square;
    let _ = writeln!(
        o,
        "0 0 1 rg {:.3} {:.3} {s:.3} {s:.3} re f",
        ts[0],
        ts[1],
        s = TEST_SQUARE_MM
    );
    let _ = writeln!(
        o,
        "BT /F1 5 Tf 1 1 1 rg {:.3} {:.3} Td (50 mm test square) Tj ET",
        ts[0] + 3.0,
        ts[1] + 3.0
    );
    for pl in &layout.placements {
        let piece = &pieces[pl.piece];
        let m = |l: &[[f64; 2]]| l.iter().map(|p| pl.map(*p)).collect::<Vec<_>>();
        o.push_str("1 0 0 RG 0.2 w\n");
        poly(&mut o, &m(&piece.cut_line), true);
        for nt in &piece.notches {
            poly(&mut o, &m(&[nt.cut, nt.inner]), false);
        }
        o.push_str("0 0 0 RG 0.3 w [2 1] 0 d\n");
        poly(&mut o, &m(&piece.sew_line), true);
        o.push_str("[] 0 d 0 0 1 RG\n");
        poly(&mut o, &m(&piece.grain_line), false);
        o.push_str("0 0.5 0 RG\n");
        for d in &piece.darts {
            for leg in &d.legs {
                poly(&mut o, &m(leg), false);
            }
        }
        o.push_str("0.5 g 0.5 G\n");
        for l in &piece.internal_lines {
            poly(&mut o, &m(l), false);
        }
        let h = piece.label.height_mm;
        for (k, line) in piece.label.lines.iter().enumerate() {
            let mut p = pl.map([piece.label.at[0], piece.label.at[1] - 1.4 * h * k as f64]);
            if pl.mirrored {
                // The start lands on the right on a mirrored copy: run the text leftwards
                // (Helvetica's mean advance is about half the text height).
                p[0] -= HELVETICA_ADVANCE * h * line.chars().count() as f64;
            }
            let _ = writeln!(
                o,
                "BT /F1 {h:.2} Tf 0 g {:.3} {:.3} Td ({}) Tj ET",
                p[0],
                p[1],
                pdf_string(line)
            );
        }
    }
    o
}

/// The tiled PDF.
pub fn tiled_pdf(
    pieces: &[PatternPiece],
    layout: &Layout,
    opts: &PdfOptions,
) -> Result<Vec<u8>, ExportError> {
    let (cols, rows, sx, sy) = tiles(layout, opts)?;
    let [pw, ph] = opts.paper.size_mm();
    let m = opts.margin_mm;
    let (aw, ah) = (pw - 2.0 * m, ph - 2.0 * m);
    let drawing = sheet_drawing(pieces, layout);
    let n = rows * cols;
    let mut objects: Vec<String> = Vec::new();
    objects.push("<< /Type /Catalog /Pages 2 0 R >>".into());
    let kids: Vec<String> = (0..n).map(|i| format!("{} 0 R", 4 + 2 * i)).collect();
    objects.push(format!(
        "<< /Type /Pages /Kids [{}] /Count {n} >>",
        kids.join(" ")
    ));
    objects.push("<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica >>".into());
    let mut page = 0;
    for r in 0..rows {
        for c in 0..cols {
            page += 1;
            // Rows count from the top of the sheet, as the pages are read.
            let x0 = c as f64 * sx;
            let y0 = layout.height_mm - ah - r as f64 * sy;
            let mut s = String::new();
            let _ = writeln!(s, "{k:.6} 0 0 {k:.6} 0 0 cm", k = PT_PER_MM);
            let _ = writeln!(s, "q {m:.3} {m:.3} {aw:.3} {ah:.3} re W n");
            let _ = writeln!(s, "1 0 0 1 {:.3} {:.3} cm", m - x0, m - y0);
            s.push_str(&drawing);
            s.push_str("Q\n");
            // Registration marks: a circle and cross at each printable corner.
            s.push_str("0 G 0.2 w\n");
            for (cx, cy) in [(m, m), (m + aw, m), (m, m + ah), (m + aw, m + ah)] {
                let k = 0.5523 * MARK_MM;
                let rr = MARK_MM;
                let _ = writeln!(
                    s,
                    "{:.3} {:.3} m {:.3} {:.3} {:.3} {:.3} {:.3} {:.3} c {:.3} {:.3} {:.3} {:.3} {:.3} {:.3} c {:.3} {:.3} {:.3} {:.3} {:.3} {:.3} c {:.3} {:.3} {:.3} {:.3} {:.3} {:.3} c S",
                    cx + rr,
                    cy,
                    cx + rr,
                    cy + k,
                    cx + k,
                    cy + rr,
                    cx,
                    cy + rr,
                    cx - k,
                    cy + rr,
                    cx - rr,
                    cy + k,
                    cx - rr,
                    cy,
                    cx - rr,
                    cy - k,
                    cx - k,
                    cy - rr,
                    cx,
                    cy - rr,
                    cx + k,
                    cy - rr,
                    cx + rr,
                    cy - k,
                    cx + rr,
                    cy
                );
                let _ = writeln!(
                    s,
                    "{:.3} {:.3} m {:.3} {:.3} l S {:.3} {:.3} m {:.3} {:.3} l S",
                    cx - 1.5 * rr,
                    cy,
                    cx + 1.5 * rr,
                    cy,
                    cx,
                    cy - 1.5 * rr,
                    cx,
                    cy + 1.5 * rr
                );
            }
            let _ = writeln!(
                s,
                "BT /F1 3 Tf 0 g {:.3} {:.3} Td (row {} col {}, page {page} of {n}; overlap {:.0} mm) Tj ET",
                m + MARK_MM * 2.0,
                m * 0.4,
                r + 1,
                c + 1,
                opts.overlap_mm
            );
            let content = 5 + 2 * (page - 1);
            objects.push(format!(
                "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {:.3} {:.3}] /Resources << /Font << /F1 3 0 R >> >> /Contents {content} 0 R >>",
                pw * PT_PER_MM,
                ph * PT_PER_MM
            ));
            objects.push(format!("<< /Length {} >>\nstream\n{s}endstream", s.len()));
        }
    }
    let mut out = String::from("%PDF-1.4\n");
    let mut offsets = Vec::with_capacity(objects.len());
    for (i, obj) in objects.iter().enumerate() {
        offsets.push(out.len());
        let _ = write!(out, "{} 0 obj\n{obj}\nendobj\n", i + 1);
    }
    let xref = out.len();
    let _ = write!(out, "xref\n0 {}\n0000000000 65535 f \n", objects.len() + 1);
    for off in offsets {
        let _ = writeln!(out, "{off:010} 00000 n ");
    }
    let _ = write!(
        out,
        "trailer\n<< /Size {} /Root 1 0 R >>\nstartxref\n{xref}\n%%EOF\n",
        objects.len() + 1
    );
    Ok(out.into_bytes())
}
