//! Isotropic remeshing (Botsch & Kobbelt 2004, "A remeshing approach to multiresolution
//! modeling"): split edges longer than 4/3·L, collapse edges shorter than 4/5·L, flip
//! towards valence 6 (4 on the boundary), relax tangentially and project back onto the
//! input surface through the BVH. Boundaries, sharp creases and given feature lines are
//! kept as polylines: vertices on them live on the input polyline by arc length, corners
//! never move. Small holes are fan-filled first, remeshed with everything else and faired
//! at the end with the rest of the surface fixed. See docs/algorithms/remesh.md.

use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::geometry::{area_weighted_vertex_normals, face_normals};
use flatcut_mesh::vec3::{add, cross, dist, dot, norm, norm2, normalize, scale, sub};
use flatcut_mesh::{INVALID, Topology, TriMesh, VertexId};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::RemeshError;
use crate::halfedge::{HalfMesh, check_manifold, twin};
use crate::holes::{fan_fill, find_holes};
use crate::quality::{QualityReport, quality_with_bvh};
use crate::taubin::taubin_smooth;

/// Split edges longer than this multiple of the target (Botsch & Kobbelt: 4/3 makes the
/// split and collapse thresholds symmetric around the target after one split).
const SPLIT_FACTOR: f64 = 4.0 / 3.0;
/// Collapse edges shorter than this multiple of the target (Botsch & Kobbelt).
const COLLAPSE_FACTOR: f64 = 4.0 / 5.0;
/// A collapse or flip may tilt a face normal by at most this much (cosine of 60°): larger
/// turns fold the surface locally, and projection would not repair the fold.
const MAX_NORMAL_TURN_COS: f64 = 0.5;
/// Faces whose doubled area is below this fraction of L² count as degenerate during edits.
const DEGENERATE_AREA_REL: f64 = 1e-10;
/// Smallest ratio of target edge to bounding-box diagonal the issue allows.
const MIN_TARGET_REL: f64 = 1e-6;
/// Feature chains made only of detected creases shorter than this many target edges are
/// scan noise, not creases: they are dropped.
const MIN_CREASE_CHAIN_EDGES: f64 = 2.0;
/// Components with less area than this many equilateral triangles of the target edge (a
/// 4 × 4 patch, about two target edges across) are copied unchanged: at that size the
/// boundary corners pin every vertex and remeshing only tangles them (the scan's debris
/// islands of 5–15 target triangles did exactly that).
const TINY_COMPONENT_TRIANGLES: f64 = 16.0;
/// Faces with a corner below this angle (degrees) after the rounds are treated as slivers
/// and removed by a flip or collapse where allowed; at most `SLIVER_PASSES` sweeps.
const SLIVER_ANGLE_DEG: f64 = 5.0;
const SLIVER_PASSES: usize = 3;
/// Corners are judged on the polyline between the points this fraction of the target edge
/// away on either side (so sub-target noise on a boundary does not make corners).
const CORNER_WINDOW_REL: f64 = 0.5;
/// Fairing of filled holes stops when no vertex moves more than this fraction of the target
/// edge in a sweep, or after `FAIR_MAX_SWEEPS` sweeps.
const FAIR_TOLERANCE_REL: f64 = 1e-7;
const FAIR_MAX_SWEEPS: usize = 3000;
/// Without `min_edge_mm`, approximation-error refinement lowers the local target edge to
/// no less than this fraction of the target: collapses stop at 4/5 of the local target, so
/// refined edges stay at or above half the target (the lower end of the issue's
/// [0.5, 1.5] × target band).
const DEVIATION_FLOOR_REL: f64 = 0.625;
/// A face over the deviation bound asks for L·√(bound/deviation) (the chord error of a
/// smooth surface grows with L²) times this margin, so one refinement usually suffices.
const DEVIATION_MARGIN: f64 = 0.9;
/// Deviation refinement stays off where the input's roughness (see `roughness_field`)
/// exceeds this fraction of the bound: there the input is noise finer than any triangle
/// the refinement may make, and refining only adds faces without meeting the bound.
const ROUGHNESS_REL: f64 = 1.0;
/// The refined sizing field may grow by at most this many mm per mm away from a refined
/// spot: a gradual transition keeps the triangles there well shaped.
const SIZING_GRADE: f64 = 0.5;
/// Rounds before the first approximation-error check (the mesh must first be near the
/// target) and rounds left after the last one (to split, relax and settle the refinement).
const DEVIATION_FIRST_ROUND: usize = 2;
const DEVIATION_SETTLE_ROUNDS: usize = 3;

/// Options of [`remesh`]. Deserializes from the pipeline TOML (`[remesh]`).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct RemeshOptions {
    /// Target edge length in mm (default 8). Must lie between 1e-6 of the object's
    /// bounding-box diagonal and the diagonal itself.
    pub target_edge_mm: f64,
    /// Smallest edge length in mm when adapting to curvature (default none: uniform). Give
    /// both `min_edge_mm` and `max_edge_mm` to adapt.
    pub min_edge_mm: Option<f64>,
    /// Largest edge length in mm when adapting to curvature (default none: uniform).
    pub max_edge_mm: Option<f64>,
    /// Chord deviation in mm the adaptive sizing aims for: L = √(6ε/κ − 3ε²) (default 0.25).
    pub adaptive_tolerance_mm: f64,
    /// Number of split–collapse–flip–relax rounds (default 10).
    pub iterations: usize,
    /// Edges whose faces meet at a dihedral angle above this are creases and kept (degrees,
    /// default 45; 180 turns crease detection off). Boundary polylines turning by more than
    /// this angle at a vertex keep that vertex as a corner.
    pub feature_angle_deg: f64,
    /// Feature lines to keep, each a polyline of input vertex ids along mesh edges
    /// (default none). Open ends are kept as corners.
    pub feature_lines: Vec<Vec<u32>>,
    /// Holes (boundary loops) with a perimeter below this are filled, in mm (default 0:
    /// none). Larger openings stay open.
    pub fill_holes_perimeter_mm: f64,
    /// Approximation-error bound in mm (default 0.5; 0 turns refinement off): where a face's
    /// centroid or an edge midpoint lies farther than this from the input surface, the
    /// local target edge is lowered (by the chord-error rule, graded smoothly) and the
    /// rounds split, relax and project there, down to `min_edge_mm` when given, else to
    /// 0.625 × `target_edge_mm` (so refined edges stay ≥ half the target). Filled holes are
    /// not checked. Deviations that persist at that floor (scan noise finer than the
    /// floor) are counted in the report's `samples_over_deviation`.
    pub max_deviation_mm: f64,
    /// Taubin λ|μ smoothing steps applied to the result (default 0: off, every vertex on the
    /// input). Boundary, corner, crease and feature-line vertices stay fixed. It removes scan
    /// noise at the working resolution without shrinking the shape (a pass band of about 19
    /// edges: [`crate::taubin`]), for pieces that flattenable processing would otherwise
    /// have to iron (docs/algorithms/remesh.md); the vertices then leave the noisy input by
    /// about the noise's amplitude (the report's distances say how far) and their provenance
    /// is their closest input point.
    pub smooth_iterations: usize,
}

impl Default for RemeshOptions {
    fn default() -> Self {
        RemeshOptions {
            target_edge_mm: 8.0,
            min_edge_mm: None,
            max_edge_mm: None,
            adaptive_tolerance_mm: 0.25,
            iterations: 10,
            feature_angle_deg: 45.0,
            feature_lines: Vec::new(),
            fill_holes_perimeter_mm: 0.0,
            max_deviation_mm: 0.5,
            smooth_iterations: 0,
        }
    }
}

/// Where an output vertex lies on the input surface.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Provenance {
    /// Input face.
    pub face: u32,
    /// Barycentric weights of the input face's three corners.
    pub barycentric: [f64; 3],
    /// The vertex lies in a filled hole: `face`/`barycentric` then give the closest input
    /// point, not the vertex itself.
    pub filled: bool,
}

