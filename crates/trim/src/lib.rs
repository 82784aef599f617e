//! Cutting a surface into pieces along lines drawn on it: surface points, geodesic cutting
//! lines, exact embedding, pieces with a provenance map, the seam ledger; and surface patches
//! from wire-frames.

mod error;
pub mod geodesic;
pub mod surface_point;

pub use error::TrimError;
pub use geodesic::{Geodesic, GeodesicOptions, GeodesicSolver, geodesic};
pub use surface_point::{Location, SurfacePoint, SurfacePointOptions, surface_point};
