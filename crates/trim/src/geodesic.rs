//! Shortest paths on the surface between two surface points, crossing faces.
//!
//! 1. A* on the edge graph (Euclidean heuristic, admissible) from the start point through the
//!    corners of its face to the corners of the end face gives an initial path and with it
//!    a homotopy class.
//! 2. The faces around that path form a triangle strip; unfolded into the plane it is a
//!    channel, and the funnel algorithm (Lee & Preparata 1984) gives the exact shortest path
//!    inside it: straight in the unfolding, bending only at strip vertices.
//! 3. Where the path bends at an interior vertex `v`, the angle on the strip's side is ≥ π
//!    (the funnel guarantees it); if the angle on the other side, Θ(v) − that, is < π, going
//!    round the other side is shorter, so the strip's fan around `v` is swapped for the other
//!    fan and the funnel run again. Each swap shortens the path strictly; at the end every
//!    bend vertex has ≥ π on both sides — the condition for a locally shortest path on a
//!    polyhedral surface (Mitchell, Mount & Papadimitriou 1987). This is the "funnel with
//!    strip updates" scheme of Xin & Wang (2007) without their window bookkeeping.
//!
//! The result is the exact polyhedral geodesic in the initial path's homotopy class up to
//! rounding; crossing parameters within [`SNAP_RELATIVE`] of an edge end are moved onto the
//! vertex (to avoid sliver triangles when the path is embedded).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use flatcut_mesh::{FaceId, Topology, TriMesh, geometry, vec3};
use serde::Deserialize;

use crate::surface_point::{Location, SNAP_RELATIVE, SurfacePoint};

/// A vertex is a place to swap the strip's side when the angle on the other side is below
/// π by more than this (radians): smaller differences are rounding, and swapping on them
/// could cycle.
pub const ANGLE_EPS_RAD: f64 = 1e-9;

/// Options for [`geodesic`].
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GeodesicOptions {
    /// Most strip updates (fan swaps) per path (default 100 000); each shortens the path,
    /// so the cap only guards against a cycle from rounding. The best path so far is returned.
    pub max_strip_updates: usize,
}

impl Default for GeodesicOptions {
    fn default() -> Self {
        Self {
            max_strip_updates: 100_000,
        }
    }
}

/// A shortest path on the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Geodesic {
    /// From the start point to the end point: the start, every edge crossing or vertex passed
    /// (as a point on that edge or vertex), the end. Consecutive points share a face, so the
    /// straight segment between them lies on the surface.
    pub points: Vec<SurfacePoint>,
    /// Length on the surface (sum of the segments' 3D lengths), mesh units.
    pub length: f64,
    /// Length of the initial edge-graph path (A*), mesh units.
    pub edge_path_length: f64,
    /// Number of strip updates made.
    pub strip_updates: usize,
}

/// Reusable geodesic machinery for one mesh (topology and vertex angle sums built once).
pub struct GeodesicSolver<'a> {
    mesh: &'a TriMesh,
    topo: Topology,
    angle_sum: Vec<f64>,
    opts: GeodesicOptions,
}

/// The shortest path from `from` to `to` on `mesh`, or `None` when no path joins them
/// (different components). Builds the topology; use [`GeodesicSolver`] for many paths.
pub fn geodesic(
    mesh: &TriMesh,
    from: SurfacePoint,
    to: SurfacePoint,
    opts: &GeodesicOptions,
) -> Result<Option<Geodesic>, crate::TrimError> {
    let solver = GeodesicSolver::new(mesh, opts)?;
    Ok(solver.path(from, to))
}

#[derive(Clone, Copy, Debug)]
struct Pt {
    p: [f64; 2],
    /// Mesh vertex id, or [`S_ID`]/[`T_ID`].
    id: u32,
}

const S_ID: u32 = u32::MAX - 1;
const T_ID: u32 = u32::MAX - 2;

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

fn cross(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[1] - u[1] * v[0]
}
fn sub2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn angle2(u: [f64; 2], v: [f64; 2]) -> f64 {
    cross(u, v).abs().atan2(u[0] * v[0] + u[1] * v[1])
}

/// A strip unfolded: per strip position the 2D corners (in `faces[f]` order) and the portal
/// to the next face (local corner index of its first vertex).
struct Unfolded {
    uv: Vec<[[f64; 2]; 3]>,
    portal: Vec<usize>,
}

