//! Quadric error decimation: face budget, distance to the input, boundaries, provenance.

#![allow(clippy::unwrap_used)]

use flatcut_mesh::shapes::{icosphere, planar_disk};
use flatcut_mesh::vec3::{add, dist, norm, scale, sub};
use flatcut_mesh::{Topology, TriMesh};
use flatcut_remesh::{DecimateOptions, RemeshError, decimate};

fn circumradius(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let area = 0.5 * norm(flatcut_mesh::vec3::cross(sub(b, a), sub(c, a)));
    dist(b, c) * dist(a, c) * dist(a, b) / (4.0 * area)
}

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
fn sphere_meets_the_budget_and_stays_within_the_sagitta() {
    let r = 100.0;
    let input = icosphere(r, 5); // 20480 faces
    let out = decimate(&input, &DecimateOptions { target_faces: 2000 }).unwrap();
    let m = &out.mesh;
    assert_valid(m);
    assert!(
        m.faces.len() <= 2000 && m.faces.len() >= 1990,
        "{}",
        m.faces.len()
    );
    assert_eq!(Topology::build(m).unwrap().euler_characteristic(), 2);
    // A sphere's quadric optimum lies between the sphere and the tangent planes of its
    // faces: within the largest output triangle's sagitta R − √(R² − ρ²) of the sphere.
    let rho = m
        .faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| m.positions[i as usize]);
            circumradius(a, b, c)
        })
        .fold(0.0, f64::max);
    let sag = r - (r * r - rho * rho).sqrt();
    for p in &m.positions {
        assert!((norm(*p) - r).abs() <= sag, "{} vs {sag}", norm(*p) - r);
    }
    let q = &out.report;
    assert!(q.hausdorff_mm <= 2.0 * sag, "{} vs {sag}", q.hausdorff_mm);
    // Uniform curvature gives near-uniform triangles.
    assert!(
        q.faces_min_angle_at_least_25_deg > 0.9,
        "{}",
        q.faces_min_angle_at_least_25_deg
    );
    // Provenance: the closest input point of each vertex, within the vertex's distance.
    for (v, p) in out.provenance.iter().enumerate() {
        let f = input.faces[p.face as usize];
        let x = (0..3).fold([0.0; 3], |s, i| {
            add(s, scale(input.positions[f[i] as usize], p.barycentric[i]))
        });
        assert!(dist(x, m.positions[v]) <= sag + 1e-9);
    }
}

#[test]
fn planar_disk_stays_planar_and_keeps_its_outline() {
    let input = planar_disk(100.0, 40); // 9600 faces
    let out = decimate(&input, &DecimateOptions { target_faces: 800 }).unwrap();
    let m = &out.mesh;
    assert_valid(m);
    assert!(m.faces.len() <= 800);
    assert!(
        m.positions
            .iter()
            .all(|p| p[2].abs() < 1e-9 * input.diagonal())
    );
    let t = Topology::build(m).unwrap();
    assert_eq!(t.boundary_loops().len(), 1);
    assert_eq!(t.euler_characteristic(), 1);
    // Boundary vertices stay within the input ring's sagitta of the circle.
    let rho = 2.0 * std::f64::consts::PI * 100.0 / 240.0;
    for v in &t.boundary_loops()[0] {
        let p = m.positions[v.idx()];
        let rr = (p[0] * p[0] + p[1] * p[1]).sqrt();
        assert!((rr - 100.0).abs() < rho, "{rr}");
    }
    assert!(out.report.hausdorff_mm < 2.0, "{}", out.report.hausdorff_mm);
}

#[test]
fn bad_budgets_and_input_are_refused() {
    let disk = planar_disk(10.0, 4);
    let e = decimate(&disk, &DecimateOptions { target_faces: 2 }).unwrap_err();
    assert!(matches!(
        e,
        RemeshError::InvalidOption {
            name: "target_faces",
            ..
        }
    ));
    let fin = flatcut_mesh::shapes::non_manifold_fin();
    let e = decimate(&fin, &DecimateOptions { target_faces: 10 }).unwrap_err();
    assert_eq!(e, RemeshError::NonManifoldEdge { a: 0, b: 1 });
    // A budget above the face count returns the mesh unchanged.
    let out = decimate(&disk, &DecimateOptions { target_faces: 1000 }).unwrap();
    assert_eq!(out.mesh.faces.len(), disk.faces.len());
    assert_eq!(out.mesh.positions, disk.positions);
}
