//! `flatcut process` end to end: a sphere-cap OBJ in, a flattenable OBJ / GLB and a JSON
//! report out; a run that cannot converge fails with exit code 1 and writes nothing.

#![allow(clippy::unwrap_used)]

mod common;

use common::{flatcut, refused};

use std::path::Path;

/// The 60° test cap (unit sphere over [−0.5, 0.5]², scaled to cm), n × n vertices.
fn cap_obj(n: usize) -> String {
    let mut s = String::new();
    for j in 0..n {
        for i in 0..n {
            let x = -0.5 + i as f64 / (n - 1) as f64;
            let y = -0.5 + j as f64 / (n - 1) as f64;
            let z = (1.0 - x * x - y * y).sqrt();
            s += &format!("v {:.17} {:.17} {:.17}\n", 10.0 * x, 10.0 * y, 10.0 * z);
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = j * n + i + 1;
            let (b, c, d) = (a + 1, a + n, a + n + 1);
            s += &format!("f {a} {b} {d}\nf {a} {d} {c}\n");
        }
    }
    s
}

fn read_obj(path: &Path) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let text = std::fs::read_to_string(path).unwrap();
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.first() {
            Some(&"v") => v.push([
                t[1].parse().unwrap(),
                t[2].parse().unwrap(),
                t[3].parse().unwrap(),
            ]),
            Some(&"f") => {
                let idx = |s: &str| s.split('/').next().unwrap().parse::<u32>().unwrap() - 1;
                f.push([idx(t[1]), idx(t[2]), idx(t[3])]);
            }
            _ => {}
        }
    }
    (v, f)
}

