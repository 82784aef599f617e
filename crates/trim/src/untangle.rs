//! Untangling cutting lines on a noisy surface, before they are embedded.
//!
//! On a scan (or a remesh that kept its noise as creases) many vertices are saddles: their
//! angle sum exceeds 2π, and polyhedral shortest paths pass *through* them rather than beside
//! them. Two failures follow, neither meant by the user:
//!
//! * **Self-loops.** A line through landmarks A → M → B whose middle landmark lies a few mm
//!   off the straight way: the geodesic A → M may pass a saddle vertex, and M → B come back
//!   through it, crossing A → M: a small loop round M. The loop is removed at the crossing
//!   point P (the line becomes … → P → …), when it is at most [`LOOP_MAX_EDGES`] local edge
//!   lengths long; a longer loop is the user's line really crossing itself, an error.
//! * **Shared stretches.** Two lines meeting at a common landmark or a T-junction may both
//!   leave it through the same saddle vertex and so share a stretch. A pattern engineer means
//!   them to share only one point, so the later line's junction slides along the earlier line
//!   to where they part (the end of the shared stretch) and its geodesic on the other side is
//!   recomputed from there; an open line's end on another line is trimmed to the point where
//!   they part. Only stretches up to [`SLIDE_MAX_EDGES`] local edge lengths slide; a longer
//!   shared stretch is a genuine overlap, an error naming both lines and the place.
//!
//! "Local edge length" is the mean edge length of the face where the event happens, so the
//! bounds follow the working resolution of the mesh.

use std::collections::HashMap;

use flatcut_mesh::{FaceId, TriMesh, vec3};

use crate::TrimError;
use crate::embed::ON_SEGMENT;
use crate::lines::{CutLine, LineContext, bary_in};
use crate::surface_point::SurfacePoint;

/// Longest loop removed from a line, in local edge lengths. A noise detour round a landmark
/// a few mm off the way passes one or two saddle vertices (measured on the scan remeshed to
/// 12 mm: 2.1 edge lengths); a loop longer than four edges is a line the user drew crossing
/// itself, which stays an error.
pub const LOOP_MAX_EDGES: f64 = 4.0;

/// Longest shared stretch along which a junction slides, in local edge lengths. Two geodesics
/// from one point that share a saddle vertex coincide up to it: within an edge or two (on the
/// scan remeshed to 8 mm: 0.8 edge lengths). Longer shared stretches are lines the user drew
/// along each other, which stay an error.
pub const SLIDE_MAX_EDGES: f64 = 3.0;

/// A point lies on a line when it is closer to the line's polyline than this, relative to the
/// local edge length: two geodesics through the same vertex or edge computed in different
/// unfoldings agree to ~1e-14 of the edge, and 1e-9 is the embedding's own merge distance
/// ([`crate::embed::MERGE_T`]).
pub const ON_LINE_RELATIVE: f64 = 1e-9;

/// At most this many junction slides per line: each removes a shared stretch; more means the
/// lines keep meeting along stretches, which is reported.
const MAX_SLIDES: usize = 8;

/// Mean edge length of face `f`.
fn face_edge(mesh: &TriMesh, f: FaceId) -> f64 {
    let [a, b, c] = mesh.faces[f.idx()].map(|v| mesh.positions[v as usize]);
    (vec3::dist(a, b) + vec3::dist(b, c) + vec3::dist(c, a)) / 3.0
}

/// Faces holding both points (the faces a straight segment between them lies in).
fn seg_faces(ctx: &LineContext, p: SurfacePoint, q: SurfacePoint) -> Vec<u32> {
    let fq = ctx.faces_of(q);
    ctx.faces_of(p)
        .into_iter()
        .filter(|f| fq.contains(f))
        .collect()
}

fn length(mesh: &TriMesh, pts: &[SurfacePoint]) -> f64 {
    pts.windows(2)
        .map(|w| vec3::dist(w[0].position(mesh), w[1].position(mesh)))
        .sum()
}

