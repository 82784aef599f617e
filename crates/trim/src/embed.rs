//! Exact embedding of cutting lines into the mesh.
//!
//! Every line point becomes a mesh vertex at its exact place: a vertex stays a vertex, a
//! point on an edge splits the edge (shared by both faces, so the mesh stays conforming), a
//! point inside a face is inserted there. Where two lines cross inside a face the crossing
//! point is computed and inserted. Each face that holds any new point is re-triangulated
//! on its own by a constrained Delaunay triangulation (spade) of its points with the line
//! pieces as constraints, in the face's barycentric chart `(w_b, w_c)`: the chart is affine,
//! so straight segments stay straight, and its three edges are the lines `v = 0`, `u = 0`,
//! `u + v = 1`, on which edge points are placed exactly (see [`edge_uv`]) — the triangulation
//! never sees an edge point off its edge, so no sliver closes the hull.
//!
//! Snapping (to avoid slivers) happened earlier, on the line points themselves
//! ([`crate::surface_point::SNAP_RELATIVE`]); here points closer than [`MERGE_T`] along one
//! edge are one vertex, and nothing else moves: the embedded line is the polyline.

use std::collections::HashMap;

use flatcut_mesh::{FaceId, TriMesh};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::TrimError;
use crate::lines::{CutLine, LineContext, bary_in};
use crate::surface_point::{Location, SurfacePoint, edge_point};

/// Two points on one edge whose parameters differ by less than this (a fraction of the edge)
/// are the same vertex: two lines crossing at an edge. 1e-9 of an edge is far below any
/// meaningful distance and far above rounding, so both faces of the edge agree on the order.
pub const MERGE_T: f64 = 1e-9;

/// A point is on a segment (or two segments are collinear) when its distance from the
/// segment's line in the barycentric chart is below this (the chart's unit is the face size).
pub const ON_SEGMENT: f64 = 1e-9;

/// The mesh with the lines embedded.
#[derive(Clone, Debug)]
pub struct Embedded {
    /// The source's vertices (same indices) followed by the new ones; faces re-triangulated
    /// where lines pass, copied elsewhere.
    pub mesh: TriMesh,
    /// For each vertex, where it lies on the source surface.
    pub vertex_source: Vec<SurfacePoint>,
    /// For each face, the source face it lies in.
    pub face_source: Vec<u32>,
    /// For each line, its vertices in order (a closed line repeats its first at the end).
    pub line_vertices: Vec<Vec<u32>>,
}

/// A line segment along a mesh edge: line, segment, edge `(a, b)`, parameters of its ends.
type EdgeSeg = (usize, usize, (u32, u32), f64, f64);
/// A stretch of an edge used by a line: line, lowest and highest parameter.
type EdgeUse = (usize, f64, f64);

struct Chord {
    line: usize,
    seg: usize,
    p: u32,
    q: u32,
}

#[derive(Default)]
struct Registry {
    positions: Vec<[f64; 3]>,
    source: Vec<SurfacePoint>,
    edge_pts: HashMap<(u32, u32), Vec<(f64, u32)>>,
    face_pts: HashMap<u32, Vec<([f64; 3], u32)>>,
}

impl Registry {
    fn push(&mut self, pos: [f64; 3], sp: SurfacePoint) -> u32 {
        self.positions.push(pos);
        self.source.push(sp);
        (self.positions.len() - 1) as u32
    }

    fn add(&mut self, mesh: &TriMesh, p: SurfacePoint) -> u32 {
        match p.location(mesh) {
            Location::Vertex(v) => v,
            Location::Edge { a, b, t } => {
                if let Some(&(_, id)) = self
                    .edge_pts
                    .get(&(a, b))
                    .and_then(|v| v.iter().find(|(t2, _)| (t - t2).abs() <= MERGE_T))
                {
                    return id;
                }
                let id = self.push(edge_point(mesh, a, b, t), p);
                self.edge_pts.entry((a, b)).or_default().push((t, id));
                id
            }
            Location::Face(f) => {
                if let Some(&(_, id)) = self
                    .face_pts
                    .get(&f)
                    .and_then(|v| v.iter().find(|(w, _)| *w == p.barycentric))
                {
                    return id;
                }
                let id = self.push(p.position(mesh), p);
                self.face_pts
                    .entry(f)
                    .or_default()
                    .push((p.barycentric, id));
                id
            }
        }
    }
}

