//! The wire-frame input (WIRE.toml) and its options, with their validation.

use flatcut_mesh::vec3::{dist, scale};
use serde::{Deserialize, Serialize};

use super::WireframeError;
use super::geom::diagonal;

/// Two input points closer than this × the loop's diagonal are "the same point" (a repeated
/// point in a curve is an error: a zero-length segment has no direction). Far above f64
/// round-off of mm coordinates, far below any drawn feature.
const REPEATED_POINT_RELATIVE: f64 = 1e-9;

/// How the parameter domain is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DomainChoice {
    /// The best-fit plane when the loop projects to a simple polygon there, else the circle.
    #[default]
    Auto,
    /// The best-fit plane only: a loop whose projection crosses itself is an error.
    Plane,
    /// The loop laid around a circle by arc length (no guide curves).
    Circle,
}

/// Tuning of [`wireframe_surface`]; the `[options]` table of WIRE.toml.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct WireframeOptions {
    /// Curve ends closer than this join (mm). Default 0.1 mm: CAD snaps are exact, hand
    /// digitised ends are not.
    pub join_tolerance_mm: f64,
    /// Which parameter domain to use. Default `auto`.
    pub domain: DomainChoice,
    /// Minimum triangle angle the Delaunay refinement keeps in the domain (degrees). Default
    /// 28°: above the 20° asked in 3D, leaving room for the lift's distortion; spade's
    /// refinement is only guaranteed to terminate up to about 30°.
    pub domain_min_angle_deg: f64,
    /// The minimum 3D angle the patch should reach (degrees); below it the patch is re-meshed
    /// in a conformal flattening of itself.
    /// Default 20°.
    pub min_angle_3d_deg: f64,
    /// At most this many re-parametrisation passes when the 3D minimum angle is below
    /// `min_angle_3d_deg`. Default 3.
    pub reparam_passes: usize,
    /// Refuse patches needing more vertices than this (a target edge far too small for the
    /// loop). Default 2 000 000.
    pub max_vertices: usize,
}

impl Default for WireframeOptions {
    fn default() -> Self {
        Self {
            join_tolerance_mm: 0.1,
            domain: DomainChoice::Auto,
            domain_min_angle_deg: 28.0,
            min_angle_3d_deg: 20.0,
            reparam_passes: 3,
            max_vertices: 2_000_000,
        }
    }
}

/// One named 3D polyline of a wire-frame.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WireCurve {
    /// The name errors and reports use.
    pub name: String,
    /// The points, in the wire-frame's `units`.
    pub points: Vec<[f64; 3]>,
}

/// A wire-frame: WIRE.toml.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WireFrame {
    /// Units of all `points`: mm, cm, dm, m or in (default mm). The caller converts
    /// (see [`WireFrame::scaled`]); [`wireframe_surface`] takes millimetres.
    #[serde(default = "default_units")]
    pub units: String,
    /// Target triangle edge length (mm, whatever `units` says).
    pub target_edge_mm: f64,
    /// Boundary curves: one closed curve, or open curves that join end to end into one loop
    /// (in any order and direction).
    #[serde(default)]
    pub curve: Vec<WireCurve>,
    /// Interior guide curves the surface must pass through (open polylines; an end may sit on
    /// the boundary within the join tolerance).
    #[serde(default)]
    pub guide: Vec<WireCurve>,
    /// Tuning from the file's `[options]` table; every field optional. [`wireframe_surface`]
    /// takes its options as a separate argument (callers pass `&wire.options` or their own).
    #[serde(default)]
    pub options: WireframeOptions,
}

fn default_units() -> String {
    "mm".to_string()
}

impl WireFrame {
    /// The wire-frame with every curve and guide point multiplied by `factor_to_mm`
    /// (`target_edge_mm` and the options are already in mm), and `units` = "mm".
    pub fn scaled(&self, factor_to_mm: f64) -> WireFrame {
        let sc = |c: &WireCurve| WireCurve {
            name: c.name.clone(),
            points: c.points.iter().map(|p| scale(*p, factor_to_mm)).collect(),
        };
        WireFrame {
            units: "mm".to_string(),
            target_edge_mm: self.target_edge_mm,
            curve: self.curve.iter().map(sc).collect(),
            guide: self.guide.iter().map(sc).collect(),
            options: self.options.clone(),
        }
    }
}

pub(super) fn check_options(o: &WireframeOptions) -> Result<(), WireframeError> {
    let bad = |name, value, expected| {
        Err(WireframeError::BadOption {
            name,
            value,
            expected,
        })
    };
    if !(o.join_tolerance_mm.is_finite() && o.join_tolerance_mm >= 0.0) {
        return bad(
            "join_tolerance_mm",
            o.join_tolerance_mm,
            "a length ≥ 0 (mm)",
        );
    }
    if !(o.domain_min_angle_deg.is_finite()
        && o.domain_min_angle_deg > 0.0
        && o.domain_min_angle_deg <= 33.0)
    {
        return bad(
            "domain_min_angle_deg",
            o.domain_min_angle_deg,
            "an angle in (0, 33] degrees (Delaunay refinement may not terminate above ~30°)",
        );
    }
    if !(o.min_angle_3d_deg.is_finite() && (0.0..60.0).contains(&o.min_angle_3d_deg)) {
        return bad(
            "min_angle_3d_deg",
            o.min_angle_3d_deg,
            "an angle in [0, 60) degrees",
        );
    }
    Ok(())
}

pub(super) fn check_polyline(
    what: &'static str,
    c: &WireCurve,
    needed: usize,
) -> Result<(), WireframeError> {
    if c.points.len() < needed {
        return Err(WireframeError::TooFewPoints {
            what,
            name: c.name.clone(),
            points: c.points.len(),
            needed,
        });
    }
    if let Some(i) = c
        .points
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        return Err(WireframeError::NonFinite {
            what,
            name: c.name.clone(),
            point: i,
            value: c.points[i],
        });
    }
    let d = diagonal(c.points.iter().copied());
    for i in 0..c.points.len() - 1 {
        if dist(c.points[i], c.points[i + 1]) <= REPEATED_POINT_RELATIVE * d.max(1.0) {
            return Err(WireframeError::RepeatedPoint {
                what,
                name: c.name.clone(),
                point: i,
            });
        }
    }
    Ok(())
}
