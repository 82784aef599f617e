//! `flatcut run` end to end through the binary: the bundled demo with no argument, the same
//! bytes on 1 and 2 threads, JSON output, batches with a summary table, and bad input.
// Test helpers unwrap: a failure is a test failure with its message.
#![allow(clippy::unwrap_used)]

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output};

fn flatcut(cwd: &Path, args: &[&str], threads: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flatcut"));
    c.current_dir(cwd).arg("run").args(args);
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    c.output().unwrap()
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "status {:?}\nstdout: {}\nstderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn failed(out: &Output) -> String {
    assert_eq!(
        out.status.code(),
        Some(1),
        "stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Every file under `dir` except timings.json, by relative path.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else if !p.ends_with("timings.json") {
                let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

#[test]
fn no_argument_runs_the_bundled_demo_identically_on_one_and_two_threads() {
    let a = tempfile::tempdir().unwrap();
    let b = tempfile::tempdir().unwrap();
    let text = ok(&flatcut(a.path(), &["--quiet"], Some("1")));
    ok(&flatcut(b.path(), &["--quiet"], Some("2")));
    let dir = a.path().join("out/wetsuit-demo");
    assert!(text.starts_with("wetsuit-demo: "), "{text}");
    assert!(text.contains("out/wetsuit-demo"), "{text}");
    let fa = files(&dir);
    // The folder the README promises: the sheet in every format, the pattern DXF, the 3D
    // pieces, the seams, the report and its page.
    for f in [
        "report.json",
        "report.html",
        "processed.glb",
        "seams.json",
        "sheet.svg",
        "sheet.png",
        "sheet.pdf",
        "pattern.dxf",
        ".flatcut-pipeline",
    ] {
        assert!(fa.contains_key(f), "{f} missing: {:?}", fa.keys());
    }
    assert!(dir.join("timings.json").is_file());
    let report: serde_json::Value = serde_json::from_slice(&fa["report.json"]).unwrap();
    // The generated dress form: no input file, its parameters recorded instead.
    assert_eq!(report["inputs"].as_array().unwrap().len(), 0);
    assert_eq!(report["generator"]["kind"], "dress-form");
    assert_eq!(report["generator"]["bust_mm"], 920.0);
    // One summary line per piece, and each piece's own files.
    for p in report["pieces"].as_array().unwrap() {
        let name = p["name"].as_str().unwrap();
        for ext in ["svg", "png", "exr", "dxf", "obj"] {
            let f = format!("pieces/{name}.{ext}");
            assert!(
                fa.get(&f).is_some_and(|b| !b.is_empty()),
                "{f} missing or empty"
            );
        }
        assert!(
            text.lines().any(|l| l.trim_start().starts_with(name)),
            "{name}: {text}"
        );
    }
    let fb = files(&b.path().join("out/wetsuit-demo"));
    assert_eq!(fa.keys().collect::<Vec<_>>(), fb.keys().collect::<Vec<_>>());
    for (k, v) in &fa {
        assert!(v == &fb[k], "{k} differs between 1 and 2 threads");
    }
    let timings: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("timings.json")).unwrap()).unwrap();
    assert_eq!(timings["threads"], 1);
}

#[test]
fn json_output_carries_the_reports() {
    let tmp = tempfile::tempdir().unwrap();
    let patch = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../pipelines/patch-demo.toml");
    let out = tmp.path().join("o");
    let text = ok(&flatcut(
        tmp.path(),
        &[
            patch.to_str().unwrap(),
            "--json",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    ));
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let run = &v["runs"][0];
    assert_eq!(run["ok"], true);
    assert_eq!(run["pipeline"], "patch-demo");
    // The printed report is the written one.
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(run["report"], written);
    assert!(
        run["report"]["pieces"][0]["process"]["theta_err_after"]
            .as_f64()
            .unwrap()
            <= 1e-9
    );
}

#[test]
fn a_batch_prints_a_summary_table_and_fails_if_one_pipeline_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let patch = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../pipelines/patch-demo.toml");
    std::fs::write(
        tmp.path().join("bad.toml"),
        "schema = 1\nname = \"bad\"\n[input]\ngenerator = { kind = \"saddle\" }\n[flatten]\nmethod = \"magic\"\n",
    )
    .unwrap();
    let out = flatcut(
        tmp.path(),
        &[
            patch.to_str().unwrap(),
            "bad.toml",
            "--quiet",
            "--out",
            "batch",
        ],
        None,
    );
    let err = failed(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(err.contains("1 of 2 pipelines failed"), "{err}");
    assert!(err.contains("bad.toml:6:10:"), "{err}");
    let table: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("pipeline "))
        .collect();
    assert_eq!(table.len(), 3, "{text}");
    assert!(
        table[1].starts_with("patch-demo ") && table[1].ends_with("ok"),
        "{text}"
    );
    assert!(
        table[2].starts_with("bad.toml ") && table[2].ends_with("FAILED"),
        "{text}"
    );
    // The good one is complete, in DIR/<name>; the bad one left nothing.
    assert!(tmp.path().join("batch/patch-demo/report.json").is_file());
    assert!(!tmp.path().join("batch/bad").exists());
}

#[test]
fn bad_input_is_refused_with_the_line_and_leaves_no_folder() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("p.toml"),
        "schema = 1\nname = \"p\"\n[input]\nmesh = \"missing.obj\"\n",
    )
    .unwrap();
    let err = failed(&flatcut(tmp.path(), &["p.toml", "--quiet"], None));
    assert!(err.contains("p.toml:4:8: input.mesh:"), "{err}");
    assert!(err.contains("missing.obj"), "{err}");
    assert!(!tmp.path().join("out").exists());

    // A folder of another pipeline: refused, and --force is suggested.
    std::fs::write(
        tmp.path().join("q.toml"),
        "schema = 1\nname = \"q\"\noutput = \"out/p\"\n[input]\ngenerator = { kind = \"saddle\", n = 5 }\n",
    )
    .unwrap();
    std::fs::write(
        tmp.path().join("p.toml"),
        "schema = 1\nname = \"p\"\n[input]\ngenerator = { kind = \"saddle\", n = 5 }\n",
    )
    .unwrap();
    ok(&flatcut(tmp.path(), &["p.toml", "--quiet"], None));
    let err = failed(&flatcut(tmp.path(), &["q.toml", "--quiet"], None));
    assert!(
        err.contains("pipeline \"p\"") && err.contains("--force"),
        "{err}"
    );
    ok(&flatcut(
        tmp.path(),
        &["q.toml", "--quiet", "--force"],
        None,
    ));
}