impl<'a> GeodesicSolver<'a> {
    /// Prepares `mesh` (topology and angle sums).
    pub fn new(mesh: &'a TriMesh, opts: &GeodesicOptions) -> Result<Self, crate::TrimError> {
        let topo = Topology::build(mesh)?;
        let angle_sum = geometry::angle_sums(&mesh.positions, &mesh.faces);
        Ok(Self {
            mesh,
            topo,
            angle_sum,
            opts: opts.clone(),
        })
    }

    /// The topology built for the mesh.
    pub fn topology(&self) -> &Topology {
        &self.topo
    }

    fn pos(&self, v: u32) -> [f64; 3] {
        self.mesh.positions[v as usize]
    }

    /// The shortest path from `from` to `to`, `None` if they are not connected.
    pub fn path(&self, from: SurfacePoint, to: SurfacePoint) -> Option<Geodesic> {
        let (verts, edge_len) = self.astar(from, to)?;
        let mut strip = self.initial_strip(from, to, &verts)?;
        let mut updates = 0;
        loop {
            let unf = self.unfold(&strip);
            let (s, t, portals) = self.portals(&strip, &unf, from, to);
            let apexes = funnel(&portals, s, t);
            if updates < self.opts.max_strip_updates
                && let Some(new) = self.update_strip(&strip, &unf, &portals, &apexes)
            {
                strip = new;
                updates += 1;
                continue;
            }
            let points = self.crossings(&strip, &unf, &portals, &apexes, from, to);
            let length = points
                .windows(2)
                .map(|w| vec3::dist(w[0].position(self.mesh), w[1].position(self.mesh)))
                .sum();
            return Some(Geodesic {
                points,
                length,
                edge_path_length: edge_len,
                strip_updates: updates,
            });
        }
    }

    /// A* over vertices plus the two points; returns the vertices passed and the length.
    fn astar(&self, from: SurfacePoint, to: SurfacePoint) -> Option<(Vec<u32>, f64)> {
        let n = self.mesh.positions.len();
        let (src, dst) = (n as u32, n as u32 + 1);
        let ps = from.position(self.mesh);
        let pt = to.position(self.mesh);
        let fs = self.mesh.faces[from.face.idx()];
        let ft = self.mesh.faces[to.face.idx()];
        let mut dist = vec![f64::INFINITY; n + 2];
        let mut prev = vec![u32::MAX; n + 2];
        let mut done = vec![false; n + 2];
        let h = |v: u32| -> f64 {
            if v == dst {
                0.0
            } else if v == src {
                vec3::dist(ps, pt)
            } else {
                vec3::dist(self.pos(v), pt)
            }
        };
        let mut heap = BinaryHeap::new();
        dist[src as usize] = 0.0;
        heap.push(Node(h(src), src));
        while let Some(Node(_, u)) = heap.pop() {
            if done[u as usize] {
                continue;
            }
            done[u as usize] = true;
            if u == dst {
                break;
            }
            let du = dist[u as usize];
            let mut relax = |v: u32, w: f64, heap: &mut BinaryHeap<Node>| {
                let nd = du + w;
                if nd < dist[v as usize] {
                    dist[v as usize] = nd;
                    prev[v as usize] = u;
                    heap.push(Node(nd + h(v), v));
                }
            };
            if u == src {
                for &c in &fs {
                    relax(c, vec3::dist(ps, self.pos(c)), &mut heap);
                }
                if from.face == to.face {
                    relax(dst, vec3::dist(ps, pt), &mut heap);
                }
                continue;
            }
            let pu = self.pos(u);
            for &hh in self.topo.outgoing(flatcut_mesh::VertexId(u)) {
                let a = self.topo.to_vertex(hh).0;
                let b = self.topo.from_vertex(Topology::prev(hh)).0;
                relax(a, vec3::dist(pu, self.pos(a)), &mut heap);
                relax(b, vec3::dist(pu, self.pos(b)), &mut heap);
            }
            if ft.contains(&u) {
                relax(dst, vec3::dist(pu, pt), &mut heap);
            }
        }
        if !done[dst as usize] {
            return None;
        }
        let mut verts = Vec::new();
        let mut v = prev[dst as usize];
        while v != src {
            verts.push(v);
            v = prev[v as usize];
        }
        verts.reverse();
        Some((verts, dist[dst as usize]))
    }

    fn corner(&self, f: u32, v: u32) -> Option<usize> {
        self.mesh.faces[f as usize].iter().position(|&x| x == v)
    }

    /// The next face counter-clockwise around `v` from `f`.
    fn ccw(&self, f: u32, v: u32) -> Option<u32> {
        let k = self.corner(f, v)? as u32;
        let h_in = Topology::prev(3 * f + k);
        self.topo.twin(h_in).map(|t| t / 3)
    }

