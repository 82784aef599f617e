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
        // The sheet shown is sheet.svg itself, byte for byte.
        if let Some(svg) = got.get("sheet.svg") {
            let embedded = html
                .split_once("src=\"data:image/svg+xml;base64,")
                .and_then(|(_, rest)| rest.split_once('"'))
                .map(|(b64, _)| b64)
                .expect("report.html embeds the sheet");
            assert!(decode_base64(embedded) == *svg, "{}", path.display());
        }
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

/// Standard base64 (RFC 4648, with padding), decoded here independently of the encoder.
fn decode_base64(s: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c:?}"),
    };
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    for chunk in s.as_bytes().chunks(4) {
        let n = chunk.iter().filter(|&&c| c != b'=').count();
        let mut acc = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            let v = if c == b'=' { 0 } else { value(c) };
            acc |= u32::from(v) << (18 - 6 * i);
        }
        out.extend_from_slice(&acc.to_be_bytes()[1..n]);
    }
    out
}

/// The points of the SVG path with id `id` (its `d` holds only M/L/Z and coordinates).
fn svg_path_points(svg: &str, id: &str) -> Vec<[f64; 2]> {
    let at = svg
        .find(&format!("id=\"{id}\""))
        .unwrap_or_else(|| panic!("no {id}"));
    let d = svg[at..]
        .split_once(" d=\"")
        .and_then(|(_, rest)| rest.split_once('"'))
        .unwrap()
        .0;
    let nums: Vec<f64> = d
        .split(|c: char| c == ' ' || c.is_ascii_alphabetic())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect();
    nums.chunks(2).map(|c| [c[0], c[1]]).collect()
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
    // Every bundled pipeline that needs no shared data (those run in the real-data tests).
    for path in all_pipelines().into_iter().filter(|p| !needs_data(p)) {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
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
    // Its RMS is bounded by the max and by the max's own share of the mean square, over the
    // 19² interior vertices (measured 2.24e-3 against a max of 3.53e-3).
    let (max, rms) = (cap.process.theta_err_before, cap.process.theta_rms_before);
    assert!(rms <= max && rms >= max / 19.0, "RMS {rms} vs max {max}");
    // After: developable to the robust tolerance (1e-9 rad).
    assert!(cap.process.converged);
    assert!(cap.process.theta_err_after <= 1e-9, "{:?}", cap.process);
    assert!(cap.process.theta_rms_after <= cap.process.theta_err_after);
    assert_eq!(
        cap.process.theta_err_history.first().copied(),
        Some(cap.process.theta_err_before)
    );
    assert_eq!(
        cap.process.theta_err_history.last().copied(),
        Some(cap.process.theta_err_after)
    );
    // The cap's flattenable neighbour is smooth: no edge bends 30° more than in the input
    // (measured: 0°), though the faces turn (~30° at the rim).
    assert_eq!(cap.process.creased_edges, 0, "{:?}", cap.process);
    assert!(cap.process.max_crease_deg < 30.0, "{:?}", cap.process);
    assert!(cap.process.max_normal_turn_deg > 1.0, "{:?}", cap.process);
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
    // The README's caption: the four upper pieces crease, each in saddle-like surface (the
    // form's angle defect under the crease is negative), where a seam or gusset helps and a
    // dart does not; the lower pieces stay smooth.
    for p in &r.pieces {
        let kind = flatcut_flattenable::CreaseKind::of(p.process.creased_defect_rad);
        if p.name.ends_with("-upper") {
            assert!(p.process.creased_edges > 0, "{p:?}");
            assert_eq!(
                kind,
                Some(flatcut_flattenable::CreaseKind::SaddleLike),
                "{}: {}",
                p.name,
                p.process.creased_defect_rad
            );
            assert!(p.process.sharpest_crease_position_mm.is_some());
        } else {
            assert_eq!(p.process.creased_edges, 0, "{p:?}");
        }
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

#[test]
fn sofa_demo_makes_two_leather_pieces_from_wireframes() {
    let tmp = tempfile::tempdir().unwrap();
    let path = pipelines_dir().join("sofa-demo.toml");
    let out = run(&path, &tmp.path().join("o"), None);
    let r = &out.report;
    // Both wire-frames are inputs, hashed from their bytes.
    assert_eq!(r.inputs.len(), 2);
    for (i, name) in ["seat", "back"].iter().enumerate() {
        let file = pipelines_dir().join(format!("../fixtures/wireframes/{name}.toml"));
        assert_eq!(r.inputs[i].key, "input.wireframes");
        assert_eq!(r.inputs[i].sha256, sha256(&std::fs::read(&file).unwrap()));
    }
    let names: Vec<&str> = r.pieces.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["seat", "back"]);
    for p in &r.pieces {
        assert_eq!(
            (p.boundary_loops, p.euler_characteristic),
            (1, 1),
            "{}",
            p.name
        );
        assert_eq!(p.fabric, "leather");
        assert!(
            p.process.converged && p.process.theta_err_after <= 1e-9,
            "{p:?}"
        );
        assert!(p.flatten.max_edge_strain <= 1e-4, "{p:?}");
        assert_eq!(p.flatten.flipped_faces, 0, "{}", p.name);
        // Leather: no shrink, so the pattern inside its sew line has the flattening's size
        // (the flattening already put the grain along +y).
        assert_eq!(
            (p.pattern.shrink_along_grain, p.pattern.shrink_across_grain),
            (0.0, 0.0)
        );
        for k in 0..2 {
            assert!(
                (p.pattern.size_mm[k] - p.flatten.size_mm[k]).abs() <= 1e-9 * p.flatten.size_mm[k],
                "{p:?}"
            );
        }
    }
    // The seat spans 600 × 550 mm in plan and rises 30 mm to its crown: its flattened
    // boundary is at least the plan's perimeter (2 × (600 + 550) = 2300 mm) and not far
    // more; the back's boundary is 3D-to-2D length-preserving like every boundary here.
    let seat = &r.pieces[0].flatten;
    assert!(
        seat.boundary_3d_mm > 2300.0 && seat.boundary_3d_mm < 2400.0,
        "{seat:?}"
    );
    for p in &r.pieces {
        let f = &p.flatten;
        assert!((f.boundary_2d_mm - f.boundary_3d_mm).abs() <= 1e-3, "{f:?}");
    }
}

/// A 60° cap (R = 200 mm, rim radius 100 mm at z = R cos 30°) with a dart from the rim at
/// +x to 40 mm from the axis and a feature curve along y, size and fabric; `shrink` is an
/// optional `shrink = …` line.
fn dart_cap_toml(feature_weight: f64, shrink: &str) -> String {
    let z = |r: f64| (200.0f64 * 200.0 - r * r).sqrt();
    cap_toml(
        "dart-cap",
        15,
        &format!(
            r#"grain = [0.0, 1.0, 0.0]
{shrink}
darts = [{{ name = "d", from = [100.0, 0.0, {z100}], tip = [40.0, 0.0, {z40}] }}]
features = [[[-10.0, -70.0, {z70}], [-10.0, 70.0, {z70}]]]
fabric = "neoprene"
size = "38"

[process]
feature_weight = {feature_weight}"#,
            z100 = z(100.0),
            z40 = z(40.0),
            z70 = z((70.0f64 * 70.0 + 100.0).sqrt()),
        ),
    )
}

/// A pipeline on the 60° cap (R = 200 mm, an `n` × `n` grid) with one piece "cap" seeded at
/// the pole, `lines` after its seed (more piece keys, then any further tables), written as
/// SVG only.
fn cap_toml(name: &str, n: usize, lines: &str) -> String {
    format!(
        r#"schema = 1
name = "{name}"

[input]
generator = {{ kind = "sphere-cap", n = {n}, cap_angle_deg = 60.0, radius_mm = 200.0 }}

[[piece]]
name = "cap"
seed = [0.0, 0.0, 200.0]
{lines}

[export]
formats = ["svg"]
"#
    )
}

fn run_text(text: &str, dir: &Path, name: &str) -> (flatcut_pipeline::RunOutcome, PathBuf) {
    let toml = dir.join(format!("{name}.toml"));
    std::fs::write(&toml, text).unwrap();
    let out = dir.join(name);
    (run(&toml, &out, None), out)
}

#[test]
fn a_dart_opens_the_piece_its_legs_match_in_2d_and_it_is_in_the_seams() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, dir) = run_text(&dart_cap_toml(10.0, ""), tmp.path(), "a");
    let r = &out.report;
    let cap = &r.pieces[0];
    assert_eq!(cap.darts, ["d"]);
    // Opened along the dart, still one disk, developable and flattened without stretch.
    assert_eq!((cap.boundary_loops, cap.euler_characteristic), (1, 1));
    assert!(
        cap.process.converged && cap.process.theta_err_after <= 1e-9,
        "{cap:?}"
    );
    assert!(cap.flatten.max_edge_strain <= 1e-6, "{cap:?}");
    // The dart is a seam of the cap with itself; processing never moves boundary vertices,
    // and both legs are copies of one 3D path, so an isometric flattening gives both legs
    // the dart's 3D length: from the rim (100 mm from the axis) to 40 mm from it along the
    // sphere, R (asin(100/R) − asin(40/R)) for the great-circle path through the axis plane.
    let row = r.seam_table.iter().find(|s| s.id == "d/0").unwrap();
    assert_eq!(serde_json::to_value(row.kind).unwrap(), "dart");
    assert_eq!((row.a_piece.as_str(), row.b_piece.as_str()), ("cap", "cap"));
    assert!(row.difference_mm.abs() <= 1e-6, "{row:?}");
    // The mesh's path runs on chords of the sphere (grid spacing ≈ 15 mm): shorter than the
    // great circle by O(h²/R²) — measured 1.6e-4 relative.
    let great_circle = 200.0 * ((100.0f64 / 200.0).asin() - (40.0f64 / 200.0).asin());
    assert!(
        row.length_3d_mm < great_circle && row.length_3d_mm > (1.0 - 1e-3) * great_circle,
        "{row:?}"
    );
    assert!(
        (row.a_2d_mm - row.length_3d_mm).abs() <= 1e-5 * row.length_3d_mm,
        "{row:?}"
    );
    // report.json says the same, and seams.json and the pattern carry the dart.
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap();
    let jrow = json["seam_table"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["id"] == "d/0")
        .unwrap();
    assert!(jrow["difference_mm"].as_f64().unwrap().abs() <= 1e-6);
    let seams = std::fs::read_to_string(dir.join("seams.json")).unwrap();
    assert!(
        seams.contains("\"d/0\"") && seams.contains("\"dart\""),
        "{seams}"
    );
    let svg = std::fs::read_to_string(dir.join("pieces/cap.svg")).unwrap();
    // Both legs drawn on the dart layer, and the dart is a seam of the piece in the SVG.
    assert_eq!(svg.matches("id=\"cap-dart-").count(), 2, "both legs drawn");
    assert!(svg.matches("data-seam-id=\"d/0\"").count() >= 2);
    // Size and fabric reach the pattern's label.
    assert!(
        svg.contains(">size 38<") && svg.contains(">neoprene<"),
        "label"
    );
    // …and the report page's piece heading.
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    assert!(
        html.contains("size 38 · neoprene · darts d · feature 0:"),
        "report.html piece line"
    );
}

