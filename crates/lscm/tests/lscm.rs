//! LSCM: exactness on planar pieces, the energy against an independent evaluation,
//! optimality by finite differences, components, holes, pins, and refusals.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_lscm::{
    FlattenOptions, LscmError, LscmOptions, Pins, conformal_energy, distortion, flatten, lscm,
    split_pieces,
};
use flatcut_mesh::vec3::{cross, dot, norm, sub};
use flatcut_mesh::{Topology, TriMesh, VertexId};

/// E_C = Σ ½ A (|∇u|² + |∇v|² − 2 n·(∇u × ∇v)) with 3D gradients ∇φ_k = n × e_k / 2A:
/// evaluated without the local frames or the assembled matrix of the library.
fn energy_3d(mesh: &TriMesh, uv: &[[f64; 2]]) -> f64 {
    mesh.faces
        .iter()
        .map(|f| {
            let p = f.map(|v| mesh.positions[v as usize]);
            let n2 = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            let a2 = norm(n2);
            let n = [n2[0] / a2, n2[1] / a2, n2[2] / a2];
            let mut gu = [0.0; 3];
            let mut gv = [0.0; 3];
            for k in 0..3 {
                let g = cross(n, sub(p[(k + 2) % 3], p[(k + 1) % 3]));
                for c in 0..3 {
                    gu[c] += uv[f[k] as usize][0] * g[c] / a2;
                    gv[c] += uv[f[k] as usize][1] * g[c] / a2;
                }
            }
            0.5 * (0.5 * a2) * (dot(gu, gu) + dot(gv, gv) - 2.0 * dot(n, cross(gu, gv)))
        })
        .sum()
}

#[test]
fn planar_piece_comes_back_congruent() {
    let mesh = common::planar(14);
    let flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    let topo = Topology::build(&mesh).unwrap();
    let d = distortion(&mesh, &topo, &flat.uv);
    assert!(d.e_h.max < 1e-9, "E_h {}", d.e_h.max);
    assert!(d.e_r.max < 1e-9, "E_r {}", d.e_r.max);
    assert!(d.max_edge_strain < 1e-9, "strain {}", d.max_edge_strain);
    assert_eq!(d.flipped_faces, 0);
    assert!(flat.pieces[0].conformal_energy < 1e-18 * d.area_3d_mm2);
}

#[test]
fn energy_matches_independent_evaluation_and_is_stationary() {
    let mesh = common::saddle(9);
    let flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    let p = &flat.pieces[0];
    let e_lib = conformal_energy(&p.piece, &p.uv);
    let e_ind = energy_3d(&mesh, &flat.uv);
    assert!(e_lib > 1e-3, "a saddle is not conformally flat: {e_lib}");
    assert!((e_lib - e_ind).abs() <= 1e-10 * e_ind, "{e_lib} vs {e_ind}");
    assert!((p.conformal_energy - e_ind).abs() <= 1e-10 * e_ind);

    // Central differences of the (quadratic) independent energy: exact up to rounding.
    let h = 1e-3;
    let grad = |uv: &[[f64; 2]], v: usize, c: usize| {
        let mut a = uv.to_vec();
        let mut b = uv.to_vec();
        a[v][c] += h;
        b[v][c] -= h;
        (energy_3d(&mesh, &a) - energy_3d(&mesh, &b)) / (2.0 * h)
    };
    // Scale: the gradient after moving one vertex by 1 mm.
    let mut moved = flat.uv.clone();
    moved[40][0] += 1.0;
    let scale = grad(&moved, 40, 0).abs();
    assert!(scale > 1e-3);
    for v in 0..mesh.vertex_count() {
        let pinned = p.pins.contains(&VertexId(v as u32));
        for c in 0..2 {
            let g = grad(&flat.uv, v, c);
            if !pinned {
                assert!(g.abs() < 1e-7 * scale, "vertex {v} coord {c}: gradient {g}");
            }
        }
    }
    // The pins hold the solution: their gradient need not vanish, and it does not.
    let pin = p.pins[0].idx();
    assert!(
        grad(&flat.uv, pin, 0)
            .abs()
            .max(grad(&flat.uv, pin, 1).abs())
            > 1e-6 * scale
    );
}

