//! The internal halfedge structure the edit loops run on: flat arrays, twins paired as
//! `2e` / `2e + 1`, boundary halfedges stored explicitly (face `INVALID`) so that rotation
//! around a boundary vertex needs no special case. Split, collapse and flip follow the
//! PMP library's (Sieger & Botsch) connectivity updates. Deleted elements are only flagged
//! here; [`HalfMesh::to_trimesh`] compacts them away, so nothing tombstoned leaves the crate.

use flatcut_mesh::{INVALID, Topology, TriMesh};

use crate::RemeshError;

/// Mutable halfedge mesh. Vertex ids of the input are kept (new vertices are appended).
#[derive(Clone, Debug, Default)]
pub(crate) struct HalfMesh {
    pub pos: Vec<[f64; 3]>,
    /// One outgoing halfedge per vertex; a boundary one if the vertex is on the boundary.
    pub v_out: Vec<u32>,
    pub v_dead: Vec<bool>,
    /// Halfedge records, twins adjacent (`2e`, `2e + 1`).
    pub h: Vec<Half>,
    /// Edge `e` is the halfedge pair `2e`, `2e + 1`.
    pub e_dead: Vec<bool>,
    pub f_h: Vec<u32>,
    pub f_dead: Vec<bool>,
}

/// One halfedge: the fields a traversal reads together share a cache line (with its twin's,
/// as twins are adjacent), where separate arrays cost a cache miss per field on the large
/// meshes decimation and remeshing walk in cost order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Half {
    /// Vertex the halfedge points to.
    pub to: u32,
    pub next: u32,
    pub prev: u32,
    /// Face of the halfedge, `INVALID` on the boundary.
    pub face: u32,
}

impl Half {
    const UNSET: Half = Half {
        to: INVALID,
        next: INVALID,
        prev: INVALID,
        face: INVALID,
    };
}

/// Rings up to this valence are gathered on the stack for the link condition.
const LINK_RING: usize = 32;

#[inline]
pub(crate) fn twin(h: u32) -> u32 {
    h ^ 1
}

impl HalfMesh {
    /// Builds from a manifold, consistently oriented mesh (checked by the caller with
    /// [`check_manifold`]). Unreferenced vertices are marked dead.
    pub fn build(mesh: &TriMesh, topo: &Topology) -> HalfMesh {
        let nv = mesh.positions.len();
        let ne = topo.edges().len();
        let nf = mesh.faces.len();
        let mut m = HalfMesh {
            pos: mesh.positions.clone(),
            v_out: vec![INVALID; nv],
            v_dead: vec![true; nv],
            h: vec![Half::UNSET; 2 * ne],
            e_dead: vec![false; ne],
            f_h: vec![INVALID; nf],
            f_dead: vec![false; nf],
        };
        let edges = topo.edges();
        // Face halfedge 3f+k -> our halfedge id.
        let map = |h: u32| -> u32 {
            let e = topo.edge_of(h);
            let from = topo.from_vertex(h).0;
            if from == edges[e as usize][0] {
                2 * e
            } else {
                2 * e + 1
            }
        };
        for (f, face) in mesh.faces.iter().enumerate() {
            let hs = [0u32, 1, 2].map(|k| map(3 * f as u32 + k));
            for k in 0..3 {
                let h = hs[k] as usize;
                m.h[h].to = face[(k + 1) % 3];
                m.h[h].next = hs[(k + 1) % 3];
                m.h[h].prev = hs[(k + 2) % 3];
                m.h[h].face = f as u32;
                let v = face[k] as usize;
                m.v_dead[v] = false;
                if m.v_out[v] == INVALID {
                    m.v_out[v] = hs[k];
                }
            }
            m.f_h[f] = hs[0];
        }
        // Boundary halfedges: the unset twin of a face halfedge.
        let mut bnd_out = vec![INVALID; nv];
        for h in 0..2 * ne as u32 {
            if m.h[h as usize].face == INVALID {
                let t = twin(h);
                let to = m.to_from_twin(t);
                m.h[h as usize].to = to;
                let from = m.h[t as usize].to;
                bnd_out[from as usize] = h;
                m.v_out[from as usize] = h;
            }
        }
        for h in 0..2 * ne as u32 {
            if m.h[h as usize].face == INVALID {
                let n = bnd_out[m.h[h as usize].to as usize];
                m.h[h as usize].next = n;
                m.h[n as usize].prev = h;
            }
        }
        m
    }