/// A saddle z = c (x² − y²) (c = 0.001/mm, 300 mm square, 15 × 15 vertices) with a feature
/// curve along y = 50 mm from x = −100 to 100 mm, weighted `feature_weight`, processed with
/// `target` ("zero" or "detail").
fn saddle_feature_toml(feature_weight: f64, target: &str) -> String {
    let z = |x: f64, y: f64| 0.001 * (x * x - y * y);
    format!(
        r#"schema = 1
name = "feature-saddle"

[input]
generator = {{ kind = "saddle", n = 15 }}

[[piece]]
name = "s"
seed = [0.0, 0.0, 0.0]
features = [[[-100.0, 50.0, {a}], [100.0, 50.0, {a}]]]

[process]
feature_weight = {feature_weight}
target = "{target}"

[export]
formats = ["svg"]
"#,
        a = z(100.0, 50.0),
    )
}

#[test]
fn a_feature_curve_moves_less_when_weighted() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |weight: f64, target: &str| {
        run_text(
            &saddle_feature_toml(weight, target),
            tmp.path(),
            &format!("w{weight}-{target}"),
        )
    };
    // Fig. 5 is about the paper's steps, so first with the zero target. Weight 1 is
    // processing without the feature (every vertex weighs 1).
    let (weighted, dir) = run(10.0, "zero");
    let (plain, _) = run(1.0, "zero");
    let (pw, pp) = (&weighted.report.pieces[0], &plain.report.pieces[0]);
    let (fw, fp) = (&pw.features[0], &pp.features[0]);
    // The same chain: the grid row y = 50 mm between x = ±100 mm (grid spacing 300/14 mm,
    // so the landmarks snap to the nearest grid points), one vertex per column.
    assert_eq!(fw.vertices, fp.vertices);
    assert_eq!(fw.vertices.len(), 11, "{fw:?}");
    assert!(fw.length_3d_mm >= 200.0 - 2.0 * 300.0 / 14.0, "{fw:?}");
    // Both developable; the weighted curve moves much less (measured: RMS 3.7 vs 21.0 mm).
    for p in [pw, pp] {
        assert!(
            p.process.converged && p.process.theta_err_after <= 1e-9,
            "{p:?}"
        );
    }
    assert!(fp.rms_displacement_mm > 10.0, "{fp:?}");
    assert!(
        fw.rms_displacement_mm < 0.5 * fp.rms_displacement_mm,
        "{fw:?} vs {fp:?}"
    );
    assert!(
        fw.max_displacement_mm < fp.max_displacement_mm,
        "{fw:?} vs {fp:?}"
    );
    // The default (detail) target pulls the whole saddle back towards the input, the
    // unweighted curve too (measured RMS 4.8 mm against the zero target's 21.0), and the
    // weighted curve still moves less (2.9 mm; max 6.1 against 11.2 mm).
    let (weighted_detail, _) = run(10.0, "detail");
    let (plain_detail, _) = run(1.0, "detail");
    let (dw, dp) = (
        &weighted_detail.report.pieces[0],
        &plain_detail.report.pieces[0],
    );
    for p in [dw, dp] {
        assert!(
            p.process.converged && p.process.theta_err_after <= 1e-9,
            "{p:?}"
        );
    }
    let (gw, gp) = (&dw.features[0], &dp.features[0]);
    assert!(
        gp.rms_displacement_mm < fp.rms_displacement_mm,
        "{gp:?} vs {fp:?}"
    );
    assert!(
        gw.rms_displacement_mm < gp.rms_displacement_mm,
        "{gw:?} vs {gp:?}"
    );
    assert!(
        gw.max_displacement_mm < gp.max_displacement_mm,
        "{gw:?} vs {gp:?}"
    );
    // It is drawn as an internal line of the pattern.
    let svg = std::fs::read_to_string(dir.join("pieces/s.svg")).unwrap();
    assert!(svg.contains("id=\"s-internal-0\""));
}

