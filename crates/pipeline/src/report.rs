//! report.json and timings.json: what went in (hashes), what came out, per piece.
//!
//! The report holds no time and no absolute path, so the same TOML and inputs give the same
//! bytes on any machine and thread count; wall times go to timings.json. Numbers are written
//! with [`REPORT_SIGNIFICANT_DIGITS`] significant digits.

use std::collections::BTreeMap;

use flatcut_lscm::Summary;
use flatcut_mesh::clean::CleanReport;
use serde::Serialize;

use crate::pieces::DroppedComponent;
use crate::seams::SeamRow;

/// Significant digits of every number in report.json and timings.json: far more than any
/// measurement here is worth (θ_err, strains, mm), few enough that a reader sees clean
/// numbers. The values are the algorithms' own; rounding is for the reader only.
pub const REPORT_SIGNIFICANT_DIGITS: usize = 12;

/// The whole report.json.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// flatcut's version.
    pub flatcut_version: String,
    /// The pipeline schema.
    pub schema: u32,
    /// The pipeline name.
    pub pipeline: String,
    /// The pipeline file's name (no folder) and its SHA-256.
    pub toml: FileHash,
    /// Every input file (key, path as written in the TOML, SHA-256, size).
    pub inputs: Vec<InputHash>,
    /// The generator and its parameters when the surface was generated.
    pub generator: Option<serde_json::Value>,
    /// Units the input coordinates were read in.
    pub units: String,
    /// The surface before cleaning.
    pub input_mesh: MeshCounts,
    /// What cleaning changed.
    pub clean: CleanReport,
    /// Components no `[[piece]]` seed named (left out).
    pub dropped_components: Vec<DroppedComponent>,
    /// One entry per piece, in `[[piece]]` order (or component order).
    pub pieces: Vec<PieceReport>,
    /// Every seam of the ledger (seams.json) with its 3D length and both mates' 2D lengths.
    pub seam_table: Vec<SeamRow>,
    /// Every file written (except report.json and timings.json), sorted, with its SHA-256.
    pub files: Vec<OutputFile>,
    /// Things worth reading: pieces that did not converge, folded flattenings, dropped
    /// components.
    pub warnings: Vec<String>,
}

/// A file and its SHA-256.
#[derive(Clone, Debug, Serialize)]
pub struct FileHash {
    /// As given on the command line (or the embedded pipeline's name).
    pub path: String,
    /// Lower-case hex SHA-256 of its bytes.
    pub sha256: String,
}

/// An input file.
#[derive(Clone, Debug, Serialize)]
pub struct InputHash {
    /// The TOML key that names it.
    pub key: String,
    /// As written in the TOML.
    pub path: String,
    /// Lower-case hex SHA-256 of its bytes.
    pub sha256: String,
    /// Size in bytes.
    pub bytes: u64,
}

/// Vertex and face counts.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct MeshCounts {
    /// Vertices.
    pub vertices: usize,
    /// Faces.
    pub faces: usize,
}

/// One output file.
#[derive(Clone, Debug, Serialize)]
pub struct OutputFile {
    /// Path inside the output folder, `/`-separated.
    pub name: String,
    /// Size in bytes.
    pub bytes: usize,
    /// Lower-case hex SHA-256.
    pub sha256: String,
}

/// One piece.
#[derive(Clone, Debug, Serialize)]
pub struct PieceReport {
    /// Name.
    pub name: String,
    /// Faces.
    pub faces: usize,
    /// Vertices.
    pub vertices: usize,
    /// Boundary loops (1 for a disk).
    pub boundary_loops: usize,
    /// Euler characteristic (1 for a disk).
    pub euler_characteristic: i64,
    /// Copies to cut.
    pub quantity: u32,
    /// Cut as a mirrored pair.
    pub mirror: bool,
    /// Size label (`[[piece]].size`, may be empty).
    pub size: String,
    /// Fabric (`[[piece]].fabric`, may be empty).
    pub fabric: String,
    /// Darts cut into the piece, by name (their seams are in `seam_table`, kind `dart`).
    pub darts: Vec<String>,
    /// Feature curves: their vertices and how far processing moved them.
    pub features: Vec<FeatureSummary>,
    /// Flattenable processing.
    pub process: ProcessSummary,
    /// Flattening and its distortion.
    pub flatten: FlattenSummary,
    /// The pattern piece: shrink applied and its size.
    pub pattern: PatternSummary,
}

/// A feature curve of a piece.
#[derive(Clone, Debug, Serialize)]
pub struct FeatureSummary {
    /// Its vertex chain on the (darted) piece.
    pub vertices: Vec<u32>,
    /// Length of the chain on the input piece (mm).
    pub length_3d_mm: f64,
    /// Largest displacement of its vertices by processing (mm).
    pub max_displacement_mm: f64,
    /// RMS displacement of its vertices by processing (mm).
    pub rms_displacement_mm: f64,
}

/// What the pattern stage made of a piece.
#[derive(Clone, Debug, Serialize)]
pub struct PatternSummary {
    /// Shrink along the grain applied (fraction).
    pub shrink_along_grain: f64,
    /// Shrink across the grain applied (fraction).
    pub shrink_across_grain: f64,
    /// Width (across the grain, x) and height (along the grain, y) of the piece inside its
    /// sew line, after grain rotation and shrink (mm).
    pub size_mm: [f64; 2],
}

