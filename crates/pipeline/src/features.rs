//! Feature curves of a `[[piece]]` (`features = [[[x, y, z], …], …]`) as vertex chains of the
//! piece: each landmark snaps to the closest corner of the face nearest to it, and
//! consecutive landmarks are joined by the shortest path along the piece's edges (Dijkstra,
//! Euclidean edge lengths). The chains weight processing (`ProcessOptions::feature_curves`)
//! and become the pattern's internal lines.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::{TriMesh, vec3};

/// Why a feature curve could not be placed on its piece.
#[derive(Clone, Debug, PartialEq)]
pub enum FeatureError {
    /// Landmark `landmark` lies `distance_mm` from the piece (more than the tolerance).
    OffPiece {
        /// Index of the landmark in the curve.
        landmark: usize,
        /// Distance to the piece's surface, mm.
        distance_mm: f64,
    },
    /// No edge path joins landmarks `landmark` − 1 and `landmark`.
    NoPath {
        /// Index of the second landmark.
        landmark: usize,
    },
}

/// Dijkstra queue entry, ordered by distance, then vertex (deterministic ties).
#[derive(Clone, Copy, PartialEq)]
struct Entry {
    d: f64,
    v: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        // Reversed: BinaryHeap is a max-heap.
        o.d.total_cmp(&self.d).then_with(|| o.v.cmp(&self.v))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Vertex adjacency of `mesh` (every face edge, both ways), sorted per vertex.
fn adjacency(mesh: &TriMesh) -> Vec<Vec<u32>> {
    let mut adj = vec![Vec::new(); mesh.positions.len()];
    for f in &mesh.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            adj[a as usize].push(b);
            adj[b as usize].push(a);
        }
    }
    for a in &mut adj {
        a.sort_unstable();
        a.dedup();
    }
    adj
}

/// Shortest edge path from `from` to `to` (inclusive), or `None` if they are not connected.
fn shortest_path(mesh: &TriMesh, adj: &[Vec<u32>], from: u32, to: u32) -> Option<Vec<u32>> {
    let n = mesh.positions.len();
    let mut dist = vec![f64::INFINITY; n];
    let mut prev = vec![u32::MAX; n];
    let mut heap = BinaryHeap::new();
    dist[from as usize] = 0.0;
    heap.push(Entry { d: 0.0, v: from });
    while let Some(Entry { d, v }) = heap.pop() {
        if v == to {
            break;
        }
        if d > dist[v as usize] {
            continue;
        }
        for &w in &adj[v as usize] {
            let nd = d + vec3::dist(mesh.positions[v as usize], mesh.positions[w as usize]);
            if nd < dist[w as usize] {
                dist[w as usize] = nd;
                prev[w as usize] = v;
                heap.push(Entry { d: nd, v: w });
            }
        }
    }
    if !dist[to as usize].is_finite() {
        return None;
    }
    let mut path = vec![to];
    let mut v = to;
    while v != from {
        v = prev[v as usize];
        path.push(v);
    }
    path.reverse();
    Some(path)
}

/// The vertex chain of one feature curve on `mesh` (mm): landmarks (mm) within
/// `tolerance_mm` of the surface, joined by shortest edge paths. Consecutive repeats are
/// removed (two landmarks may snap to one vertex).
pub fn feature_chain(
    mesh: &TriMesh,
    bvh: &Bvh,
    landmarks_mm: &[[f64; 3]],
    tolerance_mm: f64,
) -> Result<Vec<u32>, FeatureError> {
    let adj = adjacency(mesh);
    let mut snapped = Vec::with_capacity(landmarks_mm.len());
    for (k, &x) in landmarks_mm.iter().enumerate() {
        let hit = bvh.closest_point(x);
        let Some(hit) = hit.filter(|h| h.distance <= tolerance_mm) else {
            return Err(FeatureError::OffPiece {
                landmark: k,
                distance_mm: hit.map_or(f64::INFINITY, |h| h.distance),
            });
        };
        let face = mesh.faces[hit.face.idx()];
        // The corner with the largest barycentric weight is the face's closest corner.
        let c = (0..3)
            .max_by(|&a, &b| hit.barycentric[a].total_cmp(&hit.barycentric[b]))
            .unwrap_or(0);
        snapped.push(face[c]);
    }
    let mut chain: Vec<u32> = vec![snapped[0]];
    for k in 1..snapped.len() {
        let path = shortest_path(mesh, &adj, snapped[k - 1], snapped[k])
            .ok_or(FeatureError::NoPath { landmark: k })?;
        chain.extend(path.into_iter().skip(1));
    }
    chain.dedup();
    Ok(chain)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use flatcut_mesh::shapes::grid_patch;

    #[test]
    fn a_straight_feature_on_a_grid_follows_the_grid_line() {
        // 11 × 11 vertices over 100 mm: the row y = 0 has 11 vertices 10 mm apart; the
        // shortest edge path between its ends is that row (any diagonal detour is longer).
        let m = grid_patch(11, 11, 100.0, |_, _| 0.0);
        let bvh = Bvh::build(&m);
        let row: Vec<u32> = (0..m.positions.len() as u32)
            .filter(|&v| m.positions[v as usize][1].abs() < 1e-9)
            .collect();
        assert_eq!(row.len(), 11);
        let a = m.positions[row[0] as usize];
        let b = m.positions[row[10] as usize];
        // Landmarks 1 mm above the plane (within tolerance), at the row's ends.
        let chain = feature_chain(&m, &bvh, &[[a[0], a[1], 1.0], [b[0], b[1], 1.0]], 5.0).unwrap();
        let len: f64 = chain
            .windows(2)
            .map(|w| vec3::dist(m.positions[w[0] as usize], m.positions[w[1] as usize]))
            .sum();
        assert!((len - 100.0).abs() < 1e-9, "{len}");
        assert!(
            chain
                .iter()
                .all(|v| m.positions[*v as usize][1].abs() < 1e-9)
        );
        // A landmark 6 mm off the surface is refused with its index and distance.
        let e = feature_chain(&m, &bvh, &[a, [b[0], b[1], 6.0]], 5.0).unwrap_err();
        assert_eq!(
            e,
            FeatureError::OffPiece {
                landmark: 1,
                distance_mm: 6.0
            }
        );
    }
}
