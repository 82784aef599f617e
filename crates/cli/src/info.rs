//! `flatcut info MESH`: what is in a mesh file, as read.

use std::path::PathBuf;

use anyhow::Context;
use flatcut_io::Units;
use flatcut_mesh::{Topology, mesh_info};

/// Arguments of `flatcut info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// Mesh file (.obj, .ply, .stl, .gltf, .glb).
    pub mesh: PathBuf,
    /// Units of the file: mm, cm, dm, m or in (default: m for .gltf/.glb, as glTF fixes, else mm). Lengths are reported in mm.
    #[arg(long, value_parser = crate::util::parse_units)]
    pub units: Option<Units>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `flatcut info`.
pub fn run(args: &InfoArgs) -> anyhow::Result<()> {
    let loaded = flatcut_io::read_mesh(&args.mesh, crate::util::units_for(&args.mesh, args.units))?;
    let mesh = &loaded.mesh;
    let topo = Topology::build(mesh).with_context(|| format!("{}", args.mesh.display()))?;
    let info = mesh_info(mesh, &topo);
    let mut o = String::new();
    if args.json {
        let mut value = serde_json::to_value(&info)?;
        if let Some(obj) = value.as_object_mut() {
            obj.insert("file".into(), args.mesh.display().to_string().into());
            obj.insert(
                "units".into(),
                format!("{:?}", crate::util::units_for(&args.mesh, args.units))
                    .to_lowercase()
                    .into(),
            );
            obj.insert("warnings".into(), loaded.source.warnings.clone().into());
        }
        outln!(o, "{}", serde_json::to_string_pretty(&value)?);
        return crate::util::emit(&o);
    }
    let p = |v: [f64; 3]| format!("({:.3}, {:.3}, {:.3})", v[0], v[1], v[2]);
    outln!(o, "file                 {}", args.mesh.display());
    outln!(
        o,
        "vertices             {} (+{} unreferenced)",
        info.vertices,
        info.unreferenced_vertices
    );
    outln!(o, "faces                {}", info.faces);
    outln!(o, "edges                {}", info.edges);
    outln!(o, "components           {}", info.components);
    outln!(o, "boundary loops       {}", info.boundary_loops.len());
    for (i, (n, len)) in info
        .boundary_loops
        .iter()
        .zip(&info.boundary_loop_lengths_mm)
        .enumerate()
    {
        outln!(o, "  loop {i:<4}           {n} vertices, {len:.3} mm");
    }
    outln!(o, "euler characteristic {}", info.euler_characteristic);
    if !info.closed_component_genus.is_empty() {
        outln!(o, "genus (closed comps) {:?}", info.closed_component_genus);
    }
    outln!(o, "non-manifold edges   {}", info.non_manifold_edges);
    outln!(o, "non-manifold verts   {}", info.non_manifold_vertices);
    outln!(
        o,
        "misoriented edges    {}",
        info.inconsistently_oriented_edges
    );
    outln!(o, "degenerate faces     {}", info.degenerate_faces);
    outln!(o, "duplicate vertices   {}", info.duplicate_vertices);
    outln!(o, "bbox min (mm)        {}", p(info.bbox_min));
    outln!(o, "bbox max (mm)        {}", p(info.bbox_max));
    outln!(o, "interior vertices    {}", info.interior_vertices);
    outln!(o, "angle defect max     {:.6e} rad", info.max_angle_defect);
    outln!(o, "angle defect mean    {:.6e} rad", info.mean_angle_defect);
    for w in &loaded.source.warnings {
        outln!(o, "warning: {w}");
    }
    crate::util::emit(&o)
}
