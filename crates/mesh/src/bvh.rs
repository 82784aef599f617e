//! A bounding volume hierarchy over the faces (and, separately, the vertices) of a mesh for
//! closest-point, ray and nearest-vertex queries.
//!
//! The tree is a flat node array built top-down by median split on the longest axis of the
//! centroid bounds (`select_nth_unstable`, so O(n log n) overall); a node's two children are
//! stored next to each other. Triangles are copied into leaf order so queries touch memory
//! sequentially. Queries are exact: point–triangle distance by Ericson's region test
//! (Real-Time Collision Detection §5.1.5), rays by Möller–Trumbore.

use crate::vec3::{add, cross, dot, norm2, scale, sub};
use crate::{FaceId, TriMesh, VertexId};

/// Primitives per leaf at most: small enough that a leaf test is cheap, large enough to keep
/// the tree shallow.
const LEAF_SIZE: usize = 4;

/// Slack on the Möller–Trumbore barycentric tests, relative: a ray through a shared edge
/// or vertex hits (at least) one of the faces despite rounding ("watertight-ish"; exact
/// watertightness needs the Woop et al. 2013 shear, not worth it for our queries).
const BARY_SLACK: f64 = 1e-12;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Leaf: first primitive in leaf order; internal: index of the left child (right = +1).
    first: u32,
    /// Leaf: number of primitives (> 0); internal: 0.
    count: u32,
}

/// A tree over boxes: nodes and the primitive ids in leaf order.
#[derive(Clone, Debug, Default)]
struct Tree {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Tree {
    fn build(lo: &[[f64; 3]], hi: &[[f64; 3]]) -> Tree {
        let n = lo.len();
        if n == 0 {
            return Tree::default();
        }
        let centroid: Vec<[f64; 3]> = lo
            .iter()
            .zip(hi)
            .map(|(a, b)| scale(add(*a, *b), 0.5))
            .collect();
        let mut order: Vec<u32> = (0..n as u32).collect();
        let mut nodes = Vec::with_capacity(2 * n / LEAF_SIZE + 1);
        nodes.push(Node {
            lo: [0.0; 3],
            hi: [0.0; 3],
            first: 0,
            count: n as u32,
        });
        // (node, start, end) still to split.
        let mut stack = vec![(0usize, 0usize, n)];
        while let Some((ni, s, e)) = stack.pop() {
            let (mut blo, mut bhi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for &i in &order[s..e] {
                let i = i as usize;
                for k in 0..3 {
                    blo[k] = blo[k].min(lo[i][k]);
                    bhi[k] = bhi[k].max(hi[i][k]);
                    clo[k] = clo[k].min(centroid[i][k]);
                    chi[k] = chi[k].max(centroid[i][k]);
                }
            }
            nodes[ni].lo = blo;
            nodes[ni].hi = bhi;
            if e - s <= LEAF_SIZE {
                nodes[ni].first = s as u32;
                nodes[ni].count = (e - s) as u32;
                continue;
            }
            let ext = sub(chi, clo);
            let axis = if ext[0] >= ext[1] && ext[0] >= ext[2] {
                0
            } else if ext[1] >= ext[2] {
                1
            } else {
                2
            };
            let mid = s + (e - s) / 2;
            order[s..e].select_nth_unstable_by(mid - s, |&a, &b| {
                centroid[a as usize][axis]
                    .total_cmp(&centroid[b as usize][axis])
                    .then(a.cmp(&b))
            });
            let left = nodes.len();
            let empty = Node {
                lo: [0.0; 3],
                hi: [0.0; 3],
                first: 0,
                count: 0,
            };
            nodes.push(empty);
            nodes.push(empty);
            nodes[ni].first = left as u32;
            nodes[ni].count = 0;
            stack.push((left + 1, mid, e));
            stack.push((left, s, mid));
        }
        Tree { nodes, order }
    }

    fn bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<Node>() + self.order.capacity() * 4
    }
}

/// The traversal stack of one query, on the call stack. A query used to start from
/// `vec![0]` and grow it by reallocation: several heap calls per query, which in the remesher's
/// parallel closest-point passes (1.4M queries on a 428k-face scan) made the threads queue on
/// the allocator's locks (a quarter of the run in futex calls, by `perf`). The tree is split
/// at the median, so its depth is at most log2 of the face count plus one and a depth-first
/// stack holds at most depth + 1 nodes: 64 inline slots always suffice; the spill vector
/// (empty, never allocated) only keeps an impossible overflow from being a panic.
struct NodeStack {
    inline: [usize; 64],
    len: usize,
    spill: Vec<usize>,
}

impl NodeStack {
    fn root() -> Self {
        Self {
            inline: [0; 64],
            len: 1,
            spill: Vec::new(),
        }
    }

