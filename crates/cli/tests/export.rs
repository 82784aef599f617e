//! `flatcut export` end to end: a cylinder piece flattened by `flatcut flatten` and exported to
//! every format; two flat pieces with a hand-made seam ledger; bad input refused with nothing
//! left behind.

#![allow(clippy::unwrap_used)]

mod common;

use common::flatcut;

use std::path::Path;

/// A 120° cylinder piece (radius 50 mm, 80 mm tall), `nu × nv` vertices, as OBJ text.
fn cylinder_obj(nu: usize, nv: usize) -> String {
    let mut s = String::new();
    for j in 0..nv {
        for i in 0..nu {
            let a = (120.0f64).to_radians() * i as f64 / (nu - 1) as f64;
            let y = 80.0 * j as f64 / (nv - 1) as f64;
            s += &format!(
                "v {:.17} {:.17} {:.17}\n",
                50.0 * a.cos(),
                y,
                -50.0 * a.sin()
            );
        }
    }
    for j in 0..nv - 1 {
        for i in 0..nu - 1 {
            let a = i + nu * j + 1;
            let (b, c, d) = (a + 1, a + 1 + nu, a + nu);
            s += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    s
}

/// A flat grid [x0, x0+w] × [0, h] with nx × ny vertices, as OBJ text (z = 0).
fn flat_obj(x0: f64, w: f64, h: f64, nx: usize, ny: usize) -> String {
    let mut s = String::new();
    for j in 0..ny {
        for i in 0..nx {
            let x = x0 + w * i as f64 / (nx - 1) as f64;
            let y = h * j as f64 / (ny - 1) as f64;
            s += &format!("v {x} {y} 0\n");
        }
    }
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = i + nx * j + 1;
            let (b, c, d) = (a + 1, a + 1 + nx, a + nx);
            s += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    s
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn flattened_cylinder_to_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let solid = dir.path().join("panel.obj");
    let flat = dir.path().join("panel-flat.obj");
    std::fs::write(&solid, cylinder_obj(13, 9)).unwrap();
    let st = flatcut()
        .arg("flatten")
        .arg(&solid)
        .arg(&flat)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let out = dir.path().join("out");
    let st = flatcut()
        .arg("export")
        .arg(format!("{}={}", flat.display(), solid.display()))
        .arg("--out")
        .arg(&out)
        .args([
            "--formats",
            "svg,png,exr,dxf,pdf,glb",
            "--seam-allowance-mm",
            "12",
            "--json",
        ])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&st.stdout).unwrap();
    let piece = &report["pieces"][0];
    assert_eq!(piece["name"], "panel");
    // The unrolled 120° cylinder is 104.72 × 80 mm: perimeter 369.44 mm.
    let per = piece["sew_length_mm"].as_f64().unwrap();
    let want = 2.0 * (50.0 * 120f64.to_radians() + 80.0);
    assert!((per - want).abs() < 0.5, "{per} vs {want}");
    assert_eq!(
        files(&out),
        vec![
            "panel-e_h.glb",
            "panel-e_h.png",
            "panel-e_r.png",
            "panel-strain.png",
            "panel.exr",
            "panel.svg",
            "pattern.dxf",
            "sheet-tiled.pdf",
            "sheet.png",
            "sheet.svg"
        ]
    );
    let svg = std::fs::read_to_string(out.join("panel.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("mm\" viewBox="));
}

#[test]
fn two_pieces_with_a_ledger() {
    let dir = tempfile::tempdir().unwrap();
    let left = dir.path().join("left.obj");
    let right = dir.path().join("right.obj");
    std::fs::write(&left, flat_obj(0.0, 100.0, 250.0, 3, 6)).unwrap();
    std::fs::write(&right, flat_obj(100.0, 100.0, 250.0, 3, 6)).unwrap();
    let seams = dir.path().join("seams.json");
    std::fs::write(
        &seams,
        r#"{"schema":1,"pieces":["left","right"],"seams":[{"id":"centre/0","line":"centre","kind":"seam",
        "a":{"piece":"left","vertices":[2,5,8,11,14,17]},"b":{"piece":"right","vertices":[0,3,6,9,12,15]},
        "length_3d_mm":250.0,"start_mm":[100,0,0],"end_mm":[100,250,0]}]}"#,
    )
    .unwrap();
    let meta = dir.path().join("meta.json");
    std::fs::write(
        &meta,
        r#"{"left": {"size": "M", "quantity": 2, "mirror": true, "shrink_across_grain": -0.05}}"#,
    )
    .unwrap();
    let out = dir.path().join("out");
    let st = flatcut()
        .args(["export"])
        .arg("--meta")
        .arg(&meta)
        .arg(&left)
        .arg(&right)
        .arg("--seams")
        .arg(&seams)
        .arg("--out")
        .arg(&out)
        .args(["--formats", "svg,dxf", "--json"])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&st.stdout).unwrap();
    // 250 mm seam at ≤ 100 mm spacing: ends + 2 intermediate = 4 notches on each mate.
    for p in 0..2 {
        assert_eq!(report["pieces"][p]["notches"], 4);
        assert_eq!(report["pieces"][p]["seams"][0]["length_2d_mm"], 250.0);
    }
    let svg = std::fs::read_to_string(out.join("right.svg")).unwrap();
    assert!(svg.contains("data-seam-id=\"centre/0\""));
    // The left piece: −5 % across the grain (x), cut as a mirrored pair.
    let l = &report["pieces"][0];
    assert!((l["area_mm2"].as_f64().unwrap() - 0.95 * 25_000.0).abs() < 1e-6);
    let svg = std::fs::read_to_string(out.join("left.svg")).unwrap();
    assert!(svg.contains(">cut 2, mirrored<") && svg.contains(">size M<"));
    let sheet = std::fs::read_to_string(out.join("sheet.svg")).unwrap();
    assert!(sheet.contains("id=\"left-1\"") && sheet.contains("id=\"right-0\""));
}

