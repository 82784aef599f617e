//! Cutting lines on the surface: polylines of surface points whose segments are shortest
//! paths (geodesics) between the user's points.
//!
//! * `points`: each point snaps to the closest surface point; consecutive points are joined
//!   by the geodesic between them (not by a plane slice: a geodesic is what a pattern maker's
//!   tape measure follows, and it needs no choice of plane).
//! * `vertices`: consecutive vertices sharing an edge are joined along it, others by the
//!   geodesic.
//! * Closed lines join the last point to the first.
//! * An open line's two ends must lie on the mesh boundary or on another line: an end within
//!   `end_snap_mm` is moved exactly onto the nearest boundary edge or line segment (a
//!   T-junction), and the line is recomputed from there. Lines that end on other lines are
//!   resolved after those lines, in dependency order.

use flatcut_mesh::{FaceId, Topology, TriMesh, VertexId, bvh::Bvh, vec3};

use crate::cuts::Cuts;
use crate::surface_point::{
    Location, SNAP_RELATIVE, SurfacePoint, SurfacePointOptions, surface_point,
};
use crate::untangle::SegIndex;
use crate::{GeodesicSolver, TrimError};

/// One cutting line on the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct CutLine {
    /// The line's name.
    pub name: String,
    /// A loop? Then `points` ends with its first point again.
    pub closed: bool,
    /// The polyline: consecutive points lie on a common face, so each segment is straight on
    /// the surface.
    pub points: Vec<SurfacePoint>,
    /// Length on the surface, mesh units.
    pub length: f64,
}

/// Everything [`cut_lines`] needs about the mesh, built once.
pub(crate) struct LineContext<'a> {
    pub mesh: &'a TriMesh,
    pub solver: GeodesicSolver<'a>,
    pub bvh: Bvh,
    /// Boundary halfedges (no twin).
    boundary: Vec<u32>,
}

impl<'a> LineContext<'a> {
    pub fn new(mesh: &'a TriMesh, max_strip_updates: usize) -> Result<Self, TrimError> {
        let solver = GeodesicSolver::new(mesh, &crate::GeodesicOptions { max_strip_updates })?;
        let topo = solver.topology();
        let boundary = (0..3 * mesh.faces.len() as u32)
            .filter(|&h| topo.twin(h).is_none())
            .collect();
        Ok(Self {
            mesh,
            bvh: Bvh::build(mesh),
            solver,
            boundary,
        })
    }

    pub fn topo(&self) -> &Topology {
        self.solver.topology()
    }

    /// Faces whose closure holds `p`.
    pub fn faces_of(&self, p: SurfacePoint) -> Vec<u32> {
        match p.location(self.mesh) {
            Location::Vertex(v) => self.topo().vertex_faces(VertexId(v)).map(|f| f.0).collect(),
            Location::Edge { a, b, .. } => self
                .topo()
                .vertex_faces(VertexId(a))
                .map(|f| f.0)
                .filter(|&f| self.mesh.faces[f as usize].contains(&b))
                .collect(),
            Location::Face(f) => vec![f],
        }
    }

    /// A face holding both points, if any.
    pub fn common_face(&self, p: SurfacePoint, q: SurfacePoint) -> Option<u32> {
        let fq = self.faces_of(q);
        self.faces_of(p).into_iter().find(|f| fq.contains(f))
    }

    /// Closest point of the mesh boundary to `x`: (distance, surface point).
    fn closest_on_boundary(&self, x: [f64; 3]) -> Option<(f64, SurfacePoint)> {
        closest_on_halfedges(self.mesh, self.boundary.iter().copied(), x)
    }

    /// Closest point of a line's polyline to `x`: (distance, surface point on the line).
    fn closest_on_line(&self, line: &CutLine, x: [f64; 3]) -> Option<(f64, SurfacePoint)> {
        let mut best: Option<(f64, SurfacePoint)> = None;
        for w in line.points.windows(2) {
            let (p, q) = (w[0], w[1]);
            let (pa, pb) = (p.position(self.mesh), q.position(self.mesh));
            let s = segment_param(x, pa, pb);
            let d = vec3::dist(x, vec3::add(pa, vec3::scale(vec3::sub(pb, pa), s)));
            if best.is_some_and(|(bd, _)| d >= bd) {
                continue;
            }
            let sp = if s <= SNAP_RELATIVE {
                p
            } else if s >= 1.0 - SNAP_RELATIVE {
                q
            } else {
                let Some(f) = self.common_face(p, q) else {
                    continue;
                };
                let (Some(wp), Some(wq)) = (bary_in(self.mesh, p, f), bary_in(self.mesh, q, f))
                else {
                    continue;
                };
                let mut w = [0.0; 3];
                for k in 0..3 {
                    w[k] = (1.0 - s) * wp[k] + s * wq[k];
                }
                // Weights zero on both ends stay exactly zero: a point on an edge-aligned
                // segment stays on the edge.
                SurfacePoint {
                    face: FaceId(f),
                    barycentric: w,
                }
            };
            best = Some((d, sp));
        }
        best
    }
}

