//! Cutting a surface into pieces along lines drawn on it: surface points, geodesic cutting
//! lines, exact embedding, pieces with a provenance map, the seam ledger; and surface patches
//! from wire-frames.

pub mod wireframe;

pub use wireframe::{
    DomainChoice, DomainKind, VertexOrigin, WireCurve, WireFrame, WireframeError, WireframeOptions,
    WireframePatch, WireframeReport, wireframe_surface,
};
