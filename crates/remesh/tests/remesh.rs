//! Isotropic remeshing on the procedural catalogue and the real scan.

#![allow(clippy::unwrap_used)]

use flatcut_mesh::shapes::{cylinder_patch, icosphere, patch_with_holes, planar_disk};
use flatcut_mesh::vec3::{add, dist, dot, norm, scale, sub};
use flatcut_mesh::{Topology, TriMesh};
use flatcut_remesh::{Provenance, RemeshError, RemeshOptions, remesh};

/// Distance from `p` to segment `ab`.
fn seg_dist(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(b, a);
    let l = dot(d, d);
    let t = if l > 0.0 {
        (dot(sub(p, a), d) / l).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, add(a, scale(d, t)))
}

/// Largest distance of the output's boundary vertices to the input's boundary polylines.
fn boundary_deviation(input: &TriMesh, out: &TriMesh) -> f64 {
    let ti = Topology::build(input).unwrap();
    let to = Topology::build(out).unwrap();
    let mut segs = Vec::new();
    for l in ti.boundary_loops() {
        for i in 0..l.len() {
            segs.push((
                input.positions[l[i].idx()],
                input.positions[l[(i + 1) % l.len()].idx()],
            ));
        }
    }
    let mut worst: f64 = 0.0;
    for l in to.boundary_loops() {
        for v in l {
            let p = out.positions[v.idx()];
            let d = segs
                .iter()
                .map(|&(a, b)| seg_dist(p, a, b))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    worst
}

/// The mapped input point of each output vertex equals the vertex (outside filled holes).
fn provenance_error(input: &TriMesh, out: &TriMesh, prov: &[Provenance]) -> f64 {
    assert_eq!(prov.len(), out.positions.len());
    let mut worst: f64 = 0.0;
    for (v, p) in prov.iter().enumerate() {
        if p.filled {
            continue;
        }
        let f = input.faces[p.face as usize];
        let b = p.barycentric;
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-9, "{b:?}");
        assert!(b.iter().all(|&x| x >= -1e-12), "{b:?}");
        let q = (0..3).fold([0.0; 3], |s, i| {
            add(s, scale(input.positions[f[i] as usize], b[i]))
        });
        worst = worst.max(dist(q, out.positions[v]));
    }
    worst
}

/// No non-manifold edge, no degenerate or flipped face (against the input normal at the
/// vertex's provenance).
fn assert_valid(out: &TriMesh) {
    let t = Topology::build(out).unwrap();
    assert!(t.non_manifold_edges().is_empty());
    assert!(t.non_manifold_vertices().is_empty());
    assert!(t.inconsistent_edges().is_empty());
    let diag = out.diagonal();
    for f in &out.faces {
        let [a, b, c] = f.map(|i| out.positions[i as usize]);
        let area = 0.5 * norm(flatcut_mesh::vec3::cross(sub(b, a), sub(c, a)));
        assert!(area > 1e-10 * diag * diag, "degenerate face {f:?}");
    }
}

#[test]
fn sphere_stays_on_the_sphere_within_the_chord_bound() {
    let r = 100.0;
    let input = icosphere(r, 4);
    let target = 12.0;
    let out = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: target,
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    let m = &out.mesh;
    assert_valid(m);
    // Every point of an input triangle lies between the sphere and the sphere shrunk by
    // the triangle's sagitta R − √(R² − ρ²), ρ its circumradius.
    let circum = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        let (la, lb, lc) = (dist(b, c), dist(a, c), dist(a, b));
        let area = 0.5 * norm(flatcut_mesh::vec3::cross(sub(b, a), sub(c, a)));
        la * lb * lc / (4.0 * area)
    };
    let rho_in = input
        .faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| input.positions[i as usize]);
            circum(a, b, c)
        })
        .fold(0.0, f64::max);
    let sag_in = r - (r * r - rho_in * rho_in).sqrt();
    for p in &m.positions {
        let d = norm(*p);
        assert!(d <= r + 1e-9 && d >= r - sag_in - 1e-9, "|p| = {d}");
    }
    // Centroids: the output triangle's own sagitta on top. No face is flipped: every
    // normal points away from the centre.
    for f in &m.faces {
        let [a, b, c] = f.map(|i| m.positions[i as usize]);
        assert!(dot(flatcut_mesh::vec3::cross(sub(b, a), sub(c, a)), a) > 0.0);
        let rho = circum(a, b, c);
        let cen = scale(add(add(a, b), c), 1.0 / 3.0);
        let bound = sag_in + r - (r * r - rho * rho).sqrt();
        assert!(r - norm(cen) <= bound + 1e-9);
    }
    let q = &out.report;
    eprintln!("{q:#?}");
    assert!(
        q.edges_within_half_to_1_5 >= 0.99,
        "{}",
        q.edges_within_half_to_1_5
    );
    assert!(q.faces_min_angle_at_least_25_deg >= 0.995);
    assert!(q.min_angle_deg > 15.0);
    // Euler characteristic kept.
    assert_eq!(Topology::build(m).unwrap().euler_characteristic(), 2);
    // Roughly the face count of equilateral triangles of the target size: 4πR² / (√3/4 L²).
    let expect = 4.0 * std::f64::consts::PI * r * r / (3f64.sqrt() / 4.0 * target * target);
    let nf = m.faces.len() as f64;
    assert!(nf > 0.7 * expect && nf < 1.4 * expect, "{nf} vs {expect}");
    assert!(provenance_error(&input, m, &out.provenance) < 1e-9 * input.diagonal());
}

