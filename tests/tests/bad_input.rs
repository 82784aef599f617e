//! Bad pipeline input gives a clear error naming the key and its line, and never leaves an
//! output folder that looks complete.
// Test helpers unwrap: a failure is a test failure with its message.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use flatcut_pipeline::{Pipeline, PipelineError, RunOptions};

const GOOD: &str = r#"schema = 1
name = "t"

[input]
generator = { kind = "sphere-cap", n = 7 }
"#;

fn parse(text: &str) -> Result<Pipeline, PipelineError> {
    Pipeline::parse(text, Path::new("t.toml"), Path::new("."))
}

fn run_in(text: &str, dir: &Path, out: &Path, force: bool) -> Result<(), PipelineError> {
    let toml = dir.join("t.toml");
    std::fs::write(&toml, text).unwrap();
    let p = Pipeline::read(&toml)?;
    flatcut_pipeline::run(
        &p,
        &RunOptions {
            out: Some(out.to_path_buf()),
            force,
            quiet: true,
            ..Default::default()
        },
    )
    .map(|_| ())
}

#[test]
fn an_unknown_key_names_the_key_its_line_and_what_is_allowed() {
    let text = GOOD.replace("name = \"t\"", "name = \"t\"\ncolour = \"red\"");
    let e = parse(&text).unwrap_err().to_string();
    assert!(e.starts_with("t.toml:3:1:"), "{e}");
    assert!(e.contains("colour") && e.contains("input"), "{e}");

    // Inside a stage table: the key of that crate's options struct.
    let text = format!("{GOOD}\n[process]\nmode = \"robust\"\ntolerance = 1e-9\n");
    let e = parse(&text).unwrap_err().to_string();
    assert!(e.starts_with("t.toml:9:1:"), "{e}");
    assert!(
        e.contains("tolerance") && e.contains("tolerance_rad"),
        "{e}"
    );

    // A wrong value names what is allowed.
    let text = format!("{GOOD}\n[flatten]\nmethod = \"arap\"\n");
    let e = parse(&text).unwrap_err().to_string();
    assert!(e.starts_with("t.toml:8:10:"), "{e}");
    assert!(e.contains("lscm+arap"), "{e}");

    // A wrong type.
    let e = parse(&GOOD.replace("schema = 1", "schema = \"1\""))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("t.toml:1:10:"), "{e}");

    // An unknown generator parameter: the line of the generator.
    let e = parse(&GOOD.replace("n = 7", "n = 7, chest_mm = 900"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("t.toml:5:"), "{e}");
    assert!(e.contains("chest_mm"), "{e}");
}

#[test]
fn inconsistent_values_are_refused_with_their_line() {
    let e = parse(&GOOD.replace("schema = 1", "schema = 2"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("t.toml:1:10: schema:"), "{e}");
    let e = parse(&GOOD.replace("generator", "mesh = \"a.obj\"\ngenerator"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("t.toml:6:") && e.contains("not both"), "{e}");
    let two = format!(
        "{GOOD}\n[[piece]]\nname = \"a\"\nseed = [0, 0, 200]\n\n[[piece]]\nname = \"a\"\nseed = [0, 0, 200]\n"
    );
    let e = parse(&two).unwrap_err().to_string();
    assert!(e.contains("t.toml:12:") && e.contains("line 8"), "{e}");
    let e = parse(&GOOD.replace("name = \"t\"", "name = \"../x\""))
        .unwrap_err()
        .to_string();
    assert!(e.contains("t.toml:2:8: name:"), "{e}");
}

#[test]
fn seeds_off_the_surface_or_sharing_a_piece_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    // The cap's pole is at (0, 0, 200): 50 mm above it lies in no piece.
    let text = format!("{GOOD}\n[[piece]]\nname = \"a\"\nseed = [0, 0, 250]\n");
    let e = run_in(&text, tmp.path(), &out, false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("t.toml:9:8: piece.seed:") && e.contains("50.000 mm"),
        "{e}"
    );
    assert!(!out.exists(), "a failed run must leave no output folder");
    let text = format!(
        "{GOOD}\n[[piece]]\nname = \"a\"\nseed = [0, 0, 200]\n\n[[piece]]\nname = \"b\"\nseed = [1, 0, 200]\n"
    );
    let e = run_in(&text, tmp.path(), &out, false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("t.toml:13:") && e.contains("\"a\""), "{e}");
    assert!(!out.exists());
}

#[test]
fn a_missing_mesh_names_the_file_and_the_toml_line() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let text = "schema = 1\nname = \"t\"\n[input]\nmesh = \"scans/none.obj\"\n";
    let e = run_in(text, tmp.path(), &out, false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("t.toml:4:8: input.mesh:"), "{e}");
    assert!(e.contains("none.obj"), "{e}");
    assert!(!out.exists());
    // An unset environment variable in a path.
    let text = "schema = 1\nname = \"t\"\n[input]\nmesh = \"${FLATCUT_NO_SUCH_VAR}/a.obj\"\n";
    let e = run_in(text, tmp.path(), &out, false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("t.toml:4:8:") && e.contains("FLATCUT_NO_SUCH_VAR"),
        "{e}"
    );
}

