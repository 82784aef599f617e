//! `flatcut flatten` end to end: a developable OBJ in, a true-size planar OBJ and metrics out.

#![allow(clippy::unwrap_used)]

mod common;

use common::{flatcut, refused, succeed, succeed_json};

use std::path::Path;

/// A 120° cylinder piece (radius 50 mm, 80 mm tall) as OBJ text, `nu × nv` vertices.
fn cylinder_obj(nu: usize, nv: usize) -> (String, Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let mut p = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let a = (120.0f64).to_radians() * i as f64 / (nu - 1) as f64;
            p.push([
                50.0 * a.cos(),
                80.0 * j as f64 / (nv - 1) as f64,
                -50.0 * a.sin(),
            ]);
        }
    }
    let mut f = Vec::new();
    for j in 0..nv - 1 {
        for i in 0..nu - 1 {
            let (a, b, c, d) = (
                i + nu * j,
                i + 1 + nu * j,
                i + 1 + nu * (j + 1),
                i + nu * (j + 1),
            );
            f.push([a, b, c]);
            f.push([a, c, d]);
        }
    }
    let mut s = String::new();
    for q in &p {
        s += &format!("v {:.17} {:.17} {:.17}\n", q[0], q[1], q[2]);
    }
    for t in &f {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    (s, p, f)
}

/// `v`, `vt` and `f` (0-based) lines of an OBJ file.
type Obj = (Vec<[f64; 3]>, Vec<[f64; 2]>, Vec<[usize; 3]>);

fn read_obj(path: &Path) -> Obj {
    let text = std::fs::read_to_string(path).unwrap();
    let (mut v, mut vt, mut f) = (Vec::new(), Vec::new(), Vec::new());
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.map(|t| t.parse().unwrap()).collect();
                v.push([c[0], c[1], c[2]]);
            }
            Some("vt") => {
                let c: Vec<f64> = it.map(|t| t.parse().unwrap()).collect();
                vt.push([c[0], c[1]]);
            }
            Some("f") => {
                let c: Vec<usize> = it
                    .map(|t| t.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect();
                f.push([c[0], c[1], c[2]]);
            }
            _ => {}
        }
    }
    (v, vt, f)
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn flattens_a_cylinder_to_true_size_with_metrics() {
    let dir = tempfile::tempdir().unwrap();
    let (obj, p3, f3) = cylinder_obj(13, 6);
    let input = dir.path().join("cyl.obj");
    std::fs::write(&input, obj).unwrap();
    let output = dir.path().join("flat.obj");
    let metrics = dir.path().join("m.json");
    let out = succeed(
        flatcut()
            .arg("flatten")
            .arg(&input)
            .arg(&output)
            .args(["--grain", "0,1,0", "--metrics"])
            .arg(&metrics)
            .arg("--json"),
    );
    let (v, _vt, f) = read_obj(&output);
    assert_eq!(f, f3, "same faces in the same order");
    assert_eq!(v.len(), p3.len());
    assert!(v.iter().all(|q| q[2] == 0.0));
    // True size: every edge keeps its 3D length (up to the text round trip).
    for t in &f {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let l3 = dist(&p3[a], &p3[b]);
            let l2 = dist(&v[a][..2], &v[b][..2]);
            assert!((l2 / l3 - 1.0).abs() < 1e-9, "edge {a}-{b}: {l2} vs {l3}");
        }
        // Counter-clockwise: never mirrored.
        let [a, b, c] = t.map(|i| v[i]);
        assert!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0);
    }
    // Grain: the cylinder's rulings (3D +y) run along +y.
    assert!((v[13 * 5][0] - v[0][0]).abs() < 1e-9 && (v[13 * 5][1] - v[0][1] - 80.0).abs() < 1e-9);
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&metrics).unwrap()).unwrap();
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(file, printed);
    for key in [
        "faces",
        "components",
        "seconds",
        "e_h",
        "e_r",
        "max_edge_strain",
        "area_3d_mm2",
        "area_2d_mm2",
        "flipped_faces",
    ] {
        assert!(file.get(key).is_some(), "metrics lack {key}");
    }
    assert_eq!(file["faces"], 120);
    assert_eq!(file["components"], 1);
    assert_eq!(file["flipped_faces"], 0);
    for key in ["mean", "max", "p95"] {
        assert!(file["e_h"][key].as_f64().unwrap() < 1e-9);
        assert!(file["e_r"][key].as_f64().unwrap() < 1e-9);
    }
    assert!(file["max_edge_strain"].as_f64().unwrap() < 1e-9);
    let (a3, a2) = (
        file["area_3d_mm2"].as_f64().unwrap(),
        file["area_2d_mm2"].as_f64().unwrap(),
    );
    // Area of the facetted cylinder: 12 planar strips of chord width 2·50·sin(5°) × 80 mm.
    let exact = 12.0 * 2.0 * 50.0 * (5.0f64).to_radians().sin() * 80.0;
    assert!((a3 - exact).abs() < 1e-9 * exact && (a2 - exact).abs() < 1e-9 * exact);
}