#[test]
fn shrink_scales_the_pattern_along_and_across_the_grain() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, _) = run_text(
        &dart_cap_toml(
            10.0,
            "shrink = { along_grain = -0.05, across_grain = 0.02 }",
        ),
        tmp.path(),
        "s",
    );
    let cap = &out.report.pieces[0];
    assert_eq!(
        (
            cap.pattern.shrink_along_grain,
            cap.pattern.shrink_across_grain
        ),
        (-0.05, 0.02)
    );
    // The pattern is the flattening (grain already along +y) scaled by 1 + across in x and
    // 1 + along in y; the extremes of a disk's flattening lie on its boundary, the sew line.
    let (w, h) = (cap.flatten.size_mm[0], cap.flatten.size_mm[1]);
    assert!(
        (cap.pattern.size_mm[0] - 1.02 * w).abs() <= 1e-9 * w,
        "{cap:?}"
    );
    assert!(
        (cap.pattern.size_mm[1] - 0.95 * h).abs() <= 1e-9 * h,
        "{cap:?}"
    );
}

#[test]
fn a_dart_starting_on_a_seam_splits_the_seam_and_every_mate_still_matches() {
    // The 60° cap cut in two along x = 0; a dart in the east half starts on that seam.
    let z = |r: f64| (200.0f64 * 200.0 - r * r).sqrt();
    let text = format!(
        r#"schema = 1
name = "seam-dart"

[input]
generator = {{ kind = "sphere-cap", n = 15, cap_angle_deg = 60.0, radius_mm = 200.0 }}

[[cut]]
name = "c"
points = [[0.0, -100.0, {rim}], [0.0, 0.0, 200.0], [0.0, 100.0, {rim}]]

[[piece]]
name = "east"
seed = [50.0, 0.0, {z50}]
darts = [{{ name = "d", from = [0.0, 40.0, {z40}], tip = [45.0, 40.0, {z60}] }}]

[[piece]]
name = "west"
seed = [-50.0, 0.0, {z50}]

[export]
formats = ["svg"]
"#,
        rim = z(100.0),
        z50 = z(50.0),
        z40 = z(40.0),
        z60 = z((45.0f64 * 45.0 + 40.0 * 40.0).sqrt()),
    );
    let tmp = tempfile::tempdir().unwrap();
    let (out, _) = run_text(&text, tmp.path(), "a");
    let r = &out.report;
    assert_eq!(r.pieces[0].darts, ["d"]);
    for p in &r.pieces {
        assert!(
            p.process.converged && p.process.theta_err_after <= 1e-9,
            "{p:?}"
        );
        assert!(p.flatten.max_edge_strain <= 1e-6, "{p:?}");
    }
    let ids: Vec<&str> = r.seam_table.iter().map(|s| s.id.as_str()).collect();
    // The dart's mouth opens the seam in two at the dart's start.
    assert_eq!(ids, ["c/0.1", "c/0.2", "d/0"], "{:?}", r.seam_table);
    let (c1, c2) = (&r.seam_table[0], &r.seam_table[1]);
    // The two parts add up to the cut line's length: from rim to rim through the pole,
    // 2 R · 30° on the sphere, a little less on the mesh's chords.
    let arc = 2.0 * 200.0 * 30f64.to_radians();
    let total = c1.length_3d_mm + c2.length_3d_mm;
    assert!(
        total < arc && total > (1.0 - 1e-3) * arc,
        "{total} vs {arc}"
    );
    // Mates agree in 2D with each other and with 3D (processing keeps the boundary).
    for s in &r.seam_table {
        assert!(s.difference_mm.abs() <= 1e-6, "{s:?}");
        assert!(
            (s.a_2d_mm - s.length_3d_mm).abs() <= 1e-5 * s.length_3d_mm,
            "{s:?}"
        );
    }
}

