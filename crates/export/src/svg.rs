//! SVG at true scale: `width`/`height` in mm and a `viewBox` in mm (one user unit = 1 mm), one
//! group per layer (`cut`, `sew`, `notch`, `grain`, `dart`, `label`, `internal`), one `<path>`
//! per line kind and per seam, with ids and `data-` attributes.

use std::fmt::Write as _;

use flatcut_pattern::geom::{bbox, polyline_length};
use flatcut_pattern::{Layout, PatternPiece, TEST_SQUARE_MM};
use serde::{Deserialize, Serialize};

use crate::text::{ident, xml_escape};

/// Colours of the layers (any SVG colour).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct LayerColours {
    /// Cut line (default `#ff0000`: laser shops cut red hairlines).
    pub cut: String,
    /// Sew line (default `#000000`).
    pub sew: String,
    /// Notches (default `#ff0000`: they are cut too).
    pub notch: String,
    /// Grain line (default `#0000ff`).
    pub grain: String,
    /// Darts (default `#008000`).
    pub dart: String,
    /// Label text (default `#000000`).
    pub label: String,
    /// Internal lines (default `#808080`).
    pub internal: String,
}

impl Default for LayerColours {
    fn default() -> Self {
        Self {
            cut: "#ff0000".into(),
            sew: "#000000".into(),
            notch: "#ff0000".into(),
            grain: "#0000ff".into(),
            dart: "#008000".into(),
            label: "#000000".into(),
            internal: "#808080".into(),
        }
    }
}

/// Options of the SVG writers.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SvgOptions {
    /// Layer colours.
    pub colours: LayerColours,
    /// Stroke width of the cut line and notches, mm (default 0.01: a laser hairline).
    pub cut_stroke_mm: f64,
    /// Stroke width of the other lines, mm (default 0.3).
    pub stroke_mm: f64,
    /// Margin round a single piece, mm (default 10).
    pub margin_mm: f64,
}

impl Default for SvgOptions {
    fn default() -> Self {
        Self {
            colours: LayerColours::default(),
            cut_stroke_mm: 0.01,
            stroke_mm: 0.3,
            margin_mm: 10.0,
        }
    }
}

/// Number format of coordinates: µm.
fn f(x: f64) -> String {
    let s = format!("{x:.3}");
    if s == "-0.000" { "0.000".into() } else { s }
}

fn path_d(pts: &[[f64; 2]], closed: bool, map: &dyn Fn([f64; 2]) -> [f64; 2]) -> String {
    let mut d = String::new();
    for (i, p) in pts.iter().enumerate() {
        let q = map(*p);
        let _ = write!(
            d,
            "{}{} {}",
            if i == 0 { "M" } else { " L" },
            f(q[0]),
            f(q[1])
        );
    }
    if closed {
        d.push_str(" Z");
    }
    d
}

fn header(o: &mut String, w: f64, h: f64) {
    let _ = writeln!(o, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}mm" height="{h}mm" viewBox="0 0 {w} {h}">"#,
        w = f(w),
        h = f(h)
    );
}

