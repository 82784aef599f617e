//! Measurements of a finished patch: boundary order, deviation from the input, angles.

use std::collections::{HashMap, HashSet};

use flatcut_mesh::TriMesh;
use flatcut_mesh::geometry::corner_angles;
use flatcut_mesh::vec3::{dist, point_segment_distance};

use super::{VertexOrigin, WireCurve};

/// Distance of a boundary/guide vertex from the input segment its origin names.
pub(super) fn deviation(
    o: VertexOrigin,
    p: [f64; 3],
    curves: &[WireCurve],
    guides: &[WireCurve],
) -> Option<f64> {
    let seg_dist = |pts: &[[f64; 3]], s: usize| -> f64 {
        point_segment_distance(p, pts[s], pts[(s + 1).min(pts.len() - 1)])
    };
    match o {
        VertexOrigin::CurvePoint { curve, point } => Some(dist(p, curves[curve].points[point])),
        VertexOrigin::OnCurve { curve, segment, .. } => {
            Some(seg_dist(&curves[curve].points, segment))
        }
        VertexOrigin::GuidePoint { guide, point } => Some(dist(p, guides[guide].points[point])),
        VertexOrigin::OnGuide { guide, segment, .. } => {
            Some(seg_dist(&guides[guide].points, segment))
        }
        VertexOrigin::Interior => None,
    }
}

/// The boundary vertices in loop order, starting at the first curve's first point.
pub(super) fn boundary_order(mesh: &TriMesh, origins: &[VertexOrigin]) -> Vec<u32> {
    // Directed boundary edges (u → v) of CCW faces: edges without a twin.
    let mut directed: HashSet<(u32, u32)> = HashSet::new();
    for f in &mesh.faces {
        for k in 0..3 {
            directed.insert((f[k], f[(k + 1) % 3]));
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &(u, v) in &directed {
        if !directed.contains(&(v, u)) {
            next.insert(u, v);
        }
    }
    let start = origins
        .iter()
        .position(|o| *o == VertexOrigin::CurvePoint { curve: 0, point: 0 })
        .map(|i| i as u32)
        .or_else(|| next.keys().min().copied());
    let Some(start) = start else {
        return Vec::new();
    };
    let mut out = vec![start];
    let mut cur = start;
    while let Some(&n) = next.get(&cur) {
        if n == start || out.len() > next.len() {
            break;
        }
        out.push(n);
        cur = n;
    }
    out
}

pub(super) fn min_angle_deg(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> f64 {
    corner_angles(positions, faces)
        .iter()
        .flatten()
        .fold(f64::INFINITY, |a, &b| a.min(b))
        .to_degrees()
}