#[test]
fn writes_texture_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cyl.obj");
    std::fs::write(&input, cylinder_obj(5, 3).0).unwrap();
    let output = dir.path().join("flat.obj");
    let st = flatcut()
        .arg("flatten")
        .arg(&input)
        .arg(&output)
        .status()
        .unwrap();
    assert!(st.success());
    let (v, vt, _) = read_obj(&output);
    assert_eq!(vt.len(), v.len());
    for (a, b) in v.iter().zip(&vt) {
        assert_eq!([a[0], a[1]], *b);
    }
}

#[test]
fn lscm_method_and_given_pins() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cyl.obj");
    std::fs::write(&input, cylinder_obj(7, 4).0).unwrap();
    let output = dir.path().join("flat.obj");
    let m = succeed_json(
        flatcut()
            .arg("flatten")
            .arg(&input)
            .arg(&output)
            .args(["--method", "lscm", "--pins", "0,27", "--json"]),
    );
    assert_eq!(m["pins"][0], serde_json::json!([0, 27]));
    // Conformal only: sizes drift on a curved piece.
    assert!(m["e_h"]["max"].as_f64().unwrap() > 1e-3);
    assert!(m["e_r"]["max"].as_f64().unwrap() < 1e-9);
}

#[test]
fn refuses_a_closed_piece_and_bad_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tet.obj");
    std::fs::write(
        &input,
        "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
    )
    .unwrap();
    let output = dir.path().join("flat.obj");
    let out = flatcut()
        .arg("flatten")
        .arg(&input)
        .arg(&output)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("tet.obj") && err.contains("closed"), "{err}");
    assert!(!output.exists());
    for bad in [["--pins", "1"], ["--grain", "0,0,0"], ["--method", "magic"]] {
        let out = flatcut()
            .arg("flatten")
            .arg(&input)
            .arg(&output)
            .args(bad)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
}

/// OUT or --metrics naming the input (here as `dir/./in.obj`) is refused, the input untouched.
#[test]
fn flatten_refuses_to_overwrite_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.obj");
    let (text, _, _) = cylinder_obj(6, 4);
    std::fs::write(&input, &text).unwrap();
    let dotted = dir.path().join(".").join("in.obj");
    let err = refused(["flatten".as_ref(), input.as_os_str(), dotted.as_os_str()]);
    assert!(
        err.contains("OUT") && err.contains("is the input IN"),
        "{err}"
    );
    let out = dir.path().join("out.obj");
    let err = refused([
        "flatten".as_ref(),
        input.as_os_str(),
        out.as_os_str(),
        "--metrics".as_ref(),
        input.as_os_str(),
    ]);
    assert!(err.contains("--metrics"), "{err}");
    assert_eq!(std::fs::read_to_string(&input).unwrap(), text);
    assert!(!out.exists());
}
