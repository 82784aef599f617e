//! Coarsening of a piece for coarse-to-fine processing: half-edge collapses of interior
//! vertices only, so every boundary vertex (and every kept interior vertex) keeps its input
//! position bit for bit, and a map from every fine vertex to a coarse face with
//! barycentric coordinates for prolongation.
//!
//! A collapse v → u removes the interior vertex v and its two faces on the edge (u, v); the
//! other faces of v take u instead. u keeps its position (a half-edge collapse: no new
//! positions are ever made, so the coarse mesh is a subset of the fine vertices). The order
//! is by cost Q_v(u) + |u − v|²·`LENGTH_WEIGHT`, with Q_v the sum of the squared distances
//! to the planes of the fine faces merged into v (Garland–Heckbert quadric, unweighted):
//! on smooth pieces the length term dominates and the coarsening is uniform; at creases the
//! quadric keeps the crease vertices. A collapse is refused when it breaks the link
//! condition (the mesh would stop being a manifold disk of the same topology), leaves an
//! interior vertex with valence < 3 or a boundary vertex without face, turns a face normal
//! by more than `MAX_NORMAL_TURN_DEG`, or makes a corner below `MIN_CORNER_DEG`.
//!
//! Prolongation: every removed fine vertex is located on the coarse surface by the closest
//! point over the faces of the fan that replaced the one it was in (re-located at every
//! collapse that touches its face). Its barycentric coordinates interpolate any per-vertex
//! field; a kept vertex takes its coarse value exactly. On a planar piece the closest point
//! is the vertex itself, so a linear field is reproduced exactly.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use flatcut_mesh::vec3::{add, cross, dot, norm, scale, sub};
use flatcut_mesh::{INVALID, Topology, TriMesh, VertexId};
use smallvec::SmallVec;

use crate::FlattenableError;

/// Weight of the squared edge length in the collapse cost (dimensionless: both terms are
/// squared lengths). Small enough that the quadric decides at creases (a crease vertex is
/// ~one edge length off the planes of the other side), large enough to order collapses by
/// length on smooth pieces, where the quadric is ~(h²/R)² ≪ h².
const LENGTH_WEIGHT: f64 = 0.1;
/// Largest turn of a face normal a collapse may cause (degrees): keeps the coarse surface
/// close to the fine one in orientation, so the fold guard of the fine level (normals
/// against the input) is not fighting a prolongated start.
const MAX_NORMAL_TURN_DEG: f64 = 45.0;
/// Smallest corner a collapse may create (degrees): the coarse level is itself processed,
/// and slivers make A Aᵀ badly conditioned and trip the fold guard.
const MIN_CORNER_DEG: f64 = 15.0;

/// One-ring sizes kept on the stack (valence 6 is typical; 16 covers scan meshes' spread).
const RING_INLINE: usize = 16;
type Ring = SmallVec<[u32; RING_INLINE]>;

/// Where a fine vertex lives on the coarse mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Location {
    /// Kept: this coarse vertex (same position bit for bit).
    Kept(u32),
    /// Removed: the point Σ bary_k · corner_k of this coarse face.
    InFace {
        /// Coarse face index.
        face: u32,
        /// Barycentric coordinates (non-negative, sum 1) of the closest point.
        bary: [f64; 3],
    },
}

/// A coarse version of a piece and the way back to the fine one.
#[derive(Clone, Debug)]
pub struct Coarsened {
    /// The coarse mesh: a subset of the fine vertices (positions bit-identical), new faces.
    pub mesh: TriMesh,
    /// Fine vertex of each coarse vertex.
    pub fine_of_coarse: Vec<u32>,
    /// Location of every fine vertex on the coarse mesh.
    pub location: Vec<Location>,
}

impl Coarsened {
    /// Interpolates a per-coarse-vertex field to every fine vertex: kept vertices take their
    /// value exactly, removed ones the barycentric combination on their coarse face.
    pub fn prolongate(&self, coarse: &[[f64; 3]]) -> Vec<[f64; 3]> {
        self.location
            .iter()
            .map(|loc| match *loc {
                Location::Kept(c) => coarse[c as usize],
                Location::InFace { face, bary } => {
                    let f = self.mesh.faces[face as usize];
                    let mut out = [0.0; 3];
                    for k in 0..3 {
                        out = add(out, scale(coarse[f[k] as usize], bary[k]));
                    }
                    out
                }
            })
            .collect()
    }
}

