//! The seam table of the report: every seam of the ledger with its 3D length and the 2D
//! lengths of both mates in the flattened pieces, so that a mismatch (one side of a seam
//! longer than the other after flattening, which puckers when sewn) is visible.

use std::collections::BTreeMap;

use flatcut_mesh::{SeamKind, SeamLedger};
use serde::Serialize;

/// Mates whose 2D lengths differ by more than this (mm) are highlighted: the issue's
/// acceptance bound, and about what a sewer eases in by hand over a seam.
pub const SEAM_MISMATCH_MM: f64 = 0.5;

/// One row of the seam table.
#[derive(Clone, Debug, Serialize)]
pub struct SeamRow {
    /// Seam id (`line/k`).
    pub id: String,
    /// The cutting line or dart it lies on.
    pub line: String,
    /// `seam` or `dart`.
    pub kind: SeamKind,
    /// Piece of side a.
    pub a_piece: String,
    /// Piece of side b.
    pub b_piece: String,
    /// Length on the 3D surface (mm), from the ledger.
    pub length_3d_mm: f64,
    /// Length of side a in its flattened piece (mm).
    pub a_2d_mm: f64,
    /// Length of side b in its flattened piece (mm).
    pub b_2d_mm: f64,
    /// a_2d_mm − b_2d_mm.
    pub difference_mm: f64,
    /// |difference| > [`SEAM_MISMATCH_MM`].
    pub mismatch: bool,
}

/// Length of a vertex chain in a flattening; `None` if an index is out of range.
fn chain_length(chain: &[u32], uv: &[[f64; 2]]) -> Option<f64> {
    let mut l = 0.0;
    for w in chain.windows(2) {
        let (a, b) = (uv.get(w[0] as usize)?, uv.get(w[1] as usize)?);
        l += (a[0] - b[0]).hypot(a[1] - b[1]);
    }
    Some(l)
}

/// The table of `ledger` given each piece's flattening (by piece name). Seams whose pieces
/// were not flattened or whose chains do not fit them are skipped and named in the second
/// return value.
pub fn seam_table(
    ledger: &SeamLedger,
    uv: &BTreeMap<String, &[[f64; 2]]>,
) -> (Vec<SeamRow>, Vec<String>) {
    let mut rows = Vec::with_capacity(ledger.seams.len());
    let mut skipped = Vec::new();
    for s in &ledger.seams {
        let len = |side: &flatcut_mesh::SeamSide| {
            uv.get(&side.piece)
                .and_then(|q| chain_length(&side.vertices, q))
        };
        match (len(&s.a), len(&s.b)) {
            (Some(a), Some(b)) => rows.push(SeamRow {
                id: s.id.clone(),
                line: s.line.clone(),
                kind: s.kind,
                a_piece: s.a.piece.clone(),
                b_piece: s.b.piece.clone(),
                length_3d_mm: s.length_3d_mm,
                a_2d_mm: a,
                b_2d_mm: b,
                difference_mm: a - b,
                mismatch: (a - b).abs() > SEAM_MISMATCH_MM,
            }),
            _ => skipped.push(s.id.clone()),
        }
    }
    (rows, skipped)
}

#[cfg(test)]
mod tests {
    use super::*;
    use flatcut_mesh::{Seam, SeamSide};

    #[test]
    fn mates_are_measured_in_their_own_flattenings() {
        // Side a: a 3-4-5 right angle path of length 3 + 4; side b: a straight 7.2 mm.
        let a_uv = [[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]];
        let b_uv = [[0.0, 0.0], [7.2, 0.0]];
        let ledger = SeamLedger {
            schema: 1,
            pieces: vec!["a".into(), "b".into()],
            seams: vec![Seam {
                id: "l/0".into(),
                line: "l".into(),
                kind: SeamKind::Seam,
                a: SeamSide {
                    piece: "a".into(),
                    vertices: vec![0, 1, 2],
                },
                b: SeamSide {
                    piece: "b".into(),
                    vertices: vec![0, 1, 1],
                },
                length_3d_mm: 7.0,
                start_mm: [0.0; 3],
                end_mm: [0.0; 3],
            }],
        };
        let mut uv: BTreeMap<String, &[[f64; 2]]> = BTreeMap::new();
        uv.insert("a".into(), &a_uv);
        uv.insert("b".into(), &b_uv);
        let (rows, skipped) = seam_table(&ledger, &uv);
        assert!(skipped.is_empty());
        assert_eq!(rows[0].a_2d_mm, 7.0);
        assert!((rows[0].b_2d_mm - 7.2).abs() < 1e-12);
        assert!((rows[0].difference_mm + 0.2).abs() < 1e-12);
        assert!(!rows[0].mismatch);
        uv.remove("b");
        let (rows, skipped) = seam_table(&ledger, &uv);
        assert!(rows.is_empty());
        assert_eq!(skipped, ["l/0"]);
    }
}
