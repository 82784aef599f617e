//! The triangle mesh: plain arrays, validated once.

use crate::{FaceId, MeshError, VertexId};

/// Optional data carried per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexAttributes {
    /// Linear RGBA colour in [0, 1], one per vertex.
    pub colors: Option<Vec<[f32; 4]>>,
    /// A scalar field (an error map, a weight), one per vertex.
    pub scalar: Option<Vec<f64>>,
    /// 2D texture / pattern coordinates in millimetres, one per vertex (a flattening).
    pub texcoords: Option<Vec<[f64; 2]>>,
}

/// Named groups of faces (OBJ `g`/`o`, glTF primitives), one label per face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceLabels {
    /// Label names; `labels[f]` indexes into this.
    pub names: Vec<String>,
    /// One entry per face.
    pub labels: Vec<u32>,
}

/// A triangle mesh with f64 positions (millimetres inside flatcut) and u32 faces.
///
/// Connectivity is derived on demand by [`crate::Topology::build`] and geometry by
/// the functions in [`crate::geometry`]; the mesh itself is just the arrays.
/// Faces are counter-clockwise seen from the side the normal points to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as three vertex indices.
    pub faces: Vec<[u32; 3]>,
    /// Optional per-vertex data.
    pub attributes: VertexAttributes,
    /// Optional face groups.
    pub face_labels: Option<FaceLabels>,
}

impl TriMesh {
    /// A mesh from positions and faces, checked with [`TriMesh::validate`].
    pub fn new(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        let mesh = Self {
            positions,
            faces,
            ..Default::default()
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// Number of vertices (referenced or not).
    #[inline]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    #[inline]
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Position of a vertex.
    #[inline]
    pub fn position(&self, v: VertexId) -> [f64; 3] {
        self.positions[v.idx()]
    }

    /// The three corner positions of a face.
    #[inline]
    pub fn triangle(&self, f: FaceId) -> [[f64; 3]; 3] {
        let [a, b, c] = self.faces[f.idx()];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Checks every invariant the algorithms rely on: indices in range, finite
    /// positions, counts addressable by u32, attribute lengths.
    pub fn validate(&self) -> Result<(), MeshError> {
        if self.positions.len() > u32::MAX as usize {
            return Err(MeshError::TooLarge {
                what: "vertices",
                count: self.positions.len(),
            });
        }
        if self.faces.len() > u32::MAX as usize {
            return Err(MeshError::TooLarge {
                what: "faces",
                count: self.faces.len(),
            });
        }
        for (i, p) in self.positions.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFinitePosition {
                    vertex: VertexId(i as u32),
                    position: *p,
                });
            }
        }
        let n = self.positions.len();
        for (f, face) in self.faces.iter().enumerate() {
            for &i in face {
                if i as usize >= n {
                    return Err(MeshError::FaceIndexOutOfRange {
                        face: FaceId(f as u32),
                        index: i,
                        vertex_count: n,
                    });
                }
            }
        }
        if let Some(c) = &self.attributes.colors
            && c.len() != n
        {
            return Err(MeshError::AttributeLength {
                name: "colors",
                len: c.len(),
                vertex_count: n,
            });
        }
        if let Some(s) = &self.attributes.scalar
            && s.len() != n
        {
            return Err(MeshError::AttributeLength {
                name: "scalar",
                len: s.len(),
                vertex_count: n,
            });
        }
        if let Some(t) = &self.attributes.texcoords
            && t.len() != n
        {
            return Err(MeshError::AttributeLength {
                name: "texcoords",
                len: t.len(),
                vertex_count: n,
            });
        }
        if let Some(l) = &self.face_labels
            && l.labels.len() != self.faces.len()
        {
            return Err(MeshError::FaceLabelLength {
                len: l.labels.len(),
                face_count: self.faces.len(),
            });
        }
        Ok(())
    }

    /// Axis-aligned bounding box of the referenced vertices, or `None` without faces.
    pub fn bounding_box(&self) -> Option<([f64; 3], [f64; 3])> {
        let used = self.referenced_vertices();
        let mut it = used
            .iter()
            .enumerate()
            .filter(|(_, u)| **u)
            .map(|(i, _)| self.positions[i]);
        let first = it.next()?;
        let (mut lo, mut hi) = (first, first);
        for p in it {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }

    /// One flag per vertex: does any face use it?
    pub fn referenced_vertices(&self) -> Vec<bool> {
        let mut used = vec![false; self.positions.len()];
        for f in &self.faces {
            for &i in f {
                if let Some(u) = used.get_mut(i as usize) {
                    *u = true;
                }
            }
        }
        used
    }

    /// Length of the bounding-box diagonal of the referenced vertices (0 without faces);
    /// the natural scale for relative tolerances.
    pub fn diagonal(&self) -> f64 {
        self.bounding_box()
            .map_or(0.0, |(lo, hi)| crate::vec3::norm(crate::vec3::sub(hi, lo)))
    }

    /// Heap bytes held by the positions, faces, attributes and labels (from capacities).
    pub fn heap_bytes(&self) -> usize {
        let a = &self.attributes;
        self.positions.capacity() * 24
            + self.faces.capacity() * 12
            + a.colors.as_ref().map_or(0, |c| c.capacity() * 16)
            + a.scalar.as_ref().map_or(0, |c| c.capacity() * 8)
            + a.texcoords.as_ref().map_or(0, |c| c.capacity() * 16)
            + self.face_labels.as_ref().map_or(0, |l| {
                l.labels.capacity() * 4 + l.names.iter().map(|n| n.capacity() + 24).sum::<usize>()
            })
    }

    /// Multiplies every position (and texcoord) by `factor` (unit conversion).
    pub fn scale(&mut self, factor: f64) {
        for p in &mut self.positions {
            for c in p.iter_mut() {
                *c *= factor;
            }
        }
        // Texcoords of a flattening are lengths too (mm), so a unit change scales them alike.
        if let Some(t) = &mut self.attributes.texcoords {
            for uv in t.iter_mut() {
                uv[0] *= factor;
                uv[1] *= factor;
            }
        }
    }
}
