//! The triangle mesh of flatcut and everything derived from it.
//!
//! [`TriMesh`] is plain arrays (f64 positions in millimetres, u32 triangles).
//! [`Topology`] derives connectivity from it once; [`geometry`] computes angles, areas and
//! weights; [`bvh`] answers closest-point and ray queries; [`clean`] repairs scans;
//! [`shapes`] makes the procedural surfaces tests and the demo run on.

pub mod atan2;
pub mod bvh;
pub mod clean;
mod error;
pub mod geometry;
mod ids;
mod info;
mod seam_ledger;
pub mod shapes;
mod submesh;
mod topology;
mod trimesh;
pub mod vec3;

pub use error::MeshError;
pub use ids::{FaceId, VertexId};
pub use info::{MeshInfo, mesh_info};
pub use seam_ledger::{SEAM_LEDGER_SCHEMA, Seam, SeamKind, SeamLedger, SeamLedgerError, SeamSide};
pub use submesh::submesh;
pub use topology::{ComponentSummary, INVALID, Topology};
pub use trimesh::{FaceLabels, TriMesh, VertexAttributes};