#[test]
fn process_makes_a_cap_flattenable_and_reports() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cap.obj");
    std::fs::write(&input, cap_obj(12)).unwrap();
    let out = dir.path().join("flat.obj");
    let report = dir.path().join("report.json");
    let run = flatcut()
        .args([
            "process",
            input.to_str().unwrap(),
            out.to_str().unwrap(),
            "--units",
            "cm",
        ])
        .args(["--report", report.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("converged"), "{stdout}");
    // The progress spinner draws only on a terminal: piped, standard error stays clean.
    assert!(
        run.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rep: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    for key in [
        "iterations",
        "converged",
        "theta_err",
        "final_theta_err",
        "max_displacement_mm",
        "rms_displacement_mm",
        "area_change_percent",
        "folded_faces",
        "seconds",
        "pieces",
    ] {
        assert!(rep.get(key).is_some(), "missing {key}");
    }
    assert_eq!(rep["converged"], true);
    assert!(rep["final_theta_err"].as_f64().unwrap() <= 1e-9);
    // Displacements are in mm: the cap (radius 100 mm) is pushed down by ~1 cm.
    let maxd = rep["max_displacement_mm"].as_f64().unwrap();
    assert!((5.0..20.0).contains(&maxd), "{maxd}");
    // The written OBJ (in cm, as the input) is flattenable: θ recomputed from the file.
    let (v, f) = read_obj(&out);
    let theta = flatcut_mesh::geometry::angle_sums(&v, &f);
    let mesh = flatcut_mesh::TriMesh::new(v, f).unwrap();
    let topo = flatcut_mesh::Topology::build(&mesh).unwrap();
    let worst = (0..mesh.vertex_count())
        .filter(|&i| topo.is_interior_vertex(flatcut_mesh::VertexId(i as u32)))
        .map(|i| (theta[i] - std::f64::consts::TAU).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-9, "{worst}");
    assert!(mesh.diagonal() < 20.0, "written in cm");

    // GLB output with colours, paper mode, JSON on stdout.
    let glb = dir.path().join("flat.glb");
    let run = flatcut()
        .args(["process", input.to_str().unwrap(), glb.to_str().unwrap()])
        .args([
            "--mode",
            "paper",
            "--update",
            "least-square",
            "--laplacian",
            "uniform",
            "--json",
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rep: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(rep["mode"], "paper");
    let loaded = flatcut_io::read_mesh(&glb, flatcut_io::Units::Mm).unwrap();
    assert!(loaded.mesh.attributes.colors.is_some());
}

#[test]
fn unconverged_run_fails_and_writes_nothing_unless_asked() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cap.obj");
    std::fs::write(&input, cap_obj(10)).unwrap();
    let out = dir.path().join("out.obj");
    let report = dir.path().join("r.json");
    let run = flatcut()
        .args([
            "process",
            input.to_str().unwrap(),
            out.to_str().unwrap(),
            "--max-iterations",
            "2",
        ])
        .args(["--report", report.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("did not converge")
            && err.contains("best θ_err")
            && err.contains(", RMS ")
            && err.contains("(input "),
        "{err}"
    );
    assert!(!out.exists());
    let rep: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(rep["converged"], false);
    let run = flatcut()
        .args([
            "process",
            input.to_str().unwrap(),
            out.to_str().unwrap(),
            "--max-iterations",
            "2",
        ])
        .arg("--keep-best")
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(out.exists());
    // A bad weights file names the file and the problem.
    let w = dir.path().join("w.txt");
    std::fs::write(&w, "1 2 x\n").unwrap();
    let run = flatcut()
        .args([
            "process",
            input.to_str().unwrap(),
            out.to_str().unwrap(),
            "--weights",
            w.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("w.txt:1"));
}

/// `flatcut process INPUT DIR/NAME.obj --report DIR/NAME.json EXTRA…`, which must succeed:
/// the output's positions and the report.
fn process_into(
    dir: &std::path::Path,
    input: &std::path::Path,
    name: &str,
    extra: &[&str],
) -> (Vec<[f64; 3]>, serde_json::Value) {
    let out = dir.join(format!("{name}.obj"));
    let report = dir.join(format!("{name}.json"));
    let status = flatcut()
        .args(["process", input.to_str().unwrap(), out.to_str().unwrap()])
        .args(["--report", report.to_str().unwrap()])
        .args(extra)
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(0), "{status:?}");
    let rep: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    (read_obj(&out).0, rep)
}

/// The largest distance between corresponding vertices of two outputs.
fn farthest_apart(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0f64, f64::max)
}

/// `--no-local-polish` ends the run with global steps: the 55×55 cap (2 809 interior
/// vertices) ends with a region by default and without one with the flag; both are flat to
/// the tolerance and the same surface to a hundredth of the grid spacing. (The 40×40 cap
/// ended with a region until the merit's dead zone let its global steps finish first, the
/// 60×60 cap until the damping's descent learnt the step cap.)
#[test]
fn no_local_polish_ends_with_global_steps() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cap.obj");
    std::fs::write(&input, cap_obj(55)).unwrap();
    // The zero target: the detail target's pull-backs start from each run's end and may
    // settle apart (0.03 mm here since the twenty-fifth session's projection).
    let (polished, a) = process_into(dir.path(), &input, "polished", &["--target", "zero"]);
    let (global, b) = process_into(
        dir.path(),
        &input,
        "global",
        &["--target", "zero", "--no-local-polish"],
    );
    let polish_messages = |rep: &serde_json::Value| {
        rep["pieces"][0]["messages"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|m| m.as_str().unwrap().starts_with("local polish"))
            .count()
    };
    assert_eq!(polish_messages(&a), 1, "{a}");
    assert_eq!(polish_messages(&b), 0, "{b}");
    for rep in [&a, &b] {
        assert_eq!(rep["converged"], true);
        assert!(rep["final_theta_err"].as_f64().unwrap() <= 1e-9);
    }
    // Grid spacing: the file's 10 units over 54 intervals (read and written as mm).
    let spacing_mm = 10.0 / 54.0;
    let farthest = farthest_apart(&polished, &global);
    assert!(farthest < 0.01 * spacing_mm, "{farthest} mm");
}

/// `--damping graph-laplacian` reaches the library: the 20×20 cap converges under it too, on
/// another path than the default identity damping (the surfaces differ beyond round-off);
/// an unknown damping is refused with the choices named.
#[test]
fn damping_flag_chooses_the_damping_shape() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cap.obj");
    std::fs::write(&input, cap_obj(20)).unwrap();
    let run = |name: &str, extra: &[&str]| {
        let (positions, rep) = process_into(dir.path(), &input, name, extra);
        assert_eq!(rep["converged"], true, "{name}: {rep}");
        assert!(rep["final_theta_err"].as_f64().unwrap() <= 1e-9);
        positions
    };
    let identity = run("identity", &[]);
    let explicit = run("explicit", &["--damping", "identity"]);
    let shaped = run("shaped", &["--damping", "graph-laplacian"]);
    assert_eq!(identity, explicit);
    let farthest = farthest_apart(&identity, &shaped);
    assert!(farthest > 1e-6, "{farthest} mm");

    let bad = flatcut()
        .args(["process", input.to_str().unwrap()])
        .arg(dir.path().join("bad.obj"))
        .args(["--damping", "marquardt"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(
        stderr.contains("unknown damping 'marquardt': use identity or graph-laplacian"),
        "{stderr}"
    );
    assert!(!dir.path().join("bad.obj").exists());
}

/// Inputs are never overwritten and one output never overwrites another, however the path is
/// spelt (`dir/./x`, a symbolic link): each is refused before anything is read or written.
#[test]
fn process_refuses_to_overwrite_an_input_or_another_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = cap_obj(6);
    std::fs::write(d.join("cap.obj"), &text).unwrap();
    std::fs::write(d.join("w.txt"), "1\n".repeat(36)).unwrap();
    std::os::unix::fs::symlink(d.join("cap.obj"), d.join("link.obj")).unwrap();
    let p = |name: &str| d.join(name).into_os_string();
    let dotted = |name: &str| d.join(".").join(name).into_os_string();
    let cases: [(Vec<std::ffi::OsString>, &str); 5] = [
        (vec![p("cap.obj"), dotted("cap.obj")], "is the input IN"),
        (vec![p("cap.obj"), p("link.obj")], "is the input IN"),
        (
            vec![p("cap.obj"), p("out.obj"), "--report".into(), p("cap.obj")],
            "--report",
        ),
        (
            vec![
                p("cap.obj"),
                p("out.obj"),
                "--report".into(),
                dotted("out.obj"),
            ],
            "--report and OUT are both",
        ),
        (
            vec![
                p("cap.obj"),
                p("out.obj"),
                "--weights".into(),
                p("w.txt"),
                "--report".into(),
                p("w.txt"),
            ],
            "is the input --weights",
        ),
    ];
    for (args, said) in cases {
        let err = refused(std::iter::once("process".into()).chain(args));
        assert!(err.contains(said), "{err}");
    }
    assert_eq!(std::fs::read_to_string(d.join("cap.obj")).unwrap(), text);
    assert_eq!(
        std::fs::read_to_string(d.join("w.txt")).unwrap(),
        "1\n".repeat(36)
    );
    assert!(!d.join("out.obj").exists());
}

/// An output into a folder that does not exist names the file and the system's reason, once
/// (the chain of causes repeated it).
#[test]
fn an_unwritable_output_names_its_reason_once() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cap.obj");
    std::fs::write(&input, cap_obj(6)).unwrap();
    let out = dir.path().join("missing").join("out.obj");
    let err = refused(["process".as_ref(), input.as_os_str(), out.as_os_str()]);
    assert!(err.contains("cannot write"), "{err}");
    assert_eq!(err.matches("(os error 2)").count(), 1, "{err}");
}