/// Result of [`remesh`].
#[derive(Clone, Debug)]
pub struct Remeshed {
    /// The new mesh (mm).
    pub mesh: TriMesh,
    /// Per output vertex, its point on the input surface.
    pub provenance: Vec<Provenance>,
    /// Quality of the result.
    pub report: QualityReport,
}

/// A feature polyline of the input: points and cumulative arc length.
#[derive(Clone, Debug)]
struct Chain {
    pts: Vec<[f64; 3]>,
    cum: Vec<f64>,
    /// Per segment: an input face on it and the corner slots of the segment's two ends.
    seg_face: Vec<(u32, u8, u8)>,
    closed: bool,
    /// Input vertices along the chain (first = last for closed chains).
    verts: Vec<u32>,
    /// First and last input vertex (equal for closed chains).
    start: u32,
    end: u32,
    kind_crease_only: bool,
}

impl Chain {
    fn total(&self) -> f64 {
        *self.cum.last().unwrap_or(&0.0)
    }

    fn wrap(&self, s: f64) -> f64 {
        let t = self.total();
        if self.closed && t > 0.0 {
            s.rem_euclid(t)
        } else {
            s.clamp(0.0, t)
        }
    }

    /// Point at arc length `s`, with its segment and parameter.
    fn at(&self, s: f64) -> ([f64; 3], usize, f64) {
        let s = self.wrap(s);
        let n = self.pts.len() - 1;
        let i = match self.cum.binary_search_by(|c| c.total_cmp(&s)) {
            Ok(i) => i.min(n - 1),
            Err(i) => i.saturating_sub(1).min(n - 1),
        };
        let len = self.cum[i + 1] - self.cum[i];
        let t = if len > 0.0 {
            ((s - self.cum[i]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let p = add(scale(self.pts[i], 1.0 - t), scale(self.pts[i + 1], t));
        (p, i, t)
    }

    fn provenance(&self, s: f64) -> Provenance {
        let (_, i, t) = self.at(s);
        let (face, ka, kb) = self.seg_face[i];
        let mut b = [0.0; 3];
        b[ka as usize] = 1.0 - t;
        b[kb as usize] += t;
        Provenance {
            face,
            barycentric: b,
            filled: false,
        }
    }

    /// Shortest signed way from `from` to `to` along the chain.
    fn delta(&self, from: f64, to: f64) -> f64 {
        let mut d = to - from;
        if self.closed {
            let t = self.total();
            if d > t / 2.0 {
                d -= t;
            } else if d < -t / 2.0 {
                d += t;
            }
        }
        d
    }
}

/// Feature edges (chain per topology edge), the chains, and the corner vertices.
struct Features {
    e_chain: Vec<u32>,
    chains: Vec<Chain>,
    corner: Vec<bool>,
}

/// The working state of the remesher.
struct Work<'a> {
    m: HalfMesh,
    /// Per vertex: its chain (`INVALID`: free), arc length, corner flag, target edge.
    v_chain: Vec<u32>,
    v_s: Vec<f64>,
    v_corner: Vec<bool>,
    v_len: Vec<f64>,
    /// Per vertex: the working-surface face it projects onto (`INVALID`: unknown).
    v_face: Vec<u32>,
    /// Per edge: its chain (`INVALID`: not a feature).
    e_chain: Vec<u32>,
    chains: Vec<Chain>,
    /// Live non-corner vertices per chain.
    chain_count: Vec<usize>,
    bvh: &'a Bvh,
    surf: &'a TriMesh,
    /// Sizing per working-surface vertex.
    sizing: Vec<f64>,
    /// Per input vertex: an input face of it and its slot there.
    input_face: Vec<(u32, u8)>,
    /// Neighbours of each working-surface vertex (CSR: `surf_adj[surf_off[v]..surf_off[v + 1]]`),
    /// for grading the sizing field; empty without a deviation bound.
    surf_off: Vec<u32>,
    surf_adj: Vec<u32>,
    /// Working-surface faces from this index on are hole fill.
    n_input_faces: u32,
    /// Approximation-error bound (0: off) and the smallest local target it may ask for.
    dev_bound: f64,
    dev_floor: f64,
    /// Per working-surface vertex: the noise level of the input there (mm; empty: not
    /// computed).
    roughness: Vec<f64>,
}

/// Remeshes `mesh` to edges of about `opts.target_edge_mm` (see the module docs).
///
/// Components whose area is below `TINY_COMPONENT_TRIANGLES` target-sized triangles (scan
/// debris) cannot carry the target resolution; they are copied unchanged and counted in
/// the report's `components_kept_unchanged`.
pub fn remesh(mesh: &TriMesh, opts: &RemeshOptions) -> Result<Remeshed, RemeshError> {
    mesh.validate()?;
    if mesh.faces.is_empty() {
        return Err(RemeshError::EmptyMesh);
    }
    check_options(mesh, opts)?;
    let topo = Topology::build(mesh)?;
    check_manifold(mesh, &topo)?;
    let t = opts.target_edge_mm;
    let tiny_area = TINY_COMPONENT_TRIANGLES * 3f64.sqrt() / 4.0 * t * t;
    let mut comp_area = vec![0.0; topo.component_count()];
    for (f, face) in mesh.faces.iter().enumerate() {
        let [a, b, c] = face.map(|i| mesh.positions[i as usize]);
        comp_area[topo.face_components()[f] as usize] += 0.5 * norm(cross(sub(b, a), sub(c, a)));
    }
    let tiny: Vec<bool> = comp_area.iter().map(|&a| a < tiny_area).collect();
    if !tiny.iter().any(|&x| x) || tiny.iter().all(|&x| x) {
        return remesh_manifold(mesh, topo, opts);
    }
    let (big, small): (Vec<u32>, Vec<u32>) = (0..mesh.faces.len() as u32)
        .partition(|&f| !tiny[topo.face_components()[f as usize] as usize]);
    let (sub_mesh, _) = flatcut_mesh::submesh(mesh, &big);
    let sub_topo = Topology::build(&sub_mesh)?;
    let mut r = remesh_manifold(&sub_mesh, sub_topo, opts)?;
    for p in &mut r.provenance {
        p.face = big[p.face as usize];
    }
    // Append the small components verbatim, each vertex mapped to one of its own faces.
    let mut local = vec![INVALID; mesh.positions.len()];
    for &f in &small {
        let face = mesh.faces[f as usize];
        let mut out_face = [0u32; 3];
        for (slot, &v) in face.iter().enumerate() {
            if local[v as usize] == INVALID {
                local[v as usize] = r.mesh.positions.len() as u32;
                r.mesh.positions.push(mesh.positions[v as usize]);
                let mut b = [0.0; 3];
                b[slot] = 1.0;
                r.provenance.push(Provenance {
                    face: f,
                    barycentric: b,
                    filled: false,
                });
            }
            out_face[slot] = local[v as usize];
        }
        r.mesh.faces.push(out_face);
    }
    let filled: Vec<bool> = r.provenance.iter().map(|p| p.filled).collect();
    let holes = std::mem::take(&mut r.report.holes);
    let n_filled = r.report.holes_filled;
    let bound = (opts.max_deviation_mm > 0.0).then_some(opts.max_deviation_mm);
    let rough = r.report.rough_input_fraction;
    r.report = crate::quality::quality_report(&r.mesh, mesh, Some(t), bound, &filled);
    // Measured on the remeshed part; the copied debris does not change it noticeably.
    r.report.rough_input_fraction = rough;
    r.report.holes = holes;
    r.report.holes_filled = n_filled;
    r.report.components_kept_unchanged = tiny.iter().filter(|&&x| x).count();
    Ok(r)
}

/// [`remesh`] of a checked manifold mesh.
fn remesh_manifold(
    mesh: &TriMesh,
    topo: Topology,
    opts: &RemeshOptions,
) -> Result<Remeshed, RemeshError> {
    let target = opts.target_edge_mm;
    let holes = find_holes(mesh, &topo, opts.fill_holes_perimeter_mm);
    let any_filled = holes.iter().any(|h| h.filled);
    let (surf, surf_topo) = if any_filled {
        let s = fan_fill(mesh, &topo, opts.fill_holes_perimeter_mm);
        let t = Topology::build(&s)?;
        (s, t)
    } else {
        (mesh.clone(), topo)
    };
    let n_input_faces = mesh.faces.len() as u32;
    let bvh = Bvh::build(&surf);
    let sizing = sizing_field(&surf, &surf_topo, opts);
    let feats = extract_features(&surf, &surf_topo, opts, n_input_faces)?;
    let m = HalfMesh::build(&surf, &surf_topo);
    let mut w = Work::new(m, feats, &bvh, &surf, sizing, mesh);
    w.n_input_faces = n_input_faces;
    w.dev_bound = opts.max_deviation_mm;
    if w.dev_bound > 0.0 {
        w.roughness = roughness_field(&surf, &surf_topo);
        let n = surf.positions.len();
        let mut off = vec![0u32; n + 1];
        for e in surf_topo.edges() {
            off[e[0] as usize + 1] += 1;
            off[e[1] as usize + 1] += 1;
        }
        for v in 0..n {
            off[v + 1] += off[v];
        }
        let mut fill = off.clone();
        let mut adj = vec![0u32; off[n] as usize];
        for e in surf_topo.edges() {
            for (a, b) in [(e[0], e[1]), (e[1], e[0])] {
                adj[fill[a as usize] as usize] = b;
                fill[a as usize] += 1;
            }
        }
        w.surf_off = off;
        w.surf_adj = adj;
    }
    w.dev_floor = opts
        .min_edge_mm
        .unwrap_or(DEVIATION_FLOOR_REL * target)
        .min(target);
    for round in 0..opts.iterations {
        w.split_long();
        w.collapse_short();
        w.flip_to_valence();
        w.relax();
        if round >= DEVIATION_FIRST_ROUND && round + DEVIATION_SETTLE_ROUNDS < opts.iterations {
            w.refine_by_deviation();
        }
    }
    w.remove_slivers();
    w.final_projection();
    if any_filled {
        w.fair_filled(n_input_faces, target);
    }
    let (mut out, old_id) = w.m.to_trimesh();
    if opts.smooth_iterations > 0 {
        let fixed: Vec<bool> = old_id
            .iter()
            .map(|&v| w.is_feature_v(v) || w.m.is_boundary_v(v))
            .collect();
        taubin_smooth(&mut out, &fixed, opts.smooth_iterations);
    }
    let input_bvh = if any_filled {
        Some(Bvh::build(mesh))
    } else {
        None
    };
    let ibvh = input_bvh.as_ref().unwrap_or(&bvh);
    // Located at the output position: smoothed vertices left the input, and their provenance
    // is their closest input point (one query per vertex).
    let provenance: Vec<Provenance> = old_id
        .par_iter()
        .zip(&out.positions)
        .map(|(&v, &at)| w.provenance(v, at, n_input_faces, mesh, ibvh))
        .collect();
    let filled: Vec<bool> = provenance.iter().map(|p| p.filled).collect();
    let bound = (opts.max_deviation_mm > 0.0).then_some(opts.max_deviation_mm);
    let mut report = quality_with_bvh(&out, mesh, ibvh, Some(target), bound, &filled);
    report.rough_input_fraction = if bound.is_some() {
        rough_fraction(mesh, &w.roughness, opts.max_deviation_mm)
    } else {
        0.0
    };
    report.holes = holes;
    report.holes_filled = report.holes.iter().filter(|h| h.filled).count();
    Ok(Remeshed {
        mesh: out,
        provenance,
        report,
    })
}

fn check_options(mesh: &TriMesh, opts: &RemeshOptions) -> Result<(), RemeshError> {
    let diag = mesh.diagonal();
    let t = opts.target_edge_mm;
    let bad = |name, value, reason| {
        Err(RemeshError::InvalidOption {
            name,
            value,
            reason,
        })
    };
    if !(t.is_finite() && t > 0.0) {
        return bad("target_edge_mm", t, "must be a finite length > 0 in mm");
    }
    if t > diag {
        return Err(RemeshError::TargetTooLarge {
            target_edge_mm: t,
            diagonal_mm: diag,
        });
    }
    if t < MIN_TARGET_REL * diag {
        return Err(RemeshError::TargetTooSmall {
            target_edge_mm: t,
            diagonal_mm: diag,
        });
    }
    match (opts.min_edge_mm, opts.max_edge_mm) {
        (None, None) => {}
        (Some(a), Some(b)) => {
            if !(a.is_finite() && a > 0.0 && a < MIN_TARGET_REL * diag || a <= b) {
                return bad("min_edge_mm", a, "must be > 0 and ≤ max_edge_mm");
            }
            if !(b.is_finite() && b <= diag && a >= MIN_TARGET_REL * diag) {
                return bad(
                    "max_edge_mm",
                    b,
                    "must be finite, at most the object's diagonal, with min_edge_mm ≥ 1e-6 of it",
                );
            }
            let e = opts.adaptive_tolerance_mm;
            if !(e.is_finite() && e > 0.0) {
                return bad(
                    "adaptive_tolerance_mm",
                    e,
                    "must be a finite length > 0 in mm",
                );
            }
        }
        (Some(a), None) => return bad("min_edge_mm", a, "give max_edge_mm too"),
        (None, Some(b)) => return bad("max_edge_mm", b, "give min_edge_mm too"),
    }
    if !(opts.feature_angle_deg.is_finite() && opts.feature_angle_deg > 0.0) {
        return bad(
            "feature_angle_deg",
            opts.feature_angle_deg,
            "must be an angle > 0 in degrees (180 turns creases off)",
        );
    }
    if !(opts.fill_holes_perimeter_mm.is_finite() && opts.fill_holes_perimeter_mm >= 0.0) {
        return bad(
            "fill_holes_perimeter_mm",
            opts.fill_holes_perimeter_mm,
            "must be a finite length ≥ 0 in mm",
        );
    }
    if !(opts.max_deviation_mm.is_finite() && opts.max_deviation_mm >= 0.0) {
        return bad(
            "max_deviation_mm",
            opts.max_deviation_mm,
            "must be a finite distance ≥ 0 in mm (0 turns refinement off)",
        );
    }
    if opts.iterations > 1000 {
        return bad("iterations", opts.iterations as f64, "at most 1000");
    }
    Ok(())
}

/// Target edge length per working-surface vertex: uniform, or from a curvature estimate
/// (largest normal curvature towards a neighbour, averaged once over the ring) by Botsch &
/// Kobbelt's chord-error rule L = √(6ε/κ − 3ε²), clamped to [min, max].
fn sizing_field(surf: &TriMesh, topo: &Topology, opts: &RemeshOptions) -> Vec<f64> {
    let n = surf.positions.len();
    let (Some(lo), Some(hi)) = (opts.min_edge_mm, opts.max_edge_mm) else {
        return vec![opts.target_edge_mm; n];
    };
    let vn = area_weighted_vertex_normals(&surf.positions, &surf.faces);
    let mut kappa = vec![0.0f64; n];
    for e in topo.edges() {
        let (a, b) = (e[0] as usize, e[1] as usize);
        let d = sub(surf.positions[b], surf.positions[a]);
        let l2 = norm2(d);
        if l2 == 0.0 {
            continue;
        }
        let ka = (2.0 * dot(normalize(vn[a]), d) / l2).abs();
        let kb = (2.0 * dot(normalize(vn[b]), d) / l2).abs();
        kappa[a] = kappa[a].max(ka);
        kappa[b] = kappa[b].max(kb);
    }
    // One ring average to tame scan noise.
    let mut sum = kappa.clone();
    let mut cnt = vec![1.0f64; n];
    for e in topo.edges() {
        let (a, b) = (e[0] as usize, e[1] as usize);
        sum[a] += kappa[b];
        sum[b] += kappa[a];
        cnt[a] += 1.0;
        cnt[b] += 1.0;
    }
    let eps = opts.adaptive_tolerance_mm;
    (0..n)
        .map(|v| {
            let k = sum[v] / cnt[v];
            let l = if k > 0.0 {
                let q = 6.0 * eps / k - 3.0 * eps * eps;
                if q > 0.0 { q.sqrt() } else { lo }
            } else {
                hi
            };
            l.clamp(lo, hi)
        })
        .collect()
}

/// Noise level of the surface per vertex, in mm: the normal component of the second
/// difference of positions, |n·(Δx_i − mean_j Δx_j)| with Δ the uniform Laplacian, averaged
/// over the one-ring. Smooth curvature makes Δx vary slowly from vertex to vertex, so its
/// difference is small (≈ 0.01 mm on the subdivided body); independent noise of amplitude σ
/// gives about σ (≈ 2 mm on mh_body_scanlike).
fn roughness_field(surf: &TriMesh, topo: &Topology) -> Vec<f64> {
    let n = surf.positions.len();
    let vn = area_weighted_vertex_normals(&surf.positions, &surf.faces);
    let edges = topo.edges();
    let ring_mean = |val: &[[f64; 3]]| -> Vec<[f64; 3]> {
        let mut sum = vec![[0.0; 3]; n];
        let mut cnt = vec![0.0f64; n];
        for e in edges {
            let (a, b) = (e[0] as usize, e[1] as usize);
            sum[a] = add(sum[a], val[b]);
            sum[b] = add(sum[b], val[a]);
            cnt[a] += 1.0;
            cnt[b] += 1.0;
        }
        (0..n)
            .map(|i| {
                if cnt[i] > 0.0 {
                    scale(sum[i], 1.0 / cnt[i])
                } else {
                    val[i]
                }
            })
            .collect()
    };
    let avg = ring_mean(&surf.positions);
    let lap: Vec<[f64; 3]> = (0..n).map(|i| sub(avg[i], surf.positions[i])).collect();
    let lap_avg = ring_mean(&lap);
    let r: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let nn = normalize(vn[i]);
            let x = dot(nn, sub(lap[i], lap_avg[i])).abs();
            [if x.is_finite() { x } else { 0.0 }, 0.0, 0.0]
        })
        .collect();
    ring_mean(&r).iter().map(|x| x[0]).collect()
}