fn dedup(mesh: &TriMesh, pts: &mut Vec<SurfacePoint>) {
    let mut out: Vec<SurfacePoint> = Vec::with_capacity(pts.len());
    for &p in pts.iter() {
        if let Some(q) = out.last() {
            let tol = ON_LINE_RELATIVE * face_edge(mesh, p.face);
            if vec3::dist(q.position(mesh), p.position(mesh)) <= tol {
                continue;
            }
        }
        out.push(p);
    }
    // Keep the last point as given (an end on a boundary or a line, a loop's closure).
    if let (Some(&last), Some(o)) = (pts.last(), out.last_mut()) {
        *o = last;
    }
    *pts = out;
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Where segments `a b` and `c d` (chart coordinates) meet: parameter along `a b`, or
/// `None`. Collinear overlapping segments meet at the first point of `c d` on `a b`.
fn meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> Option<f64> {
    let (r, s) = (sub(b, a), sub(d, c));
    let (lr, ls) = (r[0].hypot(r[1]), s[0].hypot(s[1]));
    if lr == 0.0 || ls == 0.0 {
        return None;
    }
    let den = cross(r, s);
    let eps = ON_SEGMENT;
    if den.abs() <= eps * lr * ls {
        if (cross(r, sub(c, a)) / lr).abs() > eps {
            return None;
        }
        let along = |x: [f64; 2]| ((x[0] - a[0]) * r[0] + (x[1] - a[1]) * r[1]) / (lr * lr);
        return [along(c), along(d)]
            .into_iter()
            .find(|t| (-eps..=1.0 + eps).contains(t))
            .map(|t| t.clamp(0.0, 1.0));
    }
    let t = cross(sub(c, a), s) / den;
    let u = cross(sub(c, a), r) / den;
    ((-eps..=1.0 + eps).contains(&t) && (-eps..=1.0 + eps).contains(&u)).then(|| t.clamp(0.0, 1.0))
}

/// Removes the small loops of a line crossing itself (see the module docs); an error when a
/// loop is longer than [`LOOP_MAX_EDGES`].
pub(crate) fn remove_loops(
    ctx: &LineContext,
    name: &str,
    closed: bool,
    pts: &mut Vec<SurfacePoint>,
) -> Result<(), TrimError> {
    let mesh = ctx.mesh;
    dedup(mesh, pts);
    'again: loop {
        // Segments by the faces they lie in.
        let mut by_face: HashMap<u32, Vec<usize>> = HashMap::new();
        for s in 0..pts.len().saturating_sub(1) {
            for f in seg_faces(ctx, pts[s], pts[s + 1]) {
                by_face.entry(f).or_default().push(s);
            }
        }
        let mut faces: Vec<u32> = by_face.keys().copied().collect();
        faces.sort_unstable();
        // The first crossing along the line (smallest s, then smallest t).
        let mut best: Option<(usize, usize, u32, f64)> = None;
        for f in faces {
            let segs = &by_face[&f];
            let uv = |p: SurfacePoint| bary_in(mesh, p, f).map(|w| [w[1], w[2]]);
            for (i, &s) in segs.iter().enumerate() {
                for &t in &segs[i + 1..] {
                    // Neighbours share a point; so do a loop's first and last segments.
                    let closure = closed && s == 0 && t + 2 == pts.len();
                    if t <= s + 1 || closure || best.is_some_and(|b| (s, t) >= (b.0, b.1)) {
                        continue;
                    }
                    let (Some(a), Some(b), Some(c), Some(d)) =
                        (uv(pts[s]), uv(pts[s + 1]), uv(pts[t]), uv(pts[t + 1]))
                    else {
                        continue;
                    };
                    if let Some(alpha) = meet(a, b, c, d) {
                        best = Some((s, t, f, alpha));
                    }
                }
            }
        }
        // A line folding straight back on itself at a point (a spur): drop the point.
        for s in 0..pts.len().saturating_sub(2) {
            if best.is_some_and(|b| b.0 <= s) {
                break;
            }
            let (p, q, r) = (
                pts[s].position(mesh),
                pts[s + 1].position(mesh),
                pts[s + 2].position(mesh),
            );
            let (u, v) = (vec3::sub(p, q), vec3::sub(r, q));
            let (lu, lv) = (vec3::norm(u), vec3::norm(v));
            if lu > 0.0
                && lv > 0.0
                && vec3::norm(vec3::cross(u, v)) <= ON_SEGMENT * lu * lv
                && vec3::dot(u, v) > 0.0
            {
                let tol = LOOP_MAX_EDGES * face_edge(mesh, pts[s + 1].face);
                if 2.0 * lu.min(lv) > tol {
                    return Err(TrimError::SelfCrossing {
                        line: name.to_string(),
                        point_mm: q,
                    });
                }
                pts.remove(s + 1);
                dedup(mesh, pts);
                continue 'again;
            }
        }
        let Some((s, t, f, alpha)) = best else {
            return Ok(());
        };
        let (Some(wa), Some(wb)) = (bary_in(mesh, pts[s], f), bary_in(mesh, pts[s + 1], f)) else {
            return Ok(());
        };
        let mut w = [0.0; 3];
        for k in 0..3 {
            w[k] = (1.0 - alpha) * wa[k] + alpha * wb[k];
        }
        let p = SurfacePoint {
            face: FaceId(f),
            barycentric: w,
        }
        .snapped();
        let x = p.position(mesh);
        let mut lp = vec![p];
        lp.extend_from_slice(&pts[s + 1..=t]);
        lp.push(p);
        let loop_len = length(mesh, &lp);
        if loop_len > LOOP_MAX_EDGES * face_edge(mesh, FaceId(f)) {
            return Err(TrimError::SelfCrossing {
                line: name.to_string(),
                point_mm: x,
            });
        }
        pts.splice(s + 1..=t, [p]);
        dedup(mesh, pts);
    }
}

