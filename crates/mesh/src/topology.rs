//! Connectivity derived from the face list once: halfedges and twins, edges, boundary
//! loops in order, ordered one-rings, connected components, and the defects a scan
//! brings (non-manifold edges and vertices, inconsistently oriented edges).
//!
//! Halfedge `h = 3·f + k` runs from `faces[f][k]` to `faces[f][(k + 1) % 3]`, so
//! `next`, `prev` and `face` are arithmetic and only twins are stored.
//! Everything is built in linear time (a CSR bucket per vertex, no hash map), so that
//! 1M faces take well under a second.

use crate::{FaceId, MeshError, TriMesh, VertexId};

/// Marks "no such halfedge / edge / vertex".
pub const INVALID: u32 = u32::MAX;

/// Derived connectivity of a [`TriMesh`]. Build once with [`Topology::build`] and pass it to
/// every algorithm that needs it; it is never rebuilt per iteration.
#[derive(Clone, Debug)]
pub struct Topology {
    vertex_count: usize,
    faces: Vec<[u32; 3]>,
    /// Opposite halfedge across a manifold, consistently oriented edge; `INVALID` otherwise.
    twin: Vec<u32>,
    /// Undirected edge of each halfedge.
    halfedge_edge: Vec<u32>,
    /// Undirected edges as (smaller, larger) vertex index.
    edges: Vec<[u32; 2]>,
    /// Number of faces on each edge.
    edge_face_count: Vec<u32>,
    /// Edges whose two faces traverse them in the same direction.
    inconsistent_edges: Vec<u32>,
    /// CSR: faces incident to each vertex, as halfedges leaving it.
    vertex_out_offsets: Vec<u32>,
    vertex_out: Vec<u32>,
    referenced: Vec<bool>,
    boundary_vertex: Vec<bool>,
    non_manifold_vertex: Vec<bool>,
    boundary_loops: Vec<Vec<VertexId>>,
    open_boundary_chains: Vec<Vec<VertexId>>,
    /// CSR: ordered one-ring of each manifold vertex (empty for others).
    ring_offsets: Vec<u32>,
    ring: Vec<u32>,
    face_component: Vec<u32>,
    vertex_component: Vec<u32>,
    component_count: usize,
}