/// Per vertex of `mesh`, the input's noise level in mm (see `roughness_field`): where it
/// exceeds `max_deviation_mm`, remeshing does not refine for the bound.
pub fn roughness(mesh: &TriMesh) -> Result<Vec<f64>, RemeshError> {
    mesh.validate()?;
    let topo = Topology::build(mesh)?;
    Ok(roughness_field(mesh, &topo))
}

/// Fraction of `mesh`'s area on faces with a corner rougher than the bound (the same test
/// as the refinement's); `rough` covers at least the mesh's vertices.
fn rough_fraction(mesh: &TriMesh, rough: &[f64], bound: f64) -> f64 {
    let (mut all, mut bad) = (0.0, 0.0);
    for face in &mesh.faces {
        let [a, b, c] = face.map(|i| mesh.positions[i as usize]);
        let area = norm(cross(sub(b, a), sub(c, a)));
        all += area;
        if face.iter().any(|&v| {
            rough
                .get(v as usize)
                .is_some_and(|&r| r > ROUGHNESS_REL * bound)
        }) {
            bad += area;
        }
    }
    if all > 0.0 { bad / all } else { 0.0 }
}

/// Feature edges (per working-surface topology edge: chain id) and their chains.
fn extract_features(
    surf: &TriMesh,
    topo: &Topology,
    opts: &RemeshOptions,
    n_input_faces: u32,
) -> Result<Features, RemeshError> {
    let ne = topo.edges().len();
    let nf = surf.faces.len();
    // 0: none, 1: boundary, 2: user line, 3: crease.
    let mut kind = vec![0u8; ne];
    let mut edge_h = vec![INVALID; ne];
    let fnorm = face_normals(&surf.positions, &surf.faces);
    let cos_feat = opts.feature_angle_deg.to_radians().cos();
    for h in 0..3 * nf as u32 {
        let e = topo.edge_of(h) as usize;
        if edge_h[e] == INVALID {
            edge_h[e] = h;
        }
        match topo.twin(h) {
            None => kind[e] = 1,
            Some(t) => {
                let (f, g) = (h / 3, t / 3);
                if h < t
                    && opts.feature_angle_deg < 180.0
                    && f < n_input_faces
                    && g < n_input_faces
                    && dot(fnorm[f as usize], fnorm[g as usize]) < cos_feat
                {
                    kind[e] = 3;
                }
            }
        }
    }
    for (line, poly) in opts.feature_lines.iter().enumerate() {
        for &v in poly {
            if v as usize >= surf.positions.len() || !topo.is_referenced(VertexId(v)) {
                return Err(RemeshError::FeatureVertexOutOfRange {
                    line,
                    vertex: v,
                    vertex_count: surf.positions.len(),
                });
            }
        }
        for w in poly.windows(2) {
            let e = topo
                .outgoing(VertexId(w[0]))
                .iter()
                .chain(topo.outgoing(VertexId(w[1])))
                .map(|&h| (h, topo.edge_of(h)))
                .find(|&(_, e)| {
                    let [a, b] = topo.edges()[e as usize];
                    (a, b) == (w[0].min(w[1]), w[0].max(w[1]))
                });
            match e {
                Some((_, e)) => {
                    if kind[e as usize] != 1 {
                        kind[e as usize] = 2;
                    }
                }
                None => {
                    return Err(RemeshError::FeatureNotAnEdge {
                        line,
                        a: w[0],
                        b: w[1],
                    });
                }
            }
        }
    }
    let mut user_end = vec![false; surf.positions.len()];
    for poly in &opts.feature_lines {
        if let (Some(&a), Some(&b)) = (poly.first(), poly.last()) {
            if a != b {
                user_end[a as usize] = true;
                user_end[b as usize] = true;
            }
        }
    }
    let min_crease = MIN_CREASE_CHAIN_EDGES * opts.target_edge_mm;
    let (chains, corner) = loop {
        let (chains, corner) = trace_chains(surf, topo, &kind, &edge_h, &user_end, opts);
        let short = |c: &Chain| c.kind_crease_only && c.total() < min_crease;
        if !chains.iter().any(|(c, _)| short(c)) {
            break (chains, corner);
        }
        for (c, edges) in &chains {
            if short(c) {
                for &e in edges {
                    kind[e as usize] = 0;
                }
            }
        }
    };
    let mut e_chain = vec![INVALID; ne];
    let mut out = Vec::with_capacity(chains.len());
    for (i, (c, edges)) in chains.into_iter().enumerate() {
        for e in edges {
            e_chain[e as usize] = i as u32;
        }
        out.push(c);
    }
    Ok(Features {
        e_chain,
        chains: out,
        corner,
    })
}