#[test]
fn relative_mesh_paths_are_relative_to_the_toml() {
    let tmp = tempfile::tempdir().unwrap();
    let sub = tmp.path().join("recipes");
    std::fs::create_dir_all(sub.join("scans")).unwrap();
    let cap = flatcut_mesh::shapes::sphere_cap_grid(7, 1.0, 200.0);
    flatcut_io::write_mesh(&sub.join("scans/cap.obj"), &cap, &Default::default()).unwrap();
    let text = "schema = 1\nname = \"t\"\n[input]\nmesh = \"scans/cap.obj\"\n";
    let out = tmp.path().join("out");
    run_in(text, &sub, &out, false).unwrap();
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["inputs"][0]["path"], "scans/cap.obj");
    assert_eq!(report["inputs"][0]["key"], "input.mesh");
    assert_eq!(report["input_mesh"]["faces"], 72);
}

#[test]
fn output_folder_rules() {
    let tmp = tempfile::tempdir().unwrap();
    // A file where the folder should be.
    let file = tmp.path().join("taken");
    std::fs::write(&file, "x").unwrap();
    let e = run_in(GOOD, tmp.path(), &file, false).unwrap_err();
    assert!(matches!(e, PipelineError::OutputIsFile { .. }), "{e}");
    assert_eq!(std::fs::read(&file).unwrap(), b"x");

    // A folder of another pipeline is refused without --force, kept intact.
    let out: PathBuf = tmp.path().join("out");
    run_in(GOOD, tmp.path(), &out, false).unwrap();
    let other = GOOD.replace("name = \"t\"", "name = \"other\"");
    let before = std::fs::read(out.join("report.json")).unwrap();
    let e = run_in(&other, tmp.path(), &out, false).unwrap_err();
    assert!(
        matches!(&e, PipelineError::OutputForeign { owner: Some(o), .. } if o == "t"),
        "{e}"
    );
    assert_eq!(std::fs::read(out.join("report.json")).unwrap(), before);
    // …and taken over with --force.
    run_in(&other, tmp.path(), &out, true).unwrap();
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(r["pipeline"], "other");

    // A non-empty folder flatcut did not write.
    let mine = tmp.path().join("mine");
    std::fs::create_dir_all(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), "keep").unwrap();
    let e = run_in(GOOD, tmp.path(), &mine, false).unwrap_err();
    assert!(
        matches!(e, PipelineError::OutputForeign { owner: None, .. }),
        "{e}"
    );
    assert_eq!(std::fs::read(mine.join("notes.txt")).unwrap(), b"keep");

    // An input inside the output folder under an output's name is never overwritten, even
    // with --force.
    let clash = tmp.path().join("clash");
    std::fs::create_dir_all(&clash).unwrap();
    let cap = flatcut_mesh::shapes::sphere_cap_grid(7, 1.0, 200.0);
    flatcut_io::write_mesh(&clash.join("processed.glb"), &cap, &Default::default()).unwrap();
    let input_bytes = std::fs::read(clash.join("processed.glb")).unwrap();
    let text = "schema = 1\nname = \"t\"\nunits = \"m\"\n[input]\nmesh = \"clash/processed.glb\"\n";
    let e = run_in(text, tmp.path(), &clash, true).unwrap_err();
    assert!(
        matches!(e, PipelineError::WouldOverwriteInput { .. }),
        "{e}"
    );
    assert_eq!(
        std::fs::read(clash.join("processed.glb")).unwrap(),
        input_bytes
    );

    // Nor is an input removed as a file an earlier run wrote and this one does not: a run
    // reading piece "a" of an earlier run (its folder's pieces/a.obj), whose own piece has
    // another name, deleted it.
    let again = tmp.path().join("again");
    let with_a = format!("{GOOD}\n[[piece]]\nname = \"a\"\nseed = [0, 0, 200]\n");
    run_in(&with_a, tmp.path(), &again, false).unwrap();
    let piece = again.join("pieces").join("a.obj");
    let piece_bytes = std::fs::read(&piece).unwrap();
    let text = "schema = 1\nname = \"t\"\nunits = \"mm\"\n[input]\nmesh = \"again/pieces/a.obj\"\n";
    for force in [false, true] {
        let e = run_in(text, tmp.path(), &again, force).unwrap_err();
        assert!(matches!(e, PipelineError::WouldRemoveInput { .. }), "{e}");
        assert!(e.to_string().contains("a.obj"), "{e}");
        assert_eq!(std::fs::read(&piece).unwrap(), piece_bytes);
    }
}