    #[inline]
    fn push(&mut self, v: usize) {
        if self.len < self.inline.len() {
            self.inline[self.len] = v;
            self.len += 1;
        } else {
            self.spill.push(v);
        }
    }

    #[inline]
    fn pop(&mut self) -> Option<usize> {
        if let Some(v) = self.spill.pop() {
            return Some(v);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len])
    }
}

/// Pushes the two children of internal node `n` so that the one whose box is nearer to `p`
/// is popped first (a nearest-query visits it first and prunes more of the other).
#[inline]
fn push_children_nearer_last(nodes: &[Node], n: &Node, p: [f64; 3], stack: &mut NodeStack) {
    let (l, r) = (n.first as usize, n.first as usize + 1);
    if box_dist2(p, nodes[l].lo, nodes[l].hi) <= box_dist2(p, nodes[r].lo, nodes[r].hi) {
        stack.push(r);
        stack.push(l);
    } else {
        stack.push(l);
        stack.push(r);
    }
}

/// Squared distance from `p` to the box `[lo, hi]` (0 inside).
#[inline]
fn box_dist2(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let mut d = 0.0;
    for k in 0..3 {
        let e = (lo[k] - p[k]).max(0.0).max(p[k] - hi[k]);
        d += e * e;
    }
    d
}

/// Entry parameter of the ray `o + t d` into the box, if it enters within `[0, t_max]`.
#[inline]
fn box_ray(o: [f64; 3], inv_d: [f64; 3], lo: [f64; 3], hi: [f64; 3], t_max: f64) -> Option<f64> {
    let (mut t0, mut t1) = (0.0f64, t_max);
    for k in 0..3 {
        if inv_d[k].is_infinite() {
            // Parallel to this slab: inside it for every t or for none (avoids 0 · ∞ = NaN
            // when the origin lies on a slab plane).
            if o[k] < lo[k] || o[k] > hi[k] {
                return None;
            }
            continue;
        }
        let a = (lo[k] - o[k]) * inv_d[k];
        let b = (hi[k] - o[k]) * inv_d[k];
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
        if t0 > t1 {
            return None;
        }
    }
    Some(t0)
}

/// The closest point of a triangle to `p` and its barycentric coordinates (weights of
/// `a`, `b`, `c`), by Ericson's Voronoi-region test. Degenerate (collinear) triangles fall
/// back to the closest of their three edges.
pub fn closest_point_on_triangle(
    p: [f64; 3],
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
) -> ([f64; 3], [f64; 3]) {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (add(a, scale(ab, v)), [1.0 - v, v, 0.0]);
    }
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (add(a, scale(ac, w)), [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (add(b, scale(sub(c, b), w)), [0.0, 1.0 - w, w]);
    }
    let denom = va + vb + vc;
    if denom > 0.0 && denom.is_finite() {
        let (v, w) = (vb / denom, vc / denom);
        return (add(a, add(scale(ab, v), scale(ac, w))), [1.0 - v - w, v, w]);
    }
    // Collinear corners: the closest point is on one of the edges.
    let seg = |x: [f64; 3], y: [f64; 3]| {
        let d = sub(y, x);
        let l = norm2(d);
        let t = if l > 0.0 {
            (dot(sub(p, x), d) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (add(x, scale(d, t)), t)
    };
    let (q0, t0) = seg(a, b);
    let (q1, t1) = seg(b, c);
    let (q2, t2) = seg(c, a);
    let cands = [
        (q0, [1.0 - t0, t0, 0.0]),
        (q1, [0.0, 1.0 - t1, t1]),
        (q2, [t2, 0.0, 1.0 - t2]),
    ];
    let mut best = cands[0];
    for cand in &cands[1..] {
        if norm2(sub(p, cand.0)) < norm2(sub(p, best.0)) {
            best = *cand;
        }
    }
    best
}

/// Möller–Trumbore: the parameter `t` and barycentric weights of `a`, `b`, `c` where the ray
/// `o + t d` meets the triangle, if it does for `t ∈ [0, t_max]` (either side of the face).
pub fn ray_triangle(
    o: [f64; 3],
    d: [f64; 3],
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    t_max: f64,
) -> Option<(f64, [f64; 3])> {
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = sub(o, a);
    let u = dot(tv, pv) * inv;
    if !(-BARY_SLACK..=1.0 + BARY_SLACK).contains(&u) {
        return None;
    }
    let qv = cross(tv, e1);
    let v = dot(d, qv) * inv;
    if v < -BARY_SLACK || u + v > 1.0 + BARY_SLACK {
        return None;
    }
    let t = dot(e2, qv) * inv;
    if !(0.0..=t_max).contains(&t) {
        return None;
    }
    Some((t, [1.0 - u - v, u, v]))
}

/// Result of [`Bvh::closest_point`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The face the point lies on (the lowest face id among equally close faces is not
    /// guaranteed; any closest face may be returned).
    pub face: FaceId,
    /// The closest surface point.
    pub point: [f64; 3],
    /// Weights of the face's three corners, in `faces[face]` order; non-negative, sum 1.
    pub barycentric: [f64; 3],
    /// Euclidean distance from the query to `point`.
    pub distance: f64,
}

/// Result of [`Bvh::ray_intersect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The face hit first.
    pub face: FaceId,
    /// Ray parameter of the hit: the point is `origin + t · dir` (in units of `|dir|`).
    pub t: f64,
    /// Weights of the face's corners at the hit, in `faces[face]` order.
    pub barycentric: [f64; 3],
}