/// Traces feature edges into chains between corners (and closed loops without corners).
/// Returns each chain with its topology edges.
fn trace_chains(
    surf: &TriMesh,
    topo: &Topology,
    kind: &[u8],
    edge_h: &[u32],
    user_end: &[bool],
    opts: &RemeshOptions,
) -> (Vec<(Chain, Vec<u32>)>, Vec<bool>) {
    let nv = surf.positions.len();
    let edges = topo.edges();
    // CSR of feature edges per vertex.
    let mut deg = vec![0u32; nv + 1];
    for (e, &k) in kind.iter().enumerate() {
        if k != 0 {
            deg[edges[e][0] as usize] += 1;
            deg[edges[e][1] as usize] += 1;
        }
    }
    let mut off = vec![0u32; nv + 1];
    for v in 0..nv {
        off[v + 1] = off[v] + deg[v];
    }
    let mut fill = off.clone();
    let mut adj = vec![0u32; off[nv] as usize];
    for (e, &k) in kind.iter().enumerate() {
        if k != 0 {
            for &v in &edges[e] {
                adj[fill[v as usize] as usize] = e as u32;
                fill[v as usize] += 1;
            }
        }
    }
    let other = |e: u32, v: u32| {
        let [a, b] = edges[e as usize];
        if a == v { b } else { a }
    };
    let cos_corner = opts.feature_angle_deg.min(179.0).to_radians().cos();
    // Turning of the polyline at each degree-2 feature vertex, measured between the points
    // half a target edge away on either side: scan noise on a boundary turns sharply from
    // vertex to vertex but not at the scale of the output, and only that scale matters.
    let window = CORNER_WINDOW_REL * opts.target_edge_mm;
    let reach = |v: u32, first: u32| -> [f64; 3] {
        let (mut at, mut e, mut acc) = (v, first, 0.0);
        loop {
            let nx = other(e, at);
            acc += dist(surf.positions[at as usize], surf.positions[nx as usize]);
            at = nx;
            if acc >= window || deg[at as usize] != 2 || at == v {
                return surf.positions[at as usize];
            }
            let es = &adj[off[at as usize] as usize..off[at as usize + 1] as usize];
            e = if es[0] == e { es[1] } else { es[0] };
        }
    };
    let turn_cos: Vec<f64> = (0..nv)
        .map(|v| {
            if deg[v] != 2 {
                return 1.0;
            }
            let es = &adj[off[v] as usize..off[v + 1] as usize];
            let p = surf.positions[v];
            let a = reach(v as u32, es[0]);
            let b = reach(v as u32, es[1]);
            dot(normalize(sub(p, a)), normalize(sub(b, p)))
        })
        .collect();
    let corner: Vec<bool> = (0..nv)
        .map(|v| {
            let d = deg[v];
            if d == 0 {
                return false;
            }
            if d != 2 || user_end[v] {
                return true;
            }
            if turn_cos[v] >= cos_corner {
                return false;
            }
            // Keep only the sharpest vertex of a turn (non-maximum suppression).
            adj[off[v] as usize..off[v + 1] as usize].iter().all(|&e| {
                let u = other(e, v as u32) as usize;
                turn_cos[v] < turn_cos[u] || (turn_cos[v] == turn_cos[u] && v < u)
            })
        })
        .collect();
    let mut used = vec![false; kind.len()];
    let mut out = Vec::new();
    let walk = |start: u32, first_e: u32, used: &mut Vec<bool>| -> (Chain, Vec<u32>) {
        let mut verts = vec![start];
        let mut es = vec![first_e];
        used[first_e as usize] = true;
        let mut v = other(first_e, start);
        let mut crease_only = kind[first_e as usize] == 3;
        loop {
            verts.push(v);
            if corner[v as usize] || v == start {
                break;
            }
            let nxt = adj[off[v as usize] as usize..off[v as usize + 1] as usize]
                .iter()
                .copied()
                .find(|&e| !used[e as usize]);
            match nxt {
                Some(e) => {
                    used[e as usize] = true;
                    es.push(e);
                    crease_only &= kind[e as usize] == 3;
                    v = other(e, v);
                }
                None => break,
            }
        }
        let closed = verts.first() == verts.last();
        let pts: Vec<[f64; 3]> = verts.iter().map(|&v| surf.positions[v as usize]).collect();
        let mut cum = Vec::with_capacity(pts.len());
        let mut acc = 0.0;
        cum.push(0.0);
        for w in pts.windows(2) {
            acc += dist(w[0], w[1]);
            cum.push(acc);
        }
        let seg_face = es
            .iter()
            .zip(verts.windows(2))
            .map(|(&e, w)| {
                let h = edge_h[e as usize];
                let f = h / 3;
                let face = surf.faces[f as usize];
                let slot = |x: u32| face.iter().position(|&y| y == x).unwrap_or(0) as u8;
                (f, slot(w[0]), slot(w[1]))
            })
            .collect();
        (
            Chain {
                pts,
                cum,
                seg_face,
                closed,
                verts: verts.clone(),
                start: verts[0],
                end: *verts.last().unwrap_or(&verts[0]),
                kind_crease_only: crease_only,
            },
            es,
        )
    };
    for v in 0..nv as u32 {
        if !corner[v as usize] {
            continue;
        }
        for i in off[v as usize]..off[v as usize + 1] {
            let e = adj[i as usize];
            if !used[e as usize] {
                out.push(walk(v, e, &mut used));
            }
        }
    }
    for e in 0..kind.len() as u32 {
        if kind[e as usize] != 0 && !used[e as usize] {
            let v = edges[e as usize][0];
            out.push(walk(v, e, &mut used));
        }
    }
    (out, corner)
}