/// A segment of a finished line: line index and the two 3D end points.
type IndexedSeg = (usize, [f64; 3], [f64; 3]);

/// Segments of finished lines by the faces they lie in.
pub(crate) struct SegIndex {
    by_face: HashMap<u32, Vec<IndexedSeg>>,
}

impl SegIndex {
    pub fn new() -> Self {
        Self {
            by_face: HashMap::new(),
        }
    }

    /// Adds line `li`'s segments.
    pub fn add(&mut self, ctx: &LineContext, li: usize, line: &CutLine) {
        for w in line.points.windows(2) {
            let (a, b) = (w[0].position(ctx.mesh), w[1].position(ctx.mesh));
            for f in seg_faces(ctx, w[0], w[1]) {
                self.by_face.entry(f).or_default().push((li, a, b));
            }
        }
    }

    /// The lines whose polyline passes within the on-line tolerance of `p`.
    fn lines_at(&self, ctx: &LineContext, p: SurfacePoint) -> Vec<usize> {
        let x = p.position(ctx.mesh);
        let tol = ON_LINE_RELATIVE * face_edge(ctx.mesh, p.face);
        let mut out = Vec::new();
        for f in ctx.faces_of(p) {
            for &(li, a, b) in self.by_face.get(&f).into_iter().flatten() {
                if !out.contains(&li) && vec3::point_segment_distance(x, a, b) <= tol {
                    out.push(li);
                }
            }
        }
        out
    }
}

/// Does the segment `p q` run along the mesh boundary? There it cuts nothing, so lines may
/// share it (on a scan, two lines often hug one hole).
fn on_boundary(ctx: &LineContext, p: SurfacePoint, q: SurfacePoint) -> bool {
    let faces = seg_faces(ctx, p, q);
    let [f] = faces[..] else { return false };
    let (Some(wp), Some(wq)) = (bary_in(ctx.mesh, p, f), bary_in(ctx.mesh, q, f)) else {
        return false;
    };
    (0..3).any(|k| {
        let opposite = (k + 2) % 3;
        ctx.topo().twin(3 * f + k as u32).is_none() && wp[opposite] == 0.0 && wq[opposite] == 0.0
    })
}

/// The first run of segments `k..m` (points `k..=m`) of `pts` lying on one other line:
/// (k, m, that line).
fn shared_run(
    ctx: &LineContext,
    index: &SegIndex,
    pts: &[SurfacePoint],
) -> Option<(usize, usize, usize)> {
    let mesh = ctx.mesh;
    let on: Vec<Vec<usize>> = pts.iter().map(|&p| index.lines_at(ctx, p)).collect();
    let seg_on = |s: usize, li: usize| -> bool {
        if !(on[s].contains(&li) && on[s + 1].contains(&li)) || on_boundary(ctx, pts[s], pts[s + 1])
        {
            return false;
        }
        // The midpoint too: two lines crossing twice in a row are not along each other.
        let Some(f) = seg_faces(ctx, pts[s], pts[s + 1]).first().copied() else {
            return false;
        };
        let (Some(wa), Some(wb)) = (bary_in(mesh, pts[s], f), bary_in(mesh, pts[s + 1], f)) else {
            return false;
        };
        let mid = SurfacePoint {
            face: FaceId(f),
            barycentric: [0, 1, 2].map(|k| 0.5 * (wa[k] + wb[k])),
        };
        index.lines_at(ctx, mid).contains(&li)
    };
    for (s, on_s) in on.iter().enumerate().take(pts.len().saturating_sub(1)) {
        for &li in on_s {
            if seg_on(s, li) {
                let mut m = s + 1;
                while m + 1 < pts.len() && seg_on(m, li) {
                    m += 1;
                }
                return Some((s, m, li));
            }
        }
    }
    None
}

