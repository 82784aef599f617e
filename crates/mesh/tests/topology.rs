//! Topology against independent evidence: Euler characteristics and loop counts from the
//! shapes' definitions, halfedge identities checked against the face list, and the defects
//! of hand-built broken meshes.

// Test code: unwrap is allowed (RULES), index loops mirror the formulas.
#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

use std::collections::{HashMap, HashSet};

use flatcut_mesh::shapes::{catalogue, icosphere, non_manifold_bowtie, non_manifold_fin, torus};
use flatcut_mesh::{INVALID, Topology, TriMesh, VertexId};

/// Directed edges of the face list, with the face they belong to.
fn directed(m: &TriMesh) -> HashMap<(u32, u32), Vec<usize>> {
    let mut d: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (fi, f) in m.faces.iter().enumerate() {
        for k in 0..3 {
            d.entry((f[k], f[(k + 1) % 3])).or_default().push(fi);
        }
    }
    d
}

fn undirected_count(m: &TriMesh) -> HashMap<(u32, u32), usize> {
    let mut c = HashMap::new();
    for f in &m.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            *c.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    c
}

#[test]
fn halfedges_match_the_face_list_on_every_shape() {
    for (name, m) in catalogue() {
        let t = Topology::build(&m).unwrap();
        let counts = undirected_count(&m);
        assert_eq!(t.edges().len(), counts.len(), "{name}");
        for (e, c) in t.edges().iter().zip(t.edge_face_counts()) {
            assert!(e[0] < e[1]);
            assert_eq!(counts[&(e[0], e[1])], *c as usize, "{name}");
        }
        for h in 0..3 * m.face_count() as u32 {
            let (a, b) = (t.from_vertex(h), t.to_vertex(h));
            let f = m.faces[Topology::face(h).idx()];
            assert_eq!((a.0, b.0), (f[(h % 3) as usize], f[(h as usize + 1) % 3]));
            assert_eq!(t.from_vertex(Topology::next(h)), b);
            assert_eq!(Topology::next(Topology::prev(h)), h);
            let e = t.edges()[t.edge_of(h) as usize];
            assert_eq!((e[0], e[1]), (a.0.min(b.0), a.0.max(b.0)));
            if let Some(g) = t.twin(h) {
                assert_eq!(t.twin(g), Some(h), "{name}: twin(twin(h)) != h");
                assert_eq!((t.from_vertex(g), t.to_vertex(g)), (b, a));
                assert_ne!(Topology::face(g), Topology::face(h));
            } else {
                // No twin: boundary, non-manifold or inconsistently oriented edge.
                assert!(
                    counts[&(a.0.min(b.0), a.0.max(b.0))] != 2
                        || !t.inconsistent_edges().is_empty()
                );
            }
        }
        for v in 0..m.vertex_count() as u32 {
            for &h in t.outgoing(VertexId(v)) {
                assert_eq!(t.from_vertex(h).0, v);
            }
        }
    }
}

#[test]
fn boundary_loops_follow_face_orientation() {
    for (name, m) in catalogue() {
        let t = Topology::build(&m).unwrap();
        let d = directed(&m);
        let counts = undirected_count(&m);
        let boundary_edges = counts.values().filter(|&&c| c == 1).count();
        let mut seen = HashSet::new();
        let mut total = 0;
        for lp in t.boundary_loops() {
            total += lp.len();
            for i in 0..lp.len() {
                let (a, b) = (lp[i].0, lp[(i + 1) % lp.len()].0);
                assert_eq!(
                    counts[&(a.min(b), a.max(b))],
                    1,
                    "{name}: loop edge {a}-{b} not a boundary edge"
                );
                assert!(
                    d.contains_key(&(a, b)),
                    "{name}: loop runs against its face at {a}-{b}"
                );
                assert!(seen.insert((a, b)), "{name}: boundary edge in two loops");
                assert!(t.is_boundary_vertex(lp[i]));
            }
        }
        for ch in t.open_boundary_chains() {
            assert!(
                name.starts_with("non_manifold"),
                "{name}: open chain on a manifold"
            );
            total += ch.len() - 1;
            for w in ch.windows(2) {
                let (a, b) = (w[0].0, w[1].0);
                assert_eq!(counts[&(a.min(b), a.max(b))], 1, "{name}");
                assert!(
                    d.contains_key(&(a, b)),
                    "{name}: chain runs against its face"
                );
                assert!(seen.insert((a, b)), "{name}: boundary edge used twice");
            }
        }
        assert_eq!(total, boundary_edges, "{name}: loops miss boundary edges");
    }
}

#[test]
fn one_rings_are_counter_clockwise_fans() {
    for (name, m) in catalogue() {
        let t = Topology::build(&m).unwrap();
        let d = directed(&m);
        for v in 0..m.vertex_count() as u32 {
            let vid = VertexId(v);
            let Some(ring) = t.one_ring(vid) else {
                assert!(
                    t.is_non_manifold_vertex(vid) || !t.is_referenced(vid),
                    "{name}: {v} has no ring"
                );
                continue;
            };
            let nf = t.outgoing(vid).len();
            let boundary = t.is_boundary_vertex(vid);
            assert_eq!(ring.len(), if boundary { nf + 1 } else { nf }, "{name}");
            let pairs = if boundary { ring.len() - 1 } else { ring.len() };
            for k in 0..pairs {
                let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                // Face (v, a, b) in this cyclic order: CCW around v, seen from the normal side.
                let fa = d.get(&(v, a)).unwrap();
                let fb = d.get(&(b, v)).unwrap();
                assert!(
                    fa.iter().any(|f| fb.contains(f)),
                    "{name}: ring of {v} not CCW at {a},{b}"
                );
            }
            let distinct: HashSet<_> = ring.iter().collect();
            assert_eq!(distinct.len(), ring.len(), "{name}: repeated ring vertex");
        }
    }
}