impl<'a> Work<'a> {
    fn new(
        m: HalfMesh,
        feats: Features,
        bvh: &'a Bvh,
        surf: &'a TriMesh,
        sizing: Vec<f64>,
        input: &TriMesh,
    ) -> Self {
        let Features {
            e_chain: e_feat_topo,
            chains,
            corner,
        } = feats;
        let nv = m.pos.len();
        let ne = m.edge_count();
        // HalfMesh::build keeps the topology's edge numbering.
        let mut e_chain = vec![INVALID; ne];
        e_chain[..e_feat_topo.len()].copy_from_slice(&e_feat_topo);
        let mut v_chain = vec![INVALID; nv];
        let mut v_s = vec![0.0; nv];
        let mut chain_count = vec![0usize; chains.len()];
        for (k, c) in chains.iter().enumerate() {
            let n = if c.closed {
                c.verts.len() - 1
            } else {
                c.verts.len()
            };
            for i in 0..n {
                let v = c.verts[i] as usize;
                if !corner[v] {
                    v_chain[v] = k as u32;
                    v_s[v] = c.cum[i];
                    chain_count[k] += 1;
                }
            }
        }
        let mut input_face = vec![(INVALID, 0u8); input.positions.len()];
        for (f, face) in input.faces.iter().enumerate() {
            for (slot, &v) in face.iter().enumerate() {
                if input_face[v as usize].0 == INVALID {
                    input_face[v as usize] = (f as u32, slot as u8);
                }
            }
        }
        Work {
            m,
            v_chain,
            v_s,
            v_corner: corner,
            v_len: sizing.clone(),
            v_face: vec![INVALID; nv],
            e_chain,
            chains,
            chain_count,
            bvh,
            surf,
            sizing,
            input_face,
            surf_off: Vec::new(),
            surf_adj: Vec::new(),
            n_input_faces: u32::MAX,
            dev_bound: 0.0,
            dev_floor: 0.0,
            roughness: Vec::new(),
        }
    }

    #[inline]
    fn is_feature_v(&self, v: u32) -> bool {
        self.v_corner[v as usize] || self.v_chain[v as usize] != INVALID
    }

    /// Arc length of vertex `u` on chain `k`, unwrapped next to `near`.
    fn s_on(&self, u: u32, k: u32, near: f64) -> f64 {
        let c = &self.chains[k as usize];
        let s = if self.v_corner[u as usize] {
            if u == c.start && u != c.end {
                0.0
            } else if u == c.end && u != c.start {
                c.total()
            } else if near < c.total() / 2.0 {
                0.0
            } else {
                c.total()
            }
        } else {
            self.v_s[u as usize]
        };
        near + c.delta(near, s)
    }