/// The weights of surface point `p` in face `f`, if `f`'s closure holds it.
pub fn bary_in(mesh: &TriMesh, p: SurfacePoint, f: u32) -> Option<[f64; 3]> {
    if p.face.0 == f {
        return Some(p.barycentric);
    }
    let face = mesh.faces[f as usize];
    let idx = |v: u32| face.iter().position(|&x| x == v);
    let mut w = [0.0; 3];
    match p.location(mesh) {
        Location::Vertex(v) => w[idx(v)?] = 1.0,
        Location::Edge { a, b, t } => {
            w[idx(a)?] = 1.0 - t;
            w[idx(b)?] = t;
        }
        Location::Face(_) => return None,
    }
    Some(w)
}

/// Parameter in [0, 1] of the point of segment `a b` closest to `x`.
/// Closest point to `x` on the edges `halfedges` (halfedge `3·f + k` runs from corner `k` to
/// `k + 1` of face `f`), e.g. a mesh's boundary: (distance, surface point, snapped to a vertex
/// when at one). `None` when there is no halfedge. Shared by cut-line end snapping and darts.
pub fn closest_on_halfedges(
    mesh: &TriMesh,
    halfedges: impl IntoIterator<Item = u32>,
    x: [f64; 3],
) -> Option<(f64, SurfacePoint)> {
    let mut best: Option<(f64, SurfacePoint)> = None;
    for h in halfedges {
        let f = h / 3;
        let k = (h % 3) as usize;
        let face = mesh.faces[f as usize];
        let (a, b) = (
            mesh.positions[face[k] as usize],
            mesh.positions[face[(k + 1) % 3] as usize],
        );
        let s = segment_param(x, a, b);
        let d = vec3::dist(x, vec3::add(a, vec3::scale(vec3::sub(b, a), s)));
        if best.is_none_or(|(bd, _)| d < bd) {
            let mut w = [0.0; 3];
            w[k] = 1.0 - s;
            w[(k + 1) % 3] = s;
            let sp = SurfacePoint {
                face: FaceId(f),
                barycentric: w,
            }
            .snapped();
            best = Some((d, sp));
        }
    }
    best
}

