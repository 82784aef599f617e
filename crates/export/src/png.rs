//! PNG pictures (tiny-skia): a piece filled with a per-triangle colour map of E_h, E_r or edge
//! strain, with a legend and a scale bar; and the sheet.

use flatcut_pattern::geom::bbox;
use flatcut_pattern::{Layout, PatternPiece, TEST_SQUARE_MM};
use serde::{Deserialize, Serialize};
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

use crate::ExportError;

/// Largest raster side (pixels): 16384 is what most viewers open.
pub const MAX_SIDE_PX: u64 = 16_384;

/// The smallest top of the colour ramp when it is taken from the data: 0.1 % distortion, far
/// below what fabric shows, so a numerically exact flattening (values ~1e-13) draws uniformly
/// dark instead of as amplified noise.
pub const MIN_RAMP_TOP: f64 = 1e-3;

/// The per-face value shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Field {
    /// Area distortion |σ₁σ₂ − 1| (default).
    #[default]
    EH,
    /// Shape distortion 1 − σ₂/σ₁.
    ER,
    /// Edge strain.
    EdgeStrain,
}

impl Field {
    /// The piece's values of this field (empty when unknown).
    pub fn values(self, piece: &PatternPiece) -> &[f64] {
        match self {
            Field::EH => &piece.e_h,
            Field::ER => &piece.e_r,
            Field::EdgeStrain => &piece.edge_strain,
        }
    }
    /// Short name for legends and file names.
    pub fn name(self) -> &'static str {
        match self {
            Field::EH => "e_h",
            Field::ER => "e_r",
            Field::EdgeStrain => "strain",
        }
    }
}

/// Options of the PNG writers.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PngOptions {
    /// Resolution, pixels per mm (default 2).
    pub px_per_mm: f64,
    /// Field shown.
    pub field: Field,
    /// Value mapped to the top of the colour ramp (default `None`: the field's maximum over
    /// the pieces drawn, at least [`MIN_RAMP_TOP`]; the bottom is always 0, where every
    /// measure means no distortion).
    pub max_value: Option<f64>,
}

impl Default for PngOptions {
    fn default() -> Self {
        Self {
            px_per_mm: 2.0,
            field: Field::EH,
            max_value: None,
        }
    }
}

/// Viridis, sampled at nine stops (linear RGB in between is close enough for a legend).
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// The colour of `t` in [0, 1] (clamped).
pub fn viridis(t: f64) -> [u8; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [0, 1, 2].map(|k| (a[k] as f64 + f * (b[k] as f64 - a[k] as f64)).round() as u8)
}

/// 3 × 5 pixel glyphs (rows top to bottom, 3 bits each, `#` = ink).
fn glyph(c: char) -> Option<[&'static str; 5]> {
    Some(match c {
        '0' => ["###", "#.#", "#.#", "#.#", "###"],
        '1' => [".#.", "##.", ".#.", ".#.", "###"],
        '2' => ["###", "..#", "###", "#..", "###"],
        '3' => ["###", "..#", ".##", "..#", "###"],
        '4' => ["#.#", "#.#", "###", "..#", "..#"],
        '5' => ["###", "#..", "###", "..#", "###"],
        '6' => ["###", "#..", "###", "#.#", "###"],
        '7' => ["###", "..#", ".#.", ".#.", ".#."],
        '8' => ["###", "#.#", "###", "#.#", "###"],
        '9' => ["###", "#.#", "###", "..#", "###"],
        '.' => ["...", "...", "...", "...", ".#."],
        '-' => ["...", "...", "###", "...", "..."],
        '+' => ["...", ".#.", "###", ".#.", "..."],
        '_' => ["...", "...", "...", "...", "###"],
        'e' => ["...", "###", "###", "#..", "###"],
        'm' => ["...", "##.", "###", "#.#", "#.#"],
        'h' => ["#..", "#..", "###", "#.#", "#.#"],
        'r' => ["...", "###", "#..", "#..", "#.."],
        's' => ["...", ".##", ".#.", "..#", "##."],
        't' => [".#.", "###", ".#.", ".#.", ".##"],
        'a' => ["...", "##.", ".##", "#.#", "###"],
        'i' => [".#.", "...", ".#.", ".#.", ".#."],
        'n' => ["...", "##.", "#.#", "#.#", "#.#"],
        ' ' => ["...", "...", "...", "...", "..."],
        _ => return None,
    })
}