    #[inline]
    fn edge_target(&self, a: u32, b: u32) -> f64 {
        0.5 * (self.v_len[a as usize] + self.v_len[b as usize])
    }

    fn edge_len(&self, e: u32) -> f64 {
        dist(
            self.m.pos[self.m.to(2 * e) as usize],
            self.m.pos[self.m.to(2 * e + 1) as usize],
        )
    }

    fn split_long(&mut self) {
        let mut e = 0u32;
        while (e as usize) < self.m.edge_count() {
            if self.m.e_dead[e as usize] {
                e += 1;
                continue;
            }
            let a = self.m.to(2 * e + 1);
            let b = self.m.to(2 * e);
            if self.edge_len(e) <= SPLIT_FACTOR * self.edge_target(a, b) {
                e += 1;
                continue;
            }
            let k = self.e_chain[e as usize];
            let (p, s) = if k != INVALID {
                let sa = if self.v_corner[a as usize] {
                    let sb = self.v_s[b as usize];
                    self.s_on(a, k, if self.v_corner[b as usize] { 0.0 } else { sb })
                } else {
                    self.v_s[a as usize]
                };
                let sb = self.s_on(b, k, sa);
                let s = self.chains[k as usize].wrap(0.5 * (sa + sb));
                (self.chains[k as usize].at(s).0, s)
            } else {
                (
                    scale(add(self.m.pos[a as usize], self.m.pos[b as usize]), 0.5),
                    0.0,
                )
            };
            let v = self.m.new_vertex(p);
            self.v_chain.push(if k != INVALID { k } else { INVALID });
            self.v_s.push(s);
            self.v_corner.push(false);
            self.v_len
                .push(0.5 * (self.v_len[a as usize] + self.v_len[b as usize]));
            self.v_face.push(INVALID);
            if k != INVALID {
                self.chain_count[k as usize] += 1;
            }
            let new_edges = self.m.split(e, v);
            for (i, ne) in new_edges.iter().enumerate() {
                if *ne != INVALID {
                    while self.e_chain.len() <= *ne as usize {
                        self.e_chain.push(INVALID);
                    }
                    self.e_chain[*ne as usize] = if i == 0 { k } else { INVALID };
                }
            }
            // Re-check e (now one half of the old edge).
        }
    }

    /// Whether removing `v0` by collapsing halfedge `h` (v0 → v1) is allowed: features,
    /// topology, no new long edge, no folded or degenerate face.
    fn collapse_allowed(&self, h: u32) -> bool {
        let v0 = self.m.from(h);
        let v1 = self.m.to(h);
        if self.v_corner[v0 as usize] {
            return false;
        }
        let k = self.v_chain[v0 as usize];
        if k != INVALID {
            if self.e_chain[(h >> 1) as usize] != k {
                return false;
            }
            let c = &self.chains[k as usize];
            let min_left = if c.closed && !self.v_corner[c.start as usize] {
                3
            } else if c.start == c.end {
                2
            } else {
                0
            };
            if self.chain_count[k as usize] <= min_left {
                return false;
            }
        } else if self.e_chain[(h >> 1) as usize] != INVALID {
            return false;
        }
        if !self.m.collapse_ok(h) {
            return false;
        }
        let p1 = self.m.pos[v1 as usize];
        let p0 = self.m.pos[v0 as usize];
        let mut ok = true;
        let lmin = self.v_len[v1 as usize];
        self.m.for_out(v0, |g| {
            if !ok {
                return;
            }
            let x = self.m.to(g);
            if x != v1 && dist(p1, self.m.pos[x as usize]) > SPLIT_FACTOR * self.edge_target(v1, x)
            {
                ok = false;
                return;
            }
            let f = self.m.face(g);
            if f == INVALID {
                return;
            }
            let y = self.m.to(self.m.next(g));
            if x == v1 || y == v1 {
                return;
            }
            let (px, py) = (self.m.pos[x as usize], self.m.pos[y as usize]);
            let n_old = cross(sub(px, p0), sub(py, p0));
            let n_new = cross(sub(px, p1), sub(py, p1));
            let (lo, ln) = (norm(n_old), norm(n_new));
            if ln <= DEGENERATE_AREA_REL * lmin * lmin
                || dot(n_old, n_new) < MAX_NORMAL_TURN_COS * lo * ln
            {
                ok = false;
            }
        });
        ok
    }

    fn collapse_short(&mut self) {
        for e in 0..self.m.edge_count() as u32 {
            if self.m.e_dead[e as usize] {
                continue;
            }
            let h01 = 2 * e + 1; // from to(2e) to to(2e+1)
            let h10 = 2 * e;
            let v0 = self.m.from(h01);
            let v1 = self.m.to(h01);
            if self.edge_len(e) >= COLLAPSE_FACTOR * self.edge_target(v0, v1) {
                continue;
            }
            let mut c01 = self.collapse_allowed(h01);
            let mut c10 = self.collapse_allowed(h10);
            if c01 && c10 {
                if self.m.valence(v0) < self.m.valence(v1) {
                    c10 = false;
                } else {
                    c01 = false;
                }
            }
            let h = if c01 {
                h01
            } else if c10 {
                h10
            } else {
                continue;
            };
            let removed = self.m.from(h);
            let k = self.v_chain[removed as usize];
            if k != INVALID {
                self.chain_count[k as usize] -= 1;
            }
            let merged = self.m.collapse(h);
            for (del, kept) in merged {
                if del != INVALID
                    && self.e_chain[del as usize] != INVALID
                    && self.e_chain[kept as usize] == INVALID
                {
                    self.e_chain[kept as usize] = self.e_chain[del as usize];
                }
            }
        }
    }

    fn target_valence(&self, v: u32) -> i32 {
        if self.m.is_boundary_v(v) { 4 } else { 6 }
    }

    fn flip_to_valence(&mut self) {
        for e in 0..self.m.edge_count() as u32 {
            if self.m.e_dead[e as usize]
                || self.e_chain[e as usize] != INVALID
                || !self.m.flip_ok(e)
            {
                continue;
            }
            let a = self.m.to(2 * e + 1);
            let b = self.m.to(2 * e);
            let c = self.m.to(self.m.next(2 * e));
            let d = self.m.to(self.m.next(2 * e + 1));
            let val = |v: u32| self.m.valence(v) as i32;
            let (va, vb, vc, vd) = (val(a), val(b), val(c), val(d));
            let (ta, tb, tc, td) = (
                self.target_valence(a),
                self.target_valence(b),
                self.target_valence(c),
                self.target_valence(d),
            );
            let sq = |x: i32| x * x;
            let before = sq(va - ta) + sq(vb - tb) + sq(vc - tc) + sq(vd - td);
            let after = sq(va - 1 - ta) + sq(vb - 1 - tb) + sq(vc + 1 - tc) + sq(vd + 1 - td);
            if after >= before || !self.flip_geometry_ok(a, b, c, d) {
                continue;
            }
            self.m.flip(e);
        }
    }

    /// The faces (a, d, c) and (b, c, d) replacing (a, b, c) and (b, a, d) must not be
    /// degenerate nor turn against the old ones.
    fn flip_geometry_ok(&self, a: u32, b: u32, c: u32, d: u32) -> bool {
        let p = |v: u32| self.m.pos[v as usize];
        let n = |x: u32, y: u32, z: u32| cross(sub(p(y), p(x)), sub(p(z), p(x)));
        let (o1, o2) = (n(a, b, c), n(b, a, d));
        let (n1, n2) = (n(a, d, c), n(b, c, d));
        let l = self.edge_target(a, b);
        let eps = DEGENERATE_AREA_REL * l * l;
        if norm(n1) <= eps || norm(n2) <= eps {
            return false;
        }
        let o = add(normalize(o1), normalize(o2));
        let ok = |x: [f64; 3], y: [f64; 3]| dot(x, y) >= MAX_NORMAL_TURN_COS * norm(x) * norm(y);
        ok(n1, o) && ok(n2, o) && ok(n1, n2)
    }