impl Topology {
    /// Derives the connectivity of `mesh`. Fails only if a face index is out of range.
    pub fn build(mesh: &TriMesh) -> Result<Self, MeshError> {
        let n = mesh.positions.len();
        for (f, face) in mesh.faces.iter().enumerate() {
            for &i in face {
                if i as usize >= n {
                    return Err(MeshError::FaceIndexOutOfRange {
                        face: FaceId(f as u32),
                        index: i,
                        vertex_count: n,
                    });
                }
            }
        }
        if mesh.faces.len() * 3 >= INVALID as usize {
            return Err(MeshError::TooLarge {
                what: "faces",
                count: mesh.faces.len(),
            });
        }
        let faces = mesh.faces.clone();
        let nh = faces.len() * 3;
        let head = |h: usize| faces[h / 3][(h % 3 + 1) % 3];
        let tail = |h: usize| faces[h / 3][h % 3];

        // Outgoing halfedges per vertex (CSR), used for one-rings and fans.
        let mut vertex_out_offsets = vec![0u32; n + 1];
        for h in 0..nh {
            vertex_out_offsets[tail(h) as usize + 1] += 1;
        }
        for v in 0..n {
            vertex_out_offsets[v + 1] += vertex_out_offsets[v];
        }
        let mut fill = vertex_out_offsets.clone();
        let mut vertex_out = vec![0u32; nh];
        for h in 0..nh {
            let t = tail(h) as usize;
            vertex_out[fill[t] as usize] = h as u32;
            fill[t] += 1;
        }
        let referenced: Vec<bool> = (0..n)
            .map(|v| vertex_out_offsets[v + 1] > vertex_out_offsets[v])
            .collect();

        // Halfedges bucketed by their smaller endpoint; within a bucket, grouped by the larger.
        let mut key_offsets = vec![0u32; n + 1];
        for h in 0..nh {
            let m = tail(h).min(head(h)) as usize;
            key_offsets[m + 1] += 1;
        }
        for v in 0..n {
            key_offsets[v + 1] += key_offsets[v];
        }
        let mut fill = key_offsets.clone();
        let mut by_key = vec![0u32; nh];
        for h in 0..nh {
            let m = tail(h).min(head(h)) as usize;
            by_key[fill[m] as usize] = h as u32;
            fill[m] += 1;
        }
        let mut twin = vec![INVALID; nh];
        let mut halfedge_edge = vec![INVALID; nh];
        let mut edges = Vec::with_capacity(nh / 2 + 1);
        let mut edge_face_count = Vec::with_capacity(nh / 2 + 1);
        let mut inconsistent_edges = Vec::new();
        let mut bucket: Vec<(u32, u32)> = Vec::new();
        for m in 0..n {
            let (s, e) = (key_offsets[m] as usize, key_offsets[m + 1] as usize);
            bucket.clear();
            bucket.extend(
                by_key[s..e]
                    .iter()
                    .map(|&h| (tail(h as usize).max(head(h as usize)), h)),
            );
            bucket.sort_unstable();
            let mut i = 0;
            while i < bucket.len() {
                let other = bucket[i].0;
                let mut j = i;
                while j < bucket.len() && bucket[j].0 == other {
                    j += 1;
                }
                let e = edges.len() as u32;
                edges.push([m as u32, other]);
                edge_face_count.push((j - i) as u32);
                for &(_, h) in &bucket[i..j] {
                    halfedge_edge[h as usize] = e;
                }
                if j - i == 2 {
                    let (h0, h1) = (bucket[i].1 as usize, bucket[i + 1].1 as usize);
                    if tail(h0) == head(h1) {
                        twin[h0] = h1 as u32;
                        twin[h1] = h0 as u32;
                    } else {
                        inconsistent_edges.push(e);
                    }
                }
                i = j;
            }
        }

        // Boundary halfedges: on an edge with exactly one face.
        let is_boundary_he = |h: usize| edge_face_count[halfedge_edge[h] as usize] == 1;
        let mut boundary_vertex = vec![false; n];
        for h in 0..nh {
            if is_boundary_he(h) {
                boundary_vertex[tail(h) as usize] = true;
                boundary_vertex[head(h) as usize] = true;
            }
        }

        // Non-manifold vertices: incident faces that do not form one fan joined by
        // two-face edges (a bowtie, or a vertex on a non-manifold edge whose fans split).
        let mut non_manifold_vertex = vec![false; n];
        let mut parent: Vec<usize> = Vec::new();
        for v in 0..n {
            let outs =
                &vertex_out[vertex_out_offsets[v] as usize..vertex_out_offsets[v + 1] as usize];
            if outs.len() <= 1 {
                continue;
            }
            parent.clear();
            parent.extend(0..outs.len());
            fn find(p: &mut [usize], mut x: usize) -> usize {
                while p[x] != x {
                    p[x] = p[p[x]];
                    x = p[x];
                }
                x
            }
            for a in 0..outs.len() {
                let ha = outs[a] as usize;
                let ea = [
                    halfedge_edge[ha],
                    halfedge_edge[3 * (ha / 3) + (ha % 3 + 2) % 3],
                ];
                for (b, &hb) in outs.iter().enumerate().skip(a + 1) {
                    let hb = hb as usize;
                    let eb = [
                        halfedge_edge[hb],
                        halfedge_edge[3 * (hb / 3) + (hb % 3 + 2) % 3],
                    ];
                    let shares = ea
                        .iter()
                        .any(|x| edge_face_count[*x as usize] == 2 && eb.contains(x));
                    if shares {
                        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
                        parent[ra] = rb;
                    }
                }
            }
            let root = find(&mut parent, 0);
            if (1..outs.len()).any(|a| find(&mut parent, a) != root) {
                non_manifold_vertex[v] = true;
            }
        }

        let mut topo = Topology {
            vertex_count: n,
            faces,
            twin,
            halfedge_edge,
            edges,
            edge_face_count,
            inconsistent_edges,
            vertex_out_offsets,
            vertex_out,
            referenced,
            boundary_vertex,
            non_manifold_vertex,
            boundary_loops: Vec::new(),
            open_boundary_chains: Vec::new(),
            ring_offsets: Vec::new(),
            ring: Vec::new(),
            face_component: Vec::new(),
            vertex_component: Vec::new(),
            component_count: 0,
        };
        (topo.boundary_loops, topo.open_boundary_chains) = topo.trace_boundary_loops();
        topo.build_rings();
        topo.label_components();
        Ok(topo)
    }

