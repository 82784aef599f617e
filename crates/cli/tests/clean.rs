//! `flatcut clean` end to end: a soup with a duplicate vertex, a degenerate face, a flipped
//! face and a stray triangle comes back repaired, counted, and the input untouched.

mod common;

use common::{flatcut, succeed_json};

// A unit square as two triangles with vertex 4 duplicating vertex 2, the second triangle
// flipped, a degenerate face (repeated index) and a far-away stray triangle (5, 6, 7).
const SOUP: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 1 0\nv 5 5 0\nv 6 5 0\nv 5 6 0\n\
f 1 2 3\nf 1 4 5\nf 1 1 2\nf 6 7 8\n";

#[test]
fn clean_repairs_counts_and_never_touches_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("soup.obj");
    std::fs::write(&input, SOUP).unwrap();
    let output = dir.path().join("clean.obj");
    let report = succeed_json(
        flatcut()
            .args(["clean", "--keep", "largest", "--json"])
            .arg(&input)
            .arg(&output),
    );
    assert_eq!(report["welded_vertices"], 1);
    assert_eq!(report["degenerate_faces"], 1);
    assert_eq!(report["flipped_faces"], 1);
    assert_eq!(report["dropped_components"], 1);
    assert_eq!(report["output_faces"], 2);
    assert_eq!(report["output_vertices"], 4);
    assert_eq!(
        std::fs::read_to_string(&input).unwrap(),
        SOUP,
        "the input must not change"
    );

    // The result is one consistently oriented square: χ = 1, one loop of 4.
    let info = flatcut()
        .args(["info", "--json"])
        .arg(&output)
        .output()
        .unwrap();
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(info["vertices"], 4);
    assert_eq!(info["faces"], 2);
    assert_eq!(info["euler_characteristic"], 1);
    assert_eq!(info["inconsistently_oriented_edges"], 0);
    assert_eq!(info["boundary_loops"], serde_json::json!([4]));
}

#[test]
fn clean_refuses_to_overwrite_its_input_and_bad_weld_distances() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("soup.obj");
    std::fs::write(&input, SOUP).unwrap();
    let out = flatcut()
        .arg("clean")
        .arg(&input)
        .arg(&input)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("never overwrites its input"));
    assert_eq!(std::fs::read_to_string(&input).unwrap(), SOUP);
    let out = flatcut()
        .args(["clean", "--weld-mm", "-1"])
        .arg(&input)
        .arg(dir.path().join("o.obj"))
        .output()
        .unwrap();
    assert_ne!(out.status.code(), Some(0));
}
