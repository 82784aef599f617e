//! Dart suggestions: tips where the angle defect (discrete Gaussian curvature) is
//! concentrated, starts at the nearest boundary point, ranked by how much curvature the dart
//! frees.
//!
//! 1. Concentration: for every interior vertex, the angle defect 2π − θ summed over the
//!    vertices within [`SuggestOptions::radius_mm`] along the edge graph — the integral of
//!    the Gaussian curvature over a geodesic disk, which smooths scan noise and peaks at the
//!    centre of a dome. Candidates are the interior vertices where this sum is positive and
//!    largest in their neighbourhood. Only positive concentrations get darts: a dart removes
//!    material (the legs are sewn together), which is what a dome needs; a saddle (negative
//!    defect) needs material added — a slash and a gusset, not a dart.
//! 2. Start: among the boundary vertices nearest to the tip along the edge graph, the one at
//!    the shortest exact geodesic distance (flatcut_trim's solver).
//! 3. Ranking proxy (cheap, no processing run): the total |2π − θ| left at the interior
//!    vertices once the dart is cut open, against the piece's before. The tip and the legs
//!    become boundary, whose angle sums need not be 2π; the larger the drop, the less the
//!    remaining interior has to deform. Measured against flattenable processing in
//!    docs/algorithms/darts.md.
//! 4. Selection: best proxy first, skipping a candidate whose tip is within `radius_mm` of a
//!    chosen tip or whose dart would meet a chosen dart.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use flatcut_mesh::{Topology, TriMesh, VertexId, geometry, vec3};
use flatcut_trim::{GeodesicOptions, GeodesicSolver, SurfacePoint};
use serde::{Deserialize, Serialize};

use crate::{DartError, DartOptions, DartSpec, dart};

/// The default neighbourhood radius as a fraction of the piece's bounding-box diagonal: a
/// tenth is the size of a shoulder blade on a back piece, and wide enough to average a
/// scan's per-vertex curvature noise.
pub const DEFAULT_RADIUS_FRACTION: f64 = 0.1;

/// Default smallest concentrated defect worth a dart, radians: the dart opens into a wedge of
/// about this angle in 2D, and one narrower than ~0.6° cannot be sewn as a dart (it is ease).
pub const DEFAULT_MIN_DEFECT_RAD: f64 = 0.01;

/// Options of [`suggest`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SuggestOptions {
    /// Radius of the geodesic neighbourhood the defect is summed over, mm. Default `None`:
    /// [`DEFAULT_RADIUS_FRACTION`] of the piece's diagonal.
    pub radius_mm: Option<f64>,
    /// Smallest concentrated defect (radians) that gets a dart. Default
    /// [`DEFAULT_MIN_DEFECT_RAD`] (0.01).
    pub min_defect_rad: f64,
    /// Candidate tips examined per dart asked for. Default 4.
    pub candidates_per_dart: usize,
    /// Boundary vertices (nearest along edges) tried with exact geodesics for the start.
    /// Default 8.
    pub start_candidates: usize,
    /// Options of the darts themselves.
    pub dart: DartOptions,
}

impl Default for SuggestOptions {
    fn default() -> Self {
        Self {
            radius_mm: None,
            min_defect_rad: DEFAULT_MIN_DEFECT_RAD,
            candidates_per_dart: 4,
            start_candidates: 8,
            dart: DartOptions::default(),
        }
    }
}

/// One proposed dart.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Suggestion {
    /// The dart, ready for [`dart`] (named `suggested-<k>`).
    pub spec: DartSpec,
    /// The tip's vertex in the piece.
    pub tip_vertex: u32,
    /// The start's vertex in the piece (on the boundary).
    pub start_vertex: u32,
    /// Geodesic length from start to tip, mm.
    pub length_mm: f64,
    /// Angle defect summed over the tip's neighbourhood, radians.
    pub concentrated_defect_rad: f64,
    /// Σ |2π − θ| over the interior vertices of the piece, radians.
    pub abs_defect_before_rad: f64,
    /// The same after cutting this dart alone, radians (the ranking proxy: lower is better).
    pub abs_defect_after_rad: f64,
}

