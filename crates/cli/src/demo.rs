//! `flatcut demo`: the main job on the embedded default — a generated dress form, written as
//! OBJ and GLB (coloured by angle defect) and analysed. Needs no input file.

use std::path::PathBuf;

use anyhow::Context;
use flatcut_mesh::shapes::{BodyMeasurements, dress_form};
use flatcut_mesh::{Topology, geometry, mesh_info};

/// Arguments of `flatcut demo`.
#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// Output folder (created if missing).
    #[arg(long, default_value = "flatcut-demo")]
    pub out: PathBuf,
    /// Bust circumference in mm.
    #[arg(long, default_value_t = BodyMeasurements::default().bust_mm)]
    pub bust_mm: f64,
    /// Waist circumference in mm.
    #[arg(long, default_value_t = BodyMeasurements::default().waist_mm)]
    pub waist_mm: f64,
    /// Hip circumference in mm.
    #[arg(long, default_value_t = BodyMeasurements::default().hip_mm)]
    pub hip_mm: f64,
}

/// Runs `flatcut demo`.
pub fn run(args: &DemoArgs) -> anyhow::Result<()> {
    for (name, v) in [
        ("--bust-mm", args.bust_mm),
        ("--waist-mm", args.waist_mm),
        ("--hip-mm", args.hip_mm),
    ] {
        if !(v.is_finite() && v > 0.0) {
            anyhow::bail!("{name} must be a positive circumference in mm, got {v}");
        }
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the folder {}", args.out.display()))?;
    let measurements = BodyMeasurements {
        bust_mm: args.bust_mm,
        waist_mm: args.waist_mm,
        hip_mm: args.hip_mm,
        ..Default::default()
    };
    let mut mesh = dress_form(&measurements);
    let topo = Topology::build(&mesh)?;
    let info = mesh_info(&mesh, &topo);

    // |2π − θ(v)| per vertex (0 on the boundary) as the GLB's colour map: where the form is
    // curved, and so where a flat pattern piece will need darts or processing.
    let defects = geometry::angle_defects(&mesh.positions, &mesh.faces, &topo);
    mesh.attributes.scalar = Some(defects.iter().map(|d| d.map_or(0.0, f64::abs)).collect());

    let obj = args.out.join("dress_form.obj");
    let glb = args.out.join("dress_form_angle_defect.glb");
    let json = args.out.join("dress_form_info.json");
    flatcut_io::write_mesh(&obj, &mesh, &flatcut_io::WriteOptions::default())?;
    flatcut_io::write_mesh(&glb, &mesh, &flatcut_io::WriteOptions::default())?;
    crate::util::write_text_atomic(&json, &serde_json::to_string_pretty(&info)?)?;

    let mut o = String::new();
    outln!(
        o,
        "dress form (bust {} / waist {} / hip {} mm)",
        args.bust_mm,
        args.waist_mm,
        args.hip_mm
    );
    outln!(
        o,
        "  {} vertices, {} faces, {} boundary loops, χ = {}",
        info.vertices,
        info.faces,
        info.boundary_loops.len(),
        info.euler_characteristic
    );
    outln!(
        o,
        "  angle defect max {:.3e} rad, mean {:.3e} rad",
        info.max_angle_defect,
        info.mean_angle_defect
    );
    outln!(o, "wrote {}", obj.display());
    outln!(o, "wrote {}", glb.display());
    outln!(o, "wrote {}", json.display());
    crate::util::emit(&o)
}
