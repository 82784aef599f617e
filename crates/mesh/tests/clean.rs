//! clean() on meshes broken in known ways: each repair is checked against the intact mesh.

// Test code: unwrap is allowed (RULES), index loops mirror the formulas.
#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

use std::collections::HashSet;

use flatcut_mesh::clean::{CleanOptions, Keep, clean};
use flatcut_mesh::shapes::{grid_patch, icosphere, saddle_grid, torus};
use flatcut_mesh::vec3::{cross, dot};
use flatcut_mesh::{INVALID, MeshError, Topology, TriMesh};

fn signed_volume(m: &TriMesh) -> f64 {
    m.faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| m.positions[i as usize]);
            dot(a, cross(b, c)) / 6.0
        })
        .sum()
}

/// Every face as an unindexed triangle soup (what STL gives).
fn soup(m: &TriMesh) -> TriMesh {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for f in &m.faces {
        let i = positions.len() as u32;
        positions.extend(f.map(|v| m.positions[v as usize]));
        faces.push([i, i + 1, i + 2]);
    }
    TriMesh::new(positions, faces).unwrap()
}

/// Checks that the map describes the output: new vertices have their source positions, new
/// faces have their source face's corner positions (as a set).
fn check_provenance(src: &TriMesh, out: &TriMesh, map: &flatcut_mesh::clean::CleanMap) {
    assert_eq!(map.vertex_source.len(), out.vertex_count());
    assert_eq!(map.face_source.len(), out.face_count());
    assert_eq!(map.vertex_target.len(), src.vertex_count());
    for (v, s) in map.vertex_source.iter().enumerate() {
        assert_eq!(out.positions[v], src.positions[s.idx()]);
        assert_eq!(map.vertex_target[s.idx()], v as u32);
    }
    for (f, s) in map.face_source.iter().enumerate() {
        // Each new corner is the target of one of the source corners.
        let targets: HashSet<u32> = src.faces[s.idx()]
            .iter()
            .map(|&v| map.vertex_target[v as usize])
            .collect();
        let corners: HashSet<u32> = out.faces[f].iter().copied().collect();
        assert_eq!(targets, corners);
    }
    out.validate().unwrap();
}

#[test]
fn triangle_soup_is_welded_back_to_the_grid() {
    let grid = saddle_grid(9);
    let s = soup(&grid);
    let (out, report, map) = clean(&s, &CleanOptions::default()).unwrap();
    assert_eq!(out.vertex_count(), grid.vertex_count());
    assert_eq!(out.face_count(), grid.face_count());
    assert_eq!(
        report.welded_vertices,
        s.vertex_count() - grid.vertex_count()
    );
    assert_eq!(
        (
            report.flipped_faces,
            report.dropped_faces,
            report.unreferenced_vertices
        ),
        (0, 0, 0)
    );
    let t = Topology::build(&out).unwrap();
    assert_eq!(
        (
            t.boundary_loops().len(),
            t.euler_characteristic(),
            t.component_count()
        ),
        (1, 1, 1)
    );
    check_provenance(&s, &out, &map);
    // The representative is the lowest index: vertex sources are increasing.
    assert!(map.vertex_source.windows(2).all(|w| w[0] < w[1]));
}

#[test]
fn tolerance_welding_merges_close_vertices_only() {
    let grid = grid_patch(6, 6, 10.0, |_, _| 0.0); // spacing 2 mm
    let mut s = soup(&grid);
    // Jitter every copy by up to 0.01 mm.
    for (i, p) in s.positions.iter_mut().enumerate() {
        let j = ((i as f64 * 12.9898).sin() * 43758.5453).fract() * 0.01;
        p[0] += j;
        p[1] -= 0.5 * j;
    }
    let (exact, _, _) = clean(&s, &CleanOptions::default()).unwrap();
    assert!(exact.vertex_count() > grid.vertex_count());
    let opts = CleanOptions {
        weld_tolerance_mm: 0.05,
        ..Default::default()
    };
    let (out, report, map) = clean(&s, &opts).unwrap();
    assert_eq!(out.vertex_count(), grid.vertex_count());
    assert_eq!(
        report.welded_vertices,
        s.vertex_count() - grid.vertex_count()
    );
    check_provenance(&s, &out, &map);
    // A chain 0 – 0.9 – 1.8 with tolerance 1: transitive, all onto vertex 0.
    let m = TriMesh::new(
        vec![
            [0.0; 3],
            [0.9, 0.0, 0.0],
            [1.8, 0.0, 0.0],
            [0.0, 5.0, 0.0],
            [5.0, 0.0, 0.0],
            [5.0, 5.0, 0.0],
        ],
        vec![[0, 4, 3], [1, 4, 5], [2, 5, 3]],
    )
    .unwrap();
    let opts = CleanOptions {
        weld_tolerance_mm: 1.0,
        drop_degenerate: false,
        ..Default::default()
    };
    let (_, report, map) = clean(&m, &opts).unwrap();
    assert_eq!(report.welded_vertices, 2);
    assert_eq!(map.vertex_target[1], map.vertex_target[0]);
    assert_eq!(map.vertex_target[2], map.vertex_target[0]);
    assert_eq!(map.vertex_source[map.vertex_target[0] as usize].0, 0);
}