#[test]
fn closed_surfaces_have_their_genus() {
    for (sub, m) in [(0, icosphere(1.0, 0)), (3, icosphere(1.0, 3))] {
        let t = Topology::build(&m).unwrap();
        assert_eq!(t.euler_characteristic(), 2, "icosphere {sub}");
        assert_eq!(m.face_count(), 20 * 4usize.pow(sub));
        assert_eq!(t.edges().len() * 2, m.face_count() * 3);
        let s = t.component_summaries();
        assert_eq!(s.len(), 1);
        assert!(s[0].closed);
        assert_eq!(s[0].genus, Some(0));
        assert!((0..m.vertex_count() as u32).all(|v| t.is_interior_vertex(VertexId(v))));
    }
    let m = torus(3.0, 1.0, 12, 7);
    let t = Topology::build(&m).unwrap();
    assert_eq!(t.euler_characteristic(), 0);
    assert_eq!(t.component_summaries()[0].genus, Some(1));
    assert!(t.boundary_loops().is_empty());
}

#[test]
fn defects_of_broken_meshes_are_detected() {
    // Bowtie: vertex 0 is non-manifold, nothing else.
    let t = Topology::build(&non_manifold_bowtie()).unwrap();
    assert_eq!(t.non_manifold_vertices(), vec![VertexId(0)]);
    assert!(t.non_manifold_edges().is_empty());
    assert!(t.one_ring(VertexId(0)).is_none());
    assert!(!t.is_interior_vertex(VertexId(0)));
    assert_eq!(t.component_count(), 1);

    // Fin: three faces on edge 0–1.
    let m = non_manifold_fin();
    let t = Topology::build(&m).unwrap();
    assert_eq!(t.non_manifold_edges(), vec![[0, 1]]);
    for h in 0..9 {
        let (a, b) = (t.from_vertex(h).0, t.to_vertex(h).0);
        if a.min(b) == 0 && a.max(b) == 1 {
            assert_eq!(t.twin(h), None);
        }
    }
    assert_eq!(t.component_summaries()[0].genus, None);
    // Its boundary 1→2→0→3→1 is a cycle; 1→4→0 cannot close (0's only other boundary
    // halfedge is taken). The old tracer closed it with the non-edge 0→1 / 4→1.
    let loops: Vec<Vec<u32>> = t
        .boundary_loops()
        .iter()
        .map(|l| l.iter().map(|v| v.0).collect())
        .collect();
    let chains: Vec<Vec<u32>> = t
        .open_boundary_chains()
        .iter()
        .map(|l| l.iter().map(|v| v.0).collect())
        .collect();
    assert_eq!(loops, vec![vec![1, 2, 0, 3]]);
    assert_eq!(chains, vec![vec![1, 4, 0]]);

    // Inconsistent orientation: both faces run 0 → 1.
    let m = TriMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 1, 3]],
    )
    .unwrap();
    let t = Topology::build(&m).unwrap();
    assert_eq!(t.inconsistent_edges(), vec![[0, 1]]);
    assert!(t.non_manifold_edges().is_empty());
    assert_eq!(t.twin(0), None);
    assert_eq!(t.twin(3), None);
    // The consistent version has the twin.
    let m = TriMesh::new(m.positions.clone(), vec![[0, 1, 2], [1, 0, 3]]).unwrap();
    let t = Topology::build(&m).unwrap();
    assert!(t.inconsistent_edges().is_empty());
    assert_eq!(t.twin(0), Some(3));
    assert_eq!(t.boundary_loops().len(), 1);
    assert_eq!(t.boundary_loops()[0].len(), 4);

    // Out-of-range index is an error, not a panic.
    let bad = TriMesh {
        positions: vec![[0.0; 3]; 2],
        faces: vec![[0, 1, 2]],
        ..Default::default()
    };
    assert!(Topology::build(&bad).is_err());
}

#[test]
fn components_are_counted_and_numbered_by_first_face() {
    let a = icosphere(1.0, 1);
    let b = torus(3.0, 1.0, 8, 5);
    let mut m = b.clone();
    let off = m.positions.len() as u32;
    m.positions
        .extend(a.positions.iter().map(|p| [p[0] + 10.0, p[1], p[2]]));
    m.faces.extend(a.faces.iter().map(|f| f.map(|i| i + off)));
    m.positions.push([99.0; 3]); // unused vertex
    let t = Topology::build(&m).unwrap();
    assert_eq!(t.component_count(), 2);
    let fc = t.face_components();
    assert!(fc[..b.face_count()].iter().all(|&c| c == 0));
    assert!(fc[b.face_count()..].iter().all(|&c| c == 1));
    assert_eq!(*t.vertex_components().last().unwrap(), INVALID);
    assert_eq!(t.referenced_vertex_count(), m.positions.len() - 1);
    let s = t.component_summaries();
    assert_eq!((s[0].genus, s[1].genus), (Some(1), Some(0)));
    assert_eq!(s[0].faces + s[1].faces, m.face_count());
    assert_eq!(t.euler_characteristic(), 2);
}
