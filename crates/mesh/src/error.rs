//! The one error type of the mesh crate.

use crate::{FaceId, VertexId};

/// What can go wrong when building or checking a mesh.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MeshError {
    /// A face refers to a vertex that does not exist.
    #[error("{face} refers to vertex {index}, but the mesh has only {vertex_count} vertices")]
    FaceIndexOutOfRange {
        face: FaceId,
        index: u32,
        vertex_count: usize,
    },
    /// A position is NaN or infinite.
    #[error(
        "{vertex} has a non-finite coordinate {position:?}; fix or remove it in the source file"
    )]
    NonFinitePosition {
        vertex: VertexId,
        position: [f64; 3],
    },
    /// More vertices or faces than a `u32` index can address.
    #[error("the mesh has {count} {what}, more than the 4294967295 a u32 index can address")]
    TooLarge { what: &'static str, count: usize },
    /// A per-vertex attribute has the wrong length.
    #[error(
        "per-vertex attribute '{name}' has {len} entries but the mesh has {vertex_count} vertices"
    )]
    AttributeLength {
        name: &'static str,
        len: usize,
        vertex_count: usize,
    },
    /// A per-face label array has the wrong length.
    #[error("face labels have {len} entries but the mesh has {face_count} faces")]
    FaceLabelLength { len: usize, face_count: usize },
    /// A parameter given by the caller is out of its valid range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
}
