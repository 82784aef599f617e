//! `flatcut flatten IN OUT`: a cut piece (or several) to a true-size 2D pattern, with its
//! distortion measured.
//!
//! OUT holds `v u v 0` lines (mm), the input's faces in the input's order, and the same 2D
//! coordinates as texture coordinates. Pieces (connected components) lie side by side along
//! +x, each with its grain along +y; unreferenced input vertices are written at (0, 0).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use flatcut_io::{Units, WriteOptions};
use flatcut_lscm::{
    DistortionReport, FlattenOptions, Method, Pins, PlacementOptions, Summary, distortion,
    flatten_with_topology,
};
use flatcut_mesh::{Topology, TriMesh, VertexId};
use serde::Serialize;

/// Arguments of `flatcut flatten`.
#[derive(clap::Args, Debug)]
pub struct FlattenArgs {
    /// Input mesh (.obj, .ply, .stl, .gltf, .glb): open pieces, each component flattened.
    pub input: PathBuf,
    /// Output mesh, normally .obj: `v x y 0` (mm), the same faces, and `vt` coordinates.
    pub output: PathBuf,
    /// Units of the input: mm, cm, dm, m or in (default: m for .gltf/.glb, as glTF fixes, else mm). The output is in mm.
    #[arg(long, value_parser = crate::util::parse_units)]
    pub units: Option<Units>,
    /// `lscm` (conformal; sizes drift on curved pieces) or `lscm+arap` (as close to true size
    /// as the piece allows: an isometry on a developable piece).
    #[arg(long, default_value = "lscm+arap", value_parser = parse_method)]
    pub method: Method,
    /// `auto` (per piece, the two boundary vertices farthest apart) or `I,J`: two 0-based
    /// vertex indices of one piece.
    #[arg(long, default_value = "auto", value_parser = parse_pins)]
    pub pins: Pins,
    /// The 3D direction `X,Y,Z` that points along +y in the pattern (default: each piece's
    /// principal axis).
    #[arg(long, value_parser = parse_grain)]
    pub grain: Option<[f64; 3]>,
    /// Also write the metrics as JSON to this file.
    #[arg(long)]
    pub metrics: Option<PathBuf>,
    /// Print the metrics as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

fn parse_method(s: &str) -> Result<Method, String> {
    match s {
        "lscm" => Ok(Method::Lscm),
        "lscm+arap" => Ok(Method::LscmArap),
        _ => Err(format!("unknown method '{s}': use lscm or lscm+arap")),
    }
}

fn parse_pins(s: &str) -> Result<Pins, String> {
    if s == "auto" {
        return Ok(Pins::Auto);
    }
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    match parts.as_slice() {
        [a, b] => {
            let p = |t: &str| {
                t.parse::<u32>()
                    .map_err(|_| format!("'{t}' is not a vertex index (0-based)"))
            };
            Ok(Pins::Given([VertexId(p(a)?), VertexId(p(b)?)]))
        }
        _ => Err(format!("pins '{s}': use auto or two vertex indices I,J")),
    }
}

fn parse_grain(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("grain '{s}': use three numbers X,Y,Z"))?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) && (x * x + y * y + z * z) > 0.0 => {
            Ok([*x, *y, *z])
        }
        _ => Err(format!(
            "grain '{s}': use three finite numbers X,Y,Z, not all zero"
        )),
    }
}

/// The metrics file: the summary fields first, then the details.
#[derive(Serialize)]
struct Metrics<'a> {
    input: String,
    output: String,
    method: Method,
    faces: usize,
    components: usize,
    seconds: f64,
    e_h: Summary,
    e_r: Summary,
    edge_strain: Summary,
    max_edge_strain: f64,
    area_3d_mm2: f64,
    area_2d_mm2: f64,
    flipped_faces: usize,
    pins: Vec<[u32; 2]>,
    boundary_loops: &'a [flatcut_lscm::LoopLength],
    refine: &'a [flatcut_lscm::RefineReport],
    warnings: Vec<String>,
}