    /// The next face clockwise around `v` from `f`.
    fn cw(&self, f: u32, v: u32) -> Option<u32> {
        let k = self.corner(f, v)? as u32;
        self.topo.twin(3 * f + k).map(|t| t / 3)
    }

    /// Faces around `v` from `f` (included) until one satisfies `stop`, turning one way and
    /// then, if a boundary stops it, the other.
    fn fan_to(&self, f: u32, v: u32, stop: impl Fn(u32) -> bool) -> Option<Vec<u32>> {
        if stop(f) {
            return Some(vec![f]);
        }
        let limit = self.topo.outgoing(flatcut_mesh::VertexId(v)).len() + 1;
        for ccw in [true, false] {
            let mut fan = vec![f];
            let mut g = f;
            for _ in 0..limit {
                let next = if ccw { self.ccw(g, v) } else { self.cw(g, v) };
                let Some(nx) = next else { break };
                g = nx;
                fan.push(g);
                if stop(g) {
                    return Some(fan);
                }
            }
        }
        None
    }

    fn initial_strip(
        &self,
        from: SurfacePoint,
        to: SurfacePoint,
        verts: &[u32],
    ) -> Option<Vec<u32>> {
        let mut strip = vec![from.face.0];
        for (i, &v) in verts.iter().enumerate() {
            let cur = *strip.last()?;
            let fan = match verts.get(i + 1) {
                Some(&w) => self.fan_to(cur, v, |g| self.corner(g, w).is_some())?,
                None => self.fan_to(cur, v, |g| g == to.face.0)?,
            };
            strip.extend_from_slice(&fan[1..]);
        }
        if *strip.last()? != to.face.0 {
            // Start and end in one face, joined directly, or a vertex path ending elsewhere.
            if strip.len() == 1 && from.face == to.face {
                return Some(strip);
            }
            return None;
        }
        Some(strip)
    }

    /// Unfolds the strip: face 0 with corner 0 at the origin, each next face across its portal.
    fn unfold(&self, strip: &[u32]) -> Unfolded {
        let m = self.mesh;
        let mut uv = Vec::with_capacity(strip.len());
        let mut portal = Vec::with_capacity(strip.len());
        let f0 = m.faces[strip[0] as usize];
        let [a, b, c] = f0.map(|v| self.pos(v));
        let lab = vec3::dist(a, b);
        uv.push([
            [0.0, 0.0],
            [lab, 0.0],
            place([0.0, 0.0], [lab, 0.0], vec3::dist(a, c), vec3::dist(b, c)),
        ]);
        for k in 0..strip.len() - 1 {
            let (f, g) = (strip[k], strip[k + 1]);
            let fi = (0..3)
                .find(|&i| self.topo.twin(3 * f + i as u32).is_some_and(|t| t / 3 == g))
                .unwrap_or(0);
            portal.push(fi);
            let h = 3 * f + fi as u32;
            let t = self.topo.twin(h).unwrap_or(h);
            let j = (t % 3) as usize;
            let fc = uv[k];
            let gf = m.faces[g as usize];
            // g's corner j is f's corner fi + 1, corner j + 1 is f's corner fi.
            let p = fc[(fi + 1) % 3];
            let q = fc[fi];
            let r3 = self.pos(gf[(j + 2) % 3]);
            let r = place(
                p,
                q,
                vec3::dist(self.pos(gf[j]), r3),
                vec3::dist(self.pos(gf[(j + 1) % 3]), r3),
            );
            let mut g_uv = [[0.0; 2]; 3];
            g_uv[j] = p;
            g_uv[(j + 1) % 3] = q;
            g_uv[(j + 2) % 3] = r;
            uv.push(g_uv);
        }
        Unfolded { uv, portal }
    }

    fn bary2(&self, uv: &[[f64; 2]; 3], w: [f64; 3]) -> [f64; 2] {
        [
            w[0] * uv[0][0] + w[1] * uv[1][0] + w[2] * uv[2][0],
            w[0] * uv[0][1] + w[1] * uv[1][1] + w[2] * uv[2][1],
        ]
    }

    fn point_id(&self, sp: SurfacePoint, special: u32) -> u32 {
        match sp.location(self.mesh) {
            Location::Vertex(v) => v,
            _ => special,
        }
    }