#[test]
fn planar_disk_stays_planar_and_keeps_its_boundary() {
    let input = planar_disk(100.0, 30);
    let out = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: 9.0,
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    let m = &out.mesh;
    assert_valid(m);
    assert!(m.positions.iter().all(|p| p[2] == 0.0));
    // No face flipped: every normal is +z like the input's.
    for f in &m.faces {
        let [a, b, c] = f.map(|i| m.positions[i as usize]);
        assert!(flatcut_mesh::vec3::cross(sub(b, a), sub(c, a))[2] > 0.0);
    }
    let dev = boundary_deviation(&input, m);
    assert!(dev <= 1e-9 * input.diagonal(), "boundary off by {dev}");
    let t = Topology::build(m).unwrap();
    assert_eq!(t.boundary_loops().len(), 1);
    assert_eq!(t.euler_characteristic(), 1);
    // Boundary vertices are spaced near the target: the circle's perimeter over the count.
    let nb = t.boundary_loops()[0].len() as f64;
    let per = 2.0 * std::f64::consts::PI * 100.0;
    assert!(
        (per / nb) > 0.6 * 9.0 && (per / nb) < 1.4 * 9.0,
        "{}",
        per / nb
    );
    let q = &out.report;
    eprintln!("{q:#?}");
    assert!(q.edges_within_half_to_1_5 >= 0.99);
    assert!(q.faces_min_angle_at_least_25_deg >= 0.99);
    assert!(provenance_error(&input, m, &out.provenance) < 1e-9 * input.diagonal());
    // No fold-over: the faces tile exactly the polygon of the boundary loop (shoelace),
    // which inscribes the input's polygon.
    let area: f64 = m
        .faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| m.positions[i as usize]);
            0.5 * norm(flatcut_mesh::vec3::cross(sub(b, a), sub(c, a)))
        })
        .sum();
    let l = &t.boundary_loops()[0];
    let shoelace = 0.5
        * (0..l.len())
            .map(|i| {
                let (p, q) = (
                    m.positions[l[i].idx()],
                    m.positions[l[(i + 1) % l.len()].idx()],
                );
                p[0] * q[1] - q[0] * p[1]
            })
            .sum::<f64>()
            .abs();
    assert!(
        (area - shoelace).abs() < 1e-9 * area,
        "{area} vs {shoelace}"
    );
    assert!(area <= flatcut_mesh::geometry::total_area(&input) + 1e-9);
}

/// The real scan through FLATCUT_DATA (fails if the variable is set and the file missing).
fn real_mesh(name: &str) -> Option<TriMesh> {
    let dir = std::env::var_os("FLATCUT_DATA")?;
    let path = std::path::Path::new(&dir).join(name);
    let loaded = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
        .unwrap_or_else(|e| panic!("FLATCUT_DATA is set but {} fails: {e}", path.display()));
    Some(loaded.mesh)
}