/// Runs `flatcut flatten`.
pub fn run(args: &FlattenArgs) -> anyhow::Result<()> {
    let mut outputs = vec![("OUT", args.output.as_path())];
    outputs.extend(args.metrics.as_deref().map(|m| ("--metrics", m)));
    crate::util::refuse_overwrite(&[("IN", &args.input)], &outputs)?;
    let loaded =
        flatcut_io::read_mesh(&args.input, crate::util::units_for(&args.input, args.units))?;
    let mesh = &loaded.mesh;
    let input = args.input.display().to_string();
    let topo = Topology::build(mesh).with_context(|| input.clone())?;
    let opts = FlattenOptions {
        method: args.method,
        lscm: flatcut_lscm::LscmOptions {
            pins: args.pins,
            ..Default::default()
        },
        placement: PlacementOptions {
            grain: args.grain,
            ..Default::default()
        },
        ..Default::default()
    };
    let start = Instant::now();
    let out = flatten_with_topology(mesh, &topo, &opts)
        .with_context(|| format!("cannot flatten {input}"))?;
    let seconds = start.elapsed().as_secs_f64();
    let uv = &out.flattening.uv;
    if let Some(v) = uv
        .iter()
        .position(|q| !(q[0].is_finite() && q[1].is_finite()))
    {
        anyhow::bail!(
            "flattening {input} produced a non-finite coordinate at vertex {v}; this is a bug, please report it"
        );
    }
    let flat = TriMesh {
        positions: uv.iter().map(|q| [q[0], q[1], 0.0]).collect(),
        faces: mesh.faces.clone(),
        attributes: flatcut_mesh::VertexAttributes {
            texcoords: Some(uv.clone()),
            ..Default::default()
        },
        face_labels: mesh.face_labels.clone(),
    };
    flatcut_io::write_mesh(&args.output, &flat, &WriteOptions::default())?;

    let d: DistortionReport = distortion(mesh, &topo, uv);
    let mut warnings = loaded.source.warnings.clone();
    if d.flipped_faces > 0 {
        warnings.push(format!(
            "{} faces are flipped (the pattern folds over itself): a piece that is not a \
             topological disk (a tube, a curved piece with several boundary loops) has no \
             fold-free flattening; cut it into disks first",
            d.flipped_faces
        ));
    }
    let metrics = Metrics {
        input,
        output: args.output.display().to_string(),
        method: args.method,
        faces: d.faces,
        components: out.flattening.pieces.len(),
        seconds,
        e_h: d.e_h,
        e_r: d.e_r,
        edge_strain: d.edge_strain,
        max_edge_strain: d.max_edge_strain,
        area_3d_mm2: d.area_3d_mm2,
        area_2d_mm2: d.area_2d_mm2,
        flipped_faces: d.flipped_faces,
        pins: out
            .flattening
            .pieces
            .iter()
            .map(|p| p.pins.map(|v| v.0))
            .collect(),
        boundary_loops: &d.boundary_loops,
        refine: &out.refine,
        warnings,
    };
    let json = serde_json::to_string_pretty(&metrics)?;
    if let Some(path) = &args.metrics {
        crate::util::write_text_atomic(path, &(json.clone() + "\n"))?;
    }
    let mut o = String::new();
    if args.json {
        outln!(o, "{json}");
        return crate::util::emit(&o);
    }
    let s = |x: &Summary| format!("mean {:.3e}  p95 {:.3e}  max {:.3e}", x.mean, x.p95, x.max);
    outln!(o, "input                {}", metrics.input);
    outln!(o, "output               {}", metrics.output);
    outln!(o, "faces                {}", metrics.faces);
    outln!(o, "components           {}", metrics.components);
    outln!(o, "seconds              {:.3}", metrics.seconds);
    outln!(o, "E_h |s1 s2 - 1|      {}", s(&metrics.e_h));
    outln!(o, "E_r 1 - s2/s1        {}", s(&metrics.e_r));
    outln!(o, "max edge strain      {:.3e}", metrics.max_edge_strain);
    outln!(
        o,
        "area 3D / 2D (mm2)   {:.3} / {:.3}",
        d.area_3d_mm2,
        d.area_2d_mm2
    );
    outln!(o, "flipped faces        {}", d.flipped_faces);
    for (i, l) in d.boundary_loops.iter().enumerate() {
        outln!(
            o,
            "  loop {i:<4}           {} vertices, 3D {:.3} mm, 2D {:.3} mm",
            l.vertices,
            l.length_3d_mm,
            l.length_2d_mm
        );
    }
    for w in &metrics.warnings {
        outln!(o, "warning: {w}");
    }
    crate::util::emit(&o)
}