/// Two wire-frames side by side that share their middle curve x = 300 mm (the left one
/// draws it from y = 0 to 400, the right one back), a cylinder-like sheet
/// z = 20 sin(π x / 600) mm over 600 × 400 mm.
fn shared_wire_files(dir: &Path) {
    let h = |x: f64| 20.0 * (std::f64::consts::PI * x / 600.0).sin();
    let pts = |p: Vec<[f64; 3]>| {
        p.iter()
            .map(|q| format!("[{}, {}, {}]", q[0], q[1], q[2]))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let along_x = |x0: f64, x1: f64, y: f64| {
        (0..7)
            .map(|i| {
                let x = x0 + (x1 - x0) * i as f64 / 6.0;
                [x, y, h(x)]
            })
            .collect::<Vec<_>>()
    };
    let along_y = |x: f64, y0: f64, y1: f64| {
        (0..7)
            .map(|i| [x, y0 + (y1 - y0) * i as f64 / 6.0, h(x)])
            .collect::<Vec<_>>()
    };
    let curve = |name: &str, p: Vec<[f64; 3]>| {
        format!("[[curve]]\nname = \"{name}\"\npoints = [{}]\n", pts(p))
    };
    let head = "units = \"mm\"\ntarget_edge_mm = 40.0\n";
    let mut mid_back = along_y(300.0, 0.0, 400.0);
    mid_back.reverse();
    let a = [
        curve("front", along_x(0.0, 300.0, 0.0)),
        curve("mid", along_y(300.0, 0.0, 400.0)),
        curve("back", along_x(300.0, 0.0, 400.0)),
        curve("left", along_y(0.0, 400.0, 0.0)),
    ]
    .concat();
    let b = [
        curve("front", along_x(300.0, 600.0, 0.0)),
        curve("right", along_y(600.0, 0.0, 400.0)),
        curve("back", along_x(600.0, 300.0, 400.0)),
        curve("mid", mid_back),
    ]
    .concat();
    std::fs::write(dir.join("a.toml"), format!("{head}{a}")).unwrap();
    std::fs::write(dir.join("b.toml"), format!("{head}{b}")).unwrap();
}

#[test]
fn wireframes_sharing_a_curve_are_welded_and_a_cut_along_it_makes_the_seam() {
    let tmp = tempfile::tempdir().unwrap();
    shared_wire_files(tmp.path());
    let seeds = "[[piece]]\nname = \"a\"\nseed = [150.0, 200.0, 14.142135623730951]\n\n[[piece]]\nname = \"b\"\nseed = [450.0, 200.0, 14.142135623730951]\n";
    let head = "schema = 1\nname = \"share\"\n\n[input]\nwireframes = [\"a.toml\", \"b.toml\"]\n\n[export]\nformats = [\"svg\"]\n\n";
    // Both patches resample the shared curve alike, so cleaning welds them into one surface:
    // the two seeds then name one piece.
    let toml = tmp.path().join("one.toml");
    std::fs::write(&toml, format!("{head}{seeds}")).unwrap();
    let e = flatcut_pipeline::run(
        &Pipeline::read(&toml).unwrap(),
        &RunOptions {
            out: Some(tmp.path().join("one")),
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("lies in the same piece"), "{e}");
    // A cut along the shared curve (a straight line, so the geodesic between its ends)
    // separates them and records the seam.
    let cut = "[[cut]]\nname = \"mid\"\npoints = [[300.0, 0.0, 20.0], [300.0, 400.0, 20.0]]\n\n";
    let (out, _) = run_text(&format!("{head}{cut}{seeds}"), tmp.path(), "two");
    let r = &out.report;
    assert_eq!(r.pieces.len(), 2);
    assert_eq!(r.seam_table.len(), 1, "{:?}", r.seam_table);
    let s = &r.seam_table[0];
    assert_eq!(
        (s.id.as_str(), s.a_piece.as_str(), s.b_piece.as_str()),
        ("mid/0", "a", "b")
    );
    // 400 mm long in 3D; both mates the same in 2D (processing keeps the boundary).
    assert!((s.length_3d_mm - 400.0).abs() <= 1e-9, "{s:?}");
    assert!(
        (s.a_2d_mm - 400.0).abs() <= 1e-6 && s.difference_mm.abs() <= 1e-6,
        "{s:?}"
    );
}

#[test]
fn darts_and_features_give_identical_bytes_on_one_or_two_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let toml = tmp.path().join("d.toml");
    std::fs::write(
        &toml,
        dart_cap_toml(10.0, "shrink = { along_grain = -0.05 }"),
    )
    .unwrap();
    let (one, two) = (tmp.path().join("1"), tmp.path().join("2"));
    run(&toml, &one, Some(1));
    run(&toml, &two, Some(2));
    assert_same_outputs(&one, &two, "dart cap: 1 vs 2 threads");
}

/// One cap piece with `lines` added to its [[piece]] table, written as SVG only.
fn cap_piece_toml(lines: &str) -> String {
    cap_toml("cap-piece", 11, lines)
}

#[test]
fn quantity_two_mirrored_places_a_drawn_and_a_mirrored_copy_on_the_sheet() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, dir) = run_text(
        &cap_piece_toml("quantity = 2\nmirror = true"),
        tmp.path(),
        "q",
    );
    let p = &out.report.pieces[0];
    assert_eq!((p.quantity, p.mirror), (2, true));
    let sheet = std::fs::read_to_string(dir.join("sheet.svg")).unwrap();
    // Two copies, labelled for the cutter, and no third.
    assert_eq!(sheet.matches("data-piece=\"cap\"").count(), 2, "{sheet}");
    assert!(sheet.contains("cut 2, mirrored"));
    let a = svg_path_points(&sheet, "cap-0-cut-line");
    let b = svg_path_points(&sheet, "cap-1-cut-line");
    assert_eq!(a.len(), b.len());
    // Copy 1 is copy 0 mirrored left–right and moved: x_a + x_b and y_b − y_a are the same
    // for every point (to the file's 0.001 mm), while x_b − x_a is not (not a translation).
    let (sx, dy) = (a[0][0] + b[0][0], b[0][1] - a[0][1]);
    let mut spread: f64 = 0.0;
    for (p, q) in a.iter().zip(&b) {
        assert!((p[0] + q[0] - sx).abs() <= 2e-3, "{p:?} {q:?}");
        assert!((q[1] - p[1] - dy).abs() <= 2e-3, "{p:?} {q:?}");
        spread = spread.max(((q[0] - p[0]) - (b[0][0] - a[0][0])).abs());
    }
    assert!(
        spread > 50.0,
        "copy 1 is a translation, not a mirror: {spread}"
    );
}