    fn tail(&self, h: usize) -> u32 {
        self.faces[h / 3][h % 3]
    }

    fn head(&self, h: usize) -> u32 {
        self.faces[h / 3][(h % 3 + 1) % 3]
    }

    fn is_boundary_halfedge(&self, h: usize) -> bool {
        self.edge_face_count[self.halfedge_edge[h] as usize] == 1
    }

    /// Boundary loops follow face orientation: each step is a boundary halfedge, and the next
    /// one leaves the current head inside the same fan (found by rotating through twins).
    /// Where a non-manifold or inconsistent edge cuts the fan, the walk closes the loop if the
    /// start halfedge leaves the current vertex, else takes any unused boundary halfedge
    /// leaving it; a walk that gets stuck is returned as an open chain (second value) instead
    /// of being closed with an edge that does not exist.
    fn trace_boundary_loops(&self) -> (Vec<Vec<VertexId>>, Vec<Vec<VertexId>>) {
        let nh = self.faces.len() * 3;
        let mut used = vec![false; nh];
        let mut loops = Vec::new();
        let mut chains = Vec::new();
        for start in 0..nh {
            if used[start] || !self.is_boundary_halfedge(start) {
                continue;
            }
            let mut lp = Vec::new();
            let mut h = start;
            let closed = loop {
                used[h] = true;
                lp.push(VertexId(self.tail(h)));
                // Rotate around head(h) through twins until a boundary halfedge leaves it.
                let mut g = Self::next(h as u32) as usize;
                let mut guard = 0usize;
                while !self.is_boundary_halfedge(g) {
                    let t = self.twin[g];
                    guard += 1;
                    if t == INVALID || guard > nh {
                        break;
                    }
                    g = Self::next(t) as usize;
                }
                let found = if self.is_boundary_halfedge(g) && (!used[g] || g == start) {
                    Some(g)
                } else {
                    let outs = self.outgoing(VertexId(self.head(h)));
                    if outs.contains(&(start as u32)) {
                        Some(start)
                    } else {
                        outs.iter()
                            .map(|&x| x as usize)
                            .find(|&x| self.is_boundary_halfedge(x) && !used[x])
                    }
                };
                match found {
                    Some(g) if g == start => break true,
                    Some(g) => h = g,
                    None => break false,
                }
            };
            if closed {
                loops.push(lp);
            } else {
                lp.push(VertexId(self.head(h)));
                chains.push(lp);
            }
        }
        (loops, chains)
    }

