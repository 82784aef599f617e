//! The quality report of a remeshed or decimated mesh: corner angles, edge lengths against
//! the target, distance to the input surface (vertices and face centroids through the BVH,
//! both ways), holes.

use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::geometry::{DEGENERATE_AREA_RELATIVE, triangle_angles};
use flatcut_mesh::vec3::{add, cross, dist, norm, scale, sub};
use flatcut_mesh::{Topology, TriMesh};
use rayon::prelude::*;
use serde::Serialize;

use crate::holes::Hole;

/// Corner angle the acceptance test counts faces below (degrees).
pub const GOOD_MIN_ANGLE_DEG: f64 = 25.0;
/// Edge-length histogram bin width, relative to the target.
const HIST_BIN: f64 = 0.25;
/// Histogram bins (the last one collects everything from 2.5 × target up).
const HIST_BINS: usize = 11;

/// Distances from one surface to another, in mm.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DistanceStats {
    /// Largest distance over the samples.
    pub max_mm: f64,
    /// Root mean square over the samples.
    pub rms_mm: f64,
    /// Number of samples.
    pub samples: usize,
}

/// One bin of the edge-length histogram.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HistogramBin {
    /// Lower end, relative to the target edge.
    pub from: f64,
    /// Upper end, relative to the target edge (infinite for the last bin).
    pub to: f64,
    /// Number of edges.
    pub count: usize,
}

/// Quality of an output mesh against its input surface.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct QualityReport {
    pub vertices: usize,
    pub faces: usize,
    /// Target edge length in mm (the mean edge length when there was no target).
    pub target_edge_mm: f64,
    /// Smallest corner angle over all faces, degrees.
    pub min_angle_deg: f64,
    /// Mean over faces of each face's smallest corner angle, degrees (the mean of all
    /// corner angles is always 60°).
    pub mean_min_angle_deg: f64,
    /// Fraction of faces whose smallest angle is at least 25°.
    pub faces_min_angle_at_least_25_deg: f64,
    pub min_edge_mm: f64,
    pub mean_edge_mm: f64,
    pub max_edge_mm: f64,
    /// Fraction of edges within [0.5, 1.5] × target.
    pub edges_within_half_to_1_5: f64,
    /// Edge lengths relative to the target.
    pub edge_length_histogram: Vec<HistogramBin>,
    /// Output vertices to the input surface (outside filled holes).
    pub vertex_to_input: DistanceStats,
    /// Output face centroids to the input surface (faces touching a filled hole excluded).
    pub centroid_to_input: DistanceStats,
    /// Input vertices to the output surface.
    pub input_to_output: DistanceStats,
    /// The approximation-error bound the next two fields count against, mm (0: none).
    pub max_deviation_mm: f64,
    /// Output vertices and face centroids (outside filled holes) farther than
    /// `max_deviation_mm` from the input surface.
    pub samples_over_deviation: usize,
    /// Fraction of the input's area (outside filled holes) too rough for the bound: scan
    /// noise finer than the output's triangles, where remeshing does not refine and the
    /// bound is not attainable at the target resolution (see docs/algorithms/remesh.md).
    /// Set by `remesh`; 0 elsewhere.
    pub rough_input_fraction: f64,
    /// Largest of the three maxima: the (sampled) Hausdorff distance, mm.
    pub hausdorff_mm: f64,
    /// RMS over the output samples (vertices and centroids), mm.
    pub rms_mm: f64,
    /// Output faces whose area is degenerate (relative to the diagonal², as flatcut_mesh).
    pub degenerate_faces: usize,
    /// Output edges with more than two faces.
    pub non_manifold_edges: usize,
    /// Boundary loops of the input, smallest first.
    pub holes: Vec<Hole>,
    /// How many of them were filled.
    pub holes_filled: usize,
    /// Components too small for the target (scan debris) copied unchanged.
    pub components_kept_unchanged: usize,
}

/// Quality of `output` against the surface `input`; `excluded[v]` marks output vertices in
/// filled holes (left out of the distances, with the faces that touch them). `target_edge_mm`
/// `None` measures edges against their mean; `max_deviation_mm` (if given) is the bound
/// `samples_over_deviation` counts against.
pub fn quality_report(
    output: &TriMesh,
    input: &TriMesh,
    target_edge_mm: Option<f64>,
    max_deviation_mm: Option<f64>,
    excluded: &[bool],
) -> QualityReport {
    let bvh = Bvh::build(input);
    quality_with_bvh(
        output,
        input,
        &bvh,
        target_edge_mm,
        max_deviation_mm,
        excluded,
    )
}