    /// The from-vertex of face halfedge `t` (whose twin is being set up).
    fn to_from_twin(&self, t: u32) -> u32 {
        self.h[self.h[t as usize].prev as usize].to
    }

    #[inline]
    pub fn to(&self, h: u32) -> u32 {
        self.h[h as usize].to
    }
    #[inline]
    pub fn from(&self, h: u32) -> u32 {
        self.h[twin(h) as usize].to
    }
    #[inline]
    pub fn next(&self, h: u32) -> u32 {
        self.h[h as usize].next
    }
    #[inline]
    pub fn prev(&self, h: u32) -> u32 {
        self.h[h as usize].prev
    }
    #[inline]
    pub fn face(&self, h: u32) -> u32 {
        self.h[h as usize].face
    }
    #[inline]
    pub fn is_boundary_h(&self, h: u32) -> bool {
        self.h[h as usize].face == INVALID
    }
    #[inline]
    pub fn is_boundary_e(&self, e: u32) -> bool {
        self.is_boundary_h(2 * e) || self.is_boundary_h(2 * e + 1)
    }
    #[inline]
    pub fn is_boundary_v(&self, v: u32) -> bool {
        let h = self.v_out[v as usize];
        h != INVALID && self.is_boundary_h(h)
    }
    /// Next outgoing halfedge around the from-vertex of `h`.
    #[inline]
    pub fn rot(&self, h: u32) -> u32 {
        twin(self.prev(h))
    }
    pub fn edge_count(&self) -> usize {
        self.e_dead.len()
    }

    /// Calls `f` with every outgoing halfedge of `v`.
    #[inline]
    pub fn for_out(&self, v: u32, mut f: impl FnMut(u32)) {
        let start = self.v_out[v as usize];
        if start == INVALID {
            return;
        }
        let mut h = start;
        let mut guard = 0usize;
        loop {
            f(h);
            h = self.rot(h);
            guard += 1;
            if h == start || guard > 1 << 20 {
                break;
            }
        }
    }

    pub fn valence(&self, v: u32) -> u32 {
        let mut n = 0;
        self.for_out(v, |_| n += 1);
        n
    }

    pub fn find_halfedge(&self, a: u32, b: u32) -> u32 {
        let mut r = INVALID;
        self.for_out(a, |h| {
            if self.to(h) == b {
                r = h;
            }
        });
        r
    }

    fn set_next(&mut self, h: u32, n: u32) {
        self.h[h as usize].next = n;
        self.h[n as usize].prev = h;
    }

    fn new_edge(&mut self, start: u32, end: u32) -> u32 {
        let e = self.e_dead.len() as u32;
        self.e_dead.push(false);
        for (to, _) in [(end, 0), (start, 1)] {
            self.h.push(Half { to, ..Half::UNSET });
        }
        2 * e
    }

    fn new_face(&mut self) -> u32 {
        self.f_h.push(INVALID);
        self.f_dead.push(false);
        (self.f_h.len() - 1) as u32
    }

    pub fn new_vertex(&mut self, p: [f64; 3]) -> u32 {
        self.pos.push(p);
        self.v_out.push(INVALID);
        self.v_dead.push(false);
        (self.pos.len() - 1) as u32
    }

