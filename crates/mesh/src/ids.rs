//! Typed indices, so that a vertex index is never passed where a face index is meant.

use std::fmt;

/// Index of a vertex in [`crate::TriMesh::positions`].
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct VertexId(pub u32);

/// Index of a face in [`crate::TriMesh::faces`].
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct FaceId(pub u32);

impl VertexId {
    /// The index as `usize`, for slicing.
    #[inline]
    pub fn idx(self) -> usize {
        self.0 as usize
    }
}

impl FaceId {
    /// The index as `usize`, for slicing.
    #[inline]
    pub fn idx(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for VertexId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "vertex {}", self.0)
    }
}

impl fmt::Display for FaceId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "face {}", self.0)
    }
}