/// Draws `text` with its top-left at (x, y), each font pixel `px` screen pixels.
fn draw_text(pm: &mut Pixmap, text: &str, x: f32, y: f32, px: f32, colour: Color) {
    let mut paint = Paint::default();
    paint.set_color(colour);
    for (k, c) in text.chars().enumerate() {
        let Some(g) = glyph(c) else { continue };
        for (r, row) in g.iter().enumerate() {
            for (col, b) in row.bytes().enumerate() {
                if b == b'#' {
                    let rx = x + (4 * k + col) as f32 * px;
                    if let Some(rect) = Rect::from_xywh(rx, y + r as f32 * px, px, px) {
                        pm.fill_rect(rect, &paint, Transform::identity(), None);
                    }
                }
            }
        }
    }
}

fn number(x: f64) -> String {
    if x != 0.0 && (x.abs() < 0.01 || x.abs() >= 1e4) {
        format!("{x:.2e}")
    } else {
        format!("{x:.3}")
    }
}

fn pixmap(w: f64, h: f64) -> Result<Pixmap, ExportError> {
    let (wi, hi) = (w.ceil().max(1.0) as u64, h.ceil().max(1.0) as u64);
    if wi > MAX_SIDE_PX || hi > MAX_SIDE_PX || !w.is_finite() || !h.is_finite() {
        return Err(ExportError::TooLarge {
            width: wi,
            height: hi,
            limit: MAX_SIDE_PX,
        });
    }
    let mut pm = Pixmap::new(wi as u32, hi as u32).ok_or(ExportError::TooLarge {
        width: wi,
        height: hi,
        limit: MAX_SIDE_PX,
    })?;
    pm.fill(Color::WHITE);
    Ok(pm)
}

fn check(opts: &PngOptions) -> Result<(), ExportError> {
    if !(opts.px_per_mm.is_finite() && opts.px_per_mm > 0.0) {
        return Err(ExportError::BadOption {
            what: "px_per_mm",
            value: opts.px_per_mm,
            hint: "use a resolution > 0 pixels per mm",
        });
    }
    if let Some(m) = opts.max_value {
        if !(m.is_finite() && m > 0.0) {
            return Err(ExportError::BadOption {
                what: "max_value",
                value: m,
                hint: "use a finite value > 0",
            });
        }
    }
    Ok(())
}