/// `GOOD` with one piece "a" at the pole and `line` as its fourth line (line 10).
fn piece_with(line: &str) -> String {
    format!("{GOOD}\n[[piece]]\nname = \"a\"\nseed = [0, 0, 200]\n{line}\n")
}

#[test]
fn darts_features_and_shrink_outside_their_piece_are_refused_with_their_line() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let rim_z = 200.0 * 30f64.to_radians().cos();
    let two_darts = format!(
        "darts = [{{ from = [100, 0, {rim_z}], tip = [40, 0, 196] }}, {{ name = \"x\", from = [0, 0, 200], tip = [0, 40, 196] }}]"
    );
    // The column of the second dart's table.
    let second = format!(
        "t.toml:10:{}: piece.darts: piece \"a\": dart 1 \"x\"",
        two_darts.find("{ name").unwrap() + 1
    );
    let cases = [
        // A dart starting at the pole, 100 mm from the rim (the piece's boundary).
        (
            "darts = [{ from = [0, 0, 200], tip = [0, 40, 196] }]".to_string(),
            "t.toml:10:10: piece.darts: piece \"a\":",
            "from the piece's boundary",
        ),
        // A dart whose tip lies 60 mm above the cap.
        (
            format!("darts = [{{ from = [100, 0, {rim_z}], tip = [40, 0, 256] }}]"),
            "t.toml:10:10: piece.darts: piece \"a\":",
            "from the piece's surface",
        ),
        // The second dart is the bad one: its own table is named.
        (
            two_darts.clone(),
            second.as_str(),
            "from the piece's boundary",
        ),
        // A feature landmark 60 mm above the pole.
        (
            "features = [[[0, 0, 200], [0, 0, 260]]]".to_string(),
            "t.toml:10:13: piece.features: piece \"a\": landmark 1 of feature curve 0 is 60.000 mm",
            "on this piece",
        ),
        // Shrink out of range: the allowed range is said.
        (
            "shrink = { along_grain = 0.7 }".to_string(),
            "t.toml:10:26: piece.shrink.along_grain: piece \"a\":",
            "between -0.5 and 0.5",
        ),
        (
            "shrink = { across_grain = -5 }".to_string(),
            "t.toml:10:27: piece.shrink.across_grain:",
            "-0.05 for 5 %",
        ),
    ];
    for (line, at, what) in &cases {
        let e = run_in(&piece_with(line), tmp.path(), &out, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains(at) && e.contains(what), "{line}\n{e}");
        assert!(!out.exists(), "a failed run must leave no output folder");
    }
    // A mirrored pair needs an even quantity.
    let e = parse(&piece_with("mirror = true")).unwrap_err().to_string();
    assert!(
        e.contains("t.toml:8:8: piece.quantity:") && e.contains("even quantity"),
        "{e}"
    );
    // An unknown key inside a dart names it.
    let e = run_in(
        &piece_with("darts = [{ from = [0, 0, 200], tipp = [0, 40, 196] }]"),
        tmp.path(),
        &out,
        false,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("t.toml:10:") && e.contains("tipp"), "{e}");
    assert!(!out.exists());
}

#[test]
fn a_missing_wireframe_names_the_file_and_the_toml_line() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let text = "schema = 1\nname = \"t\"\n[input]\nwireframes = [\"w/seat.toml\"]\n";
    let e = run_in(text, tmp.path(), &out, false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("t.toml:4:15: input.wireframes:") && e.contains("seat.toml"),
        "{e}"
    );
    assert!(!out.exists());
    // A wire-frame with a bad key: its own file, line and column.
    std::fs::create_dir_all(tmp.path().join("w")).unwrap();
    std::fs::write(
        tmp.path().join("w/seat.toml"),
        "target_edge_mm = 20\ncolour = 1\n",
    )
    .unwrap();
    let e = run_in(text, tmp.path(), &out, false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("t.toml:4:15: input.wireframes:") && e.contains("seat.toml:2:1:"),
        "{e}"
    );
    assert!(!out.exists());
    // Two input sources.
    let e = parse(&GOOD.replace("[input]\n", "[input]\nwireframes = [\"a.toml\"]\n"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("input.") && e.contains("not both"), "{e}");
}