    /// Start, end and the portals (left, right) including the final (t, t).
    fn portals(
        &self,
        strip: &[u32],
        unf: &Unfolded,
        from: SurfacePoint,
        to: SurfacePoint,
    ) -> (Pt, Pt, Vec<(Pt, Pt)>) {
        let m = self.mesh;
        let s = Pt {
            p: self.bary2(&unf.uv[0], from.barycentric),
            id: self.point_id(from, S_ID),
        };
        let t = Pt {
            p: self.bary2(&unf.uv[strip.len() - 1], to.barycentric),
            id: self.point_id(to, T_ID),
        };
        let mut portals = Vec::with_capacity(strip.len());
        for (k, &sf) in strip[..strip.len() - 1].iter().enumerate() {
            let f = m.faces[sf as usize];
            let i = unf.portal[k];
            let right = Pt {
                p: unf.uv[k][i],
                id: f[i],
            };
            let left = Pt {
                p: unf.uv[k][(i + 1) % 3],
                id: f[(i + 1) % 3],
            };
            portals.push((left, right));
        }
        portals.push((t, t));
        (s, t, portals)
    }

    /// A fan swap that shortens the path, if any bend vertex has < π on its other side.
    fn update_strip(
        &self,
        strip: &[u32],
        unf: &Unfolded,
        portals: &[(Pt, Pt)],
        apexes: &[(Pt, isize)],
    ) -> Option<Vec<u32>> {
        let n = strip.len() - 1; // real portals
        let has = |k: usize, v: u32| portals[k].0.id == v || portals[k].1.id == v;
        for j in 1..apexes.len().saturating_sub(1) {
            let (a, pj) = apexes[j];
            let v = a.id;
            if v >= S_ID.min(T_ID) || pj < 0 || pj as usize >= n {
                continue;
            }
            let vid = flatcut_mesh::VertexId(v);
            if !self.topo.is_interior_vertex(vid) {
                continue;
            }
            let (mut lo, mut hi) = (pj as usize, pj as usize);
            while lo > 0 && has(lo - 1, v) {
                lo -= 1;
            }
            while hi + 1 < n && has(hi + 1, v) {
                hi += 1;
            }
            let other = |k: usize| {
                let (l, r) = portals[k];
                if l.id == v { r.p } else { l.p }
            };
            let prev = apexes[j - 1].0.p;
            let next = apexes[j + 1].0.p;
            let mut theta = angle2(sub2(prev, a.p), sub2(other(lo), a.p));
            for (&sf, u) in strip[lo + 1..=hi].iter().zip(&unf.uv[lo + 1..=hi]) {
                let f = self.mesh.faces[sf as usize];
                let c = f.iter().position(|&x| x == v)?;
                theta += angle2(sub2(u[(c + 1) % 3], u[c]), sub2(u[(c + 2) % 3], u[c]));
            }
            theta += angle2(sub2(other(hi), a.p), sub2(next, a.p));
            let phi = self.angle_sum[v as usize] - theta;
            if phi >= std::f64::consts::PI - ANGLE_EPS_RAD {
                continue;
            }
            // Swap the fan f_lo..=f_{hi+1} for the other way round v.
            let (f_in, f_out) = (strip[lo], strip[hi + 1]);
            let went_ccw = self.ccw(f_in, v) == Some(strip[lo + 1]);
            let limit = self.topo.outgoing(vid).len() + 1;
            let mut fan = vec![f_in];
            let mut g = f_in;
            let mut ok = false;
            for _ in 0..limit {
                g = if went_ccw {
                    self.cw(g, v)?
                } else {
                    self.ccw(g, v)?
                };
                fan.push(g);
                if g == f_out {
                    ok = true;
                    break;
                }
            }
            if !ok {
                continue;
            }
            let mut new = strip[..lo].to_vec();
            new.extend_from_slice(&fan);
            new.extend_from_slice(&strip[hi + 2..]);
            return Some(new);
        }
        None
    }