/// Spatial index over a mesh's faces and referenced vertices. Build once per mesh; it holds
/// a copy of the triangles, so it stays valid if the mesh is dropped but not if it moves.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    faces: Tree,
    /// Triangle corners in leaf order.
    tris: Vec<[[f64; 3]; 3]>,
    vertices: Tree,
    /// Vertex positions in leaf order.
    points: Vec<[f64; 3]>,
}

impl Bvh {
    /// Builds the trees over all faces and all referenced vertices of `mesh` in O(n log n).
    /// The mesh should pass [`TriMesh::validate`]; faces with an out-of-range index are left
    /// out rather than panicking.
    pub fn build(mesh: &TriMesh) -> Bvh {
        let nv = mesh.positions.len();
        let tri = |f: &[u32; 3]| f.map(|i| mesh.positions[i as usize]);
        let ids: Vec<u32> = (0..mesh.faces.len() as u32)
            .filter(|&f| mesh.faces[f as usize].iter().all(|&i| (i as usize) < nv))
            .collect();
        let (mut lo, mut hi) = (Vec::with_capacity(ids.len()), Vec::with_capacity(ids.len()));
        for &f in &ids {
            let t = tri(&mesh.faces[f as usize]);
            let mut l = t[0];
            let mut h = t[0];
            for p in &t[1..] {
                for k in 0..3 {
                    l[k] = l[k].min(p[k]);
                    h[k] = h[k].max(p[k]);
                }
            }
            lo.push(l);
            hi.push(h);
        }
        let mut faces = Tree::build(&lo, &hi);
        for o in &mut faces.order {
            *o = ids[*o as usize];
        }
        let tris = faces
            .order
            .iter()
            .map(|&f| tri(&mesh.faces[f as usize]))
            .collect();
        let used = mesh.referenced_vertices();
        let ids: Vec<u32> = (0..mesh.positions.len() as u32)
            .filter(|&v| used[v as usize])
            .collect();
        let pts: Vec<[f64; 3]> = ids.iter().map(|&v| mesh.positions[v as usize]).collect();
        let mut vertices = Tree::build(&pts, &pts);
        for o in &mut vertices.order {
            *o = ids[*o as usize];
        }
        let points = vertices
            .order
            .iter()
            .map(|&v| mesh.positions[v as usize])
            .collect();
        Bvh {
            faces,
            tris,
            vertices,
            points,
        }
    }

    /// Number of faces indexed.
    pub fn face_count(&self) -> usize {
        self.tris.len()
    }

    /// Heap bytes held by the index.
    pub fn heap_bytes(&self) -> usize {
        self.faces.bytes()
            + self.vertices.bytes()
            + self.tris.capacity() * 72
            + self.points.capacity() * 24
    }