#[test]
fn auto_pins_are_the_boundary_diameter_at_their_3d_distance() {
    let mesh = common::saddle(7);
    let topo = Topology::build(&mesh).unwrap();
    let flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    let p = &flat.pieces[0];
    let mut best = 0.0f64;
    let boundary: Vec<VertexId> = topo.boundary_loops().concat();
    for &a in &boundary {
        for &b in &boundary {
            best = best.max(flatcut_mesh::vec3::dist(mesh.position(a), mesh.position(b)));
        }
    }
    let [a, b] = p.pins;
    let d3 = flatcut_mesh::vec3::dist(mesh.position(a), mesh.position(b));
    assert_eq!(d3, best);
    assert_eq!(flat.uv[a.idx()], [0.0, 0.0]);
    assert_eq!(flat.uv[b.idx()], [d3, 0.0]);
}

#[test]
fn large_boundary_pin_approximation_is_close_to_the_diameter() {
    let mesh = common::saddle(40);
    let topo = Topology::build(&mesh).unwrap();
    let pieces = split_pieces(&mesh, &topo).unwrap();
    let exact = flatcut_lscm::auto_pins(&pieces[0], usize::MAX).unwrap();
    let approx = flatcut_lscm::auto_pins(&pieces[0], 10).unwrap();
    let d = |p: [u32; 2]| {
        flatcut_mesh::vec3::dist(
            pieces[0].positions[p[0] as usize],
            pieces[0].positions[p[1] as usize],
        )
    };
    assert!(
        d(approx) >= 0.989 * d(exact),
        "{} vs {}",
        d(approx),
        d(exact)
    );
}

#[test]
fn given_pins_are_used() {
    let mesh = common::saddle(6);
    let opts = LscmOptions {
        pins: Pins::Given([VertexId(0), VertexId(5)]),
        ..Default::default()
    };
    let flat = lscm(&mesh, &opts).unwrap();
    assert_eq!(flat.pieces[0].pins, [VertexId(0), VertexId(5)]);
    assert_eq!(flat.uv[0], [0.0, 0.0]);
    let d = flatcut_mesh::vec3::dist(mesh.positions[0], mesh.positions[5]);
    assert_eq!(flat.uv[5], [d, 0.0]);
}

#[test]
fn components_are_flattened_separately_and_holes_work() {
    let a = common::annulus(24, 4);
    let b = common::planar(6);
    let mesh = common::union(&a, &b);
    let flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    assert_eq!(flat.pieces.len(), 2);
    let topo = Topology::build(&mesh).unwrap();
    let d = distortion(&mesh, &topo, &flat.uv);
    // Both pieces are planar: each comes back congruent in its own frame.
    assert!(d.max_edge_strain < 1e-9, "{}", d.max_edge_strain);
    assert_eq!(d.flipped_faces, 0);
    assert_eq!(flat.pieces[0].piece.boundary_loops.len(), 2);
}

#[test]
fn unreferenced_vertices_are_ignored() {
    let mut mesh = common::planar(5);
    mesh.positions.push([1e6, 1e6, 1e6]);
    let flat = lscm(&mesh, &LscmOptions::default()).unwrap();
    assert_eq!(flat.uv.len(), mesh.vertex_count());
    assert_eq!(*flat.uv.last().unwrap(), [0.0, 0.0]);
    assert!(flat.uv.iter().flatten().all(|x| x.is_finite()));
}

fn octahedron() -> TriMesh {
    let p = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let f = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    TriMesh::new(p, f).unwrap()
}