    fn build_rings(&mut self) {
        let n = self.vertex_count;
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0u32);
        let mut ring = Vec::with_capacity(self.faces.len() * 3 + n);
        for v in 0..n {
            if let Some(r) = self.walk_ring(v) {
                ring.extend(r);
            }
            offsets.push(ring.len() as u32);
        }
        self.ring_offsets = offsets;
        self.ring = ring;
    }

    /// The neighbours of a manifold vertex counter-clockwise (seen from the normal side).
    /// For a boundary vertex the walk starts at the boundary halfedge leaving it, so the ring
    /// has one more entry than faces.
    fn walk_ring(&self, v: usize) -> Option<Vec<u32>> {
        if !self.referenced[v] || self.non_manifold_vertex[v] {
            return None;
        }
        let outs = self.outgoing(VertexId(v as u32));
        let start = if self.boundary_vertex[v] {
            *outs
                .iter()
                .find(|&&h| self.is_boundary_halfedge(h as usize))? as usize
        } else {
            outs[0] as usize
        };
        let mut r = Vec::with_capacity(outs.len() + 1);
        let mut h = start;
        loop {
            r.push(self.head(h));
            let p = Self::prev(h as u32) as usize;
            let t = self.twin[p];
            if t == INVALID {
                if self.is_boundary_halfedge(p) {
                    r.push(self.tail(p));
                    break;
                }
                return None; // fan interrupted by an inconsistent edge
            }
            h = t as usize;
            if h == start {
                break;
            }
            if r.len() > outs.len() + 1 {
                return None;
            }
        }
        let expected = if self.boundary_vertex[v] {
            outs.len() + 1
        } else {
            outs.len()
        };
        (r.len() == expected).then_some(r)
    }

    fn label_components(&mut self) {
        let n = self.vertex_count;
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn find(p: &mut [u32], mut x: u32) -> u32 {
            while p[x as usize] != x {
                p[x as usize] = p[p[x as usize] as usize];
                x = p[x as usize];
            }
            x
        }
        for f in &self.faces {
            let r0 = find(&mut parent, f[0]);
            for &w in &f[1..] {
                let r = find(&mut parent, w);
                let r0 = find(&mut parent, r0);
                if r != r0 {
                    parent[r.max(r0) as usize] = r.min(r0);
                }
            }
            let _ = r0;
        }
        let mut label = vec![INVALID; n];
        let mut count = 0u32;
        // Components numbered in order of their first face, so the numbering is stable.
        let mut face_component = Vec::with_capacity(self.faces.len());
        for fi in 0..self.faces.len() {
            let r = find(&mut parent, self.faces[fi][0]) as usize;
            if label[r] == INVALID {
                label[r] = count;
                count += 1;
            }
            face_component.push(label[r]);
        }
        let mut vertex_component = vec![INVALID; n];
        for (v, comp) in vertex_component.iter_mut().enumerate() {
            if self.referenced[v] {
                let r = find(&mut parent, v as u32) as usize;
                *comp = label[r];
            }
        }
        self.face_component = face_component;
        self.vertex_component = vertex_component;
        self.component_count = count as usize;
    }

    /// Heap bytes held (from the capacities of its arrays), for memory budgets.
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        let loops: usize = self
            .boundary_loops
            .iter()
            .chain(&self.open_boundary_chains)
            .map(|l| l.capacity() * 4)
            .sum();
        self.faces.capacity() * size_of::<[u32; 3]>()
            + (self.twin.capacity() + self.halfedge_edge.capacity()) * 4
            + self.edges.capacity() * size_of::<[u32; 2]>()
            + (self.edge_face_count.capacity() + self.inconsistent_edges.capacity()) * 4
            + (self.vertex_out_offsets.capacity() + self.vertex_out.capacity()) * 4
            + self.referenced.capacity()
            + self.boundary_vertex.capacity()
            + self.non_manifold_vertex.capacity()
            + (self.boundary_loops.capacity() + self.open_boundary_chains.capacity())
                * size_of::<Vec<VertexId>>()
            + loops
            + (self.ring_offsets.capacity() + self.ring.capacity()) * 4
            + (self.face_component.capacity() + self.vertex_component.capacity()) * 4
    }

    /// The halfedge after `h` in its face.
    #[inline]
    pub fn next(h: u32) -> u32 {
        3 * (h / 3) + (h % 3 + 1) % 3
    }

    /// The halfedge before `h` in its face.
    #[inline]
    pub fn prev(h: u32) -> u32 {
        3 * (h / 3) + (h % 3 + 2) % 3
    }

    /// The face of halfedge `h`.
    #[inline]
    pub fn face(h: u32) -> FaceId {
        FaceId(h / 3)
    }

    /// Vertex a halfedge leaves.
    #[inline]
    pub fn from_vertex(&self, h: u32) -> VertexId {
        VertexId(self.tail(h as usize))
    }

    /// Vertex a halfedge enters.
    #[inline]
    pub fn to_vertex(&self, h: u32) -> VertexId {
        VertexId(self.head(h as usize))
    }

    /// The opposite halfedge across a manifold, consistently oriented edge.
    #[inline]
    pub fn twin(&self, h: u32) -> Option<u32> {
        let t = self.twin[h as usize];
        (t != INVALID).then_some(t)
    }

    /// Undirected edge of a halfedge, indexing [`Topology::edges`].
    #[inline]
    pub fn edge_of(&self, h: u32) -> u32 {
        self.halfedge_edge[h as usize]
    }

    /// Undirected edges as (smaller, larger) vertex index.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Number of faces on each edge (1 boundary, 2 interior, more non-manifold).
    pub fn edge_face_counts(&self) -> &[u32] {
        &self.edge_face_count
    }

    /// Halfedges leaving `v` (one per incident face).
    pub fn outgoing(&self, v: VertexId) -> &[u32] {
        let i = v.idx();
        &self.vertex_out
            [self.vertex_out_offsets[i] as usize..self.vertex_out_offsets[i + 1] as usize]
    }

    /// Faces incident to `v`, in no particular order.
    pub fn vertex_faces(&self, v: VertexId) -> impl Iterator<Item = FaceId> + '_ {
        self.outgoing(v).iter().map(|&h| Self::face(h))
    }

    /// Number of vertices of the mesh this was built from (referenced or not).
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Does any face use `v`?
    pub fn is_referenced(&self, v: VertexId) -> bool {
        self.referenced[v.idx()]
    }

    /// Number of vertices some face uses.
    pub fn referenced_vertex_count(&self) -> usize {
        self.referenced.iter().filter(|r| **r).count()
    }

    /// Is `v` on a boundary edge?
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.boundary_vertex[v.idx()]
    }

    /// Is `v` used, manifold, and not on the boundary: the vertices whose θ(v) must be 2π.
    pub fn is_interior_vertex(&self, v: VertexId) -> bool {
        let i = v.idx();
        self.referenced[i] && !self.boundary_vertex[i] && !self.non_manifold_vertex[i]
    }

    /// Is `v` a non-manifold vertex (its faces form more than one fan)?
    pub fn is_non_manifold_vertex(&self, v: VertexId) -> bool {
        self.non_manifold_vertex[v.idx()]
    }

    /// Neighbours of a manifold vertex in counter-clockwise order; for a boundary vertex the
    /// first and last are its two boundary neighbours. `None` for unused or non-manifold
    /// vertices, and for vertices whose fan is cut by an inconsistently oriented edge.
    pub fn one_ring(&self, v: VertexId) -> Option<&[u32]> {
        let i = v.idx();
        let (s, e) = (
            self.ring_offsets[i] as usize,
            self.ring_offsets[i + 1] as usize,
        );
        (e > s).then(|| &self.ring[s..e])
    }

    /// Boundary loops, each a cycle of vertices in face orientation (consecutive vertices,
    /// last to first included, are a boundary halfedge), in a deterministic order. On a
    /// mesh with non-manifold or inconsistently oriented edges some boundary halfedges may not
    /// close into a cycle; they are in [`Topology::open_boundary_chains`], not here.
    pub fn boundary_loops(&self) -> &[Vec<VertexId>] {
        &self.boundary_loops
    }

    /// Boundary paths that do not close into a cycle (only on meshes with non-manifold or
    /// inconsistently oriented edges): consecutive vertices are a boundary halfedge in face
    /// orientation, but last to first is not. Empty on edge-manifold, oriented meshes.
    pub fn open_boundary_chains(&self) -> &[Vec<VertexId>] {
        &self.open_boundary_chains
    }

    /// Number of connected components (faces joined through shared vertices).
    pub fn component_count(&self) -> usize {
        self.component_count
    }

    /// Component of each face, numbered by first appearance.
    pub fn face_components(&self) -> &[u32] {
        &self.face_component
    }

    /// Component of each vertex (`INVALID` for unused vertices).
    pub fn vertex_components(&self) -> &[u32] {
        &self.vertex_component
    }

    /// Euler characteristic V − E + F over referenced vertices.
    pub fn euler_characteristic(&self) -> i64 {
        self.referenced_vertex_count() as i64 - self.edges.len() as i64 + self.faces.len() as i64
    }

    /// Edges with more than two faces.
    pub fn non_manifold_edges(&self) -> Vec<[u32; 2]> {
        self.edges
            .iter()
            .zip(&self.edge_face_count)
            .filter(|(_, c)| **c > 2)
            .map(|(e, _)| *e)
            .collect()
    }

    /// Non-manifold vertices.
    pub fn non_manifold_vertices(&self) -> Vec<VertexId> {
        (0..self.vertex_count as u32)
            .filter(|&v| self.non_manifold_vertex[v as usize])
            .map(VertexId)
            .collect()
    }

    /// Edges whose two faces run them in the same direction (orientation flips).
    pub fn inconsistent_edges(&self) -> Vec<[u32; 2]> {
        self.inconsistent_edges
            .iter()
            .map(|&e| self.edges[e as usize])
            .collect()
    }

    /// Per component: its Euler characteristic, whether it is closed (no boundary edge), and
    /// for closed, edge-manifold components the genus (2 − χ) / 2.
    pub fn component_summaries(&self) -> Vec<ComponentSummary> {
        let c = self.component_count;
        let mut s = vec![ComponentSummary::default(); c];
        for &comp in &self.face_component {
            s[comp as usize].faces += 1;
        }
        for (v, &comp) in self.vertex_component.iter().enumerate() {
            if comp != INVALID {
                s[comp as usize].vertices += 1;
                if self.boundary_vertex[v] {
                    s[comp as usize].closed = false;
                }
            }
        }
        let mut manifold = vec![true; c];
        for (e, ends) in self.edges.iter().enumerate() {
            let comp = self.vertex_component[ends[0] as usize] as usize;
            s[comp].edges += 1;
            if self.edge_face_count[e] > 2 {
                manifold[comp] = false;
            }
        }
        for (i, sum) in s.iter_mut().enumerate() {
            sum.euler_characteristic = sum.vertices as i64 - sum.edges as i64 + sum.faces as i64;
            if sum.closed && manifold[i] && sum.euler_characteristic % 2 == 0 {
                sum.genus = Some((2 - sum.euler_characteristic) / 2);
            }
        }
        s
    }
}

/// Counts of one connected component.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ComponentSummary {
    /// Referenced vertices.
    pub vertices: usize,
    /// Undirected edges.
    pub edges: usize,
    /// Triangles.
    pub faces: usize,
    /// V − E + F.
    pub euler_characteristic: i64,
    /// No boundary edge.
    pub closed: bool,
    /// (2 − χ) / 2 for closed, edge-manifold components.
    pub genus: Option<i64>,
}

impl Default for ComponentSummary {
    fn default() -> Self {
        Self {
            vertices: 0,
            edges: 0,
            faces: 0,
            euler_characteristic: 0,
            closed: true,
            genus: None,
        }
    }
}
