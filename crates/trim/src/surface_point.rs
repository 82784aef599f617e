//! Surface points: a place on the mesh as a face and barycentric weights, found for a 3D
//! landmark by the closest point on the surface.

use flatcut_mesh::{FaceId, TriMesh, bvh::Bvh, vec3};
use serde::Deserialize;

use crate::TrimError;

/// A point on the surface: weights of the face's corners (in `faces[face]` order), non-negative,
/// summing to 1. A weight that is exactly 0 puts the point on the opposite edge; a weight exactly
/// 1 puts it on that corner vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The face.
    pub face: FaceId,
    /// Corner weights.
    pub barycentric: [f64; 3],
}

/// Where a surface point is, combinatorially.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Location {
    /// On a mesh vertex.
    Vertex(u32),
    /// On the edge `(a, b)`, `a < b`, at `(1 − t)·a + t·b`, `0 < t < 1`.
    Edge {
        /// Smaller vertex index.
        a: u32,
        /// Larger vertex index.
        b: u32,
        /// Parameter from `a` to `b`.
        t: f64,
    },
    /// Inside a face.
    Face(u32),
}

/// A barycentric weight below this (relative: weights are dimensionless, so this is a fraction
/// of the face's size) is taken as zero and the point moved onto the edge or vertex: cutting
/// a face this close to an edge would leave a sliver triangle that later stages cannot flatten
/// well. 1e-6 of an edge moves the point by nanometres on a body scan.
pub const SNAP_RELATIVE: f64 = 1e-6;

/// Default distance a landmark may lie off the surface, mm.
pub const DEFAULT_LANDMARK_TOLERANCE_MM: f64 = 5.0;

/// Options for [`surface_point`].
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SurfacePointOptions {
    /// Largest distance from a landmark to the surface, mm (default 5).
    pub tolerance_mm: f64,
}

impl Default for SurfacePointOptions {
    fn default() -> Self {
        Self {
            tolerance_mm: DEFAULT_LANDMARK_TOLERANCE_MM,
        }
    }
}

impl SurfacePoint {
    /// A surface point on a mesh vertex: any face of it (`face`) with weight 1 on the corner.
    pub fn at_vertex(mesh: &TriMesh, face: u32, vertex: u32) -> Option<Self> {
        let k = mesh
            .faces
            .get(face as usize)?
            .iter()
            .position(|&v| v == vertex)?;
        let mut barycentric = [0.0; 3];
        barycentric[k] = 1.0;
        Some(Self {
            face: FaceId(face),
            barycentric,
        })
    }

    /// The 3D position.
    pub fn position(&self, mesh: &TriMesh) -> [f64; 3] {
        let t = mesh.triangle(self.face);
        let w = self.barycentric;
        let mut p = [0.0; 3];
        for (k, c) in t.iter().enumerate() {
            p = vec3::add(p, vec3::scale(*c, w[k]));
        }
        // A point on a vertex or edge is computed exactly from its corners (no weight-0 drift).
        match self.location(mesh) {
            Location::Vertex(v) => mesh.positions[v as usize],
            Location::Edge { a, b, t } => edge_point(mesh, a, b, t),
            Location::Face(_) => p,
        }
    }

    /// Where the point lies: vertex, edge or face interior (from exact zero/one weights).
    pub fn location(&self, mesh: &TriMesh) -> Location {
        let f = mesh.faces[self.face.idx()];
        let w = self.barycentric;
        if let Some(k) = (0..3).find(|&k| w[k] >= 1.0) {
            return Location::Vertex(f[k]);
        }
        if let Some(k) = (0..3).find(|&k| w[k] <= 0.0) {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let (va, vb, wb) = (f[i], f[j], w[j]);
            return if va < vb {
                Location::Edge {
                    a: va,
                    b: vb,
                    t: wb,
                }
            } else {
                Location::Edge {
                    a: vb,
                    b: va,
                    t: 1.0 - wb,
                }
            };
        }
        Location::Face(self.face.0)
    }

    /// The weights with every weight below [`SNAP_RELATIVE`] set to exactly zero (and one
    /// above `1 − SNAP_RELATIVE` to exactly one), renormalised.
    pub fn snapped(mut self) -> Self {
        let w = &mut self.barycentric;
        for c in w.iter_mut() {
            if !c.is_finite() || *c < SNAP_RELATIVE {
                *c = 0.0;
            }
        }
        if let Some(k) = (0..3).find(|&k| w[k] > 1.0 - SNAP_RELATIVE) {
            *w = [0.0; 3];
            w[k] = 1.0;
            return self;
        }
        let s: f64 = w.iter().sum();
        if s > 0.0 {
            for c in w.iter_mut() {
                *c /= s;
            }
        } else {
            *w = [1.0, 0.0, 0.0];
        }
        self
    }
}