#[test]
fn cylinder_keeps_radius_boundary_and_corners() {
    // A quarter of a cylinder: four boundary corners (90° turns) must survive exactly.
    let r = 80.0;
    let input = cylinder_patch(r, std::f64::consts::FRAC_PI_2, 200.0, 12, 20);
    let out = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: 7.0,
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    let m = &out.mesh;
    assert_valid(m);
    // Vertices lie on the input's flat strips: radius between r·cos(half strip angle) and r.
    let half = std::f64::consts::FRAC_PI_2 / 11.0 / 2.0;
    for p in &m.positions {
        let rr = (p[0] * p[0] + p[2] * p[2]).sqrt();
        assert!(rr <= r + 1e-9 && rr >= r * half.cos() - 1e-9, "{rr}");
        assert!(p[1] >= -1e-9 && p[1] <= 200.0 + 1e-9);
    }
    let corners = [
        [r, 0.0, 0.0],
        [r, 200.0, 0.0],
        [0.0, 0.0, -r],
        [0.0, 200.0, -r],
    ];
    for c in corners {
        let d = m
            .positions
            .iter()
            .map(|p| dist(*p, c))
            .fold(f64::INFINITY, f64::min);
        assert!(d < 1e-9, "corner {c:?} lost ({d})");
    }
    assert!(boundary_deviation(&input, m) <= 1e-9 * input.diagonal());
    let q = &out.report;
    assert!(
        q.edges_within_half_to_1_5 >= 0.99,
        "{}",
        q.edges_within_half_to_1_5
    );
    assert!(q.faces_min_angle_at_least_25_deg >= 0.99);
    assert!(provenance_error(&input, m, &out.provenance) < 1e-9 * input.diagonal());
}

#[test]
fn patch_with_holes_fills_only_below_the_perimeter() {
    // Two round holes of radius size/8 (perimeter ≈ 2π·25 = 157 mm at size 200) in a
    // square of perimeter 800 mm: a 300 mm threshold fills both holes, keeps the outside.
    let input = patch_with_holes(200.0, 41);
    let out = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: 8.0,
            fill_holes_perimeter_mm: 300.0,
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    let m = &out.mesh;
    assert_valid(m);
    let q = &out.report;
    assert_eq!(q.holes.len(), 3);
    assert_eq!(q.holes_filled, 2);
    assert!(q.holes[2].perimeter_mm > 790.0 && !q.holes[2].filled);
    let t = Topology::build(m).unwrap();
    assert_eq!(t.boundary_loops().len(), 1);
    assert_eq!(t.euler_characteristic(), 1);
    // A planar hole stays planar when faired (z = 0 is harmonic and biharmonic).
    assert!(m.positions.iter().all(|p| p[2].abs() < 1e-9));
    // Filled vertices sit inside the holes' circles; others on the input.
    let filled = out.provenance.iter().filter(|p| p.filled).count();
    assert!(filled > 10, "{filled}");
    for (v, p) in out.provenance.iter().enumerate() {
        if p.filled {
            let x = m.positions[v];
            let dh = [(-50.0f64, 0.0f64), (50.0, 0.0)]
                .iter()
                .map(|c| ((x[0] - c.0).powi(2) + (x[1] - c.1).powi(2)).sqrt())
                .fold(f64::INFINITY, f64::min);
            assert!(dh < 25.0 + 5.0, "filled vertex {v} at {x:?}");
        }
    }
    assert!(q.faces_min_angle_at_least_25_deg >= 0.98);
    assert!(provenance_error(&input, m, &out.provenance) < 1e-9 * input.diagonal());
    // Without the threshold every loop stays open.
    let open = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: 8.0,
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    assert_eq!(open.report.holes_filled, 0);
    assert_eq!(
        Topology::build(&open.mesh).unwrap().boundary_loops().len(),
        3
    );
    assert!(boundary_deviation(&input, &open.mesh) <= 1e-9 * input.diagonal());
}

