//! DXF in the AAMA / ASTM D6673 style: one BLOCK per piece, layer 1 cut line (and the piece
//! text), 4 notches, 7 grain line, 8 internal lines (and dart legs, holes), 13 drill holes
//! (dart tips), 14 sew line; millimetres; 7-bit ASCII only.
//!
//! R12 ("strict") is written by hand: HEADER, BLOCKS and ENTITIES only, as strict pattern-CAD
//! importers expect (some reject files with further sections). R13 is written through the dxf
//! crate, which supplies the handles, tables and objects that version needs.

use std::fmt::Write as _;

use flatcut_pattern::{Layout, PatternPiece};
use serde::{Deserialize, Serialize};

use crate::ExportError;
use crate::text::{ascii7, ident};

/// AAMA layer of the cut line and the piece text.
pub const LAYER_CUT: &str = "1";
/// AAMA layer of notches.
pub const LAYER_NOTCH: &str = "4";
/// AAMA layer of the grain line.
pub const LAYER_GRAIN: &str = "7";
/// AAMA layer of internal lines.
pub const LAYER_INTERNAL: &str = "8";
/// AAMA layer of drill holes.
pub const LAYER_DRILL: &str = "13";
/// AAMA layer of the sew line.
pub const LAYER_SEW: &str = "14";

/// DXF version written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DxfVersion {
    /// AutoCAD R12 (AC1009), hand-written ASCII: what AAMA importers expect (default).
    #[default]
    R12,
    /// AutoCAD R13 (AC1012), through the dxf crate.
    R13,
}

/// Options of [`dxf_aama`].
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct DxfOptions {
    /// Version (default R12).
    pub version: DxfVersion,
}

