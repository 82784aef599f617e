//! The one error type of the remesh crate.

use flatcut_mesh::MeshError;

/// What can go wrong when remeshing, decimating or filling holes. Every variant names the
/// element and says what to do.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum RemeshError {
    /// The mesh has no faces.
    #[error("the mesh has no faces: nothing to remesh")]
    EmptyMesh,
    /// The mesh itself is malformed (index out of range, non-finite position, ...).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A face uses one vertex twice.
    #[error("face {face} uses a vertex twice ({vertices:?}); run `flatcut clean` first")]
    RepeatedVertex { face: u32, vertices: [u32; 3] },
    /// More than two faces share an edge.
    #[error(
        "edge {a}–{b} is non-manifold (more than two faces share it); remeshing needs a manifold surface: run `flatcut clean` or split the surface there"
    )]
    NonManifoldEdge { a: u32, b: u32 },
    /// Two or more fans of faces meet only at a vertex.
    #[error(
        "vertex {vertex} is non-manifold (two fans of faces meet only there); run `flatcut clean` or duplicate the vertex per fan"
    )]
    NonManifoldVertex { vertex: u32 },
    /// Neighbouring faces disagree on orientation.
    #[error(
        "edge {a}–{b} is run in the same direction by both its faces (flipped orientation); run `flatcut clean` to orient the faces consistently"
    )]
    InconsistentOrientation { a: u32, b: u32 },
    /// An option is out of range.
    #[error("option {name} = {value} is invalid: {reason}")]
    InvalidOption {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// The target edge length is larger than the object.
    #[error(
        "target edge {target_edge_mm} mm is larger than the object (bounding-box diagonal {diagonal_mm} mm): choose a smaller --edge-mm"
    )]
    TargetTooLarge {
        target_edge_mm: f64,
        diagonal_mm: f64,
    },
    /// The target edge length is below 1e-6 of the object size.
    #[error(
        "target edge {target_edge_mm} mm is below 1e-6 of the object size (diagonal {diagonal_mm} mm): check the units or choose a larger --edge-mm"
    )]
    TargetTooSmall {
        target_edge_mm: f64,
        diagonal_mm: f64,
    },
    /// A given feature polyline steps between vertices that share no edge.
    #[error(
        "feature line {line}: vertices {a} and {b} share no edge of the mesh; feature lines must follow mesh edges"
    )]
    FeatureNotAnEdge { line: usize, a: u32, b: u32 },
    /// A feature polyline names a vertex that does not exist.
    #[error("feature line {line} names vertex {vertex}, but the mesh has {vertex_count} vertices")]
    FeatureVertexOutOfRange {
        line: usize,
        vertex: u32,
        vertex_count: usize,
    },
}