fn stats(d: &[f64]) -> DistanceStats {
    let n = d.len();
    DistanceStats {
        max_mm: d.iter().copied().fold(0.0, f64::max),
        rms_mm: if n > 0 {
            (d.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt()
        } else {
            0.0
        },
        samples: n,
    }
}

pub(crate) fn quality_with_bvh(
    output: &TriMesh,
    input: &TriMesh,
    input_bvh: &Bvh,
    target_edge_mm: Option<f64>,
    max_deviation_mm: Option<f64>,
    excluded: &[bool],
) -> QualityReport {
    let pos = &output.positions;
    let mut r = QualityReport {
        vertices: pos.len(),
        faces: output.faces.len(),
        ..QualityReport::default()
    };
    let mut min_angle = f64::INFINITY;
    let mut sum_min = 0.0;
    let mut good = 0usize;
    let diag = output.diagonal();
    for face in &output.faces {
        let [a, b, c] = face.map(|i| pos[i as usize]);
        let ang = triangle_angles(a, b, c);
        let m = ang
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .to_degrees();
        let m = if m.is_finite() { m } else { 0.0 };
        min_angle = min_angle.min(m);
        sum_min += m;
        if m >= GOOD_MIN_ANGLE_DEG {
            good += 1;
        }
        if 0.5 * norm(cross(sub(b, a), sub(c, a))) <= DEGENERATE_AREA_RELATIVE * diag * diag {
            r.degenerate_faces += 1;
        }
    }
    let nf = output.faces.len().max(1) as f64;
    r.min_angle_deg = if min_angle.is_finite() {
        min_angle
    } else {
        0.0
    };
    r.mean_min_angle_deg = sum_min / nf;
    r.faces_min_angle_at_least_25_deg = good as f64 / nf;
    if let Ok(topo) = Topology::build(output) {
        r.non_manifold_edges = topo.non_manifold_edges().len();
        let lens: Vec<f64> = topo
            .edges()
            .iter()
            .map(|e| dist(pos[e[0] as usize], pos[e[1] as usize]))
            .collect();
        let ne = lens.len().max(1) as f64;
        let mean = lens.iter().sum::<f64>() / ne;
        let t = target_edge_mm.unwrap_or(mean);
        r.target_edge_mm = t;
        r.mean_edge_mm = mean;
        r.min_edge_mm = lens.iter().copied().fold(f64::INFINITY, f64::min);
        r.max_edge_mm = lens.iter().copied().fold(0.0, f64::max);
        if !r.min_edge_mm.is_finite() {
            r.min_edge_mm = 0.0;
        }
        let mut hist = [0usize; HIST_BINS];
        let mut within = 0usize;
        for &l in &lens {
            let q = l / t;
            if (0.5..=1.5).contains(&q) {
                within += 1;
            }
            hist[((q / HIST_BIN) as usize).min(HIST_BINS - 1)] += 1;
        }
        r.edges_within_half_to_1_5 = within as f64 / ne;
        r.edge_length_histogram = hist
            .iter()
            .enumerate()
            .map(|(i, &count)| HistogramBin {
                from: i as f64 * HIST_BIN,
                to: if i + 1 == HIST_BINS {
                    f64::INFINITY
                } else {
                    (i + 1) as f64 * HIST_BIN
                },
                count,
            })
            .collect();
    }
    let is_ex = |v: u32| excluded.get(v as usize).copied().unwrap_or(false);
    let dv: Vec<f64> = (0..pos.len() as u32)
        .into_par_iter()
        .filter(|&v| !is_ex(v))
        .filter_map(|v| input_bvh.closest_point(pos[v as usize]).map(|c| c.distance))
        .collect();
    let dc: Vec<f64> = output
        .faces
        .par_iter()
        .filter(|f| !f.iter().any(|&v| is_ex(v)))
        .filter_map(|f| {
            let c = scale(
                f.iter().fold([0.0; 3], |s, &v| add(s, pos[v as usize])),
                1.0 / 3.0,
            );
            input_bvh.closest_point(c).map(|c| c.distance)
        })
        .collect();
    let out_bvh = Bvh::build(output);
    let used = input.referenced_vertices();
    let di: Vec<f64> = (0..input.positions.len())
        .into_par_iter()
        .filter(|&v| used[v])
        .filter_map(|v| {
            out_bvh
                .closest_point(input.positions[v])
                .map(|c| c.distance)
        })
        .collect();
    if let Some(b) = max_deviation_mm {
        r.max_deviation_mm = b;
        r.samples_over_deviation = dv.iter().chain(&dc).filter(|&&d| d > b).count();
    }
    r.vertex_to_input = stats(&dv);
    r.centroid_to_input = stats(&dc);
    r.input_to_output = stats(&di);
    r.hausdorff_mm = r
        .vertex_to_input
        .max_mm
        .max(r.centroid_to_input.max_mm)
        .max(r.input_to_output.max_mm);
    let both: Vec<f64> = dv.iter().chain(&dc).copied().collect();
    r.rms_mm = stats(&both).rms_mm;
    r
}