/// The point `(1 − t)·a + t·b`.
pub fn edge_point(mesh: &TriMesh, a: u32, b: u32, t: f64) -> [f64; 3] {
    let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
    vec3::add(vec3::scale(pa, 1.0 - t), vec3::scale(pb, t))
}

/// The surface point closest to `landmark` (snapped, see [`SurfacePoint::snapped`]), or
/// [`TrimError::OffSurface`] naming `what` when it is farther than `opts.tolerance_mm`.
pub fn surface_point(
    bvh: &Bvh,
    landmark: [f64; 3],
    what: &str,
    opts: &SurfacePointOptions,
) -> Result<SurfacePoint, TrimError> {
    if !landmark.iter().all(|c| c.is_finite()) {
        return Err(TrimError::NonFinitePoint {
            what: what.to_string(),
        });
    }
    let cp = bvh.closest_point(landmark).ok_or(TrimError::EmptyMesh)?;
    if cp.distance > opts.tolerance_mm {
        return Err(TrimError::OffSurface {
            what: what.to_string(),
            distance_mm: cp.distance,
            tolerance_mm: opts.tolerance_mm,
        });
    }
    Ok(SurfacePoint {
        face: cp.face,
        barycentric: cp.barycentric,
    }
    .snapped())
}

#[cfg(test)]
mod tests {
    use super::*;
    use flatcut_mesh::shapes;

    #[test]
    fn landmark_snaps_to_the_closest_surface_point() {
        let mesh = shapes::icosphere(100.0, 3);
        let bvh = Bvh::build(&mesh);
        let dir = vec3::normalize([0.3, 0.5, -0.8]);
        let sp = surface_point(&bvh, vec3::scale(dir, 102.0), "lm", &Default::default()).unwrap();
        let p = sp.position(&mesh);
        // The closest point is on the face plane, within the chordal gap of the radius.
        let r = vec3::norm(p);
        assert!(r <= 100.0 + 1e-9 && r > 99.0, "{r}");
        assert!(vec3::dist(p, vec3::scale(dir, r)) < 1.0);
        let s: f64 = sp.barycentric.iter().sum();
        assert!((s - 1.0).abs() < 1e-12);
    }

    #[test]
    fn far_landmark_is_named() {
        let mesh = shapes::icosphere(100.0, 2);
        let bvh = Bvh::build(&mesh);
        let err = surface_point(
            &bvh,
            [0.0, 0.0, 120.0],
            "landmark \"navel\"",
            &Default::default(),
        )
        .unwrap_err();
        match err {
            TrimError::OffSurface {
                what, distance_mm, ..
            } => {
                assert_eq!(what, "landmark \"navel\"");
                assert!((distance_mm - 20.0).abs() < 1.0);
            }
            e => panic!("{e}"),
        }
        let opts = SurfacePointOptions { tolerance_mm: 25.0 };
        assert!(surface_point(&bvh, [0.0, 0.0, 120.0], "x", &opts).is_ok());
    }

    #[test]
    fn location_of_edge_and_vertex_points() {
        let mesh = shapes::planar_disk(10.0, 2);
        let f = mesh.faces[3];
        let sp = SurfacePoint {
            face: FaceId(3),
            barycentric: [0.3, 0.7 - 1e-9, 1e-9],
        }
        .snapped();
        match sp.location(&mesh) {
            Location::Edge { a, b, t } => {
                assert_eq!((a, b), (f[0].min(f[1]), f[0].max(f[1])));
                let p = edge_point(&mesh, a, b, t);
                let q = vec3::add(
                    vec3::scale(mesh.positions[f[0] as usize], 0.3),
                    vec3::scale(mesh.positions[f[1] as usize], 0.7),
                );
                // Snapping moved the point by about the dropped weight times the edge length.
                assert!(vec3::dist(p, q) < 1e-7);
            }
            l => panic!("{l:?}"),
        }
        let v = SurfacePoint::at_vertex(&mesh, 3, f[2]).unwrap();
        assert_eq!(v.location(&mesh), Location::Vertex(f[2]));
    }
}