    /// The closest point of the surface to `p`, or `None` for a mesh without faces (or a
    /// non-finite `p`).
    pub fn closest_point(&self, p: [f64; 3]) -> Option<ClosestPoint> {
        if self.faces.nodes.is_empty() || !p.iter().all(|c| c.is_finite()) {
            return None;
        }
        let mut best: Option<(f64, usize, [f64; 3], [f64; 3])> = None;
        let mut best_d2 = f64::INFINITY;
        let nodes = &self.faces.nodes;
        let mut stack = NodeStack::root();
        while let Some(ni) = stack.pop() {
            let n = nodes[ni];
            if box_dist2(p, n.lo, n.hi) >= best_d2 {
                continue;
            }
            if n.count > 0 {
                for slot in n.first as usize..(n.first + n.count) as usize {
                    let [a, b, c] = self.tris[slot];
                    let (q, bary) = closest_point_on_triangle(p, a, b, c);
                    let d2 = norm2(sub(p, q));
                    if d2 < best_d2 {
                        best_d2 = d2;
                        best = Some((d2, slot, q, bary));
                    }
                }
            } else {
                push_children_nearer_last(nodes, &n, p, &mut stack);
            }
        }
        best.map(|(d2, slot, point, barycentric)| ClosestPoint {
            face: FaceId(self.faces.order[slot]),
            point,
            barycentric,
            distance: d2.sqrt(),
        })
    }

    /// The first face hit by the ray `origin + t · dir` with `t ∈ [0, t_max]` (either side of
    /// the face), or `None`. `dir` need not be unit length; `t` is in units of `|dir|`.
    pub fn ray_intersect(&self, origin: [f64; 3], dir: [f64; 3], t_max: f64) -> Option<RayHit> {
        if self.faces.nodes.is_empty() || norm2(dir) == 0.0 || t_max.is_nan() || t_max < 0.0 {
            return None;
        }
        if !origin.iter().chain(&dir).all(|c| c.is_finite()) {
            return None;
        }
        let inv = dir.map(|c| 1.0 / c);
        let nodes = &self.faces.nodes;
        let mut t_best = t_max;
        let mut best: Option<(usize, f64, [f64; 3])> = None;
        let mut stack = NodeStack::root();
        while let Some(ni) = stack.pop() {
            let n = nodes[ni];
            if box_ray(origin, inv, n.lo, n.hi, t_best).is_none() {
                continue;
            }
            if n.count > 0 {
                for slot in n.first as usize..(n.first + n.count) as usize {
                    let [a, b, c] = self.tris[slot];
                    if let Some((t, bary)) = ray_triangle(origin, dir, a, b, c, t_best)
                        && best.is_none_or(|(_, bt, _)| t < bt)
                    {
                        t_best = t;
                        best = Some((slot, t, bary));
                    }
                }
            } else {
                let (l, r) = (n.first as usize, n.first as usize + 1);
                let tl = box_ray(origin, inv, nodes[l].lo, nodes[l].hi, t_best);
                let tr = box_ray(origin, inv, nodes[r].lo, nodes[r].hi, t_best);
                match (tl, tr) {
                    (Some(a), Some(b)) if a <= b => {
                        stack.push(r);
                        stack.push(l);
                    }
                    (Some(_), Some(_)) => {
                        stack.push(l);
                        stack.push(r);
                    }
                    (Some(_), None) => stack.push(l),
                    (None, Some(_)) => stack.push(r),
                    (None, None) => {}
                }
            }
        }
        best.map(|(slot, t, barycentric)| RayHit {
            face: FaceId(self.faces.order[slot]),
            t,
            barycentric,
        })
    }

    /// The referenced vertex nearest to `p` and its distance, or `None` without vertices.
    pub fn nearest_vertex(&self, p: [f64; 3]) -> Option<(VertexId, f64)> {
        if self.vertices.nodes.is_empty() || !p.iter().all(|c| c.is_finite()) {
            return None;
        }
        let nodes = &self.vertices.nodes;
        let (mut best_d2, mut best) = (f64::INFINITY, None);
        let mut stack = NodeStack::root();
        while let Some(ni) = stack.pop() {
            let n = nodes[ni];
            if box_dist2(p, n.lo, n.hi) >= best_d2 {
                continue;
            }
            if n.count > 0 {
                for slot in n.first as usize..(n.first + n.count) as usize {
                    let d2 = norm2(sub(p, self.points[slot]));
                    if d2 < best_d2 {
                        best_d2 = d2;
                        best = Some(slot);
                    }
                }
            } else {
                push_children_nearer_last(nodes, &n, p, &mut stack);
            }
        }
        best.map(|slot| (VertexId(self.vertices.order[slot]), best_d2.sqrt()))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::shapes;

    /// xorshift64*: deterministic, no dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
        fn point(&mut self, s: f64) -> [f64; 3] {
            [self.range(-s, s), self.range(-s, s), self.range(-s, s)]
        }
    }

