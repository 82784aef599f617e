//! The real-data pipelines (pipelines/wetsuit-mh.toml, pipelines/wetsuit-scan.toml) meet the
//! done-when of issue 8, read back from the report.json they write: every piece a disk,
//! processed to θ_err ≤ 1e-9, flattened with max edge strain ≤ 1e-4 and no folds, and every
//! seam's two mates equal in 2D length to 0.5 mm; and wetsuit-mh writes the same bytes on one
//! and on two threads.
//!
//! The meshes are reached only through FLATCUT_DATA: unset, the tests pass at once; set, a
//! missing mesh fails them.
// Test helpers unwrap: a failure is a test failure with its message.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use flatcut_pipeline::{Pipeline, RunOptions};
use serde_json::Value;

/// The done-when of issue 8 for a real body.
const THETA_ERR_MAX_RAD: f64 = 1e-9;
const EDGE_STRAIN_MAX: f64 = 1e-4;
const SEAM_MISMATCH_MAX_MM: f64 = 0.5;

/// The shared meshes folder, or None when FLATCUT_DATA is unset (then the test passes early).
/// A set FLATCUT_DATA without `mesh` in it fails the test.
fn data_mesh(mesh: &str) -> Option<PathBuf> {
    let dir = PathBuf::from(std::env::var_os("FLATCUT_DATA")?);
    let path = dir.join(mesh);
    assert!(
        path.is_file(),
        "FLATCUT_DATA is set but {} is missing",
        path.display()
    );
    Some(path)
}

fn pipeline(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../pipelines")
        .join(format!("{name}.toml"))
}

/// Runs `name` into `out` on `threads` worker threads (None: rayon's default).
fn run_into(name: &str, out: &Path, threads: Option<usize>) {
    let p = Pipeline::read(&pipeline(name)).unwrap_or_else(|e| panic!("{e}"));
    run_pipeline_into(&p, out, threads);
}

/// Runs the pipeline `p` into `out` on `threads` worker threads (None: rayon's default).
fn run_pipeline_into(p: &Pipeline, out: &Path, threads: Option<usize>) {
    flatcut_pipeline::run(
        p,
        &RunOptions {
            out: Some(out.to_path_buf()),
            threads,
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{}: {e}", p.source.display()));
}

/// Runs `p` into a temporary folder and returns its report.json, parsed.
fn pipeline_report(p: &Pipeline) -> Value {
    let tmp = tempfile::tempdir().unwrap();
    // Named as before (the pipeline's file name), in case a report records it.
    let out = tmp.path().join(p.source.file_stem().unwrap());
    run_pipeline_into(p, &out, None);
    serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap()
}

/// Runs `name` into a temporary folder and returns its report.json, parsed.
fn run_report(name: &str) -> Value {
    pipeline_report(&Pipeline::read(&pipeline(name)).unwrap_or_else(|e| panic!("{e}")))
}

/// Every file under `dir` but timings.json, by relative path, with its bytes.
fn folder(dir: &Path) -> std::collections::BTreeMap<PathBuf, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if !p.ends_with("timings.json") {
                let bytes = std::fs::read(&p).unwrap();
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), bytes);
            }
        }
    }
    out
}

fn f(v: &Value) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("{v} is not a finite number"))
}

