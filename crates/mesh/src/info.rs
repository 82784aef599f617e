//! What `flatcut info` reports about a mesh: counts, topology, defects, size and curvature.

use serde::Serialize;
use std::collections::HashMap;

use crate::geometry::{angle_defects, loop_length};
use crate::vec3::dist;
use crate::{Topology, TriMesh, VertexId};

/// Summary of a mesh as read, before any cleaning. Lengths in the mesh's units (mm inside flatcut).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MeshInfo {
    /// Vertices referenced by at least one face.
    pub vertices: usize,
    /// Vertices no face references (kept apart from `vertices`).
    pub unreferenced_vertices: usize,
    /// Triangles.
    pub faces: usize,
    /// Undirected edges.
    pub edges: usize,
    /// Connected components (faces joined through shared vertices).
    pub components: usize,
    /// Vertex count of each boundary loop.
    pub boundary_loops: Vec<usize>,
    /// Length of each boundary loop, in the order of `boundary_loops`.
    pub boundary_loop_lengths_mm: Vec<f64>,
    /// V − E + F over referenced vertices.
    pub euler_characteristic: i64,
    /// Genus of each closed, edge-manifold component, in component order.
    pub closed_component_genus: Vec<i64>,
    /// Edges with more than two faces.
    pub non_manifold_edges: usize,
    /// Vertices whose faces form more than one fan.
    pub non_manifold_vertices: usize,
    /// Two-face edges traversed in the same direction by both faces.
    pub inconsistently_oriented_edges: usize,
    /// Faces with a repeated vertex or (numerically) zero area; see [`crate::geometry::is_degenerate_face`].
    pub degenerate_faces: usize,
    /// Referenced vertices at exactly the position of an earlier referenced vertex.
    pub duplicate_vertices: usize,
    /// Bounding box of the referenced vertices (zeros for an empty mesh).
    pub bbox_min: [f64; 3],
    /// Bounding box of the referenced vertices (zeros for an empty mesh).
    pub bbox_max: [f64; 3],
    /// Interior vertices (manifold, not on a boundary).
    pub interior_vertices: usize,
    /// max |2π − θ(v)| over interior vertices, radians (0 without interior vertices).
    pub max_angle_defect: f64,
    /// mean |2π − θ(v)| over interior vertices, radians (0 without interior vertices).
    pub mean_angle_defect: f64,
}

/// Computes [`MeshInfo`] from a mesh and its topology.
pub fn mesh_info(mesh: &TriMesh, topo: &Topology) -> MeshInfo {
    let vertices = topo.referenced_vertex_count();
    let loops = topo.boundary_loops();
    let boundary_loop_lengths_mm = loops
        .iter()
        .map(|lp| loop_length(&mesh.positions, lp))
        .collect();
    let defects = angle_defects(&mesh.positions, &mesh.faces, topo);
    let (mut max_d, mut sum_d, mut n_int) = (0.0f64, 0.0, 0usize);
    for d in defects.iter().flatten() {
        // NaN (angles of overflowed lengths) must show in the max as in the mean: `f64::max`
        // alone would skip it.
        max_d = if d.is_nan() || max_d.is_nan() {
            f64::NAN
        } else {
            max_d.max(d.abs())
        };
        sum_d += d.abs();
        n_int += 1;
    }
    let (bbox_min, bbox_max) = mesh.bounding_box().unwrap_or(([0.0; 3], [0.0; 3]));
    let diagonal = dist(bbox_min, bbox_max);
    let degenerate_faces = (0..mesh.faces.len())
        .filter(|&f| {
            crate::geometry::is_degenerate_face(
                mesh.faces[f],
                mesh.triangle(crate::FaceId(f as u32)),
                diagonal,
            )
        })
        .count();
    let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(vertices);
    let mut duplicate_vertices = 0;
    for v in 0..mesh.positions.len() {
        if !topo.is_referenced(VertexId(v as u32)) {
            continue;
        }
        // Bit patterns with −0 folded onto +0, so that equal coordinates compare equal.
        let key = mesh.positions[v].map(|c| (c + 0.0).to_bits());
        if seen.insert(key, v as u32).is_some() {
            duplicate_vertices += 1;
        }
    }
    let summaries = topo.component_summaries();
    MeshInfo {
        vertices,
        unreferenced_vertices: mesh.positions.len() - vertices,
        faces: mesh.faces.len(),
        edges: topo.edges().len(),
        components: topo.component_count(),
        boundary_loops: loops.iter().map(Vec::len).collect(),
        boundary_loop_lengths_mm,
        euler_characteristic: topo.euler_characteristic(),
        closed_component_genus: summaries.iter().filter_map(|s| s.genus).collect(),
        non_manifold_edges: topo.non_manifold_edges().len(),
        non_manifold_vertices: topo.non_manifold_vertices().len(),
        inconsistently_oriented_edges: topo.inconsistent_edges().len(),
        degenerate_faces,
        duplicate_vertices,
        bbox_min,
        bbox_max,
        interior_vertices: n_int,
        max_angle_defect: max_d,
        mean_angle_defect: if n_int > 0 { sum_d / n_int as f64 } else { 0.0 },
    }
}