    fn adjust_outgoing(&mut self, v: u32) {
        let mut b = INVALID;
        self.for_out(v, |h| {
            if b == INVALID && self.is_boundary_h(h) {
                b = h;
            }
        });
        if b != INVALID {
            self.v_out[v as usize] = b;
        }
    }

    /// Splits edge `e` by the new vertex `v` (already created). Returns the new edges
    /// `[continuation of e, others...]`: the first is the other half of `e`.
    pub fn split(&mut self, e: u32, v: u32) -> [u32; 3] {
        let h0 = 2 * e;
        let o0 = 2 * e + 1;
        let v2 = self.to(o0);
        let e1 = self.new_edge(v, v2);
        let t1 = twin(e1);
        let f0 = self.face(h0);
        let f3 = self.face(o0);
        self.v_out[v as usize] = h0;
        self.h[o0 as usize].to = v;
        let mut out = [e1 >> 1, INVALID, INVALID];
        if f0 != INVALID {
            let h1 = self.next(h0);
            let h2 = self.next(h1);
            let v1 = self.to(h1);
            let e0 = self.new_edge(v, v1);
            let t0 = twin(e0);
            out[1] = e0 >> 1;
            let f1 = self.new_face();
            self.f_h[f0 as usize] = h0;
            self.f_h[f1 as usize] = h2;
            for (h, f) in [(h1, f0), (t0, f0), (h0, f0), (h2, f1), (t1, f1), (e0, f1)] {
                self.h[h as usize].face = f;
            }
            self.set_next(h0, h1);
            self.set_next(h1, t0);
            self.set_next(t0, h0);
            self.set_next(e0, h2);
            self.set_next(h2, t1);
            self.set_next(t1, e0);
        } else {
            let p = self.prev(h0);
            self.set_next(p, t1);
            self.set_next(t1, h0);
        }
        if f3 != INVALID {
            let o1 = self.next(o0);
            let o2 = self.next(o1);
            let v3 = self.to(o1);
            let e2 = self.new_edge(v, v3);
            let t2 = twin(e2);
            out[2] = e2 >> 1;
            let f2 = self.new_face();
            self.f_h[f2 as usize] = o1;
            self.f_h[f3 as usize] = o0;
            for (h, f) in [(o1, f2), (t2, f2), (e1, f2), (o2, f3), (o0, f3), (e2, f3)] {
                self.h[h as usize].face = f;
            }
            self.set_next(e1, o1);
            self.set_next(o1, t2);
            self.set_next(t2, e1);
            self.set_next(o0, e2);
            self.set_next(e2, o2);
            self.set_next(o2, o0);
        } else {
            let n = self.next(o0);
            self.set_next(e1, n);
            self.set_next(o0, e1);
            self.v_out[v as usize] = e1;
        }
        if self.v_out[v2 as usize] == h0 {
            self.v_out[v2 as usize] = t1;
        }
        out
    }

    /// PMP's `is_collapse_ok` (link condition with the boundary rules) plus a valence guard
    /// so that no vertex drops below valence 3 (interior) / 2 (boundary).
    pub fn collapse_ok(&self, h0: u32) -> bool {
        let o0 = twin(h0);
        let v0 = self.to(o0);
        let v1 = self.to(h0);
        if self.is_boundary_v(v0)
            && self.is_boundary_v(v1)
            && !self.is_boundary_h(h0)
            && !self.is_boundary_h(o0)
        {
            return false;
        }
        let mut vl = INVALID;
        let mut vr = INVALID;
        if !self.is_boundary_h(h0) {
            let h1 = self.next(h0);
            let h2 = self.next(h1);
            vl = self.to(h1);
            if self.is_boundary_h(twin(h1)) && self.is_boundary_h(twin(h2)) {
                return false;
            }
            if self.valence(vl) <= if self.is_boundary_v(vl) { 2 } else { 3 } {
                return false;
            }
        }
        if !self.is_boundary_h(o0) {
            let o1 = self.next(o0);
            let o2 = self.next(o1);
            vr = self.to(o1);
            if self.is_boundary_h(twin(o1)) && self.is_boundary_h(twin(o2)) {
                return false;
            }
            if self.valence(vr) <= if self.is_boundary_v(vr) { 2 } else { 3 } {
                return false;
            }
        }
        if vl == vr {
            return false;
        }
        // Link condition: the only common neighbours of v0 and v1 are vl and vr. v1's ring
        // is gathered once (up to `LINK_RING` entries, the usual case) so that the test walks
        // two rings instead of one ring per neighbour of v0 (the walks are cache misses).
        let mut ring = [INVALID; LINK_RING];
        let mut len = 0usize;
        self.for_out(v1, |h| {
            if len < LINK_RING {
                ring[len] = self.to(h);
            }
            len += 1;
        });
        let mut ok = true;
        self.for_out(v0, |h| {
            let vv = self.to(h);
            if ok && vv != v1 && vv != vl && vv != vr {
                let common = if len <= LINK_RING {
                    ring[..len].contains(&vv)
                } else {
                    self.find_halfedge(v1, vv) != INVALID
                };
                if common {
                    ok = false;
                }
            }
        });
        ok
    }

