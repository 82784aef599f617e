//! The seam ledger: which boundary stretch of which piece is sewn to which.
//!
//! Cutting (crates/trim) and darts (crates/dart) write it; the pattern stage reads it to put
//! matching notches on both mates and to check that mates have equal 2D length; the pipeline
//! report lists it. It lives here, in the mesh crate, because producers and consumers sit on
//! different branches of the crate graph and must agree on one type. Saved as `seams.json`
//! (serde; field names below are the JSON keys). All lengths and coordinates are in mm.

use serde::{Deserialize, Serialize};

/// Version of the `seams.json` layout written by [`SeamLedger`].
pub const SEAM_LEDGER_SCHEMA: u32 = 1;

/// Every seam of a set of pieces.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeamLedger {
    /// [`SEAM_LEDGER_SCHEMA`].
    pub schema: u32,
    /// The piece names, in the order the pieces were made; every [`SeamSide::piece`] is one of them.
    pub pieces: Vec<String>,
    /// The seams, sorted by [`Seam::id`].
    pub seams: Vec<Seam>,
}

/// What made a seam.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SeamKind {
    /// Two pieces (or two stretches of one piece's boundary) sewn together along a cutting line.
    Seam,
    /// The two legs of a dart, sewn to each other; both sides are the same piece and the
    /// chains start at the dart's tip.
    Dart,
}

/// One seam: a stretch of boundary on side `a` sewn to a stretch on side `b`.
///
/// Direction is consistent: `a.vertices[k]` and `b.vertices[k]` are the same point of the
/// source surface for every `k` (so both chains have the same length, at least 2), running
/// from [`Seam::start_mm`] to [`Seam::end_mm`]. A seam ends where its cutting line ends, turns
/// at a T-junction, or meets another seam; a closed cutting line gives one seam per pair of
/// pieces it separates, whose start and end coincide when it runs all round.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Seam {
    /// Unique, stable id, e.g. `"side-left/0"` (cutting line name, then the stretch's index).
    pub id: String,
    /// Name of the cutting line or dart this seam lies on.
    pub line: String,
    /// Seam between pieces or dart legs.
    pub kind: SeamKind,
    /// One side.
    pub a: SeamSide,
    /// Its mate.
    pub b: SeamSide,
    /// Length of the seam on the 3D source surface, in mm.
    pub length_3d_mm: f64,
    /// First point of the seam on the source surface, mm.
    pub start_mm: [f64; 3],
    /// Last point of the seam on the source surface, mm.
    pub end_mm: [f64; 3],
}

/// One side of a seam: a chain of boundary vertices of one piece.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeamSide {
    /// Name of the piece (an entry of [`SeamLedger::pieces`]).
    pub piece: String,
    /// Piece-local vertex indices along its boundary, consecutive vertices joined by a boundary
    /// edge of the piece, from the seam's start to its end.
    pub vertices: Vec<u32>,
}

/// What is wrong with a ledger, found by [`SeamLedger::check`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SeamLedgerError {
    /// The ledger was written by a newer or unknown layout.
    #[error(
        "seam ledger schema {found} is not supported (this flatcut reads schema {SEAM_LEDGER_SCHEMA})"
    )]
    Schema {
        /// The schema found.
        found: u32,
    },
    /// A seam names a piece the ledger does not list.
    #[error("seam {seam:?} names piece {piece:?}, which the ledger does not list")]
    UnknownPiece {
        /// The seam id.
        seam: String,
        /// The unknown piece name.
        piece: String,
    },
    /// The two sides of a seam have different numbers of vertices, or fewer than 2.
    #[error(
        "seam {seam:?}: side a has {a} vertices and side b has {b}; both need the same count, at least 2"
    )]
    ChainLengths {
        /// The seam id.
        seam: String,
        /// Vertices on side a.
        a: usize,
        /// Vertices on side b.
        b: usize,
    },
    /// Two seams share an id.
    #[error("seam id {seam:?} is used twice")]
    DuplicateId {
        /// The repeated id.
        seam: String,
    },
    /// A length or coordinate is not finite or a length is negative.
    #[error("seam {seam:?}: {what} is not a finite non-negative number")]
    NotFinite {
        /// The seam id.
        seam: String,
        /// Which field.
        what: &'static str,
    },
}

impl SeamLedger {
    /// An empty ledger over the named pieces.
    pub fn new(pieces: Vec<String>) -> Self {
        Self {
            schema: SEAM_LEDGER_SCHEMA,
            pieces,
            seams: Vec::new(),
        }
    }