/// Fills the piece's triangles (colour map, or grey when the field is unknown) and strokes its
/// cut and sew lines; `map` takes pattern mm to pixels.
fn draw_piece(
    pm: &mut Pixmap,
    piece: &PatternPiece,
    field: Field,
    max: f64,
    map: &dyn Fn([f64; 2]) -> [f32; 2],
) {
    let vals = field.values(piece);
    let mut paint = Paint {
        anti_alias: false,
        ..Default::default()
    };
    for (fi, f) in piece.mesh.faces.iter().enumerate() {
        let [a, b, c] = f.map(|v| map(piece.uv[v as usize]));
        let rgb = vals.get(fi).map_or([200, 200, 200], |x| viridis(x / max));
        paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
        let mut pb = PathBuilder::new();
        pb.move_to(a[0], a[1]);
        pb.line_to(b[0], b[1]);
        pb.line_to(c[0], c[1]);
        pb.close();
        if let Some(path) = pb.finish() {
            pm.fill_path(
                &path,
                &paint,
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }
    for (line, rgb) in [(&piece.cut_line, [255, 0, 0]), (&piece.sew_line, [0, 0, 0])] {
        let mut pb = PathBuilder::new();
        for (i, p) in line.iter().enumerate() {
            let q = map(*p);
            if i == 0 {
                pb.move_to(q[0], q[1]);
            } else {
                pb.line_to(q[0], q[1]);
            }
        }
        pb.close();
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
        if let Some(path) = pb.finish() {
            let stroke = Stroke {
                width: 1.0,
                ..Default::default()
            };
            pm.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
        }
    }
}

fn field_max(pieces: &[&PatternPiece], opts: &PngOptions) -> f64 {
    opts.max_value.unwrap_or_else(|| {
        let m = pieces
            .iter()
            .flat_map(|p| opts.field.values(p).iter().copied())
            .fold(0.0, f64::max);
        m.max(MIN_RAMP_TOP)
    })
}

fn encode(pm: &Pixmap) -> Result<Vec<u8>, ExportError> {
    pm.encode_png().map_err(|e| ExportError::Png(e.to_string()))
}

/// Draws a scale bar (a round length ≤ 40 % of the width) with its label at (x, y) px.
fn scale_bar(pm: &mut Pixmap, x: f32, y: f32, px_per_mm: f64, width_px: f64) {
    let mm = [1000.0, 500.0, 200.0, 100.0, 50.0, 20.0, 10.0, 5.0, 2.0, 1.0]
        .into_iter()
        .find(|l| l * px_per_mm <= 0.4 * width_px)
        .unwrap_or(1.0);
    let len = (mm * px_per_mm) as f32;
    let mut paint = Paint::default();
    paint.set_color(Color::BLACK);
    if let Some(r) = Rect::from_xywh(x, y, len, 4.0) {
        pm.fill_rect(r, &paint, Transform::identity(), None);
    }
    draw_text(pm, &format!("{mm} mm"), x, y + 8.0, 2.0, Color::BLACK);
}

/// One piece with its colour map, a legend (ramp, 0 and the top value, the field name) and a
/// scale bar. Errors when the piece has no values for the field.
pub fn piece_png(piece: &PatternPiece, opts: &PngOptions) -> Result<Vec<u8>, ExportError> {
    check(opts)?;
    if opts.field.values(piece).is_empty() {
        return Err(ExportError::Piece {
            piece: piece.name.clone(),
            what: format!(
                "no {} values to draw; compute the distortion first",
                opts.field.name()
            ),
        });
    }
    let s = opts.px_per_mm;
    let b = bbox(&piece.cut_line);
    let margin = 20.0;
    let legend = 110.0;
    let (pw, ph) = ((b[1][0] - b[0][0]) * s, (b[1][1] - b[0][1]) * s);
    let mut pm = pixmap(
        pw + 2.0 * margin + legend,
        (ph + 2.0 * margin + 30.0).max(240.0),
    )?;
    let map = |p: [f64; 2]| {
        [
            ((p[0] - b[0][0]) * s + margin) as f32,
            ((b[1][1] - p[1]) * s + margin) as f32,
        ]
    };
    let max = field_max(&[piece], opts);
    draw_piece(&mut pm, piece, opts.field, max, &map);
    // Legend: a ramp 160 px tall, top = max.
    let lx = (pw + 2.0 * margin) as f32;
    let mut paint = Paint::default();
    for k in 0..160 {
        let rgb = viridis(1.0 - k as f64 / 159.0);
        paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
        if let Some(r) = Rect::from_xywh(lx, margin as f32 + 20.0 + k as f32, 16.0, 1.0) {
            pm.fill_rect(r, &paint, Transform::identity(), None);
        }
    }
    let name = match opts.field {
        Field::EH => "e_h",
        Field::ER => "e_r",
        Field::EdgeStrain => "strain",
    };
    draw_text(&mut pm, name, lx, margin as f32, 2.0, Color::BLACK);
    draw_text(
        &mut pm,
        &number(max),
        lx + 20.0,
        margin as f32 + 20.0,
        2.0,
        Color::BLACK,
    );
    draw_text(
        &mut pm,
        "0",
        lx + 20.0,
        margin as f32 + 170.0,
        2.0,
        Color::BLACK,
    );
    scale_bar(&mut pm, margin as f32, (ph + margin + 8.0) as f32, s, pw);
    encode(&pm)
}

/// The sheet: every placement coloured by the field (grey where unknown), cut lines red, the
/// blue 50 mm test square, and a scale bar.
pub fn sheet_png(
    pieces: &[PatternPiece],
    layout: &Layout,
    opts: &PngOptions,
) -> Result<Vec<u8>, ExportError> {
    check(opts)?;
    let s = opts.px_per_mm;
    let (w, h) = (layout.width_mm * s, layout.height_mm * s);
    let mut pm = pixmap(w, h + 30.0)?;
    let max = field_max(&pieces.iter().collect::<Vec<_>>(), opts);
    for pl in &layout.placements {
        let map = |p: [f64; 2]| {
            let q = pl.map(p);
            [(q[0] * s) as f32, ((layout.height_mm - q[1]) * s) as f32]
        };
        draw_piece(&mut pm, &pieces[pl.piece], opts.field, max, &map);
    }
    let ts = layout.test_square;
    let mut paint = Paint::default();
    paint.set_color_rgba8(0, 0, 255, 255);
    if let Some(r) = Rect::from_xywh(
        (ts[0] * s) as f32,
        ((layout.height_mm - ts[1] - TEST_SQUARE_MM) * s) as f32,
        (TEST_SQUARE_MM * s) as f32,
        (TEST_SQUARE_MM * s) as f32,
    ) {
        pm.fill_rect(r, &paint, Transform::identity(), None);
    }
    scale_bar(&mut pm, 10.0, (h + 6.0) as f32, s, w);
    encode(&pm)
}