    /// Collapses halfedge `h` (from `v0` to `v1`): `v0` disappears, `v1` keeps its position.
    /// Returns the edges deleted by the loop removals paired with the edge each merged into,
    /// so that callers can carry edge flags over.
    pub fn collapse(&mut self, h: u32) -> [(u32, u32); 2] {
        let h0 = h;
        let h1 = self.prev(h0);
        let o0 = twin(h0);
        let o1 = self.next(o0);
        self.remove_edge(h0);
        let mut merged = [(INVALID, INVALID); 2];
        if self.next(self.next(h1)) == h1 {
            merged[0] = self.remove_loop(h1);
        }
        if self.next(self.next(o1)) == o1 {
            merged[1] = self.remove_loop(o1);
        }
        merged
    }

    fn remove_edge(&mut self, h: u32) {
        let hn = self.next(h);
        let hp = self.prev(h);
        let o = twin(h);
        let on = self.next(o);
        let op = self.prev(o);
        let fh = self.face(h);
        let fo = self.face(o);
        let vh = self.to(h);
        let vo = self.to(o);
        let mut incoming = Vec::new();
        self.for_out(vo, |hc| incoming.push(twin(hc)));
        for t in incoming {
            self.h[t as usize].to = vh;
        }
        self.set_next(hp, hn);
        self.set_next(op, on);
        if fh != INVALID {
            self.f_h[fh as usize] = hn;
        }
        if fo != INVALID {
            self.f_h[fo as usize] = on;
        }
        if self.v_out[vh as usize] == o {
            self.v_out[vh as usize] = hn;
        }
        self.adjust_outgoing(vh);
        self.v_out[vo as usize] = INVALID;
        self.v_dead[vo as usize] = true;
        self.e_dead[(h >> 1) as usize] = true;
    }

    /// Removes the two-edge loop at `h`; returns (deleted edge, kept edge).
    fn remove_loop(&mut self, h: u32) -> (u32, u32) {
        let h0 = h;
        let h1 = self.next(h0);
        let o0 = twin(h0);
        let o1 = twin(h1);
        let v0 = self.to(h0);
        let v1 = self.to(h1);
        let fh = self.face(h0);
        let fo = self.face(o0);
        let on = self.next(o0);
        self.set_next(h1, on);
        let op = self.prev(o0);
        self.set_next(op, h1);
        self.h[h1 as usize].face = fo;
        self.v_out[v0 as usize] = h1;
        self.adjust_outgoing(v0);
        self.v_out[v1 as usize] = o1;
        self.adjust_outgoing(v1);
        if fo != INVALID && self.f_h[fo as usize] == o0 {
            self.f_h[fo as usize] = h1;
        }
        if fh != INVALID {
            self.f_dead[fh as usize] = true;
        }
        self.e_dead[(h0 >> 1) as usize] = true;
        (h0 >> 1, h1 >> 1)
    }