#[derive(PartialEq)]
struct Node(f64, u32);
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}

/// Edge-graph neighbours with edge lengths.
fn adjacency(mesh: &TriMesh, topo: &Topology) -> Vec<Vec<(u32, f64)>> {
    let mut adj = vec![Vec::new(); mesh.positions.len()];
    for &[a, b] in topo.edges() {
        let l = vec3::dist(mesh.positions[a as usize], mesh.positions[b as usize]);
        adj[a as usize].push((b, l));
        adj[b as usize].push((a, l));
    }
    adj
}

/// Dijkstra from `src`; calls `visit(v, dist)` for each settled vertex in order, stopping when
/// it returns false or the distance exceeds `cutoff`.
fn dijkstra(
    adj: &[Vec<(u32, f64)>],
    src: u32,
    cutoff: f64,
    dist: &mut [f64],
    touched: &mut Vec<u32>,
    mut visit: impl FnMut(u32, f64) -> bool,
) {
    for &t in touched.iter() {
        dist[t as usize] = f64::INFINITY;
    }
    touched.clear();
    let mut heap = BinaryHeap::new();
    dist[src as usize] = 0.0;
    touched.push(src);
    heap.push(Node(0.0, src));
    while let Some(Node(d, v)) = heap.pop() {
        if d > dist[v as usize] {
            continue;
        }
        if d > cutoff || !visit(v, d) {
            break;
        }
        for &(u, l) in &adj[v as usize] {
            let nd = d + l;
            if nd < dist[u as usize] {
                if dist[u as usize].is_infinite() {
                    touched.push(u);
                }
                dist[u as usize] = nd;
                heap.push(Node(nd, u));
            }
        }
    }
}

/// Σ |2π − θ| over interior vertices.
pub fn total_abs_defect(mesh: &TriMesh) -> Result<f64, DartError> {
    let topo = Topology::build(mesh)?;
    Ok(geometry::angle_defects(&mesh.positions, &mesh.faces, &topo)
        .into_iter()
        .flatten()
        .map(f64::abs)
        .sum())
}

