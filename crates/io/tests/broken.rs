//! Every file in fixtures/broken must be rejected with an error naming the file (and, for
//! text formats, the line); none may panic.

#![allow(clippy::unwrap_used)] // helpers outside #[test] fns unwrap too

use std::path::PathBuf;

use flatcut_io::{Units, read_mesh};

fn broken_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/broken")
}

/// Text files whose error cannot carry a line: they have no content to point at.
const NO_LINE: &[&str] = &[
    "empty.obj",
    "obj_only_vertices.obj",
    "obj_binary_garbage.obj",
    "stl_ascii_no_facets.stl",
];

fn is_text(name: &str, bytes: &[u8]) -> bool {
    name.ends_with(".obj")
        || (name.ends_with(".ply")
            && (bytes.starts_with(b"ply\nformat ascii")
                || !bytes.starts_with(b"ply\nformat binary")))
        || (name.ends_with(".stl") && bytes.starts_with(b"solid"))
}

/// Whether a message contains ":<digits>:" right after the file name.
fn has_line(msg: &str, name: &str) -> bool {
    msg.split(name).nth(1).is_some_and(|rest| {
        let rest = rest.strip_prefix(':').unwrap_or("");
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        !digits.is_empty() && digits != "0" && rest[digits.len()..].starts_with(':')
    })
}

#[test]
fn every_broken_file_is_an_error_naming_file_and_line() {
    let readme = std::fs::read_to_string(broken_dir().join("README.md")).unwrap();
    let mut count = 0;
    let mut entries: Vec<_> = std::fs::read_dir(broken_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        if name == "README.md" {
            continue;
        }
        count += 1;
        assert!(
            readme.contains(&format!("| {name} |")),
            "{name} is not described in README.md"
        );
        let bytes = std::fs::read(&path).unwrap();
        let result = read_mesh(&path, Units::Mm);
        let err = match result {
            Ok(m) => panic!(
                "{name}: expected an error, got a mesh with {} faces",
                m.mesh.faces.len()
            ),
            Err(e) => e.to_string(),
        };
        assert!(
            err.contains(&name),
            "{name}: message does not name the file: {err}"
        );
        if is_text(&name, &bytes) && !NO_LINE.contains(&name.as_str()) && !bytes.is_empty() {
            assert!(
                has_line(&err, &name),
                "{name}: message has no line number: {err}"
            );
        }
        println!("{err}");
    }
    assert!(count >= 40, "only {count} broken files");
}