/// One drawable item of a block, in piece coordinates (mm).
enum Item {
    /// A polyline on a layer, closed or not.
    Poly(&'static str, Vec<[f64; 2]>, bool),
    /// A line on a layer.
    Line(&'static str, [f64; 2], [f64; 2]),
    /// A point on a layer.
    Point(&'static str, [f64; 2]),
    /// Text on a layer: insertion point, height, text.
    Text(&'static str, [f64; 2], f64, String),
}

/// The block name of a piece: its name in 7-bit ASCII, safe for DXF.
pub fn block_name(piece: &PatternPiece) -> String {
    ident(&ascii7(&piece.name))
}

fn items(piece: &PatternPiece) -> Vec<Item> {
    let mut v = vec![
        Item::Poly(LAYER_CUT, piece.cut_line.clone(), true),
        Item::Poly(LAYER_SEW, piece.sew_line.clone(), true),
    ];
    for nt in &piece.notches {
        v.push(Item::Line(LAYER_NOTCH, nt.cut, nt.inner));
    }
    v.push(Item::Line(
        LAYER_GRAIN,
        piece.grain_line[0],
        piece.grain_line[1],
    ));
    for l in &piece.internal_lines {
        v.push(Item::Poly(LAYER_INTERNAL, l.clone(), false));
    }
    for h in &piece.holes {
        v.push(Item::Poly(LAYER_INTERNAL, h.clone(), true));
    }
    for d in &piece.darts {
        for leg in &d.legs {
            v.push(Item::Poly(LAYER_INTERNAL, leg.clone(), false));
        }
        v.push(Item::Point(LAYER_DRILL, d.tip));
    }
    let m = &piece.meta;
    let h = piece.label.height_mm;
    let mut texts = vec![format!("Piece Name: {}", piece.name)];
    if !m.size.is_empty() {
        texts.push(format!("Size: {}", m.size));
    }
    texts.push(format!("Quantity: {}", m.quantity));
    if m.mirror {
        texts.push("Annotation: cut mirrored pairs".into());
    }
    if !m.fabric.is_empty() {
        texts.push(format!("Material: {}", m.fabric));
    }
    for (k, t) in texts.into_iter().enumerate() {
        let at = [piece.label.at[0], piece.label.at[1] - 1.4 * h * k as f64];
        v.push(Item::Text(LAYER_CUT, at, h, ascii7(&t)));
    }
    v
}

/// The pieces as one DXF: a block per piece and an INSERT per piece at its first place in the
/// layout (at the origin when the layout does not place it).
pub fn dxf_aama(
    pieces: &[PatternPiece],
    layout: &Layout,
    opts: &DxfOptions,
) -> Result<Vec<u8>, ExportError> {
    let inserts: Vec<[f64; 2]> = (0..pieces.len())
        .map(|i| {
            layout
                .placements
                .iter()
                .find(|p| p.piece == i && !p.mirrored)
                .map_or([0.0, 0.0], |p| p.offset)
        })
        .collect();
    match opts.version {
        DxfVersion::R12 => Ok(r12(pieces, &inserts).into_bytes()),
        DxfVersion::R13 => r13(pieces, &inserts),
    }
}

/// Coordinates to 0.1 µm: the read-back holds to 0.001 mm with room to spare.
fn num(x: f64) -> String {
    let s = format!("{x:.4}");
    if s == "-0.0000" { "0.0000".into() } else { s }
}

fn pair(o: &mut String, code: i32, value: &str) {
    let _ = write!(o, "{code:>3}\r\n{value}\r\n");
}

fn r12(pieces: &[PatternPiece], inserts: &[[f64; 2]]) -> String {
    let mut o = String::new();
    pair(&mut o, 0, "SECTION");
    pair(&mut o, 2, "HEADER");
    pair(&mut o, 9, "$ACADVER");
    pair(&mut o, 1, "AC1009");
    pair(&mut o, 9, "$MEASUREMENT");
    pair(&mut o, 70, "1");
    pair(&mut o, 0, "ENDSEC");
    pair(&mut o, 0, "SECTION");
    pair(&mut o, 2, "BLOCKS");
    for piece in pieces {
        let name = block_name(piece);
        pair(&mut o, 0, "BLOCK");
        pair(&mut o, 8, "0");
        pair(&mut o, 2, &name);
        pair(&mut o, 70, "0");
        for (c, v) in [(10, 0.0), (20, 0.0), (30, 0.0)] {
            pair(&mut o, c, &num(v));
        }
        pair(&mut o, 3, &name);
        for item in items(piece) {
            match item {
                Item::Poly(layer, pts, closed) => {
                    pair(&mut o, 0, "POLYLINE");
                    pair(&mut o, 8, layer);
                    pair(&mut o, 66, "1");
                    for (c, v) in [(10, 0.0), (20, 0.0), (30, 0.0)] {
                        pair(&mut o, c, &num(v));
                    }
                    pair(&mut o, 70, if closed { "1" } else { "0" });
                    for p in pts {
                        pair(&mut o, 0, "VERTEX");
                        pair(&mut o, 8, layer);
                        pair(&mut o, 10, &num(p[0]));
                        pair(&mut o, 20, &num(p[1]));
                        pair(&mut o, 30, &num(0.0));
                    }
                    pair(&mut o, 0, "SEQEND");
                    pair(&mut o, 8, layer);
                }
                Item::Line(layer, a, b) => {
                    pair(&mut o, 0, "LINE");
                    pair(&mut o, 8, layer);
                    for (c, v) in [
                        (10, a[0]),
                        (20, a[1]),
                        (30, 0.0),
                        (11, b[0]),
                        (21, b[1]),
                        (31, 0.0),
                    ] {
                        pair(&mut o, c, &num(v));
                    }
                }
                Item::Point(layer, p) => {
                    pair(&mut o, 0, "POINT");
                    pair(&mut o, 8, layer);
                    for (c, v) in [(10, p[0]), (20, p[1]), (30, 0.0)] {
                        pair(&mut o, c, &num(v));
                    }
                }
                Item::Text(layer, p, h, t) => {
                    pair(&mut o, 0, "TEXT");
                    pair(&mut o, 8, layer);
                    for (c, v) in [(10, p[0]), (20, p[1]), (30, 0.0), (40, h)] {
                        pair(&mut o, c, &num(v));
                    }
                    pair(&mut o, 1, &t);
                }
            }
        }
        pair(&mut o, 0, "ENDBLK");
        pair(&mut o, 8, "0");
    }
    pair(&mut o, 0, "ENDSEC");
    pair(&mut o, 0, "SECTION");
    pair(&mut o, 2, "ENTITIES");
    for (piece, at) in pieces.iter().zip(inserts) {
        pair(&mut o, 0, "INSERT");
        pair(&mut o, 8, "0");
        pair(&mut o, 2, &block_name(piece));
        for (c, v) in [(10, at[0]), (20, at[1]), (30, 0.0)] {
            pair(&mut o, c, &num(v));
        }
    }
    pair(&mut o, 0, "ENDSEC");
    pair(&mut o, 0, "EOF");
    o
}

fn r13(pieces: &[PatternPiece], inserts: &[[f64; 2]]) -> Result<Vec<u8>, ExportError> {
    use dxf::entities::{Entity, EntityType, Insert, Line, ModelPoint, Polyline, Text, Vertex};
    use dxf::enums::{AcadVersion, Units};
    use dxf::{Block, Drawing, Point};
    let mut drawing = Drawing::new();
    drawing.header.version = AcadVersion::R13;
    drawing.header.default_drawing_units = Units::Millimeters;
    for layer in [
        LAYER_CUT,
        LAYER_NOTCH,
        LAYER_GRAIN,
        LAYER_INTERNAL,
        LAYER_DRILL,
        LAYER_SEW,
    ] {
        drawing.add_layer(dxf::tables::Layer {
            name: layer.into(),
            ..Default::default()
        });
    }
    let pt = |p: [f64; 2]| Point::new(p[0], p[1], 0.0);
    for piece in pieces {
        let mut block = Block {
            name: block_name(piece),
            ..Default::default()
        };
        for item in items(piece) {
            let (layer, specific) = match item {
                Item::Poly(layer, pts, closed) => {
                    let mut poly = Polyline::default();
                    poly.set_is_closed(closed);
                    for p in pts {
                        poly.add_vertex(&mut drawing, Vertex::new(pt(p)));
                    }
                    (layer, EntityType::Polyline(poly))
                }
                Item::Line(layer, a, b) => (layer, EntityType::Line(Line::new(pt(a), pt(b)))),
                Item::Point(layer, p) => (layer, EntityType::ModelPoint(ModelPoint::new(pt(p)))),
                Item::Text(layer, p, h, t) => {
                    let text = Text {
                        location: pt(p),
                        text_height: h,
                        value: t,
                        ..Default::default()
                    };
                    (layer, EntityType::Text(text))
                }
            };
            let mut e = Entity::new(specific);
            e.common.layer = layer.into();
            block.entities.push(e);
        }
        drawing.add_block(block);
    }
    for (piece, at) in pieces.iter().zip(inserts) {
        let ins = Insert {
            name: block_name(piece),
            location: pt(*at),
            ..Default::default()
        };
        drawing.add_entity(Entity::new(EntityType::Insert(ins)));
    }
    let mut out = Vec::new();
    drawing
        .save(&mut out)
        .map_err(|e| ExportError::Dxf(e.to_string()))?;
    Ok(out)
}