#[test]
fn broken_orientation_is_repaired_outward() {
    let sphere = icosphere(20.0, 2);
    let truth: HashSet<[u32; 3]> = sphere.faces.iter().map(|&f| canonical(f)).collect();
    // Flip a minority (1/3) and then a majority (3/4) of faces: both must come back.
    for modulus in [3, 2] {
        let mut broken = sphere.clone();
        let mut flipped = 0;
        for (i, f) in broken.faces.iter_mut().enumerate() {
            let flip_it = if modulus == 3 { i % 3 == 0 } else { i % 4 != 0 };
            if flip_it {
                f.swap(1, 2);
                flipped += 1;
            }
        }
        assert!(
            !Topology::build(&broken)
                .unwrap()
                .inconsistent_edges()
                .is_empty()
        );
        let (out, report, map) = clean(&broken, &CleanOptions::default()).unwrap();
        assert!(
            Topology::build(&out)
                .unwrap()
                .inconsistent_edges()
                .is_empty()
        );
        assert!(signed_volume(&out) > 0.0);
        assert_eq!(report.flipped_faces, flipped);
        let got: HashSet<[u32; 3]> = out.faces.iter().map(|&f| canonical(f)).collect();
        assert_eq!(got, truth);
        check_provenance(&broken, &out, &map);
    }
    // An entirely inward sphere is turned outward by the volume test.
    let mut inward = sphere.clone();
    inward.faces.iter_mut().for_each(|f| f.swap(0, 1));
    let (out, report, _) = clean(&inward, &CleanOptions::default()).unwrap();
    assert_eq!(report.flipped_faces, sphere.face_count());
    assert!(signed_volume(&out) > 0.0);
    // An open patch keeps the orientation of the majority.
    let mut patch = saddle_grid(7);
    patch.faces[5].swap(0, 2);
    let (out, report, _) = clean(&patch, &CleanOptions::default()).unwrap();
    assert_eq!(report.flipped_faces, 1);
    let canon = |m: &TriMesh| m.faces.iter().map(|&f| canonical(f)).collect::<Vec<_>>();
    assert_eq!(canon(&out), canon(&saddle_grid(7)));
}

/// Rotation-invariant form of an oriented triangle.
fn canonical(f: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| f[k]).unwrap();
    [f[k], f[(k + 1) % 3], f[(k + 2) % 3]]
}

