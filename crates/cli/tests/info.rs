//! `flatcut info` on meshes at the edge of f64: a warning instead of NaN or 300-digit numbers.

#![allow(clippy::unwrap_used)]

mod common;

use common::{flatcut, succeed, succeed_json};

/// A cone (one interior vertex, defect 0.279 rad) at 1 mm and at 1e300 mm: at 1e300 its
/// angles overflow, so the text says so and warns with the extent (no "NaN", no
/// 300-digit coordinate), and the JSON carries the warning and no NaN; at 1 mm no warning.
#[test]
fn info_warns_instead_of_printing_overflowed_angles() {
    let dir = tempfile::tempdir().unwrap();
    let cone = |s: f64| {
        let mut t = format!("v 0 0 {}\n", 0.3 * s);
        for k in 0..8 {
            let a = std::f64::consts::TAU * k as f64 / 8.0;
            t += &format!("v {:?} {:?} 0\n", s * a.cos(), s * a.sin());
        }
        for k in 0..8 {
            t += &format!("f 1 {} {}\n", k + 2, (k + 1) % 8 + 2);
        }
        t
    };
    let small = dir.path().join("small.obj");
    let huge = dir.path().join("huge.obj");
    std::fs::write(&small, cone(1.0)).unwrap();
    std::fs::write(&huge, cone(1e300)).unwrap();

    let text = |path: &std::path::Path| {
        String::from_utf8(succeed(flatcut().arg("info").arg(path)).stdout).unwrap()
    };
    let t = text(&small);
    assert!(t.contains("angle defect max     2.785128e-1 rad"), "{t}");
    assert!(!t.contains("warning"), "{t}");
    let t = text(&huge);
    assert!(!t.contains("NaN") && !t.contains("000000000000"), "{t}");
    assert!(t.contains("angle defect max     not computable"), "{t}");
    assert!(t.contains("warning: component 0 spans 2.844e300 mm"), "{t}");

    let j = succeed_json(flatcut().arg("info").arg("--json").arg(&huge));
    assert!(j["max_angle_defect"].is_null(), "{j}");
    let w = j["warnings"][0].as_str().unwrap();
    assert!(w.contains("spans 2.844e300"), "{w}");
}
