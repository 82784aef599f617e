//! `flatcut demo` (the README's main-job command) end to end: the generated dress form is
//! written as OBJ and GLB, both read back to the same surface, and its info JSON matches.

mod common;

use common::{flatcut, succeed, succeed_json};

#[test]
fn demo_writes_a_readable_dress_form_and_its_info() {
    let dir = tempfile::tempdir().unwrap();
    succeed(flatcut().args(["demo", "--out"]).arg(dir.path()));
    let info = |file: &str| -> serde_json::Value {
        succeed_json(
            flatcut()
                .args(["info", "--json"])
                .arg(dir.path().join(file)),
        )
    };
    let obj = info("dress_form.obj");
    // An open torso: one component, neck + two arm holes + bottom opening, χ = 2 − 2·0 − 4.
    assert_eq!(obj["components"], 1);
    assert_eq!(obj["boundary_loops"].as_array().unwrap().len(), 4);
    assert_eq!(obj["euler_characteristic"], -2);
    assert_eq!(obj["non_manifold_edges"], 0);
    assert_eq!(obj["inconsistently_oriented_edges"], 0);
    // The GLB (metres by the glTF convention, read back as such) is the same surface at f32.
    let glb = info("dress_form_angle_defect.glb");
    assert_eq!(glb["faces"], obj["faces"]);
    assert_eq!(glb["vertices"], obj["vertices"]);
    for k in 0..3 {
        let (a, b) = (
            glb["bbox_max"][k].as_f64().unwrap(),
            obj["bbox_max"][k].as_f64().unwrap(),
        );
        assert!(
            (a - b).abs() <= 1e-6 * b.abs().max(1.0),
            "bbox_max[{k}]: glb {a} vs obj {b}"
        );
    }
    let saved: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("dress_form_info.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(saved["faces"], obj["faces"]);
    assert_eq!(saved["boundary_loops"], obj["boundary_loops"]);
}

#[test]
fn demo_refuses_a_nonsense_measurement() {
    let dir = tempfile::tempdir().unwrap();
    let out = flatcut()
        .args(["demo", "--bust-mm=-5", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--bust-mm"));
}