    /// The seams with a side on `piece`.
    pub fn seams_of<'a>(&'a self, piece: &'a str) -> impl Iterator<Item = &'a Seam> + 'a {
        self.seams
            .iter()
            .filter(move |s| s.a.piece == piece || s.b.piece == piece)
    }

    /// Checks what can be checked without the pieces: the schema, piece names, chain lengths,
    /// unique ids, finite numbers. Vertex indices against the pieces are the reader's to check.
    pub fn check(&self) -> Result<(), SeamLedgerError> {
        if self.schema != SEAM_LEDGER_SCHEMA {
            return Err(SeamLedgerError::Schema { found: self.schema });
        }
        let mut ids = std::collections::HashSet::new();
        for seam in &self.seams {
            if !ids.insert(seam.id.as_str()) {
                return Err(SeamLedgerError::DuplicateId {
                    seam: seam.id.clone(),
                });
            }
            for side in [&seam.a, &seam.b] {
                if !self.pieces.contains(&side.piece) {
                    return Err(SeamLedgerError::UnknownPiece {
                        seam: seam.id.clone(),
                        piece: side.piece.clone(),
                    });
                }
            }
            let (a, b) = (seam.a.vertices.len(), seam.b.vertices.len());
            if a != b || a < 2 {
                return Err(SeamLedgerError::ChainLengths {
                    seam: seam.id.clone(),
                    a,
                    b,
                });
            }
            if !(seam.length_3d_mm.is_finite() && seam.length_3d_mm >= 0.0) {
                return Err(SeamLedgerError::NotFinite {
                    seam: seam.id.clone(),
                    what: "length_3d_mm",
                });
            }
            if !seam
                .start_mm
                .iter()
                .chain(&seam.end_mm)
                .all(|c| c.is_finite())
            {
                return Err(SeamLedgerError::NotFinite {
                    seam: seam.id.clone(),
                    what: "start_mm/end_mm",
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ledger() -> SeamLedger {
        let mut l = SeamLedger::new(vec!["front".into(), "back".into()]);
        l.seams.push(Seam {
            id: "side-left/0".into(),
            line: "side-left".into(),
            kind: SeamKind::Seam,
            a: SeamSide {
                piece: "front".into(),
                vertices: vec![3, 4, 5],
            },
            b: SeamSide {
                piece: "back".into(),
                vertices: vec![9, 8, 7],
            },
            length_3d_mm: 120.5,
            start_mm: [0.0, 0.0, 0.0],
            end_mm: [0.0, 120.5, 0.0],
        });
        l
    }

    #[test]
    fn json_round_trip_and_keys() {
        let l = ledger();
        let json = serde_json::to_string(&l).unwrap();
        assert!(json.contains("\"kind\":\"seam\""), "{json}");
        assert!(json.contains("\"length_3d_mm\":120.5"), "{json}");
        let back: SeamLedger = serde_json::from_str(&json).unwrap();
        assert_eq!(back, l);
        assert!(back.check().is_ok());
        assert_eq!(back.seams_of("back").count(), 1);
        assert_eq!(back.seams_of("sleeve").count(), 0);
    }

    #[test]
    fn check_names_the_fault() {
        let mut l = ledger();
        l.seams[0].b.vertices.pop();
        assert_eq!(
            l.check(),
            Err(SeamLedgerError::ChainLengths {
                seam: "side-left/0".into(),
                a: 3,
                b: 2
            })
        );
        let mut l = ledger();
        l.seams[0].b.piece = "sleeve".into();
        assert!(matches!(
            l.check(),
            Err(SeamLedgerError::UnknownPiece { .. })
        ));
        let mut l = ledger();
        l.seams.push(l.seams[0].clone());
        assert!(matches!(
            l.check(),
            Err(SeamLedgerError::DuplicateId { .. })
        ));
        let mut l = ledger();
        l.seams[0].length_3d_mm = f64::NAN;
        assert!(matches!(l.check(), Err(SeamLedgerError::NotFinite { .. })));
        let mut l = ledger();
        l.schema = 2;
        assert!(matches!(
            l.check(),
            Err(SeamLedgerError::Schema { found: 2 })
        ));
        let unknown_key = r#"{"schema":1,"pieces":[],"seams":[],"extra":1}"#;
        assert!(serde_json::from_str::<SeamLedger>(unknown_key).is_err());
    }
}
