//! The one error type of the crate.

use std::path::PathBuf;

/// What can go wrong in a pipeline run. TOML errors give the file, line and column (1-based)
/// and the key; stage errors name the piece.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The pipeline file cannot be read.
    #[error("cannot read the pipeline {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The TOML does not parse or does not match schema 1 (unknown key, wrong type, missing
    /// key); `message` is the parser's, naming the key and what is allowed.
    #[error("{}:{line}:{column}: {message}", file.display())]
    Toml {
        /// The pipeline file.
        file: PathBuf,
        /// 1-based line (0 if unknown).
        line: usize,
        /// 1-based column (0 if unknown).
        column: usize,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A value parses but is not usable (a second input, a bad name, a seed off the surface).
    #[error("{}:{line}:{column}: {key}: {message}", file.display())]
    Invalid {
        /// The pipeline file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The key, dotted (`input.mesh`, `piece.seed`).
        key: String,
        /// What is wrong and what to do.
        message: String,
    },
    /// The input mesh cannot be read.
    #[error("{}:{line}:{column}: input.mesh: {source}", file.display())]
    InputMesh {
        /// The pipeline file.
        file: PathBuf,
        /// 1-based line of `mesh = …`.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The reader's error (names the mesh file and the place in it).
        source: Box<flatcut_io::IoError>,
    },
    /// Cleaning failed (an invalid option or mesh).
    #[error("{}: [input].clean: {source}", file.display())]
    Clean {
        /// The pipeline file.
        file: PathBuf,
        /// The mesh crate's error.
        source: Box<flatcut_mesh::MeshError>,
    },
    /// Remeshing failed.
    #[error("{}: [input].remesh: {source}", file.display())]
    Remesh {
        /// The pipeline file.
        file: PathBuf,
        /// The remesh crate's error.
        source: Box<flatcut_remesh::RemeshError>,
    },
    /// Flattenable processing refused or failed on a piece.
    #[error("piece {piece:?}: [process]: {source}")]
    Process {
        /// The piece name.
        piece: String,
        /// The processing error.
        source: Box<flatcut_flattenable::FlattenableError>,
    },
    /// Flattening failed on a piece.
    #[error("piece {piece:?}: [flatten]: {source}")]
    Flatten {
        /// The piece name.
        piece: String,
        /// The flattening error.
        source: Box<flatcut_lscm::LscmError>,
    },
    /// The pattern stage refused a piece or an option.
    #[error("[pattern]: {source}")]
    Pattern {
        /// The pattern crate's error.
        source: Box<flatcut_pattern::PatternError>,
    },
    /// A writer refused its input or options.
    #[error("cannot write {file}: {source}")]
    Export {
        /// The output file's name inside the folder.
        file: String,
        /// The export crate's error.
        source: Box<flatcut_export::ExportError>,
    },
    /// A mesh could not be encoded for output (a non-finite value would have reached a file).
    #[error("cannot encode {name}: {source}")]
    Encode {
        /// The output file's name inside the folder.
        name: String,
        /// The writer's error.
        source: Box<flatcut_io::IoError>,
    },
    /// The output folder path is an existing file.
    #[error(
        "the output folder {} is an existing file; give another folder with --out or `output = …`",
        path.display()
    )]
    OutputIsFile {
        /// The path.
        path: PathBuf,
    },
    /// The output folder holds another pipeline's results (or files flatcut did not write).
    #[error(
        "the output folder {} {}; choose another with --out or `output = …`, or pass --force to write into it",
        path.display(),
        match owner {
            Some(o) => format!("holds the results of pipeline {o:?}"),
            None => "is not empty and was not written by flatcut run".to_string(),
        }
    )]
    OutputForeign {
        /// The folder.
        path: PathBuf,
        /// The pipeline that wrote it, if flatcut did.
        owner: Option<String>,
    },
    /// An output file would replace an input.
    #[error(
        "writing {} would overwrite an input of the pipeline; inputs are never written: choose another output folder",
        path.display()
    )]
    WouldOverwriteInput {
        /// The output file that is also an input.
        path: PathBuf,
    },
    /// An input is a file an earlier run wrote in the output folder and this run does not
    /// write, which the run would remove as stale.
    #[error(
        "{} is an input of the pipeline and a file an earlier run left in the output folder, which this run would remove; inputs are never removed: move it out of the folder or choose another output folder",
        path.display()
    )]
    WouldRemoveInput {
        /// The earlier run's file that is also an input.
        path: PathBuf,
    },
    /// Writing the output folder failed.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A worker thread pool could not be made.
    #[error("cannot start {threads} worker threads: {reason}")]
    Threads {
        /// Threads asked for.
        threads: usize,
        /// Why.
        reason: String,
    },
}
