//! The pipeline of flatcut: a TOML recipe (schema 1) that names the input surface, how it is
//! cleaned, cut into pieces, processed, flattened and exported, and the reproducible run of
//! that recipe into an output folder with report.json.
//!
//! [`Pipeline::parse`] reads the recipe (every table deserializes straight into the options
//! struct of the crate that uses it); [`run`] runs it and writes the folder; [`compute`] runs
//! it in memory. This crate is the orchestrator: it reads the inputs and writes the output
//! folder (see [`output`] for the folder rules); the algorithms it calls never touch files.
//! See docs/pipeline.md for the schema.

mod error;
pub mod export;
pub mod features;
pub mod html;
pub mod output;
pub mod pieces;
pub mod progress;
pub mod render;
pub mod report;
mod run;
pub mod seams;
pub mod spec;

pub use error::PipelineError;
pub use progress::Progress;
pub use report::{Report, Timings};
pub use run::{Computed, RunOptions, RunOutcome, compute, input_paths, run};
pub use spec::{Pipeline, PipelineSpec, SCHEMA};

/// How far (mm) a `[[piece]]` seed may lie from the surface: a point picked on a scan in
/// another tool lands within a few mm of this mesh (decimation, remeshing), while 5 mm is
/// well below any piece's size, so the closest piece is still the intended one. The same
/// default as trim's landmarks.
pub const SEED_TOLERANCE_MM: f64 = 5.0;

/// The bundled demo pipeline (pipelines/wetsuit-demo.toml), embedded so that `flatcut run`
/// works from any folder.
pub const WETSUIT_DEMO_TOML: &str = include_str!("../../../pipelines/wetsuit-demo.toml");