#[test]
fn bad_input_is_refused_with_the_element_named() {
    let fin = flatcut_mesh::shapes::non_manifold_fin();
    let e = remesh(
        &fin,
        &RemeshOptions {
            target_edge_mm: 0.5,
            ..RemeshOptions::default()
        },
    )
    .unwrap_err();
    assert_eq!(e, RemeshError::NonManifoldEdge { a: 0, b: 1 });
    let bow = flatcut_mesh::shapes::non_manifold_bowtie();
    let e = remesh(
        &bow,
        &RemeshOptions {
            target_edge_mm: 0.5,
            ..RemeshOptions::default()
        },
    )
    .unwrap_err();
    assert_eq!(e, RemeshError::NonManifoldVertex { vertex: 0 });
    let disk = planar_disk(10.0, 4);
    let diag = disk.diagonal();
    let e = remesh(
        &disk,
        &RemeshOptions {
            target_edge_mm: 2.0 * diag,
            ..RemeshOptions::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, RemeshError::TargetTooLarge { .. }), "{e}");
    let e = remesh(
        &disk,
        &RemeshOptions {
            target_edge_mm: 1e-7 * diag,
            ..RemeshOptions::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, RemeshError::TargetTooSmall { .. }), "{e}");
    let e = remesh(
        &disk,
        &RemeshOptions {
            target_edge_mm: f64::NAN,
            ..RemeshOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            RemeshError::InvalidOption {
                name: "target_edge_mm",
                ..
            }
        ),
        "{e}"
    );
    // A flipped face.
    let mut flipped = disk.clone();
    flipped.faces[0].swap(1, 2);
    let e = remesh(
        &flipped,
        &RemeshOptions {
            target_edge_mm: 2.0,
            ..RemeshOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(e, RemeshError::InconsistentOrientation { .. }),
        "{e}"
    );
    // A feature line that does not follow edges.
    let e = remesh(
        &disk,
        &RemeshOptions {
            target_edge_mm: 2.0,
            feature_lines: vec![vec![0, 40]],
            ..RemeshOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(e, RemeshError::FeatureNotAnEdge { line: 0, .. }),
        "{e}"
    );
    // Unknown option keys are refused when read from TOML-like input.
    let r: Result<RemeshOptions, _> = serde_json::from_str(r#"{"target_edge": 3}"#);
    assert!(r.is_err());
    let r: RemeshOptions = serde_json::from_str(r#"{"target_edge_mm": 3}"#).unwrap();
    assert_eq!(r.target_edge_mm, 3.0);
}

#[test]
fn feature_line_is_kept_as_a_polyline() {
    // A straight line of grid edges across a flat patch, given as a feature, survives.
    let input = flatcut_mesh::shapes::grid_patch(21, 21, 100.0, |x, y| 0.002 * x * y);
    // Row j = 10 of the grid: vertices 10·21 .. 10·21 + 20.
    let line: Vec<u32> = (0..21).map(|i| 10 * 21 + i).collect();
    let pts: Vec<[f64; 3]> = line.iter().map(|&v| input.positions[v as usize]).collect();
    let out = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: 9.0,
            feature_lines: vec![line],
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    let m = &out.mesh;
    assert_valid(m);
    // Ends are corners.
    for end in [pts[0], pts[20]] {
        assert!(m.positions.iter().any(|p| dist(*p, end) < 1e-12));
    }
    // Output vertices on the line's row: every edge between two of them lies on the line.
    let on_line = |p: [f64; 3]| {
        pts.windows(2)
            .map(|w| seg_dist(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min)
            <= 1e-9 * input.diagonal()
    };
    let n_on = m.positions.iter().filter(|p| on_line(**p)).count();
    // About length / target + 1 vertices on it.
    let len: f64 = pts.windows(2).map(|w| dist(w[0], w[1])).sum();
    assert!(n_on as f64 >= 0.7 * len / 9.0, "{n_on}");
    // The chain is connected: the on-line vertices form a path of output edges.
    let t = Topology::build(m).unwrap();
    let line_edges = t
        .edges()
        .iter()
        .filter(|e| on_line(m.positions[e[0] as usize]) && on_line(m.positions[e[1] as usize]))
        .count();
    assert!(
        line_edges + 1 >= n_on,
        "{line_edges} edges for {n_on} vertices"
    );
}

#[test]
#[ignore = "release-only: 148k triangles (a few seconds in release, minutes in debug)"]
fn mh_body_scanlike_at_8mm_meets_the_issue_numbers() {
    let Some(input) = real_mesh("mh_body_scanlike.obj") else {
        return;
    };
    let out = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: 8.0,
            fill_holes_perimeter_mm: 200.0,
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    let q = &out.report;
    eprintln!("{}", serde_json::to_string_pretty(q).unwrap());
    let m = &out.mesh;
    assert_valid(m);
    assert!(
        q.edges_within_half_to_1_5 >= 0.99,
        "{}",
        q.edges_within_half_to_1_5
    );
    assert!(
        q.faces_min_angle_at_least_25_deg >= 0.995,
        "{}",
        q.faces_min_angle_at_least_25_deg
    );
    // Vertices outside filled holes lie on the input surface.
    assert!(q.vertex_to_input.max_mm <= 1e-9 * input.diagonal());
    assert!(provenance_error(&input, m, &out.provenance) < 1e-9 * input.diagonal());
    // The three debris islands (11 junk faces each, 5–15 target triangles of area) are
    // copied unchanged; of the body's 16 holes the ten below 200 mm are filled and the six
    // openings (272 mm and up) stay open.
    assert_eq!(q.components_kept_unchanged, 3);
    assert_eq!(q.degenerate_faces, 0);
    assert_eq!(q.holes.len(), 16);
    assert_eq!(q.holes_filled, 10);
    assert!(
        q.holes
            .iter()
            .filter(|h| !h.filled)
            .all(|h| h.perimeter_mm > 250.0)
    );
    let t = Topology::build(m).unwrap();
    assert_eq!(t.boundary_loops().len(), 6 + 3);
    assert!(boundary_deviation(&input, m) <= 1e-9 * input.diagonal());
    // The issue's centroid bound (every centroid within 0.5 mm) is NOT met on this scan and
    // this test does not claim it: the scan's noise (≈ 2 mm at its own 6 mm spacing)
    // puts 62 % of 8 mm centroids beyond 0.5 mm, 13 % still at a uniform 4 mm and 0.17 %
    // at 2.5 mm (docs/algorithms/remesh.md). What holds: the bound is checked and
    // reported, the input is recognised as noise rougher than the bound (so the remesh
    // does not refine it into a million faces), and every centroid beyond the bound lies
    // on such noise, none on smooth input.
    assert_eq!(q.max_deviation_mm, 0.5);
    assert!(q.rough_input_fraction > 0.99, "{}", q.rough_input_fraction);
    let rough = flatcut_remesh::roughness(&input).unwrap();
    let bvh = flatcut_mesh::bvh::Bvh::build(&input);
    let mut over = 0;
    for f in &m.faces {
        if f.iter().any(|&v| out.provenance[v as usize].filled) {
            continue;
        }
        let p = f.map(|v| m.positions[v as usize]);
        let c = scale(add(add(p[0], p[1]), p[2]), 1.0 / 3.0);
        let cp = bvh.closest_point(c).unwrap();
        if cp.distance > 0.5 {
            over += 1;
            assert!(
                input.faces[cp.face.idx()]
                    .iter()
                    .any(|&v| rough[v as usize] > 0.5),
                "centroid {c:?} is {} mm off smooth input",
                cp.distance
            );
        }
    }
    assert_eq!(over, q.samples_over_deviation);
}

#[test]
fn adaptive_sizing_follows_the_chord_rule_on_spheres() {
    // With κ = 1/R the chord-error rule gives L = √(6εR − 3ε²): two spheres, two lengths.
    let eps = 0.25;
    let mut means = Vec::new();
    for r in [40.0, 160.0] {
        let input = icosphere(r, 5);
        let expect = (6.0 * eps * r - 3.0 * eps * eps).sqrt();
        let out = remesh(
            &input,
            &RemeshOptions {
                target_edge_mm: expect,
                min_edge_mm: Some(1.0),
                max_edge_mm: Some(40.0),
                adaptive_tolerance_mm: eps,
                ..RemeshOptions::default()
            },
        )
        .unwrap();
        assert_valid(&out.mesh);
        let mean = out.report.mean_edge_mm;
        assert!(
            (mean / expect - 1.0).abs() < 0.15,
            "R {r}: mean {mean} vs {expect}"
        );
        means.push(mean);
    }
    // Four times the radius, twice the edge.
    assert!((means[1] / means[0] - 2.0).abs() < 0.3, "{means:?}");
    // Clamped to the range: a max below the rule's length (15.5 mm here) caps it, and the
    // result is the uniform remesh at that length.
    let input = icosphere(160.0, 4);
    let run = |min, max| {
        remesh(
            &input,
            &RemeshOptions {
                target_edge_mm: 8.0,
                min_edge_mm: min,
                max_edge_mm: max,
                adaptive_tolerance_mm: eps,
                ..RemeshOptions::default()
            },
        )
        .unwrap()
    };
    let capped = run(Some(4.0), Some(8.0));
    let uniform = run(None, None);
    assert_eq!(capped.mesh, uniform.mesh);
}

#[test]
fn debris_smaller_than_the_target_is_copied_unchanged() {
    // A sphere plus a far-away 1 mm triangle: the triangle cannot carry 10 mm edges.
    let mut input = icosphere(100.0, 3);
    let n = input.positions.len() as u32;
    input
        .positions
        .extend([[300.0, 0.0, 0.0], [301.0, 0.0, 0.0], [300.0, 1.0, 0.0]]);
    input.faces.push([n, n + 1, n + 2]);
    let out = remesh(
        &input,
        &RemeshOptions {
            target_edge_mm: 10.0,
            ..RemeshOptions::default()
        },
    )
    .unwrap();
    assert_eq!(out.report.components_kept_unchanged, 1);
    let m = &out.mesh;
    assert_valid(m);
    let last = *m.faces.last().unwrap();
    assert_eq!(
        last.map(|v| m.positions[v as usize]),
        [[300.0, 0.0, 0.0], [301.0, 0.0, 0.0], [300.0, 1.0, 0.0]]
    );
    assert_eq!(Topology::build(m).unwrap().component_count(), 2);
    assert!(provenance_error(&input, m, &out.provenance) < 1e-9 * input.diagonal());
    assert_eq!(
        out.provenance.last().unwrap().face,
        input.faces.len() as u32 - 1
    );
}

/// `smooth_iterations`: a noisy sheet (±1.5 mm on 5 mm spacing) remeshed to 10 mm keeps the
/// noise without smoothing (its vertices lie on the input) and loses more than half of its RMS
/// with ten Taubin steps (measured 0.40×: white noise keeps a middle band, where ten steps'
/// gain is 0.59 at k = 0.5 against ≤ 0.07 above k = 1 — the exact decay is in
/// `tests/taubin.rs`); the boundary stays on the input polyline either way, and each smoothed
/// vertex's provenance is its closest input point.
#[test]
fn smoothing_removes_scan_noise_and_keeps_the_boundary() {
    let noise = |x: f64, y: f64| {
        let h = ((x * 12.9898 + y * 78.233).sin() * 43_758.545).fract();
        1.5 * (2.0 * h.abs() - 1.0)
    };
    let input = flatcut_mesh::shapes::grid_patch(81, 81, 400.0, noise);
    let run = |smooth_iterations| {
        remesh(
            &input,
            &RemeshOptions {
                target_edge_mm: 10.0,
                feature_angle_deg: 180.0,
                max_deviation_mm: 0.0,
                smooth_iterations,
                ..RemeshOptions::default()
            },
        )
        .unwrap()
    };
    let (raw, smooth) = (run(0), run(10));
    let rms_z = |m: &TriMesh| {
        let t = Topology::build(m).unwrap();
        let zs: Vec<f64> = (0..m.vertex_count())
            .filter(|&v| t.is_interior_vertex(flatcut_mesh::VertexId(v as u32)))
            .map(|v| m.positions[v][2])
            .collect();
        (zs.iter().map(|z| z * z).sum::<f64>() / zs.len() as f64).sqrt()
    };
    let (a, b) = (rms_z(&raw.mesh), rms_z(&smooth.mesh));
    assert!(b < 0.5 * a, "interior RMS height {a} → {b}");
    for r in [&raw, &smooth] {
        assert_valid(&r.mesh);
        assert!(boundary_deviation(&input, &r.mesh) <= 1e-9 * input.diagonal());
    }
    // Smoothed vertices left the input; their provenance is the closest input point.
    let bvh = flatcut_mesh::bvh::Bvh::build(&input);
    for (p, x) in smooth.provenance.iter().zip(&smooth.mesh.positions) {
        let f = input.faces[p.face as usize];
        let q = (0..3).fold([0.0; 3], |q, k| {
            add(q, scale(input.positions[f[k] as usize], p.barycentric[k]))
        });
        let c = bvh.closest_point(*x).unwrap();
        assert!((dist(q, *x) - c.distance).abs() <= 1e-9 * input.diagonal());
    }
    assert!(smooth.report.vertex_to_input.max_mm > raw.report.vertex_to_input.max_mm);
}
