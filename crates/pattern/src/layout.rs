//! Laying the pieces out on a sheet: shelf packing of cut-line bounding boxes, grain kept
//! vertical (pieces are only translated, or mirrored left–right), every copy placed.

use serde::{Deserialize, Serialize};

use crate::geom::bbox;
use crate::{PatternError, PatternPiece};

/// Side of the test square printed on every sheet (mm).
pub const TEST_SQUARE_MM: f64 = 50.0;

/// Options of [`layout`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct LayoutOptions {
    /// Sheet (fabric) width, mm (default 1500).
    pub sheet_width_mm: f64,
    /// Gap between pieces, mm (default 10).
    pub gap_mm: f64,
    /// Margin round the sheet, mm (default 10).
    pub margin_mm: f64,
}

impl Default for LayoutOptions {
    fn default() -> Self {
        Self {
            sheet_width_mm: 1500.0,
            gap_mm: 10.0,
            margin_mm: 10.0,
        }
    }
}

/// One copy of a piece on the sheet.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Placement {
    /// Index of the piece.
    pub piece: usize,
    /// Copy number (0-based) among its quantity.
    pub copy: u32,
    /// Mirrored left–right.
    pub mirrored: bool,
    /// Added after the optional mirror (x → −x), mm.
    pub offset: [f64; 2],
}

impl Placement {
    /// Where a point of the piece lands on the sheet.
    pub fn map(&self, p: [f64; 2]) -> [f64; 2] {
        let x = if self.mirrored { -p[0] } else { p[0] };
        [x + self.offset[0], p[1] + self.offset[1]]
    }
}

/// The sheet: its size, the placements and the test square's lower-left corner (all mm, y up).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Layout {
    /// Sheet width (mm).
    pub width_mm: f64,
    /// Sheet height used (mm).
    pub height_mm: f64,
    /// Every copy of every piece.
    pub placements: Vec<Placement>,
    /// Lower-left corner of the 50 mm test square.
    pub test_square: [f64; 2],
}

/// Shelf packing: items (every copy, and the test square) sorted by height, tallest first,
/// placed left to right; a new shelf starts above the tallest item of the last.
pub fn layout(pieces: &[PatternPiece], opts: &LayoutOptions) -> Result<Layout, PatternError> {
    for (what, v) in [
        ("sheet_width_mm", opts.sheet_width_mm),
        ("gap_mm", opts.gap_mm),
        ("margin_mm", opts.margin_mm),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(PatternError::BadOption {
                what: what.into(),
                value: v,
                hint: "use a finite length ≥ 0 mm",
            });
        }
    }
    let usable = opts.sheet_width_mm - 2.0 * opts.margin_mm;
    // (piece or None for the test square, copy, mirrored, box)
    type Item = (Option<usize>, u32, bool, [[f64; 2]; 2]);
    let mut items: Vec<Item> = Vec::new();
    items.push((
        None,
        0,
        false,
        [[0.0, 0.0], [TEST_SQUARE_MM, TEST_SQUARE_MM]],
    ));
    for (i, p) in pieces.iter().enumerate() {
        let b = bbox(&p.cut_line);
        if b[1][0] - b[0][0] > usable {
            return Err(PatternError::TooWide {
                piece: p.name.clone(),
                width_mm: b[1][0] - b[0][0],
                sheet_mm: usable,
            });
        }
        for c in 0..p.meta.quantity {
            let mirrored = p.meta.mirror && c % 2 == 1;
            let bm = if mirrored {
                [[-b[1][0], b[0][1]], [-b[0][0], b[1][1]]]
            } else {
                b
            };
            items.push((Some(i), c, mirrored, bm));
        }
    }
    if TEST_SQUARE_MM > usable {
        return Err(PatternError::BadOption {
            what: "sheet_width_mm".into(),
            value: opts.sheet_width_mm,
            hint: "the sheet must hold the 50 mm test square inside its margins",
        });
    }
    let h = |b: &[[f64; 2]; 2]| b[1][1] - b[0][1];
    let mut order: Vec<usize> = (1..items.len()).collect();
    order.sort_by(|&a, &b| h(&items[b].3).total_cmp(&h(&items[a].3)).then(a.cmp(&b)));
    order.insert(0, 0); // the test square first, bottom left
    let (mut x, mut y, mut shelf) = (opts.margin_mm, opts.margin_mm, 0.0f64);
    let mut placements = Vec::new();
    let mut test_square = [opts.margin_mm; 2];
    for k in order {
        let (piece, copy, mirrored, b) = items[k];
        let (w, hh) = (b[1][0] - b[0][0], b[1][1] - b[0][1]);
        if x + w > opts.margin_mm + usable && x > opts.margin_mm {
            x = opts.margin_mm;
            y += shelf + opts.gap_mm;
            shelf = 0.0;
        }
        match piece {
            None => test_square = [x, y],
            Some(piece) => placements.push(Placement {
                piece,
                copy,
                mirrored,
                offset: [x - b[0][0], y - b[0][1]],
            }),
        }
        x += w + opts.gap_mm;
        shelf = shelf.max(hh);
    }
    Ok(Layout {
        width_mm: opts.sheet_width_mm,
        height_mm: y + shelf + opts.margin_mm,
        placements,
        test_square,
    })
}