/// Makes line `x` (landmark indices `marks` into its points) share no stretch with the lines
/// in `index` (see the module docs). `names` names the lines of the index.
pub(crate) fn separate(
    ctx: &LineContext,
    index: &SegIndex,
    names: &[String],
    x: &mut CutLine,
    marks: &mut Vec<usize>,
) -> Result<(), TrimError> {
    let mesh = ctx.mesh;
    for _ in 0..MAX_SLIDES {
        let Some((k, m, li)) = shared_run(ctx, index, &x.points) else {
            return Ok(());
        };
        let pts = &x.points;
        let last = pts.len() - 1;
        let stretch = length(mesh, &pts[k..=m]);
        let overlap = || TrimError::OverlappingLines {
            a: x.name.clone(),
            b: names.get(li).cloned().unwrap_or_default(),
            point_mm: pts[k].position(mesh),
        };
        if stretch > SLIDE_MAX_EDGES * face_edge(mesh, pts[k].face) {
            return Err(overlap());
        }
        let mut new: Vec<SurfacePoint>;
        if !x.closed && k == 0 && m < last {
            // An end resting on the other line: it ends where they part.
            new = pts[m..].to_vec();
        } else if !x.closed && m == last && k > 0 {
            new = pts[..=k].to_vec();
        } else {
            // Slide the junction to where they part, on whichever side has a landmark to
            // recompute from.
            let next = marks.iter().copied().find(|&i| i > m);
            let prev = marks.iter().rev().copied().find(|&i| i < k);
            let mut options: Vec<Vec<SurfacePoint>> = Vec::new();
            if let Some(b) = next
                && let Some(g) = ctx.solver.path(pts[k], pts[b])
            {
                let mut v = pts[..=k].to_vec();
                v.extend_from_slice(&g.points[1..]);
                v.extend_from_slice(&pts[b + 1..]);
                options.push(v);
            }
            if let Some(a) = prev
                && let Some(g) = ctx.solver.path(pts[a], pts[m])
            {
                let mut v = pts[..a].to_vec();
                v.extend_from_slice(&g.points);
                v.extend_from_slice(&pts[m + 1..]);
                options.push(v);
            }
            // The first option that no longer shares this stretch (compared by place: the
            // options renumber the points).
            let (xk, xm) = (pts[k].position(mesh), pts[m].position(mesh));
            let Some(v) = options.into_iter().find(|v| {
                shared_run(ctx, index, v).is_none_or(|(k2, m2, l2)| {
                    l2 != li || v[k2].position(mesh) != xk || v[m2].position(mesh) != xm
                })
            }) else {
                return Err(overlap());
            };
            new = v;
        }
        if x.closed
            && let Some(&first) = new.first()
            && let Some(l) = new.last_mut()
        {
            *l = first;
        }
        remove_loops(ctx, &x.name, x.closed, &mut new)?;
        if new.len() < 2 {
            return Err(overlap());
        }
        // Landmarks: those still present by position, and both ends of the stretch (one is
        // the new junction, a fixed point of the line like a landmark).
        let mut keep: Vec<[f64; 3]> = marks.iter().map(|&i| x.points[i].position(mesh)).collect();
        keep.extend([pts[k].position(mesh), pts[m].position(mesh)]);
        *marks = new
            .iter()
            .enumerate()
            .filter(|(i, p)| *i == 0 || *i == new.len() - 1 || keep.contains(&p.position(mesh)))
            .map(|(i, _)| i)
            .collect();
        x.length = length(mesh, &new);
        x.points = new;
    }
    match shared_run(ctx, index, &x.points) {
        None => Ok(()),
        Some((k, _, li)) => Err(TrimError::OverlappingLines {
            a: x.name.clone(),
            b: names.get(li).cloned().unwrap_or_default(),
            point_mm: x.points[k].position(mesh),
        }),
    }
}