/// Symmetric 4×4 quadric (upper triangle, row-major).
type Quadric = [f64; 10];

fn plane_quadric(n: [f64; 3], p: [f64; 3]) -> Quadric {
    let d = -dot(n, p);
    let v = [n[0], n[1], n[2], d];
    let mut q = [0.0; 10];
    let mut k = 0;
    for i in 0..4 {
        for j in i..4 {
            q[k] = v[i] * v[j];
            k += 1;
        }
    }
    q
}

fn quadric_eval(q: &Quadric, p: [f64; 3]) -> f64 {
    let v = [p[0], p[1], p[2], 1.0];
    let mut s = 0.0;
    let mut k = 0;
    for i in 0..4 {
        for j in i..4 {
            let m = if i == j { 1.0 } else { 2.0 };
            s += m * q[k] * v[i] * v[j];
            k += 1;
        }
    }
    s
}

/// Heap entry: lowest cost first, ties by vertex ids (deterministic). The order is kept as
/// integers — `cost` as the key of `f64::total_cmp`, then (v, u), then the stamp — since
/// comparing entries was most of the heap's share of the coarsening (`perf`).
#[derive(Clone, Copy, PartialEq, Eq)]
struct Entry {
    cost_key: u64,
    v_u: u64,
    stamp: u32,
}
impl Entry {
    fn new(cost: f64, v: u32, u: u32, stamp: u32) -> Self {
        // `total_cmp`'s order as an unsigned integer: negative values' magnitude bits
        // flipped, then the sign bit flipped so that negatives come first.
        let bits = cost.to_bits() as i64;
        let ordered = bits ^ (((bits >> 63) as u64) >> 1) as i64;
        Self {
            cost_key: (ordered as u64) ^ (1 << 63),
            v_u: (u64::from(v) << 32) | u64::from(u),
            stamp,
        }
    }
    fn v(&self) -> u32 {
        (self.v_u >> 32) as u32
    }
    fn u(&self) -> u32 {
        self.v_u as u32
    }
}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        (o.cost_key, o.v_u, o.stamp).cmp(&(self.cost_key, self.v_u, self.stamp))
    }
}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Closest point of triangle (a, b, c) to p as barycentric coordinates (Ericson, Real-Time
/// Collision Detection §5.1.5) and its squared distance.
fn closest_bary(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> ([f64; 3], f64) {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    let bary = 'b: {
        if d1 <= 0.0 && d2 <= 0.0 {
            break 'b [1.0, 0.0, 0.0];
        }
        let bp = sub(p, b);
        let d3 = dot(ab, bp);
        let d4 = dot(ac, bp);
        if d3 >= 0.0 && d4 <= d3 {
            break 'b [0.0, 1.0, 0.0];
        }
        let vc = d1 * d4 - d3 * d2;
        if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            let t = d1 / (d1 - d3);
            break 'b [1.0 - t, t, 0.0];
        }
        let cp = sub(p, c);
        let d5 = dot(ab, cp);
        let d6 = dot(ac, cp);
        if d6 >= 0.0 && d5 <= d6 {
            break 'b [0.0, 0.0, 1.0];
        }
        let vb = d5 * d2 - d1 * d6;
        if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            let t = d2 / (d2 - d6);
            break 'b [1.0 - t, 0.0, t];
        }
        let va = d3 * d6 - d5 * d4;
        if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            break 'b [0.0, 1.0 - t, t];
        }
        let denom = 1.0 / (va + vb + vc);
        let v = vb * denom;
        let w = vc * denom;
        [1.0 - v - w, v, w]
    };
    let q = add(add(scale(a, bary[0]), scale(b, bary[1])), scale(c, bary[2]));
    let d = sub(p, q);
    (bary, dot(d, d))
}

struct State<'a> {
    pos: &'a [[f64; 3]],
    faces: Vec<[u32; 3]>,
    face_alive: Vec<bool>,
    vfaces: Vec<Vec<u32>>,
    /// The distinct neighbours of every vertex, kept up to date by `collapse`: `best` and
    /// `valid` ask for them for every candidate of every touched vertex, and building them
    /// each time was a sixth of the coarsening (`perf`).
    rings: Vec<Ring>,
    /// Normal (unnormalised) and its length of every live face, kept up to date by
    /// `collapse` (positions never change, so only faces that take a new vertex change).
    face_normal: Vec<([f64; 3], f64)>,
    boundary: Vec<bool>,
    quadric: Vec<Quadric>,
    /// Removed fine vertices located in each face.
    assigned: Vec<Vec<u32>>,
    loc: Vec<(u32, [f64; 3])>,
    cos_turn: f64,
    cos_corner: f64,
}

