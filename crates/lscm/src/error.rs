//! The one error type of the flattening crate.

use flatcut_mesh::{FaceId, MeshError, VertexId};

/// Why a piece could not be flattened. Every variant names the element at fault and what
/// to do about it; none of them is a panic in disguise.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum LscmError {
    /// The mesh itself is invalid (index out of range, non-finite position).
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    /// The mesh has no faces.
    #[error("the mesh has no faces; there is nothing to flatten")]
    Empty,
    /// A connected component has no boundary: it cannot be flattened without cuts.
    #[error(
        "component {component} ({faces} faces, containing {first_face}) is closed (no boundary); cut it open first (e.g. `flatcut cut`)"
    )]
    ClosedComponent {
        component: usize,
        faces: usize,
        first_face: FaceId,
    },
    /// A component is so large or so small that the flattening's products of lengths leave
    /// the range of f64 (`piece::EXTENT_RANGE`).
    #[error(
        "component {component} spans {extent:.3e} (its bounding-box diagonal), outside {min:.0e} to {max:.0e}, the extents whose powers of lengths stay finite and normal in f64; rescale the mesh (to millimetres, say) before flattening"
    )]
    ExtentOutOfRange {
        component: usize,
        extent: f64,
        min: f64,
        max: f64,
    },
    /// A vertex joins faces that do not form one fan (a bowtie): its fans would rotate
    /// freely around it.
    #[error("{vertex} is non-manifold (its faces form several fans); run `flatcut clean` first")]
    NonManifoldVertex { vertex: VertexId },
    /// An edge has more than two faces.
    #[error("the edge {a}–{b} has more than two faces; run `flatcut clean` first")]
    NonManifoldEdge { a: VertexId, b: VertexId },
    /// Two faces run a shared edge in the same direction: the piece is not oriented, so
    /// "not mirrored" has no meaning.
    #[error(
        "the faces on edge {a}–{b} are inconsistently oriented; run `flatcut clean` (orient) first"
    )]
    InconsistentOrientation { a: VertexId, b: VertexId },
    /// A face has (near) zero area; its shape, and so its flattening, is undefined.
    #[error("{face} is degenerate (repeated vertex or area ≈ 0); run `flatcut clean` to remove it")]
    DegenerateFace { face: FaceId },
    /// A given pin does not exist or is not used by any face.
    #[error("pin {vertex} is not a vertex used by any face")]
    InvalidPin { vertex: VertexId },
    /// The two pins coincide (same index or same position).
    #[error(
        "the pins {a} and {b} coincide (same vertex or same position); choose two distinct boundary vertices"
    )]
    CoincidentPins { a: VertexId, b: VertexId },
    /// The two given pins lie in different connected components.
    #[error("the pins {a} and {b} lie in different components; give two pins of one piece")]
    PinsInDifferentComponents { a: VertexId, b: VertexId },
    /// The sparse factorisation failed although the input passed every check above.
    #[error(
        "the linear system of component {component} ({stage}) failed: {cause}; the piece may contain near-degenerate faces; run `flatcut clean` and retry"
    )]
    Numerical {
        component: usize,
        stage: &'static str,
        /// What the sparse solver refused.
        #[source]
        cause: flatcut_sparse::SparseError,
    },
    /// An option is out of its valid range.
    #[error("invalid option {name} = {value}: {reason}")]
    InvalidOption {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
}
