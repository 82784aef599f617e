//! Splitting a mesh into the pieces that are flattened independently (its connected
//! components), after checking that each one can be flattened at all.

use flatcut_mesh::geometry::{component_extents, is_degenerate_face};
use flatcut_mesh::{FaceId, INVALID, Topology, TriMesh, VertexId};

use crate::LscmError;

/// One connected component of a mesh, re-indexed compactly.
///
/// `local_faces` index `positions`; `vertices[i]` / `faces[f]` map back to the source mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Component number in [`Topology::face_components`].
    pub component: usize,
    /// Source vertex of each local vertex.
    pub vertices: Vec<VertexId>,
    /// Source face of each local face (in source order).
    pub faces: Vec<FaceId>,
    /// Faces in local vertex indices, with the source orientation.
    pub local_faces: Vec<[u32; 3]>,
    /// 3D positions of the local vertices (mm).
    pub positions: Vec<[f64; 3]>,
    /// Boundary loops in local vertex indices, in face orientation (at least one).
    pub boundary_loops: Vec<Vec<u32>>,
}

/// The extents (bounding-box diagonals, mm) a component may have. Measured on a 37-vertex
/// disk 2.85 wide (`flatcut flatten`, LSCM then ARAP): scaled by a power of two it gives its
/// pattern scaled, bit for bit, from 2^-166 to 2^170 (extents 3e-50 to 4e51); at 2^175 and 2^-180 the
/// ARAP Laplacian overflowed or underflowed (the error said only that a matrix value was not
/// finite), at 2^±300 LSCM's matrix lost definiteness or its faces read as degenerate. It
/// forms up to sixth powers of lengths, and a fine piece's edges are far shorter than its
/// extent, so the bounds sit ~1e20 inside the measured ones. Real pieces span 1e-1 to 1e5 mm.
pub const EXTENT_RANGE: (f64, f64) = (1e-30, 1e30);

/// Checks that every component of `mesh` is flattenable in principle (faces present,
/// edge- and vertex-manifold, consistently oriented, no degenerate face, a boundary in every
/// component) and returns the components as [`Piece`]s, in component order.
///
/// Errors name the first offending element; unreferenced vertices are simply left out.
pub fn split_pieces(mesh: &TriMesh, topo: &Topology) -> Result<Vec<Piece>, LscmError> {
    mesh.validate()?;
    if mesh.faces.is_empty() {
        return Err(LscmError::Empty);
    }
    if let Some(e) = topo.non_manifold_edges().first() {
        return Err(LscmError::NonManifoldEdge {
            a: VertexId(e[0]),
            b: VertexId(e[1]),
        });
    }
    if let Some(&v) = topo.non_manifold_vertices().first() {
        return Err(LscmError::NonManifoldVertex { vertex: v });
    }
    if let Some(e) = topo.inconsistent_edges().first() {
        return Err(LscmError::InconsistentOrientation {
            a: VertexId(e[0]),
            b: VertexId(e[1]),
        });
    }
    let (min, max) = EXTENT_RANGE;
    let extents = component_extents(mesh, topo.face_components(), topo.component_count());
    if let Some(component) = extents.iter().position(|e| !(min..=max).contains(e)) {
        return Err(LscmError::ExtentOutOfRange {
            component,
            extent: extents[component],
            min,
            max,
        });
    }
    let diagonal = mesh.diagonal();
    for (f, face) in mesh.faces.iter().enumerate() {
        if is_degenerate_face(*face, mesh.triangle(FaceId(f as u32)), diagonal) {
            return Err(LscmError::DegenerateFace {
                face: FaceId(f as u32),
            });
        }
    }

    let nc = topo.component_count();
    let mut pieces: Vec<Piece> = (0..nc)
        .map(|c| Piece {
            component: c,
            vertices: Vec::new(),
            faces: Vec::new(),
            local_faces: Vec::new(),
            positions: Vec::new(),
            boundary_loops: Vec::new(),
        })
        .collect();
    let mut local = vec![INVALID; mesh.vertex_count()];
    let vc = topo.vertex_components();
    for (v, &c) in vc.iter().enumerate() {
        if c != INVALID {
            let p = &mut pieces[c as usize];
            local[v] = p.vertices.len() as u32;
            p.vertices.push(VertexId(v as u32));
            p.positions.push(mesh.positions[v]);
        }
    }
    for (f, (&c, face)) in topo.face_components().iter().zip(&mesh.faces).enumerate() {
        let p = &mut pieces[c as usize];
        p.faces.push(FaceId(f as u32));
        p.local_faces.push(face.map(|v| local[v as usize]));
    }
    for lp in topo.boundary_loops() {
        if let Some(first) = lp.first() {
            let c = vc[first.idx()] as usize;
            pieces[c]
                .boundary_loops
                .push(lp.iter().map(|v| local[v.idx()]).collect());
        }
    }
    for p in &pieces {
        if p.boundary_loops.is_empty() {
            return Err(LscmError::ClosedComponent {
                component: p.component,
                faces: p.faces.len(),
                first_face: p.faces[0],
            });
        }
    }
    Ok(pieces)
}