    /// PMP's `is_flip_ok`: interior edge whose flipped diagonal does not exist yet.
    pub fn flip_ok(&self, e: u32) -> bool {
        if self.is_boundary_e(e) {
            return false;
        }
        let c = self.to(self.next(2 * e));
        let d = self.to(self.next(2 * e + 1));
        c != d && self.find_halfedge(c, d) == INVALID
    }

    pub fn flip(&mut self, e: u32) {
        let a0 = 2 * e;
        let b0 = 2 * e + 1;
        let a1 = self.next(a0);
        let a2 = self.next(a1);
        let b1 = self.next(b0);
        let b2 = self.next(b1);
        let va0 = self.to(a0);
        let va1 = self.to(a1);
        let vb0 = self.to(b0);
        let vb1 = self.to(b1);
        let fa = self.face(a0);
        let fb = self.face(b0);
        self.h[a0 as usize].to = va1;
        self.h[b0 as usize].to = vb1;
        self.set_next(a0, a2);
        self.set_next(a2, b1);
        self.set_next(b1, a0);
        self.set_next(b0, b2);
        self.set_next(b2, a1);
        self.set_next(a1, b0);
        self.h[a1 as usize].face = fb;
        self.h[b1 as usize].face = fa;
        self.f_h[fa as usize] = a0;
        self.f_h[fb as usize] = b0;
        if self.v_out[va0 as usize] == b0 {
            self.v_out[va0 as usize] = a1;
        }
        if self.v_out[vb0 as usize] == a0 {
            self.v_out[vb0 as usize] = b1;
        }
    }

    /// The three vertices of a live face.
    #[inline]
    pub fn face_vertices(&self, f: u32) -> [u32; 3] {
        let h = self.f_h[f as usize];
        let h1 = self.next(h);
        [self.from(h), self.to(h), self.to(h1)]
    }

    /// Compacts live vertices and faces into a new mesh; returns it and, per output
    /// vertex, the internal vertex id.
    pub fn to_trimesh(&self) -> (TriMesh, Vec<u32>) {
        let mut new_id = vec![INVALID; self.pos.len()];
        let mut old_id = Vec::new();
        let mut positions = Vec::new();
        for (v, dead) in self.v_dead.iter().enumerate() {
            if !dead && self.v_out[v] != INVALID {
                new_id[v] = positions.len() as u32;
                positions.push(self.pos[v]);
                old_id.push(v as u32);
            }
        }
        let faces = (0..self.f_h.len() as u32)
            .filter(|&f| !self.f_dead[f as usize])
            .map(|f| self.face_vertices(f).map(|v| new_id[v as usize]))
            .collect();
        (
            TriMesh {
                positions,
                faces,
                ..TriMesh::default()
            },
            old_id,
        )
    }
}

/// Refuses what the halfedge structure cannot represent, naming the element: faces with a
/// repeated vertex, non-manifold edges and vertices, inconsistently oriented edges.
pub(crate) fn check_manifold(mesh: &TriMesh, topo: &Topology) -> Result<(), RemeshError> {
    for (f, face) in mesh.faces.iter().enumerate() {
        if face[0] == face[1] || face[1] == face[2] || face[0] == face[2] {
            return Err(RemeshError::RepeatedVertex {
                face: f as u32,
                vertices: *face,
            });
        }
    }
    if let Some(&[a, b]) = topo.non_manifold_edges().first() {
        return Err(RemeshError::NonManifoldEdge { a, b });
    }
    if let Some(v) = topo.non_manifold_vertices().first() {
        return Err(RemeshError::NonManifoldVertex { vertex: v.0 });
    }
    if let Some(&[a, b]) = topo.inconsistent_edges().first() {
        return Err(RemeshError::InconsistentOrientation { a, b });
    }
    Ok(())
}
