//! Coarsening for coarse-to-fine: boundary bit-identical, same manifold topology, exact
//! prolongation of linear fields on planar pieces, deterministic.
#![allow(clippy::unwrap_used)]

mod common;

use flatcut_flattenable::coarsen::{Location, coarsen};
use flatcut_mesh::{Topology, TriMesh, VertexId};

fn check_structure(fine: &TriMesh, target: usize) {
    let c = coarsen(fine, target).unwrap();
    let tf = Topology::build(fine).unwrap();
    let tc = Topology::build(&c.mesh).unwrap();
    // Coarsened substantially (each collapse removes two faces).
    assert!(
        c.mesh.face_count() <= target + target / 5,
        "{} faces for target {target} (fine {})",
        c.mesh.face_count(),
        fine.face_count()
    );
    // Every boundary vertex kept, bit-identical, and still on the boundary.
    for v in 0..fine.vertex_count() {
        if tf.is_boundary_vertex(VertexId(v as u32)) {
            let Location::Kept(k) = c.location[v] else {
                panic!("boundary vertex {v} removed");
            };
            assert_eq!(c.fine_of_coarse[k as usize], v as u32);
            assert_eq!(
                c.mesh.positions[k as usize].map(f64::to_bits),
                fine.positions[v].map(f64::to_bits)
            );
            assert!(tc.is_boundary_vertex(VertexId(k)));
        }
    }
    // Kept vertices are bit-identical too.
    for (k, &v) in c.fine_of_coarse.iter().enumerate() {
        assert_eq!(
            c.mesh.positions[k].map(f64::to_bits),
            fine.positions[v as usize].map(f64::to_bits)
        );
        assert_eq!(c.location[v as usize], Location::Kept(k as u32));
    }
    // Same topology: manifold, oriented, one component, same loops (as fine vertex
    // sequences, up to the starting vertex) and Euler characteristic.
    assert!(tc.non_manifold_edges().is_empty());
    assert!(tc.non_manifold_vertices().is_empty());
    assert!(tc.inconsistent_edges().is_empty());
    assert_eq!(tc.component_count(), 1);
    assert_eq!(tc.euler_characteristic(), tf.euler_characteristic());
    let mut loops_f: Vec<Vec<u32>> = tf
        .boundary_loops()
        .iter()
        .map(|l| canonical(l.iter().map(|v| v.0).collect()))
        .collect();
    let mut loops_c: Vec<Vec<u32>> = tc
        .boundary_loops()
        .iter()
        .map(|l| canonical(l.iter().map(|v| c.fine_of_coarse[v.idx()]).collect()))
        .collect();
    loops_f.sort();
    loops_c.sort();
    assert_eq!(loops_f, loops_c);
    // Interior vertices of the coarse mesh have valence ≥ 3; barycentrics are convex.
    for v in 0..c.mesh.vertex_count() as u32 {
        if tc.is_interior_vertex(VertexId(v)) {
            assert!(tc.one_ring(VertexId(v)).unwrap().len() >= 3);
        }
    }
    for loc in &c.location {
        if let Location::InFace { face, bary } = *loc {
            assert!((face as usize) < c.mesh.face_count());
            assert!(bary.iter().all(|&b| (-1e-12..=1.0 + 1e-12).contains(&b)));
            assert!((bary.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }
}

/// A loop rotated to start at its smallest vertex.
fn canonical(mut l: Vec<u32>) -> Vec<u32> {
    let i = (0..l.len()).min_by_key(|&i| l[i]).unwrap();
    l.rotate_left(i);
    l
}

#[test]
fn coarsening_keeps_boundary_and_topology_on_cap_and_saddle() {
    let cap = common::sphere_cap(30);
    check_structure(&cap, cap.face_count() / 4);
    let saddle = common::saddle(30);
    check_structure(&saddle, saddle.face_count() / 4);
}

#[test]
fn coarsening_keeps_holes() {
    let m = flatcut_mesh::shapes::patch_with_holes(100.0, 30);
    assert_eq!(Topology::build(&m).unwrap().boundary_loops().len(), 3);
    check_structure(&m, m.face_count() / 3);
}

/// A jittered planar grid: every fine vertex lies in the plane of the coarse surface, so its
/// closest point is itself and prolongation reproduces a linear field f(x) = M x + c.
#[test]
fn prolongation_of_a_linear_field_is_exact_on_a_plane() {
    let mut m = common::planar(25);
    let n = m.vertex_count();
    for (i, p) in m.positions.iter_mut().enumerate() {
        // Deterministic jitter of the interior (well under half a spacing of 1/12).
        if p[0].abs() < 0.999 && p[1].abs() < 0.999 {
            let s = ((i * 7919) % 101) as f64 / 101.0 - 0.5;
            let t = ((i * 104_729) % 103) as f64 / 103.0 - 0.5;
            p[0] += 0.02 * s;
            p[1] += 0.02 * t;
        }
    }
    let c = coarsen(&m, m.face_count() / 8).unwrap();
    assert!(c.mesh.face_count() < m.face_count() / 6);
    let field = |p: [f64; 3]| {
        [
            1.5 * p[0] - 0.25 * p[1] + 3.0,
            -0.5 * p[0] + 2.0 * p[1] - 1.0,
            0.75 * p[0] + 0.125 * p[1] + 0.5,
        ]
    };
    let coarse: Vec<[f64; 3]> = c.mesh.positions.iter().map(|&p| field(p)).collect();
    let fine = c.prolongate(&coarse);
    assert_eq!(fine.len(), n);
    let mut removed = 0;
    for (v, f) in fine.iter().enumerate() {
        let want = field(m.positions[v]);
        for k in 0..3 {
            assert!(
                (f[k] - want[k]).abs() < 1e-12,
                "vertex {v}: {f:?} vs {want:?}"
            );
        }
        if matches!(c.location[v], Location::InFace { .. }) {
            removed += 1;
        }
    }
    assert!(removed > n / 2);
    // Positions themselves are a linear field: prolongating the coarse positions gives the
    // fine ones back.
    let back = c.prolongate(&c.mesh.positions);
    for (a, b) in back.iter().zip(&m.positions) {
        assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-12));
    }
}

#[test]
fn coarsening_is_deterministic() {
    let m = common::saddle(20);
    let a = coarsen(&m, m.face_count() / 4).unwrap();
    let b = coarsen(&m, m.face_count() / 4).unwrap();
    assert_eq!(a.mesh.faces, b.mesh.faces);
    assert_eq!(a.location, b.location);
}
