//! `flatcut remesh IN OUT`: bring a scan to a working resolution (isotropic remeshing,
//! optionally after quadric decimation), fill small holes, and report the quality.

use std::path::PathBuf;

use anyhow::{Context, bail};
use flatcut_io::Units;
use flatcut_remesh::{
    DecimateOptions, QualityReport, RemeshOptions, decimate, quality_report, remesh,
};
use serde::Serialize;

/// Arguments of `flatcut remesh`.
#[derive(clap::Args, Debug)]
pub struct RemeshArgs {
    /// Input mesh file (.obj, .ply, .stl, .gltf, .glb); never modified.
    pub input: PathBuf,
    /// Output mesh file; its extension picks the format. Must differ from the input.
    pub output: PathBuf,
    /// Target edge length in mm of the isotropic remesh (omit to only decimate).
    #[arg(long)]
    pub edge_mm: Option<f64>,
    /// Smallest edge in mm when adapting to curvature (give --max-edge-mm too).
    #[arg(long)]
    pub min_edge_mm: Option<f64>,
    /// Largest edge in mm when adapting to curvature (give --min-edge-mm too).
    #[arg(long)]
    pub max_edge_mm: Option<f64>,
    /// Approximation-error bound in mm: where a face's centroid or an edge midpoint lies
    /// farther from the input, the remesh refines locally (down to 0.625 × --edge-mm, or
    /// --min-edge-mm); 0 turns it off. Scan noise finer than the triangles is not refined
    /// (the report gives how much of the surface that is).
    #[arg(long, default_value_t = 0.5)]
    pub max_deviation_mm: f64,
    /// Decimate to at most this many faces first (quadric error metrics): the fast first
    /// step for a scan of a million triangles.
    #[arg(long)]
    pub decimate_to: Option<usize>,
    /// Fill holes whose perimeter is below this many mm; larger openings stay open.
    #[arg(long, default_value_t = 0.0)]
    pub fill_holes_mm: f64,
    /// Dihedral angle in degrees above which an edge is a crease to keep (180: none).
    #[arg(long, default_value_t = 45.0)]
    pub feature_angle_deg: f64,
    /// Split–collapse–flip–relax rounds.
    #[arg(long, default_value_t = 10)]
    pub iterations: usize,
    /// Taubin smoothing steps on the result (boundaries and creases fixed): removes scan
    /// noise that flattenable processing would otherwise have to iron; vertices then leave
    /// the input by about the noise's amplitude. 0: off.
    #[arg(long, default_value_t = 0)]
    pub smooth_iterations: usize,
    /// Units of the input: mm, cm, dm, m or in (default: m for .gltf/.glb, as glTF fixes, else mm). The output is in mm.
    #[arg(long, value_parser = crate::util::parse_units)]
    pub units: Option<Units>,
    /// Write the JSON report to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print the report as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// What `flatcut remesh` reports.
#[derive(Serialize)]
struct Report {
    input_vertices: usize,
    input_faces: usize,
    /// Faces after decimation, when it ran.
    decimated_faces: Option<usize>,
    /// The output measured against the input file's surface.
    quality: QualityReport,
}

/// Runs `flatcut remesh`.
pub fn run(args: &RemeshArgs) -> anyhow::Result<()> {
    if args.edge_mm.is_none() && args.decimate_to.is_none() {
        bail!("give --edge-mm (remesh to that edge length) and/or --decimate-to (face budget)");
    }
    let mut outputs = vec![("OUT", args.output.as_path())];
    outputs.extend(args.report.as_deref().map(|r| ("--report", r)));
    crate::util::refuse_overwrite(&[("IN", &args.input)], &outputs)?;
    let loaded =
        flatcut_io::read_mesh(&args.input, crate::util::units_for(&args.input, args.units))?;
    let input = &loaded.mesh;
    let ctx = || format!("remeshing {}", args.input.display());
    let mut work = None;
    let mut decimated_faces = None;
    if let Some(n) = args.decimate_to {
        if input.faces.len() > n {
            let d = decimate(input, &DecimateOptions { target_faces: n }).with_context(ctx)?;
            decimated_faces = Some(d.mesh.faces.len());
            work = Some((d.mesh, d.report));
        }
    }
    if let Some(edge) = args.edge_mm {
        let opts = RemeshOptions {
            target_edge_mm: edge,
            min_edge_mm: args.min_edge_mm,
            max_edge_mm: args.max_edge_mm,
            iterations: args.iterations,
            feature_angle_deg: args.feature_angle_deg,
            fill_holes_perimeter_mm: args.fill_holes_mm,
            max_deviation_mm: args.max_deviation_mm,
            smooth_iterations: args.smooth_iterations,
            ..RemeshOptions::default()
        };
        let src = work.as_ref().map_or(input, |(m, _)| m);
        let r = remesh(src, &opts).with_context(ctx)?;
        let quality = if decimated_faces.is_some() {
            // Measure against the file's surface, not the decimated one.
            let filled: Vec<bool> = r.provenance.iter().map(|p| p.filled).collect();
            let bound = (args.max_deviation_mm > 0.0).then_some(args.max_deviation_mm);
            let mut q = quality_report(&r.mesh, input, Some(edge), bound, &filled);
            q.rough_input_fraction = r.report.rough_input_fraction;
            q.holes = r.report.holes.clone();
            q.holes_filled = r.report.holes_filled;
            q
        } else {
            r.report
        };
        work = Some((r.mesh, quality));
    }
    let Some((mesh, quality)) = work else {
        bail!(
            "{} already has {} faces, within --decimate-to {}: nothing to do",
            args.input.display(),
            input.faces.len(),
            args.decimate_to.unwrap_or(0)
        );
    };
    flatcut_io::write_mesh(&args.output, &mesh, &flatcut_io::WriteOptions::default())?;
    let report = Report {
        input_vertices: input.positions.len(),
        input_faces: input.faces.len(),
        decimated_faces,
        quality,
    };
    let json = serde_json::to_string_pretty(&report)?;
    if let Some(path) = &args.report {
        crate::util::write_text_atomic(path, &json)?;
    }
    let mut o = String::new();
    if args.json {
        outln!(o, "{json}");
    } else {
        let q = &report.quality;
        outln!(
            o,
            "{}: {} vertices, {} faces (input {} faces{})",
            args.output.display(),
            q.vertices,
            q.faces,
            report.input_faces,
            decimated_faces.map_or(String::new(), |n| format!(", decimated to {n}"))
        );
        outln!(
            o,
            "  edges         {:.2} / {:.2} / {:.2} mm (min/mean/max), {:.2} % within [0.5, 1.5] × {:.2} mm",
            q.min_edge_mm,
            q.mean_edge_mm,
            q.max_edge_mm,
            100.0 * q.edges_within_half_to_1_5,
            q.target_edge_mm
        );
        outln!(
            o,
            "  angles        min {:.2}°, mean smallest {:.2}°, {:.2} % of faces ≥ 25°",
            q.min_angle_deg,
            q.mean_min_angle_deg,
            100.0 * q.faces_min_angle_at_least_25_deg
        );
        outln!(
            o,
            "  distance      vertices max {:.3} mm, centroids max {:.3} mm, input→output max {:.3} mm, RMS {:.3} mm",
            q.vertex_to_input.max_mm,
            q.centroid_to_input.max_mm,
            q.input_to_output.max_mm,
            q.rms_mm
        );
        if q.max_deviation_mm > 0.0 {
            outln!(
                o,
                "  deviation     {} vertices/centroids farther than {:.3} mm; {:.2} % of the input's area is noise too rough for that bound (not refined)",
                q.samples_over_deviation,
                q.max_deviation_mm,
                100.0 * q.rough_input_fraction
            );
        }
        if q.components_kept_unchanged > 0 {
            outln!(
                o,
                "  debris        {} component(s) smaller than 16 target triangles copied unchanged (`flatcut clean --keep largest` drops them)",
                q.components_kept_unchanged
            );
        }
        outln!(
            o,
            "  holes         {} ({} filled)",
            q.holes.len(),
            q.holes_filled
        );
        for h in &q.holes {
            outln!(
                o,
                "    {:>9.1} mm perimeter, {:>5} vertices, at vertex {:>7}  {}",
                h.perimeter_mm,
                h.vertices,
                h.first_vertex,
                if h.filled { "filled" } else { "open" }
            );
        }
    }
    crate::util::emit(&o)
}
