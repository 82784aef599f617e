//! Every file in fixtures/broken/ through the CLI: exit code 1 (bad input), an error that
//! names the file, and never a panic.

use std::path::PathBuf;
use std::process::Command;

fn broken_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/broken")
}

#[test]
fn every_broken_fixture_is_refused_with_a_named_error() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(broken_dir())
        .expect("fixtures/broken exists")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e != "md" && e != "bin"))
        .collect();
    files.sort();
    assert!(
        files.len() >= 40,
        "the broken corpus must hold at least 40 files, found {}",
        files.len()
    );
    let mut problems = Vec::new();
    for path in &files {
        let out = Command::new(env!("CARGO_BIN_EXE_flatcut"))
            .arg("info")
            .arg(path)
            .output()
            .expect("run flatcut");
        let stderr = String::from_utf8_lossy(&out.stderr);
        let name = path.file_name().expect("name").to_string_lossy();
        if out.status.code() != Some(1) {
            problems.push(format!(
                "{name}: exit code {:?} (want 1); stderr: {stderr}",
                out.status.code()
            ));
        } else if !stderr.contains(name.as_ref()) {
            problems.push(format!(
                "{name}: the error does not name the file: {stderr}"
            ));
        } else if stderr.contains("internal error") || stderr.contains("panicked") {
            problems.push(format!("{name}: panicked: {stderr}"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn usage_errors_exit_with_2() {
    let out = Command::new(env!("CARGO_BIN_EXE_flatcut"))
        .args(["info"])
        .output()
        .expect("run flatcut");
    assert_eq!(out.status.code(), Some(2));
    let out = Command::new(env!("CARGO_BIN_EXE_flatcut"))
        .args(["info", "x.obj", "--units", "furlong"])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("furlong"));
}

#[test]
fn a_missing_file_is_a_bad_input_not_a_crash() {
    let out = Command::new(env!("CARGO_BIN_EXE_flatcut"))
        .args(["info", "/nonexistent/dir/scan.obj"])
        .output()
        .expect("run flatcut");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("scan.obj"));
}