#[test]
fn a_piece_grain_turns_the_pattern_so_that_it_runs_up_the_sheet() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, along_y) = run_text(&cap_piece_toml("grain = [0.0, 1.0, 0.0]"), tmp.path(), "y");
    let (_, along_x) = run_text(&cap_piece_toml("grain = [1.0, 0.0, 0.0]"), tmp.path(), "x");
    let read = |dir: &Path| {
        flatcut_io::read_mesh(&dir.join("pieces/cap.obj"), flatcut_io::Units::Mm)
            .unwrap()
            .mesh
            .positions
    };
    let (uy, ux) = (read(&along_y), read(&along_x));
    assert_eq!(uy.len(), ux.len());
    // Same flattening, so the 3D x axis that runs along +x with grain y must run along +y with
    // grain x: the second pattern is the first turned a quarter anticlockwise, (u, v) → (−v, u),
    // up to a translation.
    let (oy, ox) = (uy[0], ux[0]);
    for (p, q) in uy.iter().zip(&ux) {
        let (d, e) = ([p[0] - oy[0], p[1] - oy[1]], [q[0] - ox[0], q[1] - ox[1]]);
        assert!(
            (e[0] + d[1]).abs() <= 1e-6 && (e[1] - d[0]).abs() <= 1e-6,
            "{d:?} → {e:?}"
        );
    }
}