/// The point at parameter `tau` from corner `k` to corner `k + 1` of a face, in the chart
/// where corners are (0,0), (1,0), (0,1); exactly on the chart's edge line.
pub fn edge_uv(k: usize, tau: f64) -> [f64; 2] {
    match k {
        0 => [tau, 0.0],
        1 => {
            // u + v must be exactly 1: the larger of the two is 1 − (smaller), exact by
            // Sterbenz's lemma.
            if tau >= 0.5 {
                [1.0 - tau, tau]
            } else {
                let u = 1.0 - tau;
                [u, 1.0 - u]
            }
        }
        _ => [0.0, 1.0 - tau],
    }
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Embeds `lines` (from [`crate::cut_lines`] on the same mesh) exactly.
pub fn embed(mesh: &TriMesh, lines: &[CutLine]) -> Result<Embedded, TrimError> {
    let ctx = LineContext::new(mesh, 0)?;
    embed_with(&ctx, lines)
}

pub(crate) fn embed_with(ctx: &LineContext, lines: &[CutLine]) -> Result<Embedded, TrimError> {
    let mesh = ctx.mesh;
    let topo = ctx.topo();
    let mut reg = Registry {
        positions: mesh.positions.clone(),
        source: (0..mesh.positions.len() as u32)
            .map(|v| {
                let f = topo
                    .outgoing(flatcut_mesh::VertexId(v))
                    .first()
                    .map_or(0, |h| h / 3);
                SurfacePoint::at_vertex(mesh, f, v).unwrap_or(SurfacePoint {
                    face: FaceId(0),
                    barycentric: [1.0, 0.0, 0.0],
                })
            })
            .collect(),
        ..Default::default()
    };
    let ids: Vec<Vec<u32>> = lines
        .iter()
        .map(|l| l.points.iter().map(|&p| reg.add(mesh, p)).collect())
        .collect();

    // Segments: along an edge, or a chord through a face.
    let mut seg_chain: Vec<Vec<Vec<u32>>> = lines
        .iter()
        .map(|l| vec![Vec::new(); l.points.len().saturating_sub(1)])
        .collect();
    let mut edge_segs: Vec<EdgeSeg> = Vec::new();
    let mut chords: HashMap<u32, Vec<Chord>> = HashMap::new();
    for (li, l) in lines.iter().enumerate() {
        for s in 0..l.points.len() - 1 {
            let (p, q) = (l.points[s], l.points[s + 1]);
            let (pi, qi) = (ids[li][s], ids[li][s + 1]);
            if pi == qi {
                seg_chain[li][s] = vec![pi];
                continue;
            }
            if let Some((e, t0, t1)) = on_common_edge(ctx, p, q) {
                edge_segs.push((li, s, e, t0, t1));
                continue;
            }
            let Some(f) = ctx.common_face(p, q) else {
                return Err(TrimError::Embedding {
                    line: l.name.clone(),
                    face: p.face.0,
                    reason: format!("points {s} and {} share no face", s + 1),
                });
            };
            chords.entry(f).or_default().push(Chord {
                line: li,
                seg: s,
                p: pi,
                q: qi,
            });
        }
    }

    // Crossings inside faces, split chords; new interior points go into the registry.
    let mut face_order: Vec<u32> = chords.keys().copied().collect();
    face_order.sort_unstable();
    let mut constraints: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    for &f in &face_order {
        let fc = &chords[&f];
        let uv_of = |reg: &Registry, id: u32| -> Option<[f64; 2]> {
            let w = bary_in(mesh, reg.source[id as usize], f)?;
            Some([w[1], w[2]])
        };
        let mut splits: Vec<Vec<(f64, u32)>> = vec![Vec::new(); fc.len()];
        let mut ends = Vec::with_capacity(fc.len());
        for c in fc {
            let (Some(a), Some(b)) = (uv_of(&reg, c.p), uv_of(&reg, c.q)) else {
                return Err(TrimError::Embedding {
                    line: lines[c.line].name.clone(),
                    face: f,
                    reason: "a segment end is not on the face".into(),
                });
            };
            ends.push((a, b));
        }
        // Interior points lying on a chord (T-junctions, another line's corner).
        let interior: Vec<u32> = reg
            .face_pts
            .get(&f)
            .map_or(Vec::new(), |v| v.iter().map(|x| x.1).collect());
        for (ci, c) in fc.iter().enumerate() {
            let (a, b) = ends[ci];
            let d = sub(b, a);
            let len = d[0].hypot(d[1]);
            for &x in &interior {
                if x == c.p || x == c.q {
                    continue;
                }
                let Some(px) = uv_of(&reg, x) else { continue };
                let s = ((px[0] - a[0]) * d[0] + (px[1] - a[1]) * d[1]) / (len * len);
                if s > 0.0 && s < 1.0 && (cross(d, sub(px, a)) / len).abs() < ON_SEGMENT {
                    splits[ci].push((s, x));
                }
            }
        }
        // Chord against chord.
        for i in 0..fc.len() {
            for j in i + 1..fc.len() {
                let (ci, cj) = (&fc[i], &fc[j]);
                let (a, b) = ends[i];
                let (c, d) = ends[j];
                let (r, s) = (sub(b, a), sub(d, c));
                let den = cross(r, s);
                let (lr, ls) = (r[0].hypot(r[1]), s[0].hypot(s[1]));
                let where_mm = |reg: &Registry| reg.positions[ci.p as usize];
                let shared = [ci.p, ci.q].iter().any(|x| *x == cj.p || *x == cj.q);
                if den.abs() <= ON_SEGMENT * lr * ls {
                    // Parallel: overlapping if collinear and the parameter ranges overlap.
                    let off = (cross(r, sub(c, a)) / lr).abs();
                    if off < ON_SEGMENT {
                        let t0 = ((c[0] - a[0]) * r[0] + (c[1] - a[1]) * r[1]) / (lr * lr);
                        let t1 = ((d[0] - a[0]) * r[0] + (d[1] - a[1]) * r[1]) / (lr * lr);
                        let (lo, hi) = (t0.min(t1), t0.max(t1));
                        if hi.min(1.0) - lo.max(0.0) > ON_SEGMENT {
                            return Err(overlap(lines, ci.line, cj.line, where_mm(&reg)));
                        }
                    }
                    continue;
                }
                let t = cross(sub(c, a), s) / den;
                let u = cross(sub(c, a), r) / den;
                let eps = ON_SEGMENT;
                if t <= eps || t >= 1.0 - eps || u <= eps || u >= 1.0 - eps {
                    // Touching at an end: shared end points need nothing; an end on the other
                    // chord's interior was split above.
                    continue;
                }
                if shared {
                    continue;
                }
                if ci.line == cj.line {
                    return Err(TrimError::SelfCrossing {
                        line: lines[ci.line].name.clone(),
                        point_mm: where_mm(&reg),
                    });
                }
                let uv = [a[0] + t * r[0], a[1] + t * r[1]];
                let w = [1.0 - uv[0] - uv[1], uv[0], uv[1]];
                if !(uv[0] > 0.0 && uv[1] > 0.0 && w[0] > 0.0) {
                    return Err(TrimError::Embedding {
                        line: lines[ci.line].name.clone(),
                        face: f,
                        reason: format!(
                            "it crosses line {:?} on the face's edge",
                            lines[cj.line].name
                        ),
                    });
                }
                let sp = SurfacePoint {
                    face: FaceId(f),
                    barycentric: w,
                };
                let id = reg.push(sp.position(mesh), sp);
                reg.face_pts.entry(f).or_default().push((w, id));
                splits[i].push((t, id));
                splits[j].push((u, id));
            }
        }
        let cons = constraints.entry(f).or_default();
        for (ci, c) in fc.iter().enumerate() {
            let mut sp = std::mem::take(&mut splits[ci]);
            sp.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut chain = vec![c.p];
            chain.extend(sp.iter().map(|x| x.1));
            chain.push(c.q);
            chain.dedup();
            for w in chain.windows(2) {
                cons.push((w[0], w[1]));
            }
            seg_chain[c.line][c.seg] = chain;
        }
    }

    // Segments along edges: every point on the edge between the ends, in order.
    let mut edge_use: HashMap<(u32, u32), Vec<EdgeUse>> = HashMap::new();
    for &(li, s, (a, b), t0, t1) in &edge_segs {
        let (lo, hi) = (t0.min(t1), t0.max(t1));
        // Along the mesh boundary a line cuts nothing, so lines may share such a stretch
        // (on a scan, lines often hug the same hole).
        let on_boundary = topo
            .vertex_faces(flatcut_mesh::VertexId(a))
            .filter(|f| mesh.faces[f.idx()].contains(&b))
            .count()
            == 1;
        let uses = edge_use.entry((a, b)).or_default();
        for &(lj, lo2, hi2) in uses.iter().filter(|_| !on_boundary) {
            if hi.min(hi2) - lo.max(lo2) > MERGE_T {
                let at = lines[li].points[s].position(mesh);
                return Err(if lj == li {
                    TrimError::SelfCrossing {
                        line: lines[li].name.clone(),
                        point_mm: at,
                    }
                } else {
                    overlap(lines, li, lj, at)
                });
            }
        }
        uses.push((li, lo, hi));
        let mut pts: Vec<(f64, u32)> = vec![(0.0, a), (1.0, b)];
        pts.extend(reg.edge_pts.get(&(a, b)).into_iter().flatten().copied());
        pts.retain(|x| x.0 >= lo - MERGE_T && x.0 <= hi + MERGE_T);
        pts.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut chain: Vec<u32> = pts.iter().map(|x| x.1).collect();
        if t0 > t1 {
            chain.reverse();
        }
        seg_chain[li][s] = chain;
    }

    // Faces to re-triangulate: with chords, with points on an edge, with interior points.
    let mut touched = vec![false; mesh.faces.len()];
    for &f in chords.keys().chain(reg.face_pts.keys()) {
        touched[f as usize] = true;
    }
    for &(a, b) in reg.edge_pts.keys() {
        for f in topo.vertex_faces(flatcut_mesh::VertexId(a)) {
            if mesh.faces[f.idx()].contains(&b) {
                touched[f.idx()] = true;
            }
        }
    }
    let mut faces = Vec::with_capacity(mesh.faces.len() + 4 * face_order.len());
    let mut face_source = Vec::with_capacity(faces.capacity());
    for (f, face) in mesh.faces.iter().enumerate() {
        if !touched[f] {
            faces.push(*face);
            face_source.push(f as u32);
            continue;
        }
        let f32_ = f as u32;
        let cons = constraints.get(&f32_).map_or(&[][..], |v| v.as_slice());
        let tris = triangulate_face(mesh, &reg, f32_, cons).map_err(|reason| {
            let line = chords
                .get(&f32_)
                .and_then(|c| c.first())
                .map_or(String::new(), |c| lines[c.line].name.clone());
            TrimError::Embedding {
                line,
                face: f32_,
                reason,
            }
        })?;
        for t in tris {
            faces.push(t);
            face_source.push(f32_);
        }
    }

    // Line chains; a line may not visit a vertex twice (a closed line's closure aside).
    let mut line_vertices = Vec::with_capacity(lines.len());
    for (li, l) in lines.iter().enumerate() {
        let mut chain: Vec<u32> = Vec::new();
        for sc in &seg_chain[li] {
            for &v in sc {
                if chain.last() != Some(&v) {
                    chain.push(v);
                }
            }
        }
        let body = if l.closed && chain.len() > 1 {
            &chain[..chain.len() - 1]
        } else {
            &chain[..]
        };
        let mut seen = std::collections::HashSet::new();
        for &v in body {
            if !seen.insert(v) {
                return Err(TrimError::SelfCrossing {
                    line: l.name.clone(),
                    point_mm: reg.positions[v as usize],
                });
            }
        }
        line_vertices.push(chain);
    }

    Ok(Embedded {
        mesh: TriMesh {
            positions: reg.positions,
            faces,
            ..Default::default()
        },
        vertex_source: reg.source,
        face_source,
        line_vertices,
    })
}

fn overlap(lines: &[CutLine], a: usize, b: usize, at: [f64; 3]) -> TrimError {
    if a == b {
        TrimError::SelfCrossing {
            line: lines[a].name.clone(),
            point_mm: at,
        }
    } else {
        TrimError::OverlappingLines {
            a: lines[a].name.clone(),
            b: lines[b].name.clone(),
            point_mm: at,
        }
    }
}

/// If `p` and `q` lie on one edge: the edge `(a, b)`, `a < b`, and their parameters.
fn on_common_edge(
    ctx: &LineContext,
    p: SurfacePoint,
    q: SurfacePoint,
) -> Option<((u32, u32), f64, f64)> {
    let mesh = ctx.mesh;
    let param = |x: SurfacePoint, a: u32, b: u32| -> Option<f64> {
        match x.location(mesh) {
            Location::Vertex(v) if v == a => Some(0.0),
            Location::Vertex(v) if v == b => Some(1.0),
            Location::Edge { a: a2, b: b2, t } if a2 == a && b2 == b => Some(t),
            _ => None,
        }
    };
    let cands: Vec<(u32, u32)> = match (p.location(mesh), q.location(mesh)) {
        (Location::Edge { a, b, .. }, _) | (_, Location::Edge { a, b, .. }) => vec![(a, b)],
        (Location::Vertex(a), Location::Vertex(b)) => vec![(a.min(b), a.max(b))],
        _ => return None,
    };
    for (a, b) in cands {
        if let (Some(t0), Some(t1)) = (param(p, a, b), param(q, a, b)) {
            // The edge must exist.
            if ctx.common_face(p, q).is_some() {
                return Some(((a, b), t0, t1));
            }
        }
    }
    None
}

/// Constrained Delaunay triangulation of one source face's points in its barycentric chart.
fn triangulate_face(
    mesh: &TriMesh,
    reg: &Registry,
    f: u32,
    cons: &[(u32, u32)],
) -> Result<Vec<[u32; 3]>, String> {
    let face = mesh.faces[f as usize];
    let mut pts: Vec<(u32, [f64; 2])> = vec![
        (face[0], [0.0, 0.0]),
        (face[1], [1.0, 0.0]),
        (face[2], [0.0, 1.0]),
    ];
    for k in 0..3 {
        let (va, vb) = (face[k], face[(k + 1) % 3]);
        let key = (va.min(vb), va.max(vb));
        for &(t, id) in reg.edge_pts.get(&key).into_iter().flatten() {
            let tau = if va == key.0 { t } else { 1.0 - t };
            pts.push((id, edge_uv(k, tau)));
        }
    }
    for &(w, id) in reg.face_pts.get(&f).into_iter().flatten() {
        pts.push((id, [w[1], w[2]]));
    }
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut of_handle: Vec<u32> = Vec::new();
    let mut handle_of: HashMap<u32, spade::handles::FixedVertexHandle> = HashMap::new();
    for &(id, uv) in &pts {
        let h = cdt
            .insert(Point2::new(uv[0], uv[1]))
            .map_err(|e| format!("cannot insert a point: {e:?}"))?;
        if h.index() < of_handle.len() {
            if of_handle[h.index()] != id {
                return Err("two cut points fall on one place".into());
            }
        } else {
            of_handle.push(id);
        }
        handle_of.insert(id, h);
    }
    for &(a, b) in cons {
        let (Some(&ha), Some(&hb)) = (handle_of.get(&a), handle_of.get(&b)) else {
            return Err("a line piece ends off the face".into());
        };
        if ha == hb {
            continue;
        }
        if cdt.try_add_constraint(ha, hb).is_empty() {
            return Err("two line pieces cross where no crossing was found".into());
        }
    }
    let mut tris = Vec::with_capacity(cdt.num_inner_faces());
    for t in cdt.inner_faces() {
        let [a, b, c] = t.vertices().map(|v| of_handle[v.fix().index()]);
        tris.push([a, b, c]);
    }
    // Every constraint must be an edge of the result (no point was on it unsplit).
    for &(a, b) in cons {
        let found = tris.iter().any(|t| t.contains(&a) && t.contains(&b));
        if !found && a != b {
            return Err("a line piece passes through a point it was not split at".into());
        }
    }
    Ok(tris)
}