#[test]
fn bad_input_is_refused_with_a_named_error() {
    let opts = LscmOptions::default();
    // Closed piece.
    let err = lscm(&octahedron(), &opts).unwrap_err();
    assert!(
        matches!(err, LscmError::ClosedComponent { component: 0, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("closed"));
    // Open piece next to a closed one: still refused, naming the closed component.
    let both = common::union(&common::planar(4), &octahedron());
    assert!(matches!(
        lscm(&both, &opts).unwrap_err(),
        LscmError::ClosedComponent { component: 1, .. }
    ));
    // Empty.
    assert_eq!(
        lscm(&TriMesh::default(), &opts).unwrap_err(),
        LscmError::Empty
    );
    // Bowtie: two triangles sharing only vertex 0.
    let bow = TriMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [-1.0, -1.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 3, 4]],
    )
    .unwrap();
    assert_eq!(
        lscm(&bow, &opts).unwrap_err(),
        LscmError::NonManifoldVertex {
            vertex: VertexId(0)
        }
    );
    // Degenerate face (collinear corners).
    let mut deg = common::planar(4);
    let n = deg.positions.len() as u32;
    deg.positions.push([0.0, 0.0, 0.0]);
    deg.positions.push([1.0, 1.0, 1.0]);
    deg.positions.push([2.0, 2.0, 2.0]);
    deg.faces.push([n, n + 1, n + 2]);
    assert!(matches!(
        lscm(&deg, &opts).unwrap_err(),
        LscmError::DegenerateFace { .. }
    ));
    // Inconsistent orientation.
    let mut flip = common::planar(4);
    flip.faces[0].swap(1, 2);
    assert!(matches!(
        lscm(&flip, &opts).unwrap_err(),
        LscmError::InconsistentOrientation { .. }
    ));
    // Coincident pins: same index, and distinct indices at the same place.
    let mesh = common::planar(4);
    let same = LscmOptions {
        pins: Pins::Given([VertexId(1), VertexId(1)]),
        ..Default::default()
    };
    assert!(matches!(
        lscm(&mesh, &same).unwrap_err(),
        LscmError::CoincidentPins { .. }
    ));
    let mut dup = common::planar(4);
    let n = dup.positions.len() as u32;
    dup.positions.push(dup.positions[0]);
    dup.positions.push([500.0, 0.0, 0.0]);
    dup.positions.push([500.0, 10.0, 0.0]);
    dup.faces.push([n, n + 1, n + 2]);
    let two = LscmOptions {
        pins: Pins::Given([VertexId(0), VertexId(n)]),
        ..Default::default()
    };
    assert!(matches!(
        lscm(&dup, &two).unwrap_err(),
        LscmError::PinsInDifferentComponents { .. }
    ));
    // Pins out of range / unused.
    let bad = LscmOptions {
        pins: Pins::Given([VertexId(0), VertexId(10_000)]),
        ..Default::default()
    };
    assert_eq!(
        lscm(&mesh, &bad).unwrap_err(),
        LscmError::InvalidPin {
            vertex: VertexId(10_000)
        }
    );
}

/// Within `EXTENT_RANGE` (1e-30 to 1e30) a piece scaled by a power of two flattens (LSCM, ARAP,
/// placement) to its pattern scaled, bit for bit, near both ends; beyond it, it is refused by
/// name with its extent, where a 2^175-wide disk failed with "a matrix value is not finite"
/// and a 1e300-wide one with a Cholesky pivot.
#[test]
fn pieces_beyond_the_flattenings_range_are_refused_and_those_within_scale_bit_for_bit() {
    let mesh = common::cone(8, 5);
    let opts = FlattenOptions::default();
    let base = flatten(&mesh, &opts).unwrap().flattening.uv;
    let scaled = |s: f64| {
        let mut m = mesh.clone();
        for p in &mut m.positions {
            *p = p.map(|x| x * s);
        }
        m
    };
    let extent = mesh.diagonal();
    for k in [-105, 88] {
        let s = 2f64.powi(k);
        assert!((1e-30..=1e30).contains(&(extent * s)), "2^{k}");
        let uv = flatten(&scaled(s), &opts).unwrap().flattening.uv;
        let expected: Vec<[f64; 2]> = base.iter().map(|q| q.map(|x| x * s)).collect();
        assert_eq!(uv, expected, "2^{k}");
    }
    for s in [2f64.powi(-115), 2f64.powi(110), 1e300] {
        let err = flatten(&scaled(s), &opts).unwrap_err();
        assert!(
            matches!(err, LscmError::ExtentOutOfRange { component: 0, .. }),
            "{s:e}: {err}"
        );
        assert!(
            err.to_string().contains(&format!("{:.3e}", extent * s)),
            "{err}"
        );
    }
}

