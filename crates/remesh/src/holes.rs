//! Holes: boundary loops reported by perimeter, and the small ones closed by a fan that the
//! remeshing loop then refines and the fairing step smooths (see `remesh::fair_filled`).

use flatcut_mesh::vec3::{add, dist, scale};
use flatcut_mesh::{Topology, TriMesh};
use serde::Serialize;

/// One boundary loop of the input.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Hole {
    /// Perimeter of the loop in mm.
    pub perimeter_mm: f64,
    /// Number of boundary vertices on the loop.
    pub vertices: usize,
    /// A vertex of the loop (input numbering), to find it in a viewer.
    pub first_vertex: u32,
    /// Whether the hole was filled (perimeter below the fill threshold).
    pub filled: bool,
}

/// Every boundary loop of `mesh` with its perimeter; `filled` is set for loops whose
/// perimeter is below `fill_perimeter_mm`. Sorted by perimeter, smallest first.
pub fn find_holes(mesh: &TriMesh, topo: &Topology, fill_perimeter_mm: f64) -> Vec<Hole> {
    let mut holes: Vec<Hole> = topo
        .boundary_loops()
        .iter()
        .map(|l| {
            let perimeter_mm = loop_perimeter(mesh, l.iter().map(|v| v.0));
            Hole {
                perimeter_mm,
                vertices: l.len(),
                first_vertex: l.first().map_or(0, |v| v.0),
                filled: perimeter_mm < fill_perimeter_mm,
            }
        })
        .collect();
    holes.sort_by(|a, b| a.perimeter_mm.total_cmp(&b.perimeter_mm));
    holes
}

fn loop_perimeter(mesh: &TriMesh, l: impl Iterator<Item = u32> + Clone) -> f64 {
    let first = l.clone().next();
    let mut prev = None;
    let mut sum = 0.0;
    for v in l.chain(first) {
        let p = mesh.positions[v as usize];
        if let Some(q) = prev {
            sum += dist(p, q);
        }
        prev = Some(p);
    }
    sum
}

/// Appends a centroid vertex and a fan of faces (consistently oriented with the surface)
/// for every boundary loop with perimeter below `fill_perimeter_mm`. Returns the augmented
/// mesh; fill faces come after the input faces, so `face >= mesh.faces.len()` marks them.
pub(crate) fn fan_fill(mesh: &TriMesh, topo: &Topology, fill_perimeter_mm: f64) -> TriMesh {
    let mut out = TriMesh {
        positions: mesh.positions.clone(),
        faces: mesh.faces.clone(),
        ..TriMesh::default()
    };
    for l in topo.boundary_loops() {
        let ids: Vec<u32> = l.iter().map(|v| v.0).collect();
        if ids.len() < 3 || loop_perimeter(mesh, ids.iter().copied()) >= fill_perimeter_mm {
            continue;
        }
        // The fan runs each rim edge opposite to the input face on it.
        let (a, b) = (ids[0], ids[1]);
        let forward = topo
            .outgoing(flatcut_mesh::VertexId(a))
            .iter()
            .any(|&h| topo.to_vertex(h).0 == b);
        let c = ids
            .iter()
            .fold([0.0; 3], |s, &v| add(s, mesh.positions[v as usize]));
        let centre = out.positions.len() as u32;
        out.positions.push(scale(c, 1.0 / ids.len() as f64));
        for i in 0..ids.len() {
            let (p, q) = (ids[i], ids[(i + 1) % ids.len()]);
            out.faces.push(if forward {
                [q, p, centre]
            } else {
                [p, q, centre]
            });
        }
    }
    out
}
