//! Cutting a surface into pieces along lines drawn on it: surface points, geodesic cutting
//! lines, exact embedding, pieces with a provenance map, the seam ledger; and surface patches
//! from wire-frames.

pub mod cut;
pub mod cuts;
pub mod embed;
mod error;
pub mod geodesic;
pub mod lines;
pub mod pieces;
mod seams;
pub mod surface_point;
pub mod untangle;
mod wetsuit;

pub use cut::{LineReport, TrimReport, Trimmed, trim};
pub use cuts::{CutSpec, Cuts, PieceSpec, TrimOptions};
pub use embed::{Embedded, embed};
pub use error::TrimError;
pub use geodesic::{Geodesic, GeodesicOptions, GeodesicSolver, geodesic};
pub use lines::{CutLine, closest_on_halfedges, cut_lines};
pub use pieces::{Piece, PieceReport, Split, split_along};
pub use surface_point::{Location, SurfacePoint, SurfacePointOptions, surface_point};
pub use wetsuit::dress_form_wetsuit;
pub mod wireframe;

pub use wireframe::{
    DomainChoice, DomainKind, VertexOrigin, WireCurve, WireFrame, WireframeError, WireframeOptions,
    WireframePatch, WireframeReport, wireframe_surface,
};