/// Writes the layers of one piece, mapped by `map` (pattern mm → SVG user units), with ids
/// prefixed by `prefix`.
fn piece_layers(
    o: &mut String,
    piece: &PatternPiece,
    prefix: &str,
    map: &dyn Fn([f64; 2]) -> [f64; 2],
    mirrored: bool,
    opts: &SvgOptions,
) {
    let c = &opts.colours;
    let stroke = |colour: &str, w: f64| {
        format!(
            r#"fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round""#,
            xml_escape(colour),
            f(w)
        )
    };
    let name = xml_escape(&piece.name);
    let _ = writeln!(o, r#"<g id="{prefix}" data-piece="{name}">"#);
    // cut
    let cut_len = polyline_length(&piece.cut_line) + {
        let n = piece.cut_line.len();
        if n > 1 {
            flatcut_pattern::geom::dist(piece.cut_line[n - 1], piece.cut_line[0])
        } else {
            0.0
        }
    };
    let _ = writeln!(
        o,
        r#"<g id="{prefix}-cut" data-layer="cut" {}>"#,
        stroke(&c.cut, opts.cut_stroke_mm)
    );
    let _ = writeln!(
        o,
        r#"<path id="{prefix}-cut-line" data-length-mm="{}" d="{}"/>"#,
        f(cut_len),
        path_d(&piece.cut_line, true, map)
    );
    let _ = writeln!(o, "</g>");
    // sew: one path per seam and per free stretch, partitioning the sew line.
    let _ = writeln!(
        o,
        r#"<g id="{prefix}-sew" data-layer="sew" {}>"#,
        stroke(&c.sew, opts.stroke_mm)
    );
    let n = piece.sew_line.len();
    let start = (0..n)
        .find(|&i| piece.edge_seam[i] != piece.edge_seam[(i + n - 1) % n])
        .unwrap_or(0);
    let mut free = 0;
    let mut i = 0;
    while i < n {
        let e = (start + i) % n;
        let tag = piece.edge_seam[e];
        let mut pts = vec![piece.sew_line[e]];
        while i < n && piece.edge_seam[(start + i) % n] == tag {
            pts.push(piece.sew_line[(start + i + 1) % n]);
            i += 1;
        }
        let len = polyline_length(&pts);
        let d = path_d(&pts, false, map);
        match tag {
            Some(s) => {
                let seam = &piece.seams[s];
                let _ = writeln!(
                    o,
                    r#"<path id="{prefix}-seam-{}" data-seam-id="{}" data-side="{}" data-length-mm="{}" data-mate-length-mm="{}" d="{d}"/>"#,
                    ident(&seam.id),
                    xml_escape(&seam.id),
                    seam.side,
                    f(len),
                    f(seam.mate_length_2d_mm)
                );
            }
            None => {
                let _ = writeln!(
                    o,
                    r#"<path id="{prefix}-free-{free}" data-length-mm="{}" d="{d}"/>"#,
                    f(len)
                );
                free += 1;
            }
        }
    }
    let _ = writeln!(o, "</g>");
    // notches
    let _ = writeln!(
        o,
        r#"<g id="{prefix}-notch" data-layer="notch" {}>"#,
        stroke(&c.notch, opts.cut_stroke_mm)
    );
    for (k, nt) in piece.notches.iter().enumerate() {
        let _ = writeln!(
            o,
            r#"<path id="{prefix}-notch-{k}" data-seam-id="{}" data-arc-mm="{}" d="{}"/>"#,
            xml_escape(&nt.seam),
            f(nt.arc_mm),
            path_d(&[nt.cut, nt.inner], false, map)
        );
    }
    let _ = writeln!(o, "</g>");
    // grain: the line and a head at +y
    let [a, b] = piece.grain_line;
    let len = b[1] - a[1];
    let head = (0.08 * len).clamp(2.0, 15.0);
    let _ = writeln!(
        o,
        r#"<g id="{prefix}-grain" data-layer="grain" {}>"#,
        stroke(&c.grain, opts.stroke_mm)
    );
    let _ = writeln!(
        o,
        r#"<path id="{prefix}-grain-line" data-length-mm="{}" d="{} {}"/>"#,
        f(len),
        path_d(&[a, b], false, map),
        path_d(
            &[
                [b[0] - 0.5 * head, b[1] - head],
                b,
                [b[0] + 0.5 * head, b[1] - head]
            ],
            false,
            map
        )
    );
    let _ = writeln!(o, "</g>");
    // darts
    let _ = writeln!(
        o,
        r#"<g id="{prefix}-dart" data-layer="dart" {}>"#,
        stroke(&c.dart, opts.stroke_mm)
    );
    for d in &piece.darts {
        for (k, leg) in d.legs.iter().enumerate() {
            let _ = writeln!(
                o,
                r#"<path id="{prefix}-dart-{}-{k}" data-seam-id="{}" data-length-mm="{}" d="{}"/>"#,
                ident(&d.seam),
                xml_escape(&d.seam),
                f(polyline_length(leg)),
                path_d(leg, false, map)
            );
        }
    }
    let _ = writeln!(o, "</g>");
    // internal lines and holes
    let _ = writeln!(
        o,
        r#"<g id="{prefix}-internal" data-layer="internal" {}>"#,
        stroke(&c.internal, opts.stroke_mm)
    );
    for (k, l) in piece.internal_lines.iter().enumerate() {
        let _ = writeln!(
            o,
            r#"<path id="{prefix}-internal-{k}" data-length-mm="{}" d="{}"/>"#,
            f(polyline_length(l)),
            path_d(l, false, map)
        );
    }
    for (k, l) in piece.holes.iter().enumerate() {
        let _ = writeln!(
            o,
            r#"<path id="{prefix}-hole-{k}" d="{}"/>"#,
            path_d(l, true, map)
        );
    }
    let _ = writeln!(o, "</g>");
    // label
    let h = piece.label.height_mm;
    let _ = writeln!(
        o,
        r#"<g id="{prefix}-label" data-layer="label" fill="{}" font-family="sans-serif" font-size="{}"{}>"#,
        xml_escape(&c.label),
        f(h),
        // A mirrored copy's label start lands on the right: the text must run leftwards.
        if mirrored {
            r#" text-anchor="end""#
        } else {
            ""
        }
    );
    for (k, line) in piece.label.lines.iter().enumerate() {
        let p = map([piece.label.at[0], piece.label.at[1] - 1.4 * h * k as f64]);
        let _ = writeln!(
            o,
            r#"<text id="{prefix}-label-{k}" x="{}" y="{}">{}</text>"#,
            f(p[0]),
            f(p[1]),
            xml_escape(line)
        );
    }
    let _ = writeln!(o, "</g>");
    let _ = writeln!(o, "</g>");
}

/// One piece on its own page: the cut line's bounding box plus the margin.
pub fn piece_svg(piece: &PatternPiece, opts: &SvgOptions) -> Vec<u8> {
    let b = bbox(&piece.cut_line);
    let m = opts.margin_mm;
    let (w, h) = (b[1][0] - b[0][0] + 2.0 * m, b[1][1] - b[0][1] + 2.0 * m);
    let map = move |p: [f64; 2]| [p[0] - b[0][0] + m, b[1][1] - p[1] + m];
    let mut o = String::new();
    header(&mut o, w, h);
    piece_layers(&mut o, piece, &ident(&piece.name), &map, false, opts);
    o.push_str("</svg>\n");
    o.into_bytes()
}

/// The sheet: every placement of the layout, and the 50 mm test square (`id="test-square"`,
/// filled blue so a picture of it can be measured).
pub fn sheet_svg(pieces: &[PatternPiece], layout: &Layout, opts: &SvgOptions) -> Vec<u8> {
    let (w, h) = (layout.width_mm, layout.height_mm);
    let mut o = String::new();
    header(&mut o, w, h);
    let ts = layout.test_square;
    let _ = writeln!(
        o,
        r##"<g id="test-square"><rect x="{}" y="{}" width="{s}" height="{s}" fill="#0000ff" data-size-mm="{s}"/><text x="{}" y="{}" font-family="sans-serif" font-size="5" fill="#ffffff">{s} mm</text></g>"##,
        f(ts[0]),
        f(h - ts[1] - TEST_SQUARE_MM),
        f(ts[0] + 5.0),
        f(h - ts[1] - 5.0),
        s = f(TEST_SQUARE_MM)
    );
    for pl in &layout.placements {
        let piece = &pieces[pl.piece];
        let map = move |p: [f64; 2]| {
            let q = pl.map(p);
            [q[0], h - q[1]]
        };
        let prefix = format!("{}-{}", ident(&piece.name), pl.copy);
        piece_layers(&mut o, piece, &prefix, &map, pl.mirrored, opts);
    }
    o.push_str("</svg>\n");
    o.into_bytes()
}