/// The sheet with two holes on a sphere of radius 400 mm (tests/tests/holes.rs) as an OBJ in
/// `dir`, and a pipeline on it with `process` as its `[process]` table.
fn holed_sheet_toml(dir: &Path, process: &str) -> String {
    let mesh = flatcut_mesh::shapes::patch_with_holes_on_sphere(200.0, 25, 400.0);
    let obj = dir.join("holed-sheet.obj");
    flatcut_io::write_mesh(&obj, &mesh, &Default::default()).unwrap();
    format!(
        r#"schema = 1
name = "holed-sheet"

[input]
mesh = "{}"

[[piece]]
name = "sheet"
seed = [0.0, 90.0, {}]

[process]
{process}

[export]
formats = ["svg"]
"#,
        obj.display(),
        (400.0f64 * 400.0 - 90.0 * 90.0).sqrt()
    )
}

/// The remedy the open-hole messages name for a hole whose rim must keep its length (a seam):
/// a `[[cut]]` line from each hole's rim to the outline. Trim opens it into a seam of the piece
/// with itself, the piece becomes a disk, and with every boundary fixed (rims included) it
/// flattens without stretch, both sides of each slit as long in the pattern as in 3D.
#[test]
fn a_cut_from_each_hole_to_the_outline_makes_a_holed_piece_flatten_with_its_rims_held() {
    let tmp = tempfile::tempdir().unwrap();
    // The holes of `patch_with_holes(200, 25)` are centred at x = ∓50 mm with radius 25 mm:
    // the grid vertices (∓75, 0) are on their rims (the cell at x = ∓70.8 is removed, the one
    // at ∓79.2 kept), and (∓100, 0) on the outline.
    let z = |x: f64| (400.0f64 * 400.0 - x * x).sqrt();
    let cuts = format!(
        r#"
[[cut]]
name = "slit-left"
points = [[-75.0, 0.0, {}], [-100.0, 0.0, {}]]

[[cut]]
name = "slit-right"
points = [[75.0, 0.0, {}], [100.0, 0.0, {}]]
"#,
        z(75.0),
        z(100.0),
        z(75.0),
        z(100.0)
    );
    let text = holed_sheet_toml(tmp.path(), "").replace("[process]", &format!("{cuts}\n[process]"));
    let (out, _) = run_text(&text, tmp.path(), "slits");
    let r = &out.report;
    let piece = &r.pieces[0];
    assert_eq!(
        (piece.boundary_loops, piece.euler_characteristic),
        (1, 1),
        "{piece:?}"
    );
    assert!(
        piece.process.converged && piece.process.theta_err_after <= 1e-9,
        "{piece:?}"
    );
    assert!(
        !r.warnings.iter().any(|w| w.contains("do not close")),
        "{:?}",
        r.warnings
    );
    // Without the slits the same sheet stretches by 1.2e-2 (the test below).
    assert!(
        piece.flatten.max_edge_strain < 1e-6,
        "{}",
        piece.flatten.max_edge_strain
    );
    for slit in ["slit-left", "slit-right"] {
        let row = r.seam_table.iter().find(|s| s.line == slit).unwrap();
        assert_eq!(
            (row.a_piece.as_str(), row.b_piece.as_str()),
            ("sheet", "sheet")
        );
        // The great circle's arc from x = 75 to 100 mm, on chords of it (three grid edges):
        // shorter by O(h²/R²).
        let arc = 400.0 * ((100.0f64 / 400.0).asin() - (75.0f64 / 400.0).asin());
        assert!(
            row.length_3d_mm <= arc && row.length_3d_mm > (1.0 - 1e-4) * arc,
            "{row:?} against {arc}"
        );
        assert!(row.difference_mm.abs() <= 1e-6, "{row:?}");
        assert!(
            (row.a_2d_mm - row.length_3d_mm).abs() <= 1e-6 * row.length_3d_mm,
            "{row:?}"
        );
    }
}