#[test]
fn hole_rims_flag_leaves_holes_open_or_closes_them_and_the_report_says_which() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sheet.obj");
    // Two holes in a 200 mm sheet on a sphere of radius 400 mm.
    let sheet = flatcut_mesh::shapes::patch_with_holes_on_sphere(200.0, 25, 400.0);
    flatcut_io::write_mesh(&input, &sheet, &Default::default()).unwrap();
    let holes = |extra: &[&str], name: &str| {
        let (_, rep) = process_into(dir.path(), &input, name, extra);
        assert_eq!(rep["converged"], true, "{name}: {rep}");
        let piece = &rep["pieces"][0];
        assert_eq!(piece["holes"].as_array().unwrap().len(), 2, "{piece}");
        piece["final_hole_err"].as_f64().unwrap()
    };
    let fixed = holes(&[], "fixed");
    assert!(fixed > 1e-2, "{fixed}");
    let free = holes(&["--hole-rims", "free"], "free");
    assert!(free < 25e-9, "{free}");
    // The text report has a line for them.
    let text = flatcut()
        .args(["process", input.to_str().unwrap()])
        .arg(dir.path().join("text.obj"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&text.stdout);
    assert!(
        stdout.contains("holes: 2; the least closed turns +6.3"),
        "{stdout}"
    );

    let bad = flatcut()
        .args(["process", input.to_str().unwrap()])
        .arg(dir.path().join("bad.obj"))
        .args(["--hole-rims", "loose"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(
        stderr.contains("unknown hole rims 'loose': use fixed or free"),
        "{stderr}"
    );
}
