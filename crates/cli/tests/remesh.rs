//! `flatcut remesh` end to end: a sphere with a small and a large hole comes back at the
//! target edge length, the small hole filled, the report in JSON; bad input exits 1 with
//! the element named.

#![allow(clippy::unwrap_used)]

mod common;

use common::{flatcut, succeed, succeed_json};

use std::path::Path;

use flatcut_mesh::shapes::icosphere;
use flatcut_mesh::vec3::norm;

/// `flatcut remesh ARGS --json INPUT OUTPUT`, which must succeed; its JSON report.
fn remesh_json(args: &[&str], input: &Path, output: &Path) -> serde_json::Value {
    succeed_json(
        flatcut()
            .arg("remesh")
            .args(args)
            .arg("--json")
            .arg(input)
            .arg(output),
    )
}

/// An icosphere of radius 100 mm with the faces around two vertices removed: one small
/// hole (one ring) and one large opening (faces within 40 mm of a second vertex).
fn holed_sphere() -> flatcut_mesh::TriMesh {
    let s = icosphere(100.0, 4);
    let large = s.positions[3];
    let faces = s
        .faces
        .iter()
        .filter(|f| {
            !f.contains(&0)
                && !f.iter().any(|&v| {
                    let p = s.positions[v as usize];
                    norm(flatcut_mesh::vec3::sub(p, large)) < 40.0
                })
        })
        .copied()
        .collect();
    flatcut_mesh::TriMesh {
        positions: s.positions,
        faces,
        ..Default::default()
    }
}

#[test]
fn remesh_fills_the_small_hole_and_reports_quality() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.obj");
    flatcut_io::write_mesh(
        &input,
        &holed_sphere(),
        &flatcut_io::WriteOptions::default(),
    )
    .unwrap();
    let before = std::fs::read(&input).unwrap();
    let output = dir.path().join("out.obj");
    let r = remesh_json(
        &["--edge-mm", "10", "--fill-holes-mm", "100"],
        &input,
        &output,
    );
    let q = &r["quality"];
    assert_eq!(q["holes"].as_array().unwrap().len(), 2);
    assert_eq!(q["holes_filled"], 1);
    assert!(q["edges_within_half_to_1_5"].as_f64().unwrap() >= 0.99);
    assert!(q["vertex_to_input"]["max_mm"].as_f64().unwrap() < 1e-9);
    // The default approximation-error bound is checked and reported: 10 mm triangles on a
    // 100 mm sphere sit ≈ 0.17 mm inside it, so nothing is over it and nothing is rough.
    assert_eq!(q["max_deviation_mm"], 0.5);
    assert_eq!(q["samples_over_deviation"], 0);
    assert_eq!(q["rough_input_fraction"], 0.0);
    assert!(q["centroid_to_input"]["max_mm"].as_f64().unwrap() <= 0.5);
    assert_eq!(
        std::fs::read(&input).unwrap(),
        before,
        "the input must not change"
    );
    // The written mesh has exactly one boundary loop left: the large opening.
    let info = flatcut()
        .args(["info", "--json"])
        .arg(&output)
        .output()
        .unwrap();
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(info["boundary_loops"].as_array().unwrap().len(), 1);
    assert_eq!(info["faces"], q["faces"]);

    // Decimation first, then remesh; text output names the holes.
    let out2 = dir.path().join("out2.obj");
    let out = succeed(
        flatcut()
            .args(["remesh", "--decimate-to", "1000", "--edge-mm", "12"])
            .arg(&input)
            .arg(&out2),
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("decimated to"), "{text}");
    assert!(text.contains("open"), "{text}");
}

#[test]
fn remesh_refuses_bad_input_naming_the_element() {
    let dir = tempfile::tempdir().unwrap();
    let fin = dir.path().join("fin.obj");
    std::fs::write(
        &fin,
        "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0\nv 0.5 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    )
    .unwrap();
    let out = flatcut()
        .args(["remesh", "--edge-mm", "0.3"])
        .arg(&fin)
        .arg(dir.path().join("o.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("edge 0–1 is non-manifold"), "{err}");
    assert!(err.contains("fin.obj"), "{err}");
    // A target larger than the object.
    let out = flatcut()
        .args(["remesh", "--edge-mm", "100"])
        .arg(&fin)
        .arg(dir.path().join("o.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    // Neither --edge-mm nor --decimate-to.
    let out = flatcut()
        .arg("remesh")
        .arg(&fin)
        .arg(dir.path().join("o.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--edge-mm"));
    // A negative deviation bound names the option.
    let sphere = dir.path().join("sphere.obj");
    flatcut_io::write_mesh(
        &sphere,
        &icosphere(50.0, 3),
        &flatcut_io::WriteOptions::default(),
    )
    .unwrap();
    let out = flatcut()
        .args(["remesh", "--edge-mm", "8", "--max-deviation-mm=-1"])
        .arg(&sphere)
        .arg(dir.path().join("o.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("max_deviation_mm") && err.contains("sphere.obj"),
        "{err}"
    );
}

/// `--smooth-iterations`: on a sheet with ±1.5 mm height noise the smoothed output's vertices
/// leave the input (the report says by how much) and its interior is flatter than the plain
/// remesh, whose vertices lie on the noisy input.
#[test]
fn smooth_iterations_flattens_a_noisy_sheet() {
    let noise = |x: f64, y: f64| {
        let h = ((x * 12.9898 + y * 78.233).sin() * 43_758.545).fract();
        1.5 * (2.0 * h.abs() - 1.0)
    };
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sheet.obj");
    let sheet = flatcut_mesh::shapes::grid_patch(81, 81, 400.0, noise);
    flatcut_io::write_mesh(&input, &sheet, &flatcut_io::WriteOptions::default()).unwrap();
    let run = |smooth: &str| {
        let output = dir.path().join(format!("out{smooth}.obj"));
        let r = remesh_json(
            &[
                "--edge-mm",
                "10",
                "--feature-angle-deg",
                "180",
                "--max-deviation-mm",
                "0",
                "--smooth-iterations",
                smooth,
            ],
            &input,
            &output,
        );
        let mesh = flatcut_io::read_mesh(&output, flatcut_io::Units::Mm)
            .unwrap()
            .mesh;
        let rms = (mesh.positions.iter().map(|p| p[2] * p[2]).sum::<f64>()
            / mesh.positions.len() as f64)
            .sqrt();
        (
            r["quality"]["vertex_to_input"]["max_mm"].as_f64().unwrap(),
            rms,
        )
    };
    let (plain_off, plain_rms) = run("0");
    let (smooth_off, smooth_rms) = run("10");
    assert!(plain_off < 1e-9, "{plain_off}");
    assert!(smooth_off > 0.1, "{smooth_off}");
    assert!(smooth_rms < 0.6 * plain_rms, "{plain_rms} → {smooth_rms}");
}

/// A report over the input is refused before anything is read or written.
#[test]
fn remesh_refuses_a_report_over_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.obj");
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(&input, text).unwrap();
    let output = dir.path().join("o.obj");
    let err = common::refused([
        "remesh".as_ref(),
        "--edge-mm".as_ref(),
        "0.3".as_ref(),
        input.as_os_str(),
        output.as_os_str(),
        "--report".as_ref(),
        input.as_os_str(),
    ]);
    assert!(
        err.contains("--report") && err.contains("is the input IN"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&input).unwrap(), text);
    assert!(!output.exists());
}