#[test]
fn moebius_strip_is_reported_unorientable() {
    // A strip of n quads whose ends are glued with a half twist.
    let n = 12;
    let mut positions = Vec::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        for s in [-1.0, 1.0] {
            let (w, h) = (s * (a / 2.0).cos(), s * (a / 2.0).sin());
            let r = 10.0 + 3.0 * w;
            positions.push([r * a.cos(), 3.0 * h, r * a.sin()]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n {
        let (a, b) = (2 * i as u32, 2 * i as u32 + 1);
        let (c, d) = if i + 1 < n {
            (2 * (i + 1) as u32, 2 * (i + 1) as u32 + 1)
        } else {
            (1, 0)
        };
        faces.push([a, c, d]);
        faces.push([a, d, b]);
    }
    let m = TriMesh::new(positions, faces).unwrap();
    let t = Topology::build(&m).unwrap();
    // The twist shows as one edge run the same way by both faces; no flip can remove it.
    assert_eq!(t.inconsistent_edges(), vec![[0, 1]]);
    let (out, report, _) = clean(&m, &CleanOptions::default()).unwrap();
    assert_eq!(report.unorientable_components, 1);
    assert_eq!(report.flipped_faces, 0);
    assert_eq!(out.faces, m.faces);
}

#[test]
fn keep_largest_drops_debris() {
    let big = icosphere(20.0, 2);
    let small = torus(5.0, 1.0, 8, 4);
    let mut m = small.clone();
    let off = m.positions.len() as u32;
    m.positions
        .extend(big.positions.iter().map(|p| [p[0] + 100.0, p[1], p[2]]));
    m.faces.extend(big.faces.iter().map(|f| f.map(|v| v + off)));
    m.scalar_fill();
    let opts = CleanOptions {
        keep: Keep::Largest,
        ..Default::default()
    };
    let (out, report, map) = clean(&m, &opts).unwrap();
    assert_eq!(out.face_count(), big.face_count());
    assert_eq!(out.vertex_count(), big.vertex_count());
    assert_eq!(
        (report.dropped_components, report.dropped_component_faces),
        (1, small.face_count())
    );
    assert_eq!(report.unreferenced_vertices, small.vertex_count());
    check_provenance(&m, &out, &map);
    // The scalar attribute followed the vertices.
    let s = out.attributes.scalar.as_ref().unwrap();
    for (v, src) in map.vertex_source.iter().enumerate() {
        assert_eq!(s[v], src.0 as f64);
    }
    for v in 0..small.vertex_count() {
        assert_eq!(map.vertex_target[v], INVALID);
    }
    let (all, _, _) = clean(&m, &CleanOptions::default()).unwrap();
    assert_eq!(all.face_count(), m.face_count());
}

trait Fill {
    fn scalar_fill(&mut self);
}
impl Fill for TriMesh {
    fn scalar_fill(&mut self) {
        self.attributes.scalar = Some((0..self.vertex_count()).map(|v| v as f64).collect());
    }
}

#[test]
fn degenerate_duplicate_and_unreferenced_are_dropped_and_counted() {
    let base = saddle_grid(5);
    let mut m = base.clone();
    let nf = base.face_count() as u32;
    m.faces.push([0, 0, 1]); // repeated index
    m.positions.push([10.0, 0.0, 0.0]);
    m.positions.push([20.0, 0.0, 0.0]);
    m.positions.push([30.0, 0.0, 0.0]); // three collinear points: zero area
    let v = base.vertex_count() as u32;
    m.faces.push([v, v + 1, v + 2]);
    m.faces.push(base.faces[3]); // duplicate
    let r = base.faces[4];
    m.faces.push([r[0], r[2], r[1]]); // duplicate, reversed
    m.positions.push([1.0, 2.0, 3.0]); // unreferenced
    m.face_labels = Some(flatcut_mesh::FaceLabels {
        names: vec!["a".into(), "b".into()],
        labels: (0..m.face_count() as u32)
            .map(|f| u32::from(f >= nf))
            .collect(),
    });
    let (out, report, map) = clean(&m, &CleanOptions::default()).unwrap();
    assert_eq!(report.degenerate_faces, 2);
    assert_eq!(report.duplicate_faces, 2);
    assert_eq!(report.unreferenced_vertices, 4);
    assert_eq!(report.dropped_faces, 4);
    assert_eq!(report.flipped_faces, 0);
    assert_eq!(out.faces, base.faces);
    assert_eq!(out.positions, base.positions);
    assert!(
        out.face_labels
            .as_ref()
            .unwrap()
            .labels
            .iter()
            .all(|&l| l == 0)
    );
    check_provenance(&m, &out, &map);
    // With every drop off, nothing but welding (none here) happens.
    let keep_all = CleanOptions {
        drop_degenerate: false,
        drop_duplicate_faces: false,
        drop_unreferenced: false,
        orient: false,
        ..Default::default()
    };
    let (same, report, _) = clean(&m, &keep_all).unwrap();
    assert_eq!(same.faces, m.faces);
    assert_eq!(same.positions, m.positions);
    assert_eq!(report.dropped_faces, 0);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let mut m = saddle_grid(3);
    m.positions[4][1] = f64::NAN;
    assert!(matches!(
        clean(&m, &CleanOptions::default()),
        Err(MeshError::NonFinitePosition { .. })
    ));
    let m = saddle_grid(3);
    for tol in [-1.0, f64::NAN, f64::INFINITY] {
        let opts = CleanOptions {
            weld_tolerance_mm: tol,
            ..Default::default()
        };
        assert!(matches!(
            clean(&m, &opts),
            Err(MeshError::InvalidParameter { .. })
        ));
    }
    let empty = TriMesh::default();
    let (out, report, _) = clean(
        &empty,
        &CleanOptions {
            keep: Keep::Largest,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!((out.face_count(), report.output_vertices), (0, 0));
}

#[test]
fn options_read_from_text_with_documented_defaults() {
    let o: CleanOptions = serde_json::from_str("{}").unwrap();
    assert_eq!(o, CleanOptions::default());
    assert_eq!(o.weld_tolerance_mm, 0.0);
    assert_eq!(o.keep, Keep::All);
    assert!(o.drop_degenerate && o.drop_duplicate_faces && o.drop_unreferenced && o.orient);
    let o: CleanOptions =
        serde_json::from_str(r#"{"keep": "largest", "weld_tolerance_mm": 0.1}"#).unwrap();
    assert_eq!((o.keep, o.weld_tolerance_mm), (Keep::Largest, 0.1));
    assert!(serde_json::from_str::<CleanOptions>(r#"{"weld": 1}"#).is_err());
    let (_, report, _) = clean(&saddle_grid(3), &o).unwrap();
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["output_faces"], 8);
}

#[test]
fn tolerance_welding_matches_brute_force_components() {
    // 600 points in a 10 mm box, tolerance 0.6 mm: many chains across cell borders.
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let positions: Vec<[f64; 3]> = (0..600)
        .map(|_| [10.0 * rnd() - 5.0, 10.0 * rnd(), 3.0 * rnd()])
        .collect();
    let faces: Vec<[u32; 3]> = (0..200).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    let m = TriMesh::new(positions.clone(), faces).unwrap();
    let tol = 0.6;
    let opts = CleanOptions {
        weld_tolerance_mm: tol,
        // Pure clustering is checked here; the random soup pinches everywhere.
        weld_keeps_manifold: false,
        drop_degenerate: false,
        drop_duplicate_faces: false,
        orient: false,
        ..Default::default()
    };
    let (_, report, map) = clean(&m, &opts).unwrap();
    // Brute force: components of the "closer than tol" graph, smallest index first.
    let n = positions.len();
    let mut comp: Vec<usize> = (0..n).collect();
    loop {
        let mut changed = false;
        for a in 0..n {
            for b in 0..n {
                let d = positions[a]
                    .iter()
                    .zip(&positions[b])
                    .map(|(x, y)| (x - y) * (x - y))
                    .sum::<f64>();
                if d <= tol * tol && comp[b] < comp[a] {
                    comp[a] = comp[b];
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    let groups = comp.iter().collect::<HashSet<_>>().len();
    assert!(
        groups < n - 50 && groups > 20,
        "{groups}: the test should have many merges"
    );
    assert_eq!(report.welded_vertices, n - groups);
    for a in 0..n {
        assert_eq!(map.vertex_target[a], map.vertex_target[comp[a]]);
        assert_eq!(
            map.vertex_source[map.vertex_target[a] as usize].idx(),
            comp[a]
        );
    }
}

/// Two holes of a grid whose corners coincide (as in scans where a hole is cut right next to
/// another): welding the coincident vertices would pinch the surface into a non-manifold
/// vertex, so the weld is refused and counted, while a soup of the same grid still welds whole.
#[test]
fn welds_that_would_pinch_the_surface_are_refused() {
    // Two 2×2-quad grids side by side touching at one corner point only, given as two separate
    // vertices at the same position: a bowtie if welded.
    // grid_patch spans [−1, 1]²; the right one is moved by (2, 2): corners meet at (1, 1).
    let left = grid_patch(3, 3, 2.0, |_, _| 0.0);
    let mut right = grid_patch(3, 3, 2.0, |_, _| 0.0);
    for p in &mut right.positions {
        p[0] += 2.0;
        p[1] += 2.0;
    }
    let mut mesh = left.clone();
    let off = mesh.positions.len() as u32;
    mesh.positions.extend(&right.positions);
    mesh.faces
        .extend(right.faces.iter().map(|f| f.map(|v| v + off)));
    let before = Topology::build(&mesh).unwrap();
    assert!(before.non_manifold_vertices().is_empty());

    let (out, report, _) = clean(&mesh, &CleanOptions::default()).unwrap();
    assert_eq!(report.refused_welds, 1, "{report:?}");
    assert_eq!(report.welded_vertices, 0, "{report:?}");
    let topo = Topology::build(&out).unwrap();
    assert!(topo.non_manifold_vertices().is_empty());
    assert!(topo.non_manifold_edges().is_empty());
    assert_eq!(out.positions.len(), mesh.positions.len());

    // The same pinch at a weld tolerance, and a soup that must still weld back whole.
    let (_, report, _) = clean(
        &mesh,
        &CleanOptions {
            weld_tolerance_mm: 1e-3,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(report.refused_welds, 1);
    let (welded, report, _) = clean(&soup(&left), &CleanOptions::default()).unwrap();
    assert_eq!(report.refused_welds, 0);
    assert_eq!(welded.positions.len(), left.positions.len());
}