impl State<'_> {
    /// The distinct neighbours of `v`, in the order of its faces (their order does not
    /// matter to any caller: candidates are sorted, links are counted, touched vertices
    /// are pushed to a totally ordered heap).
    fn ring_of(&self, v: u32) -> Ring {
        // Deduplicated in a plain array while it fits (SmallVec's inline/spilled check on
        // every `contains` and `push` was half of this function's time), else in the Ring.
        let fan = &self.vfaces[v as usize];
        let mut buf = [0u32; RING_INLINE];
        let mut len = 0usize;
        if 2 * fan.len() <= RING_INLINE {
            for &f in fan {
                for w in self.faces[f as usize] {
                    if w != v && !buf[..len].contains(&w) {
                        buf[len] = w;
                        len += 1;
                    }
                }
            }
            return Ring::from_slice(&buf[..len]);
        }
        let mut n = Ring::new();
        for &f in fan {
            for w in self.faces[f as usize] {
                if w != v && !n.contains(&w) {
                    n.push(w);
                }
            }
        }
        n
    }

    fn normal(&self, f: [u32; 3]) -> [f64; 3] {
        let p = f.map(|v| self.pos[v as usize]);
        cross(sub(p[1], p[0]), sub(p[2], p[0]))
    }

    fn normal_and_length(&self, f: [u32; 3]) -> ([f64; 3], f64) {
        let n = self.normal(f);
        (n, norm(n))
    }

    /// Whether v → u keeps a manifold disk of the same topology and acceptable shapes.
    fn valid(&self, v: u32, u: u32) -> bool {
        let mut shared = [INVALID; 2];
        let mut count = 0usize;
        for &f in &self.vfaces[v as usize] {
            if self.faces[f as usize].contains(&u) {
                if count < 2 {
                    shared[count] = f;
                }
                count += 1;
            }
        }
        // v is interior, so the edge (u, v) is interior: two faces.
        if count != 2 {
            return false;
        }
        let opposite = shared.map(|f| {
            self.faces[f as usize]
                .into_iter()
                .find(|&w| w != u && w != v)
                .unwrap_or(INVALID)
        });
        // Link condition: the common neighbours of u and v are exactly the two opposite
        // vertices (otherwise the collapse makes a non-manifold edge or pinches the disk).
        let nu = &self.rings[u as usize];
        let common = self.rings[v as usize]
            .iter()
            .filter(|w| nu.contains(w))
            .count();
        if common != 2 || opposite[0] == opposite[1] {
            return false;
        }
        for &w in &opposite {
            let faces = self.vfaces[w as usize].len();
            // An interior vertex loses one neighbour (keep valence ≥ 3); a boundary vertex
            // loses one face (keep at least one).
            if (!self.boundary[w as usize] && faces < 4) || faces < 2 {
                return false;
            }
        }
        // Faces that stay: v replaced by u. Normal turn and corner floor.
        for &f in &self.vfaces[v as usize] {
            if shared.contains(&f) {
                continue;
            }
            let (n0, l0) = self.face_normal[f as usize];
            let old = self.faces[f as usize];
            let new = old.map(|w| if w == v { u } else { w });
            let n1 = self.normal(new);
            let l1 = norm(n1);
            // A zero-area (or NaN) new face is refused too.
            if l1.is_nan() || l1 <= 0.0 || dot(n0, n1) < self.cos_turn * l0 * l1 {
                return false;
            }
            // Corner k between the edges to k + 1 and k + 2: with e_k = p[k+1] − p[k],
            // those are e_k and −e_(k+2), so three edge lengths serve the three corners
            // (negation is exact: the same cosines bit for bit as six lengths would give).
            let p = new.map(|w| self.pos[w as usize]);
            let e = [sub(p[1], p[0]), sub(p[2], p[1]), sub(p[0], p[2])];
            let l = e.map(norm);
            for k in 0..3 {
                let c = -dot(e[k], e[(k + 2) % 3]) / (l[k] * l[(k + 2) % 3]);
                // Corner below the floor ⇔ cos above its cos; NaN (zero edge) refused.
                if c.is_nan() || c > self.cos_corner {
                    return false;
                }
            }
        }
        true
    }

    fn cost(&self, v: u32, u: u32) -> f64 {
        let d = sub(self.pos[u as usize], self.pos[v as usize]);
        quadric_eval(&self.quadric[v as usize], self.pos[u as usize]) + LENGTH_WEIGHT * dot(d, d)
    }

    /// Cheapest collapse of interior vertex v, valid or not: what a vertex whose
    /// neighbourhood changed is queued with. Its validity is tested when it comes off the
    /// queue, against the mesh as it is then (it is tested there anyway, since later
    /// collapses can invalidate it); testing it here too, at every change of every
    /// neighbourhood, was most of the coarsening's time (`perf`).
    fn cheapest(&self, v: u32) -> Option<(f64, u32)> {
        if self.boundary[v as usize] {
            return None;
        }
        self.rings[v as usize]
            .iter()
            .map(|&u| (self.cost(v, u), u))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
    }

    /// Cheapest valid collapse of interior vertex v.
    fn best(&self, v: u32) -> Option<(f64, u32)> {
        if self.boundary[v as usize] {
            return None;
        }
        // The cheapest valid neighbour: candidates by (cost, index), validated in that order
        // until one passes — the validity test is the expensive part and the cheapest
        // candidate usually passes.
        let mut candidates: SmallVec<[(f64, u32); RING_INLINE]> = self.rings[v as usize]
            .iter()
            .map(|&u| (self.cost(v, u), u))
            .collect();
        candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        candidates.into_iter().find(|&(_, u)| self.valid(v, u))
    }

    fn collapse(&mut self, v: u32, u: u32) {
        let fan: Vec<u32> = std::mem::take(&mut self.vfaces[v as usize]);
        let mut kept = Vec::new();
        let mut relocate = vec![v];
        for &f in &fan {
            relocate.append(&mut self.assigned[f as usize]);
            let face = self.faces[f as usize];
            if face.contains(&u) {
                self.face_alive[f as usize] = false;
                for w in face {
                    if w != v {
                        self.vfaces[w as usize].retain(|&g| g != f);
                    }
                }
            } else {
                self.faces[f as usize] = face.map(|w| if w == v { u } else { w });
                self.vfaces[u as usize].push(f);
                kept.push(f);
            }
        }
        self.vfaces[u as usize].sort_unstable();
        for &f in &kept {
            self.face_normal[f as usize] = self.normal_and_length(self.faces[f as usize]);
        }
        // The links that changed: u's and those of v's neighbours (u among them).
        let ring_v = std::mem::take(&mut self.rings[v as usize]);
        for &w in &ring_v {
            self.rings[w as usize] = self.ring_of(w);
        }
        let qv = self.quadric[v as usize];
        for (a, b) in self.quadric[u as usize].iter_mut().zip(qv) {
            *a += b;
        }
        relocate.sort_unstable();
        for p in relocate {
            let x = self.pos[p as usize];
            let mut best = (INVALID, [1.0, 0.0, 0.0], f64::INFINITY);
            for &f in &kept {
                let c = self.faces[f as usize].map(|w| self.pos[w as usize]);
                let (bary, d2) = closest_bary(x, c[0], c[1], c[2]);
                if d2 < best.2 {
                    best = (f, bary, d2);
                }
            }
            self.loc[p as usize] = (best.0, best.1);
            self.assigned[best.0 as usize].push(p);
        }
    }
}