#[test]
fn bad_input_is_refused_and_nothing_is_left() {
    let dir = tempfile::tempdir().unwrap();
    let piece = dir.path().join("p.obj");
    std::fs::write(&piece, flat_obj(0.0, 60.0, 40.0, 3, 3)).unwrap();
    let out = dir.path().join("out");
    let run = |extra: &[&str]| {
        let o = flatcut()
            .arg("export")
            .arg(&piece)
            .arg("--out")
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{extra:?}");
        assert!(files(&out).is_empty(), "{extra:?} left {:?}", files(&out));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    assert!(run(&["--formats", "svg,tiff"]).contains("unknown format 'tiff'"));
    assert!(run(&["--seam-allowance-mm", "-3"]).contains("seam_allowance_mm = -3"));
    assert!(run(&["--seam-allowance-mm", "25"]).contains("more than half the piece"));
    assert!(run(&["--formats", "png"]).contains("needs the 3D piece"));
    let po = dir.path().join("po.json");
    std::fs::write(&po, r#"{"corner": {"miter": {"limit": 0.5}}}"#).unwrap();
    let e = run(&["--pattern-options", po.to_str().unwrap()]);
    assert!(e.contains("corner.miter.limit = 0.5"), "{e}");
    std::fs::write(&po, r#"{"seam_allowance": 3}"#).unwrap();
    let e = run(&["--pattern-options", po.to_str().unwrap()]);
    assert!(e.contains("unknown field `seam_allowance`"), "{e}");
    // A folded flattening: a corner pulled across the opposite edge.
    let folded = flat_obj(0.0, 60.0, 40.0, 3, 3).replace("v 60 40 0", "v -20 20 0");
    std::fs::write(&piece, folded).unwrap();
    let e = run(&[]);
    assert!(e.contains("crosses itself near"), "{e}");
}