fn segment_param(x: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = vec3::sub(b, a);
    let l = vec3::norm2(d);
    if l > 0.0 {
        (vec3::dot(vec3::sub(x, a), d) / l).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The cutting lines of `cuts` on `mesh` (mesh and points in the same units, mm).
pub fn cut_lines(mesh: &TriMesh, cuts: &Cuts) -> Result<Vec<CutLine>, TrimError> {
    let ctx = LineContext::new(mesh, cuts.options.max_strip_updates)?;
    resolve(&ctx, cuts)
}

pub(crate) fn resolve(ctx: &LineContext, cuts: &Cuts) -> Result<Vec<CutLine>, TrimError> {
    let mesh = ctx.mesh;
    if mesh.faces.is_empty() {
        return Err(TrimError::EmptyMesh);
    }
    let opts = &cuts.options;
    let sp_opts = SurfacePointOptions {
        tolerance_mm: opts.landmark_tolerance_mm,
    };
    let mut names = std::collections::HashSet::new();
    // Landmarks of every line, and whether consecutive ones may be joined along an edge.
    let mut marks: Vec<Vec<SurfacePoint>> = Vec::new();
    for c in &cuts.cuts {
        if !names.insert(c.name.as_str()) {
            return Err(TrimError::DuplicateName {
                what: "line",
                name: c.name.clone(),
            });
        }
        let bad = |reason: &str| TrimError::BadLine {
            line: c.name.clone(),
            reason: reason.to_string(),
        };
        if !c.points.is_empty() && !c.vertices.is_empty() {
            return Err(bad("give `points` or `vertices`, not both"));
        }
        let mut pts = Vec::new();
        for (i, &p) in c.points.iter().enumerate() {
            pts.push(surface_point(
                &ctx.bvh,
                p,
                &format!("line {:?} point {i}", c.name),
                &sp_opts,
            )?);
        }
        for &v in &c.vertices {
            let f = (v < mesh.positions.len() as u64)
                .then(|| ctx.topo().outgoing(VertexId(v as u32)).first().copied())
                .flatten()
                .ok_or(TrimError::BadVertex {
                    line: c.name.clone(),
                    vertex: v,
                    vertex_count: mesh.positions.len(),
                })?;
            let sp =
                SurfacePoint::at_vertex(mesh, f / 3, v as u32).ok_or(TrimError::BadVertex {
                    line: c.name.clone(),
                    vertex: v,
                    vertex_count: mesh.positions.len(),
                })?;
            pts.push(sp);
        }
        let need = if c.closed { 3 } else { 2 };
        if pts.len() < need {
            return Err(bad(&format!(
                "a{} line needs at least {need} points or vertices, it has {}",
                if c.closed { " closed" } else { "n open" },
                pts.len()
            )));
        }
        marks.push(pts);
    }

    let n = cuts.cuts.len();
    let names: Vec<String> = cuts.cuts.iter().map(|c| c.name.clone()).collect();
    // Segments of the lines made so far: a new line may not share a stretch with them.
    let mut index = SegIndex::new();
    let mut done: Vec<Option<CutLine>> = vec![None; n];
    for (i, c) in cuts.cuts.iter().enumerate() {
        if c.closed {
            let mut m = marks[i].clone();
            m.push(m[0]);
            let l = join(ctx, &index, &names, true, &m, i)?;
            index.add(ctx, i, &l);
            done[i] = Some(l);
        }
    }
    // Open lines, in dependency order: a line is resolved once each end lies near the boundary
    // or a resolved line.
    loop {
        let mut progress = false;
        let mut pending = false;
        for (i, marks_i) in marks.iter().enumerate() {
            if done[i].is_some() {
                continue;
            }
            pending = true;
            let mut m = marks_i.clone();
            let last = m.len() - 1;
            let mut ok = true;
            for e in [0, last] {
                match snap_end(ctx, &done, i, m[e].position(mesh)) {
                    Some((d, sp)) if d <= opts.end_snap_mm => m[e] = sp,
                    _ => ok = false,
                }
            }
            if ok {
                let l = join(ctx, &index, &names, false, &m, i)?;
                index.add(ctx, i, &l);
                done[i] = Some(l);
                progress = true;
            }
        }
        if !pending {
            break;
        }
        if !progress {
            // Name the first line whose end is free, with its distance to what exists.
            for (i, c) in cuts.cuts.iter().enumerate() {
                if done[i].is_some() {
                    continue;
                }
                let m = &marks[i];
                for (e, end) in [(0, "first"), (m.len() - 1, "last")] {
                    let x = m[e].position(mesh);
                    let d = snap_end(ctx, &done, i, x).map_or(f64::INFINITY, |s| s.0);
                    if d > opts.end_snap_mm {
                        // Lines not yet resolved count too, so the distance is the real one.
                        let d_any = cuts
                            .cuts
                            .iter()
                            .enumerate()
                            .filter(|&(j, _)| j != i)
                            .filter_map(|(j, cj)| {
                                let m2 = &marks[j];
                                let mut l = m2.clone();
                                if cj.closed {
                                    l.push(l[0]);
                                }
                                l.windows(2)
                                    .map(|w| {
                                        let (a, b) = (w[0].position(mesh), w[1].position(mesh));
                                        let s = segment_param(x, a, b);
                                        vec3::dist(x, vec3::add(a, vec3::scale(vec3::sub(b, a), s)))
                                    })
                                    .reduce(f64::min)
                            })
                            .fold(d, f64::min);
                        if d_any > opts.end_snap_mm {
                            return Err(TrimError::LineEndFree {
                                line: c.name.clone(),
                                end,
                                point_mm: x,
                                distance_mm: d,
                                tolerance_mm: opts.end_snap_mm,
                            });
                        }
                    }
                }
            }
            // Every end is near some line but the lines wait on each other.
            let (i, c) = cuts
                .cuts
                .iter()
                .enumerate()
                .find(|(i, _)| done[*i].is_none())
                .ok_or(TrimError::EmptyMesh)?;
            return Err(TrimError::BadLine {
                line: c.name.clone(),
                reason: format!(
                    "its ends rest only on lines that themselves end on it (a cycle of T-junctions); end one of them on a boundary or a closed line (first point {:?})",
                    marks[i][0].position(mesh)
                ),
            });
        }
    }
    Ok(done.into_iter().flatten().collect())
}

/// The nearest place to end line `i` at: boundary or a resolved other line.
fn snap_end(
    ctx: &LineContext,
    done: &[Option<CutLine>],
    i: usize,
    x: [f64; 3],
) -> Option<(f64, SurfacePoint)> {
    let mut best = ctx.closest_on_boundary(x);
    for (j, l) in done.iter().enumerate() {
        if j == i {
            continue;
        }
        if let Some(l) = l
            && let Some(c) = ctx.closest_on_line(l, x)
            && best.is_none_or(|b| c.0 < b.0)
        {
            best = Some(c);
        }
    }
    best
}

/// Joins landmarks by geodesics (or edges between adjacent vertices), then untangles the
/// line: small self-loops removed, stretches shared with the lines already in `index` slid
/// apart ([`crate::untangle`]). `li` is the line's index in `names`.
fn join(
    ctx: &LineContext,
    index: &SegIndex,
    names: &[String],
    closed: bool,
    marks: &[SurfacePoint],
    li: usize,
) -> Result<CutLine, TrimError> {
    let name = &names[li];
    let (mut line, mut at) = join_marked(ctx, name, closed, marks)?;
    let keep: Vec<[f64; 3]> = at
        .iter()
        .map(|&i| line.points[i].position(ctx.mesh))
        .collect();
    crate::untangle::remove_loops(ctx, name, closed, &mut line.points)?;
    let last = line.points.len().saturating_sub(1);
    at = (0..line.points.len())
        .filter(|&i| i == 0 || i == last || keep.contains(&line.points[i].position(ctx.mesh)))
        .collect();
    crate::untangle::separate(ctx, index, names, &mut line, &mut at)?;
    if line.points.len() < 2 {
        return Err(TrimError::BadLine {
            line: name.to_string(),
            reason: "all its points are at one place".to_string(),
        });
    }
    line.length = line
        .points
        .windows(2)
        .map(|w| vec3::dist(w[0].position(ctx.mesh), w[1].position(ctx.mesh)))
        .sum();
    Ok(line)
}

/// Joins landmarks by geodesics; also the index of each landmark in the line's points.
fn join_marked(
    ctx: &LineContext,
    name: &str,
    closed: bool,
    marks: &[SurfacePoint],
) -> Result<(CutLine, Vec<usize>), TrimError> {
    let mesh = ctx.mesh;
    let mut points: Vec<SurfacePoint> = vec![marks[0]];
    let mut at = vec![0];
    for (i, w) in marks.windows(2).enumerate() {
        let (p, q) = (w[0], w[1]);
        if crate::geodesic::same_place(mesh, p, q)
            || vec3::dist(p.position(mesh), q.position(mesh)) == 0.0
        {
            at.push(points.len() - 1);
            continue;
        }
        let adjacent = match (p.location(mesh), q.location(mesh)) {
            (Location::Vertex(a), Location::Vertex(b)) => ctx.common_face(p, q).is_some() && a != b,
            _ => false,
        };
        if adjacent {
            points.push(q);
            at.push(points.len() - 1);
            continue;
        }
        let g = ctx.solver.path(p, q).ok_or(TrimError::NoPath {
            line: name.to_string(),
            from: i,
            to: i + 1,
        })?;
        points.extend_from_slice(&g.points[1..]);
        at.push(points.len() - 1);
    }
    if closed {
        let first = points[0];
        if let Some(last) = points.last_mut() {
            *last = first;
        }
    }
    if points.len() < 2 {
        return Err(TrimError::BadLine {
            line: name.to_string(),
            reason: "all its points are at one place".to_string(),
        });
    }
    let length = points
        .windows(2)
        .map(|w| vec3::dist(w[0].position(mesh), w[1].position(mesh)))
        .sum();
    Ok((
        CutLine {
            name: name.to_string(),
            closed,
            points,
            length,
        },
        at,
    ))
}