#[test]
fn a_piece_whose_holes_stay_open_is_warned_about_and_free_rims_close_them() {
    let tmp = tempfile::tempdir().unwrap();
    let (fixed, _) = run_text(&holed_sheet_toml(tmp.path(), ""), tmp.path(), "fixed");
    let piece = &fixed.report.pieces[0];
    assert!(piece.process.converged);
    assert!(
        fixed
            .report
            .warnings
            .iter()
            .any(|w| w.contains("2 of its 2 holes do not close") && w.contains("hole_rims")),
        "{:?}",
        fixed.report.warnings
    );
    // The pattern stretches around the open holes (1.2e-2 measured by `flatcut flatten`).
    assert!(
        piece.flatten.max_edge_strain > 5e-3,
        "{}",
        piece.flatten.max_edge_strain
    );

    let (free, _) = run_text(
        &holed_sheet_toml(tmp.path(), r#"hole_rims = "free""#),
        tmp.path(),
        "free",
    );
    let piece = &free.report.pieces[0];
    assert!(piece.process.converged);
    assert!(
        !free
            .report
            .warnings
            .iter()
            .any(|w| w.contains("do not close")),
        "{:?}",
        free.report.warnings
    );
    assert!(
        piece.flatten.max_edge_strain < 1e-6,
        "{}",
        piece.flatten.max_edge_strain
    );
}
