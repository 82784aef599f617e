//! The one error type of the io crate.

use std::path::PathBuf;

use flatcut_mesh::MeshError;

/// Everything that can go wrong reading or writing a mesh file.
///
/// Every variant names the file; text formats name the 1-based line, binary formats the byte
/// offset or element index, and the message says what to do about it.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused to read or write the file.
    #[error("{path}: {source}", path = .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file extension is not one flatcut reads or writes.
    #[error(
        "{path}: unsupported mesh format '{extension}'; flatcut {action} {supported}",
        path = .path.display()
    )]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
        /// The extension found (empty if none).
        extension: String,
        /// "reads" or "writes".
        action: &'static str,
        /// The supported extensions, e.g. ".obj, .ply, .stl, .gltf, .glb".
        supported: &'static str,
    },
    /// A text file (OBJ, ASCII PLY, ASCII STL, glTF JSON) has a syntax or content error.
    #[error("{path}:{line}: {reason}", path = .path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong and what to do.
        reason: String,
    },
    /// A binary file (binary PLY/STL, GLB) has invalid content at a byte offset.
    #[error("{path}: at byte {offset}: {reason}", path = .path.display())]
    Binary {
        /// The file.
        path: PathBuf,
        /// Byte offset from the start of the file.
        offset: u64,
        /// What is wrong and what to do.
        reason: String,
    },
    /// A binary file ends before the data its header promises.
    #[error(
        "{path}: truncated: {what} needs {needed} bytes from byte {offset}, but only {available} remain; \
         the file is cut short or its header is wrong (re-export it)",
        path = .path.display()
    )]
    Truncated {
        /// The file.
        path: PathBuf,
        /// What was being read.
        what: String,
        /// Where it starts.
        offset: u64,
        /// Bytes it needs.
        needed: u64,
        /// Bytes left in the file.
        available: u64,
    },
    /// A glTF document is structurally invalid (names the JSON element, e.g. "accessor 3").
    #[error("{path}: {element}: {reason}", path = .path.display())]
    Gltf {
        /// The file.
        path: PathBuf,
        /// The glTF element, e.g. "mesh 0 primitive 1" or "buffer 0".
        element: String,
        /// What is wrong and what to do.
        reason: String,
    },
    /// The file parsed but holds no triangles.
    #[error("{path}: {reason}; nothing to flatten (check that the file holds a surface mesh)", path = .path.display())]
    NoFaces {
        /// The file.
        path: PathBuf,
        /// What was found instead.
        reason: String,
    },
    /// The mesh read (or to be written) violates a mesh invariant.
    #[error("{path}{}: {source}", line_suffix(*.line), path = .path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// The line (text formats) where the offending element was defined, when known.
        line: Option<usize>,
        /// The violated invariant (names the vertex or face).
        #[source]
        source: MeshError,
    },
}

fn line_suffix(line: Option<usize>) -> String {
    line.map_or_else(String::new, |l| format!(":{l}"))
}
