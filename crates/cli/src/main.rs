//! `flatcut`: turn 3D surfaces into 2D cut patterns that sew back without stretch.
//!
//! Exit codes: 0 success, 1 bad input or a failed run, 2 bad usage (clap's own code).
//! A panic is always a bug: the hook below says so and asks for a report.

/// Appends a line to a `String` buffer that the command prints at the end with
/// [`util::emit`] (so a closed pipe is handled in one place).
macro_rules! outln {
    ($o:ident, $($t:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($o, $($t)*);
    }};
}

mod clean;
mod dart;
mod demo;
mod export;
mod flatten;
mod info;
mod process;
mod remesh;
mod run;
mod surface;
mod trim;
mod util;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Turn 3D surfaces (body scans, furniture) into 2D cut patterns that sew back without stretch.
#[derive(Parser, Debug)]
#[command(name = "flatcut", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Report counts, topology, defects, size and curvature of a mesh file.
    Info(info::InfoArgs),
    /// Repair a scan: weld, drop degenerate/duplicate/unreferenced elements, orient, keep components.
    Clean(clean::CleanArgs),
    /// Run the main job on the embedded default: a generated dress form, written and analysed.
    Demo(demo::DemoArgs),
    /// Write flattened pieces as cut patterns: SVG, DXF (AAMA), PNG/EXR maps, tiled PDF, GLB.
    Export(export::ExportArgs),
    /// Flatten open pieces to a true-size 2D pattern (OBJ) and measure the distortion.
    Flatten(flatten::FlattenArgs),
    /// Make pieces flattenable (θ = 2π at every interior vertex) with the least-norm method.
    Process(process::ProcessArgs),
    /// Cut a surface along lines drawn on it into named pieces, with the seam ledger.
    Trim(trim::TrimArgs),
    /// Make a triangulated surface patch spanning a wire-frame of 3D boundary curves (WIRE.toml).
    Surface(surface::SurfaceArgs),
    /// Run pipeline recipes (TOML) end to end into output folders with a report; no
    /// argument runs the bundled wetsuit demo.
    Run(run::RunArgs),
    /// Remesh a scan to a working edge length (and/or decimate it), fill small holes, report quality.
    Remesh(remesh::RemeshArgs),
    /// Cut darts into a piece (boundary to tip, opened; tip one vertex), or propose where.
    Dart(dart::DartArgs),
}

fn main() -> ExitCode {
    std::panic::set_hook(Box::new(|info| {
        eprintln!("flatcut: internal error (a bug, not your input): {info}");
        eprintln!("Please report it with the command line and the input file.");
    }));
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Info(args) => info::run(args),
        Command::Clean(args) => clean::run(args),
        Command::Demo(args) => demo::run(args),
        Command::Export(args) => export::run(args),
        Command::Flatten(args) => flatten::run(args),
        Command::Process(args) => process::run(args),
        Command::Trim(args) => trim::run(args),
        Command::Surface(args) => surface::run(args),
        Command::Run(args) => run::run(args),
        Command::Remesh(args) => remesh::run(args),
        Command::Dart(args) => dart::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("flatcut: error: {}", message(&err));
            ExitCode::from(1)
        }
    }
}

/// The error and its causes, `: `-separated as anyhow's `{:#}` prints them, but without a cause
/// whose text the message already holds: the libraries' errors put their source's text in
/// their own (so that they read whole wherever they are shown), and the chain would repeat it
/// ("cannot write out.obj: out.obj: No such file or directory (os error 2): No such file or
/// directory (os error 2)").
fn message(err: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in err.chain() {
        let part = cause.to_string();
        if text.contains(&part) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&part);
    }
    text
}