#[test]
fn a_cut_landmark_off_the_surface_names_its_cut_line_and_point() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    // The cap (R = 200 mm, 60°) has its pole at (0, 0, 200) and lies above z = 170 mm;
    // (150, 0, 0) is far below it.
    let text = format!(
        "{GOOD}\n[[cut]]\nname = \"across\"\npoints = [[0.0, 0.0, 200.0], [150.0, 0.0, 0.0]]\n"
    );
    let e = run_in(&text, tmp.path(), &out, false)
        .unwrap_err()
        .to_string();
    // Located at the [[cut]] table (line 7), naming the line and the point's index.
    assert!(e.contains("t.toml:7:1: cut:"), "{e}");
    assert!(
        e.contains("line \"across\" point 1") && e.contains("mm from the surface"),
        "{e}"
    );
    assert!(!out.exists(), "a failed run must leave no output folder");
}

#[test]
fn an_output_key_naming_a_file_is_refused_at_its_line() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("taken"), "x").unwrap();
    let text = GOOD.replace("name = \"t\"\n", "name = \"t\"\noutput = \"taken\"\n");
    let toml = tmp.path().join("t.toml");
    std::fs::write(&toml, &text).unwrap();
    let p = Pipeline::read(&toml).unwrap();
    let e = flatcut_pipeline::run(
        &p,
        &RunOptions {
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with(&format!("{}:3:10: output:", toml.display())) && e.contains("existing file"),
        "{e}"
    );
    assert_eq!(std::fs::read(tmp.path().join("taken")).unwrap(), b"x");
}

#[test]
fn absolute_mesh_and_output_paths_are_used_as_given() {
    let tmp = tempfile::tempdir().unwrap();
    // The mesh and the output live outside the TOML's folder, named by absolute paths.
    let elsewhere = tmp.path().join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let mesh = elsewhere.join("cap.obj");
    let cap = flatcut_mesh::shapes::sphere_cap_grid(7, 60f64.to_radians(), 200.0);
    flatcut_io::write_mesh(&mesh, &cap, &Default::default()).unwrap();
    let out = elsewhere.join("results");
    let dir = tmp.path().join("recipes");
    std::fs::create_dir_all(&dir).unwrap();
    let text = format!(
        "schema = 1\nname = \"abs\"\noutput = {:?}\n[input]\nmesh = {:?}\n",
        out.display().to_string(),
        mesh.display().to_string()
    );
    assert!(mesh.is_absolute() && out.is_absolute());
    let toml = dir.join("abs.toml");
    std::fs::write(&toml, &text).unwrap();
    let p = Pipeline::read(&toml).unwrap();
    flatcut_pipeline::run(
        &p,
        &RunOptions {
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap();
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(r["input_mesh"]["faces"], cap.face_count());
    assert_eq!(
        r["inputs"][0]["bytes"],
        std::fs::metadata(&mesh).unwrap().len()
    );
    assert!(
        !dir.join("out").exists(),
        "nothing is written beside the TOML"
    );
}

#[test]
fn the_keys_of_the_issues_example_are_accepted_as_aliases() {
    // `chest_mm` for the dress form's bust girth and `weld_mm` for the weld tolerance, as a
    // recipe written from the original specification names them.
    let text = r#"schema = 1
name = "t"
[input]
generator = { kind = "dress-form", chest_mm = 920, waist_mm = 760, hip_mm = 980, height_mm = 1700 }
clean = { weld_mm = 0.01, keep = "largest" }
"#;
    let p = parse(text).unwrap_or_else(|e| panic!("{e}"));
    let clean = &p.spec.input.get_ref().clean;
    assert_eq!(clean.weld_tolerance_mm, 0.01);
    match p
        .spec
        .input
        .get_ref()
        .generator
        .as_ref()
        .map(|g| g.get_ref())
    {
        Some(flatcut_pipeline::spec::Generator::DressForm(m)) => assert_eq!(m.bust_mm, 920.0),
        other => panic!("{other:?}"),
    }
    // Both names at once is still an error (one definition of each parameter).
    let both = text.replace("chest_mm = 920", "chest_mm = 920, bust_mm = 900");
    assert!(parse(&both).is_err());
}