    /// The path's surface points from the funnel's apexes.
    fn crossings(
        &self,
        strip: &[u32],
        unf: &Unfolded,
        portals: &[(Pt, Pt)],
        apexes: &[(Pt, isize)],
        from: SurfacePoint,
        to: SurfacePoint,
    ) -> Vec<SurfacePoint> {
        let m = self.mesh;
        let n = strip.len() - 1;
        let mut out = vec![from];
        let mut j = 0;
        for k in 0..n {
            while j + 1 < apexes.len() - 1 && apexes[j + 1].1 <= k as isize {
                j += 1;
            }
            let (l, r) = portals[k];
            let (a, b) = (apexes[j].0, apexes[j + 1].0);
            let f = strip[k];
            let i = unf.portal[k];
            let sp = if l.id == a.id || l.id == b.id {
                SurfacePoint::at_vertex(m, f, l.id)
            } else if r.id == a.id || r.id == b.id {
                SurfacePoint::at_vertex(m, f, r.id)
            } else {
                let d = sub2(b.p, a.p);
                let e = sub2(l.p, r.p);
                let den = cross(e, d);
                let tau = if den != 0.0 {
                    (cross(sub2(a.p, r.p), d) / den).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                if tau < SNAP_RELATIVE {
                    SurfacePoint::at_vertex(m, f, r.id)
                } else if tau > 1.0 - SNAP_RELATIVE {
                    SurfacePoint::at_vertex(m, f, l.id)
                } else {
                    let mut w = [0.0; 3];
                    w[i] = 1.0 - tau;
                    w[(i + 1) % 3] = tau;
                    Some(SurfacePoint {
                        face: FaceId(f),
                        barycentric: w,
                    })
                }
            };
            if let Some(sp) = sp {
                out.push(sp);
            }
        }
        out.push(to);
        // Consecutive points at one place (a vertex passed over several portals) become one.
        let mut dedup: Vec<SurfacePoint> = Vec::with_capacity(out.len());
        for p in out {
            if let Some(q) = dedup.last()
                && same_place(m, *q, p)
            {
                // Keep the endpoints as given.
                if dedup.len() > 1 {
                    continue;
                }
                if matches!(p.location(m), Location::Vertex(_)) {
                    continue;
                }
            }
            dedup.push(p);
        }
        if dedup.len() >= 2 {
            let k = dedup.len() - 2;
            if same_place(m, dedup[k], to) && k > 0 {
                dedup.remove(k);
            }
            let last = dedup.len() - 1;
            dedup[last] = to;
        }
        dedup
    }
}

/// Do two surface points name the same vertex or edge point?
pub(crate) fn same_place(m: &TriMesh, a: SurfacePoint, b: SurfacePoint) -> bool {
    match (a.location(m), b.location(m)) {
        (Location::Vertex(x), Location::Vertex(y)) => x == y,
        (
            Location::Edge { a, b, t },
            Location::Edge {
                a: a2,
                b: b2,
                t: t2,
            },
        ) => a == a2 && b == b2 && t == t2,
        (Location::Face(f), Location::Face(g)) => f == g && a.barycentric == b.barycentric,
        _ => false,
    }
}

/// The third corner of a triangle on the left of `p → q`, at distances `dp` from p and `dq`
/// from q.
fn place(p: [f64; 2], q: [f64; 2], dp: f64, dq: f64) -> [f64; 2] {
    let e = sub2(q, p);
    let d = (e[0] * e[0] + e[1] * e[1]).sqrt();
    if d <= 0.0 {
        return p;
    }
    let x = (dp * dp - dq * dq + d * d) / (2.0 * d);
    let y = (dp * dp - x * x).max(0.0).sqrt();
    let (ex, ey) = (e[0] / d, e[1] / d);
    [p[0] + x * ex - y * ey, p[1] + x * ey + y * ex]
}

/// The simple stupid funnel algorithm (Mononen) over portals (left, right); the last portal
/// is (t, t). Returns the apexes with the portal index each was taken from (−1 for the start).
fn funnel(portals: &[(Pt, Pt)], s: Pt, t: Pt) -> Vec<(Pt, isize)> {
    let mut out = vec![(s, -1isize)];
    let mut apex = s;
    let (mut left, mut left_i) = (s, -1isize);
    let (mut right, mut right_i) = (s, -1isize);
    let mut i = 0usize;
    let mut guard = 0usize;
    let cap = portals.len() * portals.len() + 16;
    while i < portals.len() && guard < cap {
        guard += 1;
        let (l, r) = portals[i];
        if cross(sub2(right.p, apex.p), sub2(r.p, apex.p)) >= 0.0 {
            if apex.id == right.id || cross(sub2(left.p, apex.p), sub2(r.p, apex.p)) < 0.0 {
                right = r;
                right_i = i as isize;
            } else {
                out.push((left, left_i));
                apex = left;
                right = apex;
                right_i = left_i;
                i = (left_i + 1) as usize;
                continue;
            }
        }
        if cross(sub2(left.p, apex.p), sub2(l.p, apex.p)) <= 0.0 {
            if apex.id == left.id || cross(sub2(right.p, apex.p), sub2(l.p, apex.p)) > 0.0 {
                left = l;
                left_i = i as isize;
            } else {
                out.push((right, right_i));
                apex = right;
                left = apex;
                left_i = right_i;
                i = (right_i + 1) as usize;
                continue;
            }
        }
        i += 1;
    }
    if out.last().is_none_or(|a| a.0.id != t.id || a.0.p != t.p) {
        out.push((t, portals.len() as isize - 1));
    }
    out
}