/// Coarsens `mesh` (one piece: a manifold, consistently oriented surface with boundary)
/// by interior half-edge collapses until it has at most `target_faces` faces or no valid
/// collapse is left. Boundary vertices are never removed and no position changes.
pub fn coarsen(mesh: &TriMesh, target_faces: usize) -> Result<Coarsened, FlattenableError> {
    coarsen_with(mesh, &Topology::build(mesh)?, target_faces)
}

/// [`coarsen`] with the topology of `mesh` given (a piece has it already; building it again
/// was ~8 % of a coarsening).
pub fn coarsen_with(
    mesh: &TriMesh,
    topo: &Topology,
    target_faces: usize,
) -> Result<Coarsened, FlattenableError> {
    let nv = mesh.vertex_count();
    let boundary: Vec<bool> = (0..nv as u32)
        .map(|v| !topo.is_interior_vertex(VertexId(v)))
        .collect();
    let mut vfaces = vec![Vec::new(); nv];
    let mut quadric = vec![[0.0; 10]; nv];
    for (f, face) in mesh.faces.iter().enumerate() {
        let p = face.map(|w| mesh.positions[w as usize]);
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let l = norm(n);
        let q = if l > 0.0 {
            plane_quadric(scale(n, 1.0 / l), p[0])
        } else {
            [0.0; 10]
        };
        for &w in face {
            vfaces[w as usize].push(f as u32);
            for (a, b) in quadric[w as usize].iter_mut().zip(q) {
                *a += b;
            }
        }
    }
    let mut st = State {
        pos: &mesh.positions,
        faces: mesh.faces.clone(),
        face_alive: vec![true; mesh.face_count()],
        vfaces,
        rings: Vec::new(),
        face_normal: Vec::new(),
        boundary,
        quadric,
        assigned: vec![Vec::new(); mesh.face_count()],
        loc: vec![(INVALID, [0.0; 3]); nv],
        cos_turn: MAX_NORMAL_TURN_DEG.to_radians().cos(),
        cos_corner: MIN_CORNER_DEG.to_radians().cos(),
    };
    st.rings = (0..nv as u32).map(|v| st.ring_of(v)).collect();
    st.face_normal = st.faces.iter().map(|&f| st.normal_and_length(f)).collect();
    let mut stamp = vec![0u32; nv];
    // What each vertex is queued with: a vertex whose cheapest collapse did not change keeps
    // its entry (most neighbours of a collapse: the one they lost was not their cheapest)
    // rather than adding a stale one, whose pops were a fifth of the coarsening (`perf`).
    let mut queued: Vec<Option<(f64, u32)>> = vec![None; nv];
    let mut heap = BinaryHeap::new();
    for v in 0..nv as u32 {
        if let Some((cost, u)) = st.cheapest(v) {
            heap.push(Entry::new(cost, v, u, 0));
            queued[v as usize] = Some((cost, u));
        }
    }
    let mut vertex_alive = vec![true; nv];
    let mut faces_left = mesh.face_count();
    while faces_left > target_faces {
        let Some(e) = heap.pop() else { break };
        let (v, u) = (e.v(), e.u());
        if !vertex_alive[v as usize] || stamp[v as usize] != e.stamp {
            continue;
        }
        if !vertex_alive[u as usize] || !st.valid(v, u) {
            stamp[v as usize] += 1;
            queued[v as usize] = st.best(v);
            if let Some((cost, u)) = queued[v as usize] {
                heap.push(Entry::new(cost, v, u, stamp[v as usize]));
            }
            continue;
        }
        st.collapse(v, u);
        vertex_alive[v as usize] = false;
        faces_left -= 2;
        let mut touched = st.rings[u as usize].clone();
        touched.push(u);
        for w in touched {
            let next = st.cheapest(w);
            if next.map(|(c, u)| (c.to_bits(), u))
                == queued[w as usize].map(|(c, u)| (c.to_bits(), u))
            {
                continue;
            }
            stamp[w as usize] += 1;
            queued[w as usize] = next;
            if let Some((cost, u)) = next {
                heap.push(Entry::new(cost, w, u, stamp[w as usize]));
            }
        }
    }

    // Compact: coarse vertices in fine order, coarse faces in fine face order.
    let mut coarse_of_fine = vec![INVALID; nv];
    let mut fine_of_coarse = Vec::new();
    for v in 0..nv {
        if vertex_alive[v] {
            coarse_of_fine[v] = fine_of_coarse.len() as u32;
            fine_of_coarse.push(v as u32);
        }
    }
    let mut face_index = vec![INVALID; st.faces.len()];
    let mut faces = Vec::new();
    for (f, face) in st.faces.iter().enumerate() {
        if st.face_alive[f] {
            face_index[f] = faces.len() as u32;
            faces.push(face.map(|w| coarse_of_fine[w as usize]));
        }
    }
    let positions = fine_of_coarse
        .iter()
        .map(|&v| mesh.positions[v as usize])
        .collect();
    let location = (0..nv)
        .map(|v| {
            if coarse_of_fine[v] != INVALID {
                Location::Kept(coarse_of_fine[v])
            } else {
                let (f, bary) = st.loc[v];
                Location::InFace {
                    face: face_index.get(f as usize).copied().unwrap_or(INVALID),
                    bary,
                }
            }
        })
        .collect();
    let coarse = TriMesh::new(positions, faces)?;
    Ok(Coarsened {
        mesh: coarse,
        fine_of_coarse,
        location,
    })
}