/// Asserts the done-when on every piece and seam of `report`; `pieces` are the expected
/// piece names in `[[piece]]` order.
fn assert_done_when(report: &Value, pieces: &[&str]) {
    let got: Vec<&str> = report["pieces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(got, pieces);
    for p in report["pieces"].as_array().unwrap() {
        let name = p["name"].as_str().unwrap();
        // Each piece a disk: one boundary loop, Euler characteristic 1.
        assert_eq!(p["boundary_loops"], 1, "{name}");
        assert_eq!(p["euler_characteristic"], 1, "{name}");
        let pr = &p["process"];
        assert_eq!(pr["converged"], true, "{name}: {pr}");
        assert!(
            f(&pr["theta_err_after"]) <= THETA_ERR_MAX_RAD,
            "{name}: {pr}"
        );
        // The history starts at the input's θ_err and ends at the result's.
        let h = pr["theta_err_history"].as_array().unwrap();
        assert_eq!(f(&h[0]), f(&pr["theta_err_before"]), "{name}");
        assert_eq!(f(h.last().unwrap()), f(&pr["theta_err_after"]), "{name}");
        let fl = &p["flatten"];
        assert!(f(&fl["max_edge_strain"]) <= EDGE_STRAIN_MAX, "{name}: {fl}");
        assert_eq!(fl["flipped_faces"], 0, "{name}");
        // A developable piece flattens isometrically: area and boundary length are kept
        // (measured independently of the edge strains).
        let (a3, a2) = (f(&fl["area_3d_mm2"]), f(&fl["area_2d_mm2"]));
        assert!(
            (a2 - a3).abs() <= EDGE_STRAIN_MAX * 2.0 * a3,
            "{name}: {a3} {a2}"
        );
        let (b3, b2) = (f(&fl["boundary_3d_mm"]), f(&fl["boundary_2d_mm"]));
        assert!((b2 - b3).abs() <= EDGE_STRAIN_MAX * b3, "{name}: {b3} {b2}");
    }
    // Every seam between two kept pieces is measured on both mates.
    let seams = report["seam_table"].as_array().unwrap();
    assert!(!seams.is_empty());
    for s in seams {
        let d = f(&s["difference_mm"]);
        assert!(
            d.abs() <= SEAM_MISMATCH_MAX_MM && s["mismatch"] == false,
            "{s}"
        );
        // The difference is the difference of the two mates' 2D lengths.
        assert!(
            (f(&s["a_2d_mm"]) - f(&s["b_2d_mm"]) - d).abs() <= 1e-6,
            "{s}"
        );
        // Both agree with the 3D length (flattening keeps edge lengths to EDGE_STRAIN_MAX).
        let l3 = f(&s["length_3d_mm"]);
        for side in ["a_2d_mm", "b_2d_mm"] {
            assert!(
                (f(&s[side]) - l3).abs() <= EDGE_STRAIN_MAX * l3 + 1e-6,
                "{side}: {s}"
            );
        }
    }
    // The only warnings are the components no seed names (head, hands, feet).
    let dropped = report["dropped_components"].as_array().unwrap().len();
    let warnings = report["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), dropped, "{}", report["warnings"]);
    for w in warnings {
        assert!(w.as_str().unwrap().contains("was left out"), "{w}");
    }
}

/// The pieces of both wetsuit pipelines, in `[[piece]]` order.
const WETSUIT_PIECES: [&str; 16] = [
    "front-left-centre",
    "front-left-side",
    "back-left-centre",
    "back-left-side",
    "front-left-lower",
    "back-left-lower",
    "sleeve-left-front",
    "sleeve-left-back",
    "front-right-centre",
    "front-right-side",
    "back-right-centre",
    "back-right-side",
    "front-right-lower",
    "back-right-lower",
    "sleeve-right-front",
    "sleeve-right-back",
];

#[test]
fn mh_body_wetsuit_pipeline_meets_the_done_when() {
    let Some(_) = data_mesh("mh_body.obj") else {
        return;
    };
    let report = run_report("wetsuit-mh");
    assert_done_when(&report, &WETSUIT_PIECES);
    // The input is the shared mesh, recorded by its hash.
    assert_eq!(report["inputs"][0]["path"], "${FLATCUT_DATA}/mh_body.obj");
    assert_eq!(report["units"], "dm");
    // Head, two hands and two feet are cut off and left out.
    assert_eq!(report["dropped_components"].as_array().unwrap().len(), 5);
}

#[test]
fn mh_body_scanlike_wetsuit_pipeline_meets_the_done_when() {
    let (Some(_), Some(_)) = (data_mesh("mh_body_scanlike.obj"), data_mesh("mh_body.obj")) else {
        return;
    };
    let report = run_report("wetsuit-scan");
    assert_done_when(&report, &WETSUIT_PIECES);
    assert_eq!(
        report["inputs"][0]["path"],
        "${FLATCUT_DATA}/mh_body_scanlike.obj"
    );
    assert_eq!(report["units"], "mm");
    // Cleaning keeps the body and drops the scan's three debris islands.
    assert_eq!(report["input_mesh"]["faces"], 147_720);
    assert_eq!(report["clean"]["dropped_components"], 3);
    assert_eq!(report["dropped_components"].as_array().unwrap().len(), 5);
    // The same plan on the template body and on the scan cuts pieces of the same outline:
    // the scan is the template ×100 (dm → mm) plus noise, remeshed, and processing never
    // moves a piece's boundary. Their 3D boundary lengths agree to 3 % (measured: the
    // scan's are 0.4–1.5 % longer, the noise's roughness).
    let template = run_report("wetsuit-mh");
    for (s, t) in report["pieces"]
        .as_array()
        .unwrap()
        .iter()
        .zip(template["pieces"].as_array().unwrap())
    {
        let (b_scan, b_template) = (
            f(&s["flatten"]["boundary_3d_mm"]),
            f(&t["flatten"]["boundary_3d_mm"]),
        );
        assert!(
            (b_scan - b_template).abs() <= 0.03 * b_template,
            "{}: {b_scan} vs {b_template} mm",
            s["name"]
        );
    }
}

/// The scan's wetsuit at a finer working resolution, 10 mm instead of 12 (pieces of 600–5 800
/// faces, rougher: a median |2π − θ| of up to 0.12 rad) still meets the whole done-when. Its
/// back-right leg is where that is hard: depending on round-off, its rescue hierarchy's fine
/// level converges in 45 iterations or is cut by its 60-iteration budget near θ = 2π, after
/// which the direct solve and the deeper hierarchy stall on the rough piece; the rescue
/// hierarchy under the graph-Laplacian-shaped damping then converges it (before the
/// twenty-third session the cut fine level went on from its best state and converged;
/// docs/algorithms/flattenable.md, "A fine level continued", "A damping shaped like the graph
/// Laplacian").
#[test]
fn mh_body_scanlike_wetsuit_at_10_mm_meets_the_done_when() {
    let (Some(_), Some(_)) = (data_mesh("mh_body_scanlike.obj"), data_mesh("mh_body.obj")) else {
        return;
    };
    let path = pipeline("wetsuit-scan");
    let text = std::fs::read_to_string(&path).unwrap();
    let finer = text.replace("target_edge_mm = 12.0", "target_edge_mm = 10.0");
    assert_ne!(
        finer, text,
        "the pipeline's remesh line changed: update this test"
    );
    let p =
        Pipeline::parse(&finer, &path, path.parent().unwrap()).unwrap_or_else(|e| panic!("{e}"));
    assert_done_when(&pipeline_report(&p), &WETSUIT_PIECES);
}

#[test]
fn mh_body_wetsuit_pipeline_gives_the_same_bytes_on_one_and_two_threads() {
    let Some(_) = data_mesh("mh_body.obj") else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    run_into("wetsuit-mh", &one, Some(1));
    run_into("wetsuit-mh", &two, Some(2));
    let (a, b) = (folder(&one), folder(&two));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    // A whole folder: every piece's pattern files are there (so this compares real bytes).
    for name in WETSUIT_PIECES {
        for ext in ["obj", "svg", "png", "exr", "dxf"] {
            let f = PathBuf::from(format!("pieces/{name}.{ext}"));
            assert!(a.contains_key(&f), "{} missing", f.display());
        }
    }
    for (k, v) in &a {
        assert!(
            v == &b[k],
            "{} differs between 1 and 2 threads",
            k.display()
        );
    }
}

/// The scan with every coordinate scaled by 1 + 1e-12 u, u ∈ [−1, 1) from a hash of
/// `seed` and the coordinate's index: a perturbation at the scale of round-off.
fn scan_one_ulp_away(scan: &flatcut_mesh::TriMesh, seed: u64) -> flatcut_mesh::TriMesh {
    let mut out = scan.clone();
    for (i, c) in out.positions.iter_mut().flatten().enumerate() {
        // SplitMix64 of (seed, i).
        let mut z = seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(i as u64)
            .wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let u = (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0;
        *c *= 1.0 + 1e-12 * u;
    }
    out
}

/// The 10 mm scan wetsuit meets the whole done-when on scans perturbed at the scale of
/// round-off too, where its two right legs used to depend on it (see
/// `mh_body_scanlike_wetsuit_at_10_mm_meets_the_done_when`). The back-right leg's
/// identity-damped attempts stall at 4e-4–1.1e-3 there, and the graph-Laplacian-damped rescue
/// hierarchy, which converges it, runs for pieces stalled within 1e-2
/// (`SHAPED_RESCUE_AT_RAD`; at 1e-4 it was skipped and the leg ended unconverged on each of
/// these four seeds, chosen so). The front-right leg stalls in every one of those attempts on
/// seeds 2 and 5 (7.0e-4, 2.3e-3; and on 3, 4, 8 of seeds 1–8), and the direct solve under
/// that damping, the last attempt on a rough piece, converges it (docs/algorithms/
/// flattenable.md, "Rough scan pieces one ulp away", "Rough scan pieces: the shaped direct
/// solve").
#[test]
fn mh_body_scanlike_wetsuit_at_10_mm_meets_the_done_when_one_ulp_from_its_scan() {
    let (Some(scan_path), Some(_)) = (data_mesh("mh_body_scanlike.obj"), data_mesh("mh_body.obj"))
    else {
        return;
    };
    let scan = flatcut_io::read_mesh(&scan_path, flatcut_io::Units::Mm)
        .unwrap()
        .mesh;
    let path = pipeline("wetsuit-scan");
    let text = std::fs::read_to_string(&path).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    for seed in SCAN_SEEDS {
        let perturbed = tmp.path().join(format!("scan_{seed}.obj"));
        flatcut_io::write_mesh(
            &perturbed,
            &scan_one_ulp_away(&scan, seed),
            &Default::default(),
        )
        .unwrap();
        let finer = text
            .replace("target_edge_mm = 12.0", "target_edge_mm = 10.0")
            .replace(
                "${FLATCUT_DATA}/mh_body_scanlike.obj",
                perturbed.to_str().unwrap(),
            );
        assert!(
            finer.contains("target_edge_mm = 10.0") && finer.contains("scan_"),
            "the pipeline's remesh or mesh line changed: update this test"
        );
        let p = Pipeline::parse(&finer, &path, path.parent().unwrap())
            .unwrap_or_else(|e| panic!("{e}"));
        let report = pipeline_report(&p);
        let unconverged: Vec<(&str, f64)> = report["pieces"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["process"]["converged"] != true)
            .map(|p| {
                (
                    p["name"].as_str().unwrap(),
                    f(&p["process"]["theta_err_after"]),
                )
            })
            .collect();
        assert!(
            unconverged.is_empty(),
            "seed {seed}: unconverged (piece, θ_err): {unconverged:?}"
        );
        assert_done_when(&report, &WETSUIT_PIECES);
    }
}

/// Seeds of [`scan_one_ulp_away`] for the test above.
const SCAN_SEEDS: [u64; 4] = [1, 2, 5, 6];
