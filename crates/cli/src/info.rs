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
    let mut warnings = loaded.source.warnings.clone();
    // Beyond the range in which the flattening computes angles and areas, the defects below
    // are overflowed or underflowed numbers, not the surface's.
    let (min, max) = flatcut_lscm::piece::EXTENT_RANGE;
    let extents =
        flatcut_mesh::geometry::component_extents(mesh, topo.face_components(), info.components);
    if let Some((c, e)) = extents
        .iter()
        .enumerate()
        .find(|(_, e)| !(min..=max).contains(*e))
    {
        warnings.push(format!(
            "component {c} spans {e:.3e} mm, outside {min:.0e} to {max:.0e}, where flatcut computes angles and areas in f64: its angle defects are not meaningful and `flatcut flatten` refuses it; rescale the mesh"
        ));
    }
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
            obj.insert("warnings".into(), warnings.clone().into());
        }
        outln!(o, "{}", serde_json::to_string_pretty(&value)?);
        return crate::util::emit(&o);
    }
    let p = |v: [f64; 3]| format!("({}, {}, {})", mm(v[0]), mm(v[1]), mm(v[2]));
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
    outln!(o, "angle defect max     {}", rad(info.max_angle_defect));
    outln!(o, "angle defect mean    {}", rad(info.mean_angle_defect));
    for w in &warnings {
        outln!(o, "warning: {w}");
    }
    crate::util::emit(&o)
}

/// A coordinate in mm: three decimals at ordinary sizes, scientific beyond them (a 1e300 mm
/// coordinate printed 300 digits, a 1e-300 one as 0.000).
fn mm(x: f64) -> String {
    if x == 0.0 || (1e-3..1e9).contains(&x.abs()) {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}

/// An angle in radians, or why there is none (angles of a mesh whose squared lengths overflow).
fn rad(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6e} rad")
    } else {
        "not computable in f64 (see the warning)".to_string()
    }
}