    fn test_meshes() -> Vec<TriMesh> {
        vec![
            shapes::icosphere(50.0, 3),
            shapes::dress_form(&shapes::BodyMeasurements {
                resolution: 24,
                ..Default::default()
            }),
            shapes::saddle_grid(15),
            shapes::torus(40.0, 15.0, 24, 12),
        ]
    }

    #[test]
    fn closest_point_on_triangle_is_optimal() {
        // q is the projection of p onto a convex set iff (p − q)·(x − q) ≤ 0 for every x in
        // it; checking the three corners suffices (the condition is linear in x).
        let mut rng = Rng(7);
        for _ in 0..20_000 {
            let (a, b, c) = (rng.point(1.0), rng.point(1.0), rng.point(1.0));
            let p = rng.point(3.0);
            let (q, w) = closest_point_on_triangle(p, a, b, c);
            assert!(w.iter().all(|&x| x >= -1e-12) && (w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            let r = add(add(scale(a, w[0]), scale(b, w[1])), scale(c, w[2]));
            assert!(norm2(sub(r, q)) < 1e-20, "{q:?} {r:?}");
            for x in [a, b, c] {
                assert!(dot(sub(p, q), sub(x, q)) <= 1e-12, "not optimal");
            }
        }
        // Degenerate: collinear corners.
        let (q, w) =
            closest_point_on_triangle([0.5, 1.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        assert_eq!(q, [0.5, 0.0, 0.0]);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let (q, _) = closest_point_on_triangle([0.0, 2.0, 0.0], [1.0; 3], [1.0; 3], [1.0; 3]);
        assert_eq!(q, [1.0; 3]);
    }

    #[test]
    fn closest_point_matches_brute_force() {
        let mut rng = Rng(11);
        for m in test_meshes() {
            let bvh = Bvh::build(&m);
            let s = 1.3 * m.diagonal();
            for _ in 0..300 {
                let p = rng.point(s / 2.0);
                let got = bvh.closest_point(p).unwrap();
                let brute = m
                    .faces
                    .iter()
                    .map(|f| {
                        let [a, b, c] = f.map(|i| m.positions[i as usize]);
                        norm2(sub(p, closest_point_on_triangle(p, a, b, c).0)).sqrt()
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    (got.distance - brute).abs() <= 1e-12 * s,
                    "{} vs {brute}",
                    got.distance
                );
                let [a, b, c] = m.triangle(got.face);
                let w = got.barycentric;
                let r = add(add(scale(a, w[0]), scale(b, w[1])), scale(c, w[2]));
                assert!(norm2(sub(r, got.point)).sqrt() < 1e-9 * s);
                assert!((norm2(sub(p, got.point)).sqrt() - got.distance).abs() < 1e-12 * s);
            }
        }
    }

    #[test]
    fn rays_match_brute_force() {
        let mut rng = Rng(3);
        for m in test_meshes() {
            let bvh = Bvh::build(&m);
            let s = m.diagonal();
            let mut hits = 0;
            for i in 0..400 {
                let o = rng.point(s);
                // Half the rays aim at a vertex so that hits are common.
                let target = if i % 2 == 0 {
                    m.positions[(rng.next() * m.vertex_count() as f64) as usize % m.vertex_count()]
                } else {
                    rng.point(s)
                };
                let d = sub(add(target, rng.point(1e-3 * s)), o);
                let t_max = if i % 5 == 0 { 0.5 } else { f64::INFINITY };
                let got = bvh.ray_intersect(o, d, t_max);
                let brute = m
                    .faces
                    .iter()
                    .filter_map(|f| {
                        let [a, b, c] = f.map(|i| m.positions[i as usize]);
                        ray_triangle(o, d, a, b, c, t_max).map(|x| x.0)
                    })
                    .fold(f64::INFINITY, f64::min);
                match got {
                    Some(h) => {
                        hits += 1;
                        assert!(
                            (h.t - brute).abs() < 1e-12 * brute.max(1.0),
                            "{} vs {brute}",
                            h.t
                        );
                        let [a, b, c] = m.triangle(h.face);
                        let w = h.barycentric;
                        let on_face = add(add(scale(a, w[0]), scale(b, w[1])), scale(c, w[2]));
                        let on_ray = add(o, scale(d, h.t));
                        assert!(norm2(sub(on_face, on_ray)).sqrt() < 1e-9 * s);
                        assert!(h.t <= t_max);
                    }
                    None => assert!(brute.is_infinite(), "missed a hit at {brute}"),
                }
            }
            assert!(hits > 100, "{hits}");
        }
    }

    #[test]
    fn ray_through_a_shared_edge_hits() {
        // The grid's diagonal edges and vertices: rays straight down through them must hit.
        let m = shapes::grid_patch(5, 5, 4.0, |_, _| 0.0);
        let bvh = Bvh::build(&m);
        for p in &m.positions {
            let h = bvh
                .ray_intersect([p[0], p[1], 1.0], [0.0, 0.0, -1.0], 10.0)
                .unwrap();
            assert!((h.t - 1.0).abs() < 1e-15);
        }
        for x in [-1.5, -0.5, 0.5, 1.5] {
            // Midpoints of edges between cells.
            assert!(
                bvh.ray_intersect([x, x, 1.0], [0.0, 0.0, -1.0], 10.0)
                    .is_some()
            );
            assert!(
                bvh.ray_intersect([x, 0.0, 1.0], [0.0, 0.0, -1.0], 10.0)
                    .is_some()
            );
        }
        // Parallel to the plane, and pointing away: no hit.
        assert!(
            bvh.ray_intersect([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], 10.0)
                .is_none()
        );
        assert!(
            bvh.ray_intersect([0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 10.0)
                .is_none()
        );
        assert!(
            bvh.ray_intersect([0.0, 0.0, 1.0], [0.0, 0.0, 0.0], 10.0)
                .is_none()
        );
    }

    #[test]
    fn nearest_vertex_matches_brute_force() {
        let mut rng = Rng(5);
        for mut m in test_meshes() {
            m.positions.push([1e6, 0.0, 0.0]); // unreferenced: never returned
            let bvh = Bvh::build(&m);
            let used = m.referenced_vertices();
            for _ in 0..300 {
                let p = rng.point(m.diagonal());
                let (v, d) = bvh.nearest_vertex(p).unwrap();
                let brute = (0..m.vertex_count())
                    .filter(|&i| used[i])
                    .map(|i| norm2(sub(p, m.positions[i])).sqrt())
                    .fold(f64::INFINITY, f64::min);
                assert_eq!(d, brute);
                assert_eq!(norm2(sub(p, m.positions[v.idx()])).sqrt(), d);
            }
            assert_eq!(
                bvh.nearest_vertex([1e6, 0.0, 0.0])
                    .map(|x| x.0.idx() < m.vertex_count() - 1),
                Some(true)
            );
        }
    }

    #[test]
    fn empty_and_bad_queries_give_none() {
        let bvh = Bvh::build(&TriMesh::default());
        assert!(bvh.closest_point([0.0; 3]).is_none());
        assert!(bvh.ray_intersect([0.0; 3], [1.0, 0.0, 0.0], 1.0).is_none());
        assert!(bvh.nearest_vertex([0.0; 3]).is_none());
        let bvh = Bvh::build(&shapes::icosphere(1.0, 1));
        assert!(bvh.closest_point([f64::NAN, 0.0, 0.0]).is_none());
        assert!(
            bvh.ray_intersect([0.0; 3], [f64::NAN, 0.0, 0.0], 1.0)
                .is_none()
        );
        // From the centre every direction hits at t = radius-ish.
        let h = bvh
            .ray_intersect([0.0; 3], [0.0, 1.0, 0.0], f64::INFINITY)
            .unwrap();
        assert!(h.t > 0.8 && h.t <= 1.0);
        assert_eq!(bvh.face_count(), 80);
        // A face with an out-of-range index is skipped, not a panic.
        let mut bad = shapes::icosphere(1.0, 1);
        bad.faces.push([0, 1, 999]);
        let bvh = Bvh::build(&bad);
        assert_eq!(bvh.face_count(), 80);
        assert!(bvh.closest_point([0.0, 0.0, 2.0]).unwrap().face.0 < 80);
    }
}
