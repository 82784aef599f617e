//! Every pipeline in pipelines/ runs end to end, reproducibly: the same TOML gives
//! byte-identical output folders on a second run and on 1 or 2 worker threads, and the
//! report's hashes and file list describe exactly what is in the folder.
// Test helpers unwrap: a failure is a test failure with its message.
#![allow(clippy::unwrap_used)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use flatcut_pipeline::{Pipeline, RunOptions};
use sha2::Digest;

fn pipelines_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines")
}

/// Every pipeline file, with whether it needs the shared meshes.
fn all_pipelines() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(pipelines_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// Real-data pipelines name their mesh through ${FLATCUT_DATA}: they run when it is set (and
/// then a missing file fails the test) and are skipped when it is not.
fn needs_data(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .unwrap()
        .contains("${FLATCUT_DATA}")
}

fn sha256(bytes: &[u8]) -> String {
    sha2::Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Every regular file under `dir`, by `/`-separated relative path.
fn folder(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap();
                let name = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect::<Vec<_>>()
                    .join("/");
                out.insert(name, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

fn run(path: &Path, out: &Path, threads: Option<usize>) -> flatcut_pipeline::RunOutcome {
    let p = Pipeline::read(path).unwrap_or_else(|e| panic!("{e}"));
    flatcut_pipeline::run(
        &p,
        &RunOptions {
            out: Some(out.to_path_buf()),
            threads,
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_bundled_pipeline_runs_and_its_report_describes_the_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let files = all_pipelines();
    assert!(
        files.iter().any(|f| f.ends_with("wetsuit-demo.toml")),
        "the bundled demo must be in pipelines/"
    );
    for path in files {
        if needs_data(&path) && std::env::var_os("FLATCUT_DATA").is_none() {
            continue;
        }
        let out = tmp.path().join(path.file_stem().unwrap());
        let outcome = run(&path, &out, None);
        let got = folder(&out);
        let report: serde_json::Value =
            serde_json::from_slice(&got["report.json"]).expect("report.json is JSON");
        // The TOML's hash is the hash of the file's bytes.
        assert_eq!(
            report["toml"]["sha256"].as_str().unwrap(),
            sha256(&std::fs::read(&path).unwrap()),
            "{}",
            path.display()
        );
        assert_eq!(report["schema"], 1);
        assert_eq!(report["pipeline"], outcome.report.pipeline.as_str());
        // `files` lists exactly the folder's files besides the report, timings and marker,
        // each with its true size and hash.
        let listed: BTreeMap<String, (u64, String)> = report["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| {
                (
                    f["name"].as_str().unwrap().to_string(),
                    (
                        f["bytes"].as_u64().unwrap(),
                        f["sha256"].as_str().unwrap().to_string(),
                    ),
                )
            })
            .collect();
        let present: BTreeMap<String, (u64, String)> = got
            .iter()
            .filter(|(k, _)| {
                !matches!(
                    k.as_str(),
                    "report.json" | "timings.json" | ".flatcut-pipeline"
                )
            })
            .map(|(k, v)| (k.clone(), (v.len() as u64, sha256(v))))
            .collect();
        assert_eq!(listed, present, "{}", path.display());
        // One pattern file per piece.
        for piece in report["pieces"].as_array().unwrap() {
            let name = piece["name"].as_str().unwrap();
            assert!(
                present.contains_key(&format!("pieces/{name}.obj")),
                "{}: piece {name} has no pattern file",
                path.display()
            );
        }
        assert!(got.contains_key("timings.json"));
        // report.html is self-contained: every picture inline, nothing fetched (the only
        // URLs are SVG namespace names), one convergence plot and 7 pictures per piece.
        let html = String::from_utf8(got["report.html"].clone()).unwrap();
        let pieces = report["pieces"].as_array().unwrap().len();
        assert_eq!(html.matches("<svg class=\"plot\"").count(), pieces);
        assert_eq!(
            html.matches("src=\"data:image/png;base64,").count(),
            7 * pieces
        );
        // No non-finite number in the text (the base64 pictures left out: they may hold any
        // letters).
        let text: String = html
            .split("base64,")
            .enumerate()
            .map(|(i, part)| {
                if i == 0 {
                    part
                } else {
                    part.split_once('"').map_or("", |(_, rest)| rest)
                }
            })
            .collect();
        // (Checked on the text: base64 pictures can spell "http" by chance, as one of
        // wetsuit-mh's did.)
        assert_eq!(
            text.matches("http").count(),
            text.matches("xmlns=\"http://www.w3.org/2000/svg\"").count(),
            "report.html must not reference the network"
        );
        assert!(
            !text.contains("NaN") && !text.contains("inf"),
            "{}",
            path.display()
        );
        // No temporary file is left behind.
        assert!(got.keys().all(|k| !k.ends_with(".tmp")), "{:?}", got.keys());
    }
}

/// Everything but timings.json must be byte-identical.
fn assert_same_outputs(a: &Path, b: &Path, what: &str) {
    let (mut fa, mut fb) = (folder(a), folder(b));
    fa.remove("timings.json");
    fb.remove("timings.json");
    assert_eq!(
        fa.keys().collect::<Vec<_>>(),
        fb.keys().collect::<Vec<_>>(),
        "{what}: different files"
    );
    for (k, va) in &fa {
        assert!(va == &fb[k], "{what}: {k} differs");
    }
}

#[test]
fn running_twice_and_on_one_or_two_threads_gives_identical_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    for name in ["wetsuit-demo", "patch-demo"] {
        let path = pipelines_dir().join(format!("{name}.toml"));
        let one = tmp.path().join(format!("{name}-1"));
        let two = tmp.path().join(format!("{name}-2"));
        let again = tmp.path().join(format!("{name}-1-again"));
        run(&path, &one, Some(1));
        run(&path, &two, Some(2));
        run(&path, &again, Some(1));
        assert_same_outputs(&one, &again, &format!("{name}: second run"));
        assert_same_outputs(&one, &two, &format!("{name}: 1 vs 2 threads"));
        // Re-running into its own folder is allowed and gives the same bytes again.
        run(&path, &one, Some(2));
        assert_same_outputs(&one, &again, &format!("{name}: rerun in place"));
    }
}

#[test]
fn patch_demo_cap_becomes_developable_and_flattens_to_true_size() {
    let tmp = tempfile::tempdir().unwrap();
    let out = run(
        &pipelines_dir().join("patch-demo.toml"),
        &tmp.path().join("o"),
        None,
    );
    let r = &out.report;
    assert_eq!(r.pieces.len(), 1);
    let cap = &r.pieces[0];
    assert_eq!(cap.name, "cap");
    // A 60° cap on a 21 × 21 grid: 20² quads, two triangles each, one disk.
    assert_eq!(cap.faces, 800);
    assert_eq!((cap.boundary_loops, cap.euler_characteristic), (1, 1));
    // Before: the cap's Gaussian curvature concentrates as angle defects of order h²/R².
    assert!(cap.process.theta_err_before > 1e-3, "{:?}", cap.process);
    // After: developable to the robust tolerance (1e-9 rad).
    assert!(cap.process.converged);
    assert!(cap.process.theta_err_after <= 1e-9, "{:?}", cap.process);
    assert_eq!(
        cap.process.theta_err_history.first().copied(),
        Some(cap.process.theta_err_before)
    );
    assert_eq!(
        cap.process.theta_err_history.last().copied(),
        Some(cap.process.theta_err_after)
    );
    // A developable piece flattens isometrically: edge lengths, area and boundary length
    // are kept (independent measurements of one property).
    let f = &cap.flatten;
    assert!(f.max_edge_strain <= 1e-6, "{f:?}");
    assert!(
        (f.area_2d_mm2 - f.area_3d_mm2).abs() <= 1e-5 * f.area_3d_mm2,
        "{f:?}"
    );
    assert!(
        (f.boundary_2d_mm - f.boundary_3d_mm).abs() <= 1e-5 * f.boundary_3d_mm,
        "{f:?}"
    );
    assert_eq!(f.flipped_faces, 0);
    // The boundary never moves in processing: the processed piece's rim has the length of
    // the generated cap's rim, measured here on the generator's own mesh.
    let cap_mesh = flatcut_mesh::shapes::sphere_cap_grid(21, 60f64.to_radians(), 200.0);
    let topo = flatcut_mesh::Topology::build(&cap_mesh).unwrap();
    let rim: f64 = topo.boundary_loops()[0]
        .iter()
        .zip(topo.boundary_loops()[0].iter().cycle().skip(1))
        .map(|(a, b)| {
            let (p, q) = (cap_mesh.positions[a.idx()], cap_mesh.positions[b.idx()]);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .sum();
    assert!(
        (f.boundary_3d_mm - rim).abs() <= 1e-9 * rim,
        "{} vs {rim}",
        f.boundary_3d_mm
    );
    // …and the rim lies on the circle of radius R sin 30° = 100 mm, so it is a little
    // shorter than the circle.
    let circle = 2.0 * std::f64::consts::PI * 100.0;
    assert!(rim < circle && rim > 0.99 * circle, "{rim}");
}

#[test]
fn wetsuit_demo_cuts_eight_flattenable_disks_whose_seams_match_in_2d() {
    let tmp = tempfile::tempdir().unwrap();
    let out = run(
        &pipelines_dir().join("wetsuit-demo.toml"),
        &tmp.path().join("o"),
        None,
    );
    let r = &out.report;
    assert_eq!(r.pieces.len(), 8);
    for p in &r.pieces {
        // Disks, processed to the robust tolerance, flattened without stretch or folds.
        assert_eq!(
            (p.boundary_loops, p.euler_characteristic),
            (1, 1),
            "{}",
            p.name
        );
        assert!(
            p.process.converged && p.process.theta_err_after <= 1e-9,
            "{p:?}"
        );
        assert!(p.flatten.max_edge_strain <= 1e-4, "{p:?}");
        assert_eq!(p.flatten.flipped_faces, 0, "{}", p.name);
    }
    // Every seam is measured on both mates, which agree in 2D to 0.5 mm and with the 3D
    // length (processing never moves the boundary; flattening keeps edge lengths).
    assert!(r.seam_table.len() >= 8, "{}", r.seam_table.len());
    for s in &r.seam_table {
        assert!(!s.mismatch && s.difference_mm.abs() <= 0.5, "{s:?}");
        assert!(
            (s.a_2d_mm - s.length_3d_mm).abs() <= 1e-3 * s.length_3d_mm,
            "{s:?}"
        );
    }
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
}