    /// Tangential relaxation (uniform centroid, normal component removed) and projection
    /// onto the working surface; chain vertices move along their polyline, corners stay.
    fn relax(&mut self) {
        let nv = self.m.pos.len();
        let me = &*self;
        let upd: Vec<Option<([f64; 3], f64, u32)>> = (0..nv as u32)
            .into_par_iter()
            .map(|v| me.relaxed(v))
            .collect();
        for (v, u) in upd.into_iter().enumerate() {
            if let Some((p, s, f)) = u {
                self.m.pos[v] = p;
                self.v_s[v] = s;
                if f != INVALID {
                    self.v_face[v] = f;
                }
            }
        }
        self.update_sizing();
    }

    fn relaxed(&self, v: u32) -> Option<([f64; 3], f64, u32)> {
        if self.m.v_dead[v as usize] || self.m.v_out[v as usize] == INVALID {
            return None;
        }
        if self.v_corner[v as usize] {
            return None;
        }
        let k = self.v_chain[v as usize];
        if k != INVALID {
            let s = self.v_s[v as usize];
            let mut sum = 0.0;
            let mut n = 0;
            self.m.for_out(v, |h| {
                if self.e_chain[(h >> 1) as usize] == k {
                    sum += self.s_on(self.m.to(h), k, s);
                    n += 1;
                }
            });
            if n != 2 {
                return None;
            }
            let c = &self.chains[k as usize];
            let s = c.wrap(sum / 2.0);
            return Some((c.at(s).0, s, INVALID));
        }
        let p = self.m.pos[v as usize];
        let mut c = [0.0; 3];
        let mut n = [0.0; 3];
        let mut cnt = 0.0;
        self.m.for_out(v, |h| {
            let x = self.m.pos[self.m.to(h) as usize];
            c = add(c, x);
            cnt += 1.0;
            if self.m.face(h) != INVALID {
                let y = self.m.pos[self.m.to(self.m.next(h)) as usize];
                n = add(n, cross(sub(x, p), sub(y, p)));
            }
        });
        if cnt == 0.0 {
            return None;
        }
        let c = scale(c, 1.0 / cnt);
        let nn = normalize(n);
        let d = sub(c, p);
        let q = add(p, sub(d, scale(nn, dot(nn, d))));
        let q = if q.iter().all(|x| x.is_finite()) {
            q
        } else {
            p
        };
        match self.bvh.closest_point(q) {
            Some(cp) => Some((cp.point, 0.0, cp.face.0)),
            None => Some((q, 0.0, INVALID)),
        }
    }

    fn update_sizing(&mut self) {
        if self.sizing.iter().all(|&s| s == self.sizing[0]) {
            return;
        }
        for v in 0..self.m.pos.len() {
            if self.m.v_dead[v] || self.v_corner[v] {
                continue;
            }
            let k = self.v_chain[v];
            let (face, b) = if k != INVALID {
                // A chain vertex lies on a segment of its input polyline.
                let pr = self.chains[k as usize].provenance(self.v_s[v]);
                (self.surf.faces[pr.face as usize], pr.barycentric)
            } else {
                let f = self.v_face[v];
                if f == INVALID {
                    continue;
                }
                let face = self.surf.faces[f as usize];
                let t = face.map(|i| self.surf.positions[i as usize]);
                let p = self.m.pos[v];
                (
                    face,
                    flatcut_mesh::bvh::closest_point_on_triangle(p, t[0], t[1], t[2]).1,
                )
            };
            self.v_len[v] = (0..3).map(|i| b[i] * self.sizing[face[i] as usize]).sum();
        }
    }

    /// Whether working-surface face `sf` has a corner rougher than the bound allows (see
    /// `ROUGHNESS_REL`); true when no roughness was computed.
    fn rough_face(&self, sf: u32) -> bool {
        self.roughness.is_empty()
            || self.surf.faces[sf as usize]
                .iter()
                .any(|&v| self.roughness[v as usize] > ROUGHNESS_REL * self.dev_bound)
    }

    /// Approximation-error refinement: every face whose centroid or an edge midpoint lies
    /// farther than the bound from the working surface (fill faces excluded) lowers the
    /// sizing field at the working-surface faces under it to L·√(bound/d)·margin (not below
    /// the floor); the field is then graded and the following rounds split and relax there.
    /// Returns how many faces asked for refinement.
    fn refine_by_deviation(&mut self) -> usize {
        if self.dev_bound <= 0.0 {
            return 0;
        }
        let me = &*self;
        let nif = self.n_input_faces;
        let asks: Vec<(f64, [u32; 4])> = (0..self.m.f_h.len() as u32)
            .into_par_iter()
            .filter_map(|f| {
                if me.m.f_dead[f as usize] {
                    return None;
                }
                let vs = me.m.face_vertices(f);
                let mut under = [INVALID; 4];
                for (i, &v) in vs.iter().enumerate() {
                    let sf = me.v_face[v as usize];
                    if sf != INVALID && sf >= nif {
                        return None; // in a filled hole
                    }
                    under[i] = sf;
                }
                let l = vs.iter().map(|&v| me.v_len[v as usize]).sum::<f64>() / 3.0;
                if l <= me.dev_floor * (1.0 + 1e-9) {
                    return None;
                }
                // Noise under a corner: no refinement (and no samples to pay for).
                if under[..3]
                    .iter()
                    .any(|&sf| sf != INVALID && me.rough_face(sf))
                {
                    return None;
                }
                let p = vs.map(|v| me.m.pos[v as usize]);
                let samples = [
                    scale(add(add(p[0], p[1]), p[2]), 1.0 / 3.0),
                    scale(add(p[0], p[1]), 0.5),
                    scale(add(p[1], p[2]), 0.5),
                    scale(add(p[2], p[0]), 0.5),
                ];
                let mut worst = (0.0, INVALID);
                for q in samples {
                    let cp = me.bvh.closest_point(q)?;
                    if cp.face.0 >= nif {
                        return None;
                    }
                    if cp.distance > worst.0 {
                        worst = (cp.distance, cp.face.0);
                    }
                }
                if worst.0 <= me.dev_bound {
                    return None;
                }
                // Scan noise finer than the face: refining would only add faces.
                if me.rough_face(worst.1) {
                    return None;
                }
                under[3] = worst.1;
                // The chord error grows with the square of the longest edge; splits keep
                // edges below 4/3 of the local target, so ask for 3/4 of the edge needed.
                let longest = dist(p[0], p[1]).max(dist(p[1], p[2])).max(dist(p[2], p[0]));
                let need = longest * (me.dev_bound / worst.0).sqrt() * DEVIATION_MARGIN;
                let want = (need / SPLIT_FACTOR).min(l).max(me.dev_floor);
                Some((want, under))
            })
            .collect();
        if asks.is_empty() {
            return 0;
        }
        let mut queue = std::collections::VecDeque::new();
        for (want, under) in &asks {
            for &sf in under {
                if sf == INVALID {
                    continue;
                }
                for v in self.surf.faces[sf as usize] {
                    if self.sizing[v as usize] > *want {
                        self.sizing[v as usize] = *want;
                        queue.push_back(v);
                    }
                }
            }
        }
        // Grade: L(u) ≤ L(v) + SIZING_GRADE·|uv| along every working-surface edge, spread
        // from the lowered vertices only (label-correcting shortest paths).
        while let Some(v) = queue.pop_front() {
            let (lo, hi) = (
                self.surf_off[v as usize] as usize,
                self.surf_off[v as usize + 1] as usize,
            );
            for &u in &self.surf_adj[lo..hi] {
                let pv = self.surf.positions[v as usize];
                let cand = self.sizing[v as usize]
                    + SIZING_GRADE * dist(pv, self.surf.positions[u as usize]);
                if self.sizing[u as usize] > cand {
                    self.sizing[u as usize] = cand;
                    queue.push_back(u);
                }
            }
        }
        self.update_sizing();
        asks.len()
    }

