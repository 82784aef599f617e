//! The cut description: cutting lines, piece seeds and options, as read from `CUTS.toml`.
//!
//! ```toml
//! units = "dm"              # units of the mesh and of every point below (mm, cm, dm, m, in)
//! [[cut]]
//! name = "neck"
//! points = [[0.0, 14.6, 0.9], [0.8, 14.4, 0.0], [0.0, 14.6, -0.7]]
//! closed = true             # a loop through the points; open lines end on a boundary or a line
//! [[cut]]
//! name = "centre-front"
//! vertices = [5131, 5200]   # or mesh vertex indices
//! [[piece]]
//! name = "front"
//! seed = [0.0, 10.0, 1.2]   # a point in the piece
//! [options]
//! keep_unnamed = false
//! ```

use serde::{Deserialize, Serialize};

/// A whole cut description.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cuts {
    /// Units of the mesh coordinates and of every point (`mm`, `cm`, `dm`, `m`, `in`); read by the
    /// caller, which converts mesh and points to mm ([`Cuts::scale`]) before cutting. Default
    /// `None`: millimetres.
    #[serde(default)]
    pub units: Option<String>,
    /// The cutting lines (`[[cut]]`).
    #[serde(default, rename = "cut")]
    pub cuts: Vec<CutSpec>,
    /// The named pieces (`[[piece]]`).
    #[serde(default, rename = "piece")]
    pub pieces: Vec<PieceSpec>,
    /// Options (`[options]`).
    #[serde(default)]
    pub options: TrimOptions,
}

/// One cutting line: through `points` (each snapped to the surface, consecutive ones joined by
/// the shortest path on the surface) or through mesh `vertices` (consecutive ones joined by
/// their edge when they share one, else by the shortest path).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CutSpec {
    /// Unique name; seams on this line are named after it.
    pub name: String,
    /// Points the line passes through, in the cut's units.
    #[serde(default)]
    pub points: Vec<[f64; 3]>,
    /// Mesh vertex indices (0-based) the line passes through.
    #[serde(default)]
    pub vertices: Vec<u64>,
    /// A closed loop (last point joined to the first). Default false: an open line, whose two
    /// ends must lie on the mesh boundary or on another line (within `end_snap_mm`).
    #[serde(default)]
    pub closed: bool,
}

/// One named piece: the piece containing `seed`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PieceSpec {
    /// Unique name; the piece is written as `<name>.obj`.
    pub name: String,
    /// A point on the surface inside the piece, in the cut's units.
    pub seed: [f64; 3],
}

/// Options of [`crate::trim`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrimOptions {
    /// Largest distance from a line point or seed to the surface, mm (default 5).
    pub landmark_tolerance_mm: f64,
    /// An open line's end within this distance of the mesh boundary or of another line is
    /// moved onto it, mm (default 5); farther is an error.
    pub end_snap_mm: f64,
    /// Keep pieces no seed names (as `unnamed-<k>`) instead of dropping them (default false).
    /// Either way they are listed in the report.
    pub keep_unnamed: bool,
    /// Most strip updates per geodesic (default 100 000), see [`crate::GeodesicOptions`].
    pub max_strip_updates: usize,
}

impl Default for TrimOptions {
    fn default() -> Self {
        Self {
            landmark_tolerance_mm: crate::surface_point::DEFAULT_LANDMARK_TOLERANCE_MM,
            end_snap_mm: 5.0,
            keep_unnamed: false,
            max_strip_updates: crate::GeodesicOptions::default().max_strip_updates,
        }
    }
}

impl Cuts {
    /// Multiplies every point and seed by `factor` (a unit conversion to mm); options are in
    /// mm already and stay.
    pub fn scale(&mut self, factor: f64) {
        for c in &mut self.cuts {
            for p in &mut c.points {
                *p = p.map(|x| x * factor);
            }
        }
        for p in &mut self.pieces {
            p.seed = p.seed.map(|x| x * factor);
        }
    }
}
