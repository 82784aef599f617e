//! `flatcut surface` end to end: the sofa fixtures in, a disk patch (OBJ, mm) and a report
//! out; bad wire-frames refused with the file, line and element named.

#![allow(clippy::unwrap_used)]

mod common;

use common::flatcut;

use std::path::{Path, PathBuf};
use std::process::Output;

use flatcut_io::{Units, read_mesh};
use flatcut_mesh::{Topology, geometry::corner_angles, vec3::dist};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/wireframes")
        .join(name)
}

fn run(args: &[&Path]) -> Output {
    let mut c = flatcut();
    c.arg("surface");
    for a in args {
        c.arg(a);
    }
    c.output().unwrap()
}

/// The curves of a fixture in mm (read independently of flatcut_trim's parser).
fn curves_mm(path: &Path) -> Vec<Vec<[f64; 3]>> {
    let v: toml::Value = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let f = match v.get("units").and_then(|u| u.as_str()).unwrap_or("mm") {
        "mm" => 1.0,
        "cm" => 10.0,
        u => panic!("units {u}"),
    };
    v["curve"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            c["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| {
                    let a = p.as_array().unwrap();
                    [0, 1, 2].map(|k| {
                        f * a[k]
                            .as_float()
                            .or(a[k].as_integer().map(|i| i as f64))
                            .unwrap()
                    })
                })
                .collect()
        })
        .collect()
}

fn point_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let t = (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1] + (p[2] - a[2]) * ab[2]) / l2)
        .clamp(0.0, 1.0);
    dist(p, [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]])
}

/// `facing`: the direction the patch's (area-weighted mean) normal should point.
fn check_fixture(name: &str, facing: [f64; 3]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("patch.obj");
    let report = dir.path().join("report.json");
    let wire = fixture(name);
    let o = flatcut()
        .args([
            "surface".as_ref(),
            wire.as_os_str(),
            out.as_os_str(),
            "--json".as_ref(),
            "--report".as_ref(),
            report.as_os_str(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(printed, written);

    let mesh = read_mesh(&out, Units::Mm).unwrap().mesh;
    let topo = Topology::build(&mesh).unwrap();
    assert_eq!(topo.boundary_loops().len(), 1);
    assert_eq!(topo.euler_characteristic(), 1);
    assert_eq!(
        printed["faces"].as_u64().unwrap() as usize,
        mesh.faces.len()
    );

    let curves = curves_mm(&wire);
    let all: Vec<[f64; 3]> = curves.iter().flatten().copied().collect();
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &all {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let tol = 1e-9 * dist(lo, hi);
    // Every curve point is a vertex; every boundary vertex is on a curve segment.
    for q in &all {
        let d = mesh
            .positions
            .iter()
            .map(|p| dist(*p, *q))
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= tol,
            "{name}: curve point {q:?} is {d} mm from the patch"
        );
    }
    for v in &topo.boundary_loops()[0] {
        let p = mesh.positions[v.0 as usize];
        let d = curves
            .iter()
            .flat_map(|c| c.windows(2))
            .map(|w| point_segment(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= tol,
            "{name}: boundary vertex {} is {d} mm off the curves",
            v.0
        );
    }
    let min = corner_angles(&mesh.positions, &mesh.faces)
        .iter()
        .flatten()
        .fold(f64::INFINITY, |a, &b| a.min(b))
        .to_degrees();
    assert!(min >= 20.0, "{name}: min angle {min}");
    let reported = printed["min_angle_3d_deg"].as_f64().unwrap();
    assert!((reported - min).abs() < 1e-6, "{reported} vs {min}");
    assert!(printed["max_boundary_deviation_mm"].as_f64().unwrap() <= tol);
    // Area vector Σ ½ (b − a) × (c − a), normalised.
    let mut sum = [0.0; 3];
    for f in &mesh.faces {
        let [a, b, c] = f.map(|v| mesh.positions[v as usize]);
        let n =
            flatcut_mesh::vec3::cross(flatcut_mesh::vec3::sub(b, a), flatcut_mesh::vec3::sub(c, a));
        sum = flatcut_mesh::vec3::add(sum, n);
    }
    let cos = flatcut_mesh::vec3::dot(flatcut_mesh::vec3::normalize(sum), facing);
    assert!(
        cos > 0.9,
        "{name}: mean normal {sum:?} does not face {facing:?}"
    );
}

#[test]
fn sofa_seat_fixture() {
    check_fixture("seat.toml", [0.0, 0.0, 1.0]);
}

#[test]
fn sofa_back_fixture_in_cm() {
    // Leaning back 15°: the normal faces the sitter (−y), tilted up.
    let t = 15f64.to_radians();
    check_fixture("back.toml", [0.0, -t.cos(), t.sin()]);
}

#[test]
fn text_report() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("seat.ply");
    let o = run(&[&fixture("seat.toml"), &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("min angle domain/3D"), "{text}");
    assert!(out.exists());
}

fn fails_with(wire_text: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let wire = dir.path().join("wire.toml");
    std::fs::write(&wire, wire_text).unwrap();
    let out = dir.path().join("out.obj");
    let o = run(&[&wire, &out]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    for n in needles {
        assert!(err.contains(n), "stderr lacks '{n}': {err}");
    }
    assert!(!err.contains("internal error"), "{err}");
    assert!(!out.exists(), "nothing is written on bad input");
}

const SQUARE: &str = r#"
target_edge_mm = 10.0
[[curve]]
name = "sq"
points = [[0, 0, 0], [100, 0, 0], [100, 100, 0], [0, 100, 0], [0, 0, 0]]
"#;

#[test]
fn bad_wireframes_are_refused_with_their_place() {
    // Sanity: the square itself is fine.
    let dir = tempfile::tempdir().unwrap();
    let wire = dir.path().join("sq.toml");
    std::fs::write(&wire, SQUARE).unwrap();
    let o = run(&[&wire, &dir.path().join("sq.obj")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    // TOML syntax error: line and column.
    fails_with(
        "target_edge_mm = 10.0\n[[curve]]\nname = \"a\npoints = []\n",
        &["wire.toml", "line 3"],
    );
    // Unknown key (deny_unknown_fields): its line.
    fails_with(
        &SQUARE.replace("name = \"sq\"", "name = \"sq\"\ncolour = 3"),
        &["wire.toml", "line 5", "colour"],
    );
    // Units.
    fails_with(
        &format!("units = \"ft\"\n{SQUARE}"),
        &["ft", "mm, cm, dm, m, in"],
    );
    // Open loop: the curve is named.
    fails_with(
        &SQUARE.replace(", [0, 0, 0]]", "]"),
        &["does not close", "'sq'"],
    );
    // Target edge.
    fails_with(&SQUARE.replace("10.0", "-1.0"), &["target_edge_mm"]);
    // NaN coordinate: curve and point.
    fails_with(
        &SQUARE.replace("[100, 0, 0]", "[nan, 0, 0]"),
        &["'sq' point 1"],
    );
}

/// OUT naming the wire-frame file (as `dir/./x`) is refused and the wire-frame kept.
#[test]
fn surface_refuses_to_write_over_its_wire_frame() {
    let dir = tempfile::tempdir().unwrap();
    let wire = dir.path().join("wire.toml");
    std::fs::copy(fixture("seat.toml"), &wire).unwrap();
    let before = std::fs::read(&wire).unwrap();
    let out = run(&[&wire, &dir.path().join(".").join("wire.toml")]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("is the input WIRE"), "{err}");
    assert_eq!(std::fs::read(&wire).unwrap(), before);
}