/// Up to `count` darts for `piece` (mm), best first. Fewer when the piece has fewer places
/// with positive concentrated curvature that take a dart.
pub fn suggest(
    piece: &TriMesh,
    count: usize,
    opts: &SuggestOptions,
) -> Result<Vec<Suggestion>, DartError> {
    piece.validate()?;
    if piece.faces.is_empty() {
        return Err(DartError::BadPiece {
            reason: "has no faces".into(),
        });
    }
    let topo = Topology::build(piece)?;
    if topo.boundary_loops().is_empty() {
        return Err(DartError::BadPiece {
            reason: "has no boundary (a closed surface)".into(),
        });
    }
    let radius = opts
        .radius_mm
        .unwrap_or(DEFAULT_RADIUS_FRACTION * piece.diagonal());
    if !(radius.is_finite() && radius > 0.0) {
        return Err(DartError::BadPiece {
            reason: format!("gives no usable neighbourhood radius ({radius} mm)"),
        });
    }
    let defect: Vec<f64> = geometry::angle_defects(&piece.positions, &piece.faces, &topo)
        .into_iter()
        .map(|d| d.unwrap_or(0.0))
        .collect();
    let before: f64 = defect.iter().map(|d| d.abs()).sum();
    let adj = adjacency(piece, &topo);
    let n = piece.positions.len();
    let interior: Vec<bool> = (0..n as u32)
        .map(|v| topo.is_interior_vertex(VertexId(v)))
        .collect();

    // Concentration: the defect summed over each interior vertex's geodesic ball.
    let mut dist = vec![f64::INFINITY; n];
    let mut touched = Vec::new();
    let mut conc = vec![f64::NEG_INFINITY; n];
    for v in 0..n as u32 {
        if !interior[v as usize] {
            continue;
        }
        let mut s = 0.0;
        dijkstra(&adj, v, radius, &mut dist, &mut touched, |u, _| {
            s += defect[u as usize];
            true
        });
        conc[v as usize] = s;
    }
    // Candidates: at least the minimum, and the largest within the ball (ties to the lower index).
    let mut cands: Vec<u32> = Vec::new();
    for v in 0..n as u32 {
        let c = conc[v as usize];
        if !(c >= opts.min_defect_rad && c > 0.0) {
            continue;
        }
        let mut is_max = true;
        dijkstra(&adj, v, radius, &mut dist, &mut touched, |u, _| {
            let cu = conc[u as usize];
            if cu > c || (cu == c && u < v) {
                is_max = false;
            }
            is_max
        });
        if is_max {
            cands.push(v);
        }
    }
    cands.sort_by(|&a, &b| {
        conc[b as usize]
            .total_cmp(&conc[a as usize])
            .then(a.cmp(&b))
    });
    cands.truncate(opts.candidates_per_dart.max(1) * count.max(1));

    let solver = GeodesicSolver::new(
        piece,
        &GeodesicOptions {
            max_strip_updates: opts.dart.max_strip_updates,
        },
    )
    .map_err(DartError::Embedding)?;
    let at = |v: u32| -> Option<SurfacePoint> {
        let f = topo.outgoing(VertexId(v)).first()? / 3;
        SurfacePoint::at_vertex(piece, f, v)
    };
    let mut scored: Vec<Suggestion> = Vec::new();
    for &tip in &cands {
        let Some(tip_sp) = at(tip) else { continue };
        // Nearest boundary vertices along edges, then the shortest exact geodesic.
        let mut near: Vec<u32> = Vec::new();
        dijkstra(&adj, tip, f64::INFINITY, &mut dist, &mut touched, |u, _| {
            if !interior[u as usize] && topo.is_boundary_vertex(VertexId(u)) {
                near.push(u);
            }
            near.len() < opts.start_candidates.max(1)
        });
        let mut best: Option<(f64, u32)> = None;
        for &b in &near {
            let Some(b_sp) = at(b) else { continue };
            if let Some(g) = solver.path(b_sp, tip_sp)
                && best.is_none_or(|(l, _)| g.length < l)
            {
                best = Some((g.length, b));
            }
        }
        let Some((length, start)) = best else {
            continue;
        };
        let spec = DartSpec::to_tip(
            "suggested",
            piece.positions[start as usize],
            piece.positions[tip as usize],
        );
        let Ok(darted) = dart(piece, std::slice::from_ref(&spec), &opts.dart) else {
            continue;
        };
        scored.push(Suggestion {
            spec,
            tip_vertex: tip,
            start_vertex: start,
            length_mm: length,
            concentrated_defect_rad: conc[tip as usize],
            abs_defect_before_rad: before,
            abs_defect_after_rad: total_abs_defect(&darted.mesh)?,
        });
    }
    scored.sort_by(|a, b| {
        a.abs_defect_after_rad
            .total_cmp(&b.abs_defect_after_rad)
            .then(a.tip_vertex.cmp(&b.tip_vertex))
    });

    let mut chosen: Vec<Suggestion> = Vec::new();
    for s in scored {
        if chosen.len() >= count {
            break;
        }
        let near_chosen = chosen.iter().any(|c| {
            vec3::dist(
                c.spec.tip.unwrap_or_default(),
                s.spec.tip.unwrap_or_default(),
            ) < radius
        });
        if near_chosen {
            continue;
        }
        let mut specs: Vec<DartSpec> = chosen.iter().map(|c| c.spec.clone()).collect();
        specs.push(s.spec.clone());
        for (k, sp) in specs.iter_mut().enumerate() {
            sp.name = format!("suggested-{}", k + 1);
        }
        if dart(piece, &specs, &opts.dart).is_ok() {
            let mut s = s;
            s.spec.name = format!("suggested-{}", chosen.len() + 1);
            chosen.push(s);
        }
    }
    Ok(chosen)
}