    /// Last resort against slivers the rounds left (scan debris, tangled input): a face with
    /// a corner below `SLIVER_ANGLE_DEG` loses its shortest edge by collapse (a needle) or
    /// has its longest edge flipped (a cap), when the usual checks allow it.
    fn remove_slivers(&mut self) {
        let lim = SLIVER_ANGLE_DEG.to_radians();
        for _ in 0..SLIVER_PASSES {
            let mut changed = false;
            for f in 0..self.m.f_h.len() as u32 {
                if self.m.f_dead[f as usize] {
                    continue;
                }
                let h0 = self.m.f_h[f as usize];
                let hs = [h0, self.m.next(h0), self.m.next(self.m.next(h0))];
                let p = |v: u32| self.m.pos[v as usize];
                let [a, b, c] = hs.map(|h| p(self.m.from(h)));
                let ang = flatcut_mesh::geometry::triangle_angles(a, b, c);
                let (kmin, amin) = (0..3).fold((0, f64::INFINITY), |acc, k| {
                    if ang[k] < acc.1 { (k, ang[k]) } else { acc }
                });
                if amin >= lim {
                    continue;
                }
                // Corner k sits at from(hs[k]); the opposite edge is hs[(k + 1) % 3].
                let kmax = (0..3).fold(0, |m, k| if ang[k] > ang[m] { k } else { m });
                let long = hs[(kmax + 1) % 3];
                let short = hs[(kmin + 1) % 3];
                let e = long >> 1;
                if ang[kmax] > std::f64::consts::FRAC_PI_2
                    && self.e_chain[e as usize] == INVALID
                    && self.m.flip_ok(e)
                {
                    let (x, y) = (self.m.to(2 * e + 1), self.m.to(2 * e));
                    let (c1, d1) = (
                        self.m.to(self.m.next(2 * e)),
                        self.m.to(self.m.next(2 * e + 1)),
                    );
                    if self.flip_geometry_ok(x, y, c1, d1) {
                        self.m.flip(e);
                        changed = true;
                        continue;
                    }
                }
                for h in [short, twin(short)] {
                    if self.collapse_allowed(h) {
                        let removed = self.m.from(h);
                        let k = self.v_chain[removed as usize];
                        if k != INVALID {
                            self.chain_count[k as usize] -= 1;
                        }
                        for (del, kept) in self.m.collapse(h) {
                            if del != INVALID
                                && self.e_chain[del as usize] != INVALID
                                && self.e_chain[kept as usize] == INVALID
                            {
                                self.e_chain[kept as usize] = self.e_chain[del as usize];
                            }
                        }
                        changed = true;
                        break;
                    }
                }
            }
            if !changed {
                break;
            }
        }
    }

    /// Projects every free vertex once more so the output lies on the surface exactly.
    fn final_projection(&mut self) {
        let nv = self.m.pos.len();
        let me = &*self;
        let upd: Vec<Option<([f64; 3], u32)>> = (0..nv)
            .into_par_iter()
            .map(|v| {
                if me.m.v_dead[v] || me.is_feature_v(v as u32) {
                    return None;
                }
                me.bvh
                    .closest_point(me.m.pos[v])
                    .map(|cp| (cp.point, cp.face.0))
            })
            .collect();
        for (v, u) in upd.into_iter().enumerate() {
            if let Some((p, f)) = u {
                self.m.pos[v] = p;
                self.v_face[v] = f;
            }
        }
    }

    /// Fairs vertices lying on fill faces: minimises Σ‖Δx‖² (uniform Laplacian, over the
    /// filled vertices and their neighbours) with every other vertex fixed, by
    /// Gauss–Seidel coordinate descent (the patches are small).
    fn fair_filled(&mut self, n_input_faces: u32, target: f64) {
        let nv = self.m.pos.len();
        let filled: Vec<bool> = (0..nv)
            .map(|v| {
                !self.m.v_dead[v]
                    && !self.is_feature_v(v as u32)
                    && self.v_face[v] != INVALID
                    && self.v_face[v] >= n_input_faces
            })
            .collect();
        let ids: Vec<u32> = (0..nv as u32).filter(|&v| filled[v as usize]).collect();
        if ids.is_empty() {
            return;
        }
        let mut ring: Vec<u32> = Vec::with_capacity(16);
        let mut ring_j: Vec<u32> = Vec::with_capacity(16);
        for _ in 0..FAIR_MAX_SWEEPS {
            let mut moved = 0.0f64;
            for &i in &ids {
                // E_i(x) = Σ_{k ∈ {i} ∪ N(i)} |(Lx)_k|², quadratic in x_i.
                ring.clear();
                self.m.for_out(i, |h| ring.push(self.m.to(h)));
                let mut num = [0.0; 3];
                let mut den = 0.0;
                // k = i: (Lx)_i = avg(N(i)) − x_i, coefficient of x_i is −1.
                let avg_i = scale(
                    ring.iter()
                        .fold([0.0; 3], |s, &j| add(s, self.m.pos[j as usize])),
                    1.0 / ring.len() as f64,
                );
                // k = i: L_ii = −1 and the rest of (Lx)_i is avg_i.
                num = add(num, scale(avg_i, -1.0));
                den += 1.0;
                for &j in &ring {
                    ring_j.clear();
                    self.m.for_out(j, |h| ring_j.push(self.m.to(h)));
                    let nj = ring_j.len() as f64;
                    let w = 1.0 / nj;
                    let mut r = scale(self.m.pos[j as usize], -1.0);
                    for &x in &ring_j {
                        if x != i {
                            r = add(r, scale(self.m.pos[x as usize], w));
                        }
                    }
                    num = add(num, scale(r, w));
                    den += w * w;
                }
                // Minimise Σ (L_ki x_i + r_k)²: x_i = −Σ L_ki r_k / Σ L_ki².
                let x = scale(num, -1.0 / den);
                let old = self.m.pos[i as usize];
                moved = moved.max(dist(old, x));
                if x.iter().all(|c| c.is_finite()) {
                    self.m.pos[i as usize] = x;
                }
            }
            if moved < FAIR_TOLERANCE_REL * target {
                break;
            }
        }
    }

    /// Where output vertex `v`, now at `at` (its working position unless smoothing moved
    /// it), lies on the input: chain vertices on their polyline, corners at their input
    /// vertex, others at the closest input point — of the working position for vertices of
    /// filled holes (which are not on the input either way).
    fn provenance(
        &self,
        v: u32,
        at: [f64; 3],
        n_input_faces: u32,
        input: &TriMesh,
        ibvh: &Bvh,
    ) -> Provenance {
        let k = self.v_chain[v as usize];
        if k != INVALID && !self.v_corner[v as usize] {
            return self.chains[k as usize].provenance(self.v_s[v as usize]);
        }
        let f = self.v_face[v as usize];
        let filled = f != INVALID && f >= n_input_faces && !self.v_corner[v as usize];
        let p = if filled { self.m.pos[v as usize] } else { at };
        if self.v_corner[v as usize] && (v as usize) < input.positions.len() {
            // Corners are input vertices: a face of theirs with a one-hot weight.
            let (face, slot) = self.input_face[v as usize];
            if face != INVALID {
                let mut b = [0.0; 3];
                b[slot as usize] = 1.0;
                return Provenance {
                    face,
                    barycentric: b,
                    filled: false,
                };
            }
        }
        match ibvh.closest_point(p) {
            Some(cp) => Provenance {
                face: cp.face.0,
                barycentric: cp.barycentric,
                filled,
            },
            None => Provenance {
                face: 0,
                barycentric: [1.0, 0.0, 0.0],
                filled,
            },
        }
    }
}