/// What processing did to a piece.
#[derive(Clone, Debug, Serialize)]
pub struct ProcessSummary {
    /// θ_err reached `[process].tolerance_rad` (robust) or the paper's stop held.
    pub converged: bool,
    /// Accepted iterations.
    pub iterations: usize,
    /// max |θ − 2π| over interior vertices before processing (rad).
    pub theta_err_before: f64,
    /// … after (rad).
    pub theta_err_after: f64,
    /// RMS of θ − 2π before processing (rad).
    pub theta_rms_before: f64,
    /// RMS of θ − 2π after (rad).
    pub theta_rms_after: f64,
    /// RMS displacement of interior vertices (mm).
    pub rms_displacement_mm: f64,
    /// Largest displacement (mm).
    pub max_displacement_mm: f64,
    /// Change of the total area (%).
    pub area_change_percent: f64,
    /// Largest turn of a face normal against the input (degrees).
    pub max_normal_turn_deg: f64,
    /// Largest growth of an edge's bend over the input's (degrees).
    pub max_crease_deg: f64,
    /// Edges whose bend grew by more than `flatcut_flattenable::CREASE_DEG`: where the
    /// processed surface creases and the flattened piece folds.
    pub creased_edges: usize,
    /// The input's Σ (2π − θ) under the creased edges (rad): negative in saddle-like surface,
    /// where a seam or gusset helps and a dart does not (`flatcut_flattenable::CreaseKind`).
    pub creased_defect_rad: f64,
    /// Where the bend grew most (input position, mm), when an edge creased.
    pub sharpest_crease_position_mm: Option<[f64; 3]>,
    /// The input position (mm) of the interior vertex farthest from θ = 2π after processing:
    /// where an unconverged piece resists.
    pub least_flat_position_mm: Option<[f64; 3]>,
    /// Why it stopped.
    pub stop_reason: String,
    /// θ_err of the input and after every accepted iteration (rad): the convergence plot.
    pub theta_err_history: Vec<f64>,
}

/// The flattened piece.
#[derive(Clone, Debug, Serialize)]
pub struct FlattenSummary {
    /// `lscm` or `lscm+arap`.
    pub method: String,
    /// E_h = |σ1σ2 − 1| (area distortion) per face, area-weighted.
    pub e_h: Summary,
    /// E_r = 1 − σ2/σ1 (shear) per face, area-weighted.
    pub e_r: Summary,
    /// Relative edge-length change |ℓ2D/ℓ3D − 1| per face (max over its edges).
    pub edge_strain: Summary,
    /// Largest relative edge-length change.
    pub max_edge_strain: f64,
    /// 3D area (mm²).
    pub area_3d_mm2: f64,
    /// 2D area (mm²).
    pub area_2d_mm2: f64,
    /// Faces flipped in 2D (the pattern folds over itself).
    pub flipped_faces: usize,
    /// Total boundary length on the 3D piece (mm).
    pub boundary_3d_mm: f64,
    /// Total boundary length in the pattern (mm).
    pub boundary_2d_mm: f64,
    /// Pattern bounding box width × height (mm), grain along +y.
    pub size_mm: [f64; 2],
}

/// timings.json: wall times, kept out of report.json so that stays reproducible.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Timings {
    /// Pipeline name.
    pub pipeline: String,
    /// Worker threads.
    pub threads: usize,
    /// Seconds per stage, in run order.
    pub stages: Vec<StageTime>,
    /// Seconds per piece and stage.
    pub pieces: BTreeMap<String, BTreeMap<String, f64>>,
    /// Whole run (s).
    pub total_seconds: f64,
}

/// One stage's wall time.
#[derive(Clone, Debug, Serialize)]
pub struct StageTime {
    /// Stage name.
    pub stage: String,
    /// Seconds.
    pub seconds: f64,
}

/// `x` rounded to [`REPORT_SIGNIFICANT_DIGITS`] significant digits.
pub fn round_sig(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{:.*e}", REPORT_SIGNIFICANT_DIGITS - 1, x)
        .parse()
        .unwrap_or(x)
}

fn round_value(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Number(n) if n.is_f64() => {
            if let Some(r) = n
                .as_f64()
                .map(round_sig)
                .and_then(serde_json::Number::from_f64)
            {
                *n = r;
            }
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(round_value),
        serde_json::Value::Object(o) => o.values_mut().for_each(round_value),
        _ => {}
    }
}

/// Pretty JSON with every float rounded (see [`REPORT_SIGNIFICANT_DIGITS`]) and a final
/// newline. Non-finite numbers become `null` (serde_json's rule), never `NaN`.
pub fn to_json<T: Serialize>(value: &T) -> Vec<u8> {
    let mut v = serde_json::to_value(value).unwrap_or(serde_json::Value::Null);
    round_value(&mut v);
    let mut s = serde_json::to_string_pretty(&v).unwrap_or_default();
    s.push('\n');
    s.into_bytes()
}

/// Lower-case hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    use std::fmt::Write;
    let d = sha2::Sha256::digest(bytes);
    let mut s = String::with_capacity(64);
    for b in d {
        let _ = write!(s, "{b:02x}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_of_abc_is_the_fips_vector() {
        // FIPS 180-2, appendix B.1.
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn rounding_keeps_twelve_significant_digits() {
        assert_eq!(round_sig(0.1 + 0.2), 0.3);
        assert_eq!(round_sig(1.234_567_890_123_4e-10), 1.234_567_890_12e-10);
        assert_eq!(round_sig(-2.0), -2.0);
        assert_eq!(round_sig(0.0), 0.0);
    }

    #[test]
    fn json_has_no_nan_and_sorted_keys() {
        let mut m = BTreeMap::new();
        m.insert("b", f64::NAN);
        m.insert("a", 1.0 / 3.0);
        let s = String::from_utf8(to_json(&m)).expect("utf8");
        assert_eq!(s, "{\n  \"a\": 0.333333333333,\n  \"b\": null\n}\n");
    }
}
