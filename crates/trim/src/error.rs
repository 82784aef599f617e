//! The one error type of the trim crate: every variant names the line, landmark or piece at
//! fault and says what to do.

use flatcut_mesh::MeshError;

/// What went wrong while cutting a surface.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrimError {
    /// The mesh itself is unusable (index out of range, too large).
    #[error("the mesh is unusable: {0}")]
    Mesh(#[from] MeshError),
    /// The mesh has no faces.
    #[error("the mesh has no faces; there is nothing to cut")]
    EmptyMesh,
    /// A landmark or line point is too far from the surface.
    #[error(
        "{what} is {distance_mm:.3} mm from the surface (tolerance {tolerance_mm} mm); move it onto the surface or raise the tolerance"
    )]
    OffSurface {
        /// Which point, e.g. `line "neck" point 2`.
        what: String,
        /// Its distance to the closest surface point.
        distance_mm: f64,
        /// The tolerance it exceeded.
        tolerance_mm: f64,
    },
    /// A point has a non-finite coordinate.
    #[error("{what} has a non-finite coordinate; give finite numbers")]
    NonFinitePoint {
        /// Which point.
        what: String,
    },
    /// A line's vertex index is not a vertex of the mesh.
    #[error(
        "line {line:?}: vertex {vertex} is not a used vertex of the mesh ({vertex_count} vertices)"
    )]
    BadVertex {
        /// The line.
        line: String,
        /// The index given.
        vertex: u64,
        /// Vertices in the mesh.
        vertex_count: usize,
    },
    /// A line is described neither by points nor by vertices, or by both, or has too few.
    #[error("line {line:?}: {reason}")]
    BadLine {
        /// The line.
        line: String,
        /// What is wrong.
        reason: String,
    },
    /// No path on the surface joins two points (different components, non-manifold fans).
    #[error(
        "line {line:?}: no path on the surface from point {from} to point {to}; are they on the same connected part of the mesh?"
    )]
    NoPath {
        /// The line.
        line: String,
        /// Index of the first point of the segment.
        from: usize,
        /// Index of the second point.
        to: usize,
    },
    /// An open line's end is neither on the mesh boundary nor on another line.
    #[error(
        "line {line:?}: its {end} end at {point_mm:?} mm is {distance_mm:.3} mm from the nearest boundary or other line (snap tolerance {tolerance_mm} mm); extend it to a boundary or a line, or make it closed"
    )]
    LineEndFree {
        /// The line.
        line: String,
        /// "first" or "last".
        end: &'static str,
        /// The end point.
        point_mm: [f64; 3],
        /// Distance to the nearest boundary or line.
        distance_mm: f64,
        /// The snap tolerance.
        tolerance_mm: f64,
    },
    /// A line crosses or touches itself.
    #[error(
        "line {line:?} crosses itself near {point_mm:?} mm; cut it into two lines or reroute it"
    )]
    SelfCrossing {
        /// The line.
        line: String,
        /// Where.
        point_mm: [f64; 3],
    },
    /// Two lines run along each other over a stretch.
    #[error(
        "lines {a:?} and {b:?} overlap along a stretch near {point_mm:?} mm; two lines may cross or meet but not share a stretch — remove one"
    )]
    OverlappingLines {
        /// One line.
        a: String,
        /// The other.
        b: String,
        /// Where.
        point_mm: [f64; 3],
    },
    /// Two lines or two pieces share a name.
    #[error("{what} name {name:?} is used twice; give each a unique name")]
    DuplicateName {
        /// "line" or "piece".
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A seed lies on a cutting line, so it names no piece.
    #[error(
        "piece {piece:?}: its seed lies on cutting line {line:?}; move the seed into the piece"
    )]
    SeedOnLine {
        /// The piece.
        piece: String,
        /// The line.
        line: String,
    },
    /// Two seeds fall into the same piece.
    #[error(
        "pieces {first:?} and {second:?} have their seeds in the same piece; a cutting line between them is missing or does not close, or passes the seed of {second:?} on the wrong side (it is {near_mm:.1} mm from line {near_line}): move that seed into its piece"
    )]
    // The nearest line's name is not quoted: the pipeline locates an error at the first quoted
    // name of a cut in it, and the place to fix is the piece's seed.
    SeedUsedTwice {
        /// The first name.
        first: String,
        /// The second name.
        second: String,
        /// The line nearest the second seed (on a noisy scan a line may pass a seed closely,
        /// on its other side).
        near_line: String,
        /// Its distance from the second seed's surface point, mm.
        near_mm: f64,
    },
    /// The embedding failed at a face (a numerical corner case).
    #[error("cannot embed line {line:?} in source face {face}: {reason}; move the line slightly")]
    Embedding {
        /// The line.
        line: String,
        /// The source face.
        face: u32,
        /// What failed.
        reason: String,
    },
    /// A built-in cut design cannot place one of its landmarks on the given mesh.
    #[error("cannot place landmark {what} on the mesh; is it the shape this cut was designed for?")]
    NoLandmark {
        /// The landmark.
        what: String,
    },
}