#[test]
fn coincident_positions_of_distinct_pins_are_refused() {
    // Two distinct boundary vertices at one position in one component (a slit).
    let mesh = TriMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.0],
            [0.0, 0.0, 0.0],
        ],
        vec![[0, 1, 2], [3, 2, 1]],
    );
    // Face 1 runs 2→1 as face 0's 1→2: consistent. Vertex 3 duplicates vertex 0.
    let mesh = mesh.unwrap();
    let opts = LscmOptions {
        pins: Pins::Given([VertexId(0), VertexId(3)]),
        ..Default::default()
    };
    assert!(matches!(
        lscm(&mesh, &opts).unwrap_err(),
        LscmError::CoincidentPins { .. }
    ));
}

mod property {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]
        /// Any planar piece, jittered and placed anywhere in 3D, comes back congruent from
        /// LSCM alone, never mirrored.
        #[test]
        fn planar_pieces_are_congruent(
            jitter in proptest::collection::vec((-0.2f64..0.2, -0.2f64..0.2), 48),
            axis in (-1.0f64..1.0, -1.0f64..1.0, 0.1f64..1.0),
            angle in -3.0f64..3.0,
            offset in (-500.0f64..500.0, -500.0f64..500.0, -500.0f64..500.0),
            scale in 0.5f64..50.0,
        ) {
            let (nx, ny) = (8usize, 6usize);
            let mut mesh = common::grid(nx, ny, |u, v| [u * (nx - 1) as f64, v * (ny - 1) as f64, 0.0]);
            for (k, p) in mesh.positions.iter_mut().enumerate() {
                let (i, j) = (k % nx, k / nx);
                // Interior points move by at most 0.2·√2 = 0.28 each, so a vertex and the
                // line of its opposite edge approach by < 0.57, less than the smallest
                // height of a grid triangle (1/√2): no input triangle folds. (±0.3 could
                // fold one, and a folded planar input has no congruent LSCM image.)
                if i > 0 && j > 0 && i < nx - 1 && j < ny - 1 {
                    p[0] += jitter[k % 48].0;
                    p[1] += jitter[k % 48].1;
                }
            }
            for f in &mesh.faces {
                let [a, b, c] = f.map(|v| mesh.positions[v as usize]);
                let twice_area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
                prop_assert!(twice_area > 0.0, "the generator folded face {:?}", f);
            }
            // Rodrigues rotation about `axis`, then scale and offset.
            let n = norm([axis.0, axis.1, axis.2]);
            let a = [axis.0 / n, axis.1 / n, axis.2 / n];
            let (s, c) = angle.sin_cos();
            for p in &mut mesh.positions {
                let q = *p;
                let axq = cross(a, q);
                let d = dot(a, q);
                let r: Vec<f64> = (0..3).map(|k| q[k] * c + axq[k] * s + a[k] * d * (1.0 - c)).collect();
                *p = [scale * r[0] + offset.0, scale * r[1] + offset.1, scale * r[2] + offset.2];
            }
            let flat = lscm(&mesh, &LscmOptions::default()).unwrap();
            let topo = Topology::build(&mesh).unwrap();
            let d = distortion(&mesh, &topo, &flat.uv);
            prop_assert!(d.max_edge_strain < 1e-9, "strain {}", d.max_edge_strain);
            prop_assert!(d.e_r.max < 1e-9 && d.e_h.max < 1e-9);
            prop_assert_eq!(d.flipped_faces, 0);
        }
    }
}
