//! A piece of a mesh as a mesh of its own, with the map back to the source.

use std::collections::HashMap;

use crate::TriMesh;

/// The faces `faces` (indices into `mesh.faces`) as a new mesh, and for each of its vertices
/// the source vertex (the provenance map). Vertices are numbered in order of first use by
/// the listed faces, so a piece comes out the same whatever the rest of the mesh holds;
/// memory is proportional to the piece, not to the source. Attributes and labels are not
/// carried over.
///
/// Precondition: `mesh` is valid ([`TriMesh::validate`]) and every entry of `faces` is a face
/// index of it.
pub fn submesh(mesh: &TriMesh, faces: &[u32]) -> (TriMesh, Vec<u32>) {
    let mut local_of: HashMap<u32, u32> = HashMap::with_capacity(faces.len());
    let mut source = Vec::new();
    let mut local_faces = Vec::with_capacity(faces.len());
    for &f in faces {
        let face = mesh.faces[f as usize];
        local_faces.push(face.map(|v| {
            *local_of.entry(v).or_insert_with(|| {
                source.push(v);
                (source.len() - 1) as u32
            })
        }));
    }
    let piece = TriMesh {
        positions: source.iter().map(|&v| mesh.positions[v as usize]).collect(),
        faces: local_faces,
        ..Default::default()
    };
    (piece, source)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_vertices_by_first_use_and_maps_back() {
        let mesh = crate::shapes::planar_disk(10.0, 3);
        let faces: Vec<u32> = (0..mesh.faces.len() as u32).rev().step_by(2).collect();
        let (piece, source) = submesh(&mesh, &faces);
        assert_eq!(piece.faces.len(), faces.len());
        // Each local face is the source face renumbered, corner for corner.
        for (lf, &f) in piece.faces.iter().zip(&faces) {
            assert_eq!(lf.map(|v| source[v as usize]), mesh.faces[f as usize]);
        }
        for (v, &s) in source.iter().enumerate() {
            assert_eq!(piece.positions[v], mesh.positions[s as usize]);
        }
        // First use: the first face's corners are 0, 1, 2.
        assert_eq!(piece.faces[0], [0, 1, 2]);
        let mut sorted = source.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), source.len(), "no source vertex appears twice");
    }
}
