//! `flatcut info --json` against the independently measured counts of MANIFEST.md
//! (real meshes, through FLATCUT_DATA): V, F, components, boundary loops and χ of every
//! edge-manifold OBJ. Skipped when FLATCUT_DATA is unset; fails when it is set and a file
//! the manifest lists is missing.

mod common;

use common::{flatcut, succeed_json};

use std::path::{Path, PathBuf};

#[derive(Debug)]
struct Row {
    file: String,
    v: usize,
    f: usize,
    comp: usize,
    loops: usize,
    chi: i64,
    manifold: bool,
}

fn parse_manifest(text: &str) -> Vec<Row> {
    let mut header: Option<Vec<String>> = None;
    let mut rows = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if !line.starts_with('|') {
            header = None;
            continue;
        }
        let cells: Vec<String> = line
            .trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect();
        if cells
            .iter()
            .all(|c| c.chars().all(|ch| ch == '-' || ch == ':'))
        {
            continue;
        }
        let Some(h) = &header else {
            header = Some(cells);
            continue;
        };
        let col = |name: &str| h.iter().position(|c| c == name).map(|i| cells[i].clone());
        let (Some(file), Some(v), Some(f), Some(comp), Some(loops), Some(chi), Some(man)) = (
            col("file"),
            col("V"),
            col("F"),
            col("comp"),
            col("loops"),
            col("chi"),
            col("manifold"),
        ) else {
            continue;
        };
        if !file.ends_with(".obj") || v.is_empty() {
            continue;
        }
        rows.push(Row {
            file,
            v: v.parse().expect("V"),
            f: f.parse().expect("F"),
            comp: comp.parse().expect("comp"),
            loops: loops.parse().expect("loops"),
            chi: chi.parse().expect("chi"),
            manifold: man == "yes",
        });
    }
    rows
}

fn info_json(path: &Path) -> serde_json::Value {
    succeed_json(flatcut().args(["info", "--json"]).arg(path))
}

#[test]
fn info_agrees_with_manifest_on_every_edge_manifold_obj() {
    let Some(data) = std::env::var_os("FLATCUT_DATA").map(PathBuf::from) else {
        eprintln!("FLATCUT_DATA unset: skipping the MANIFEST.md check");
        return;
    };
    let manifest = std::fs::read_to_string(data.join("MANIFEST.md")).unwrap_or_else(|e| {
        panic!(
            "FLATCUT_DATA is set but {}/MANIFEST.md cannot be read: {e}",
            data.display()
        )
    });
    let rows = parse_manifest(&manifest);
    assert!(
        rows.len() >= 40,
        "expected the manifest's ~45 OBJ rows, parsed {}",
        rows.len()
    );
    let mut checked = 0;
    let mut failures = Vec::new();
    for row in &rows {
        let path = data.join(&row.file);
        assert!(
            path.exists(),
            "FLATCUT_DATA is set but {} is missing",
            path.display()
        );
        let info = info_json(&path);
        let get = |k: &str| {
            info[k]
                .as_i64()
                .unwrap_or_else(|| panic!("{}: key {k} missing", row.file))
        };
        let edge_manifold = get("non_manifold_edges") == 0;
        if !row.manifold && !edge_manifold {
            continue;
        }
        checked += 1;
        let loops = info["boundary_loops"]
            .as_array()
            .map_or(usize::MAX, Vec::len);
        let ours = (
            get("vertices") as usize,
            get("faces") as usize,
            get("components") as usize,
            loops,
            get("euler_characteristic"),
        );
        let theirs = (row.v, row.f, row.comp, row.loops, row.chi);
        if ours != theirs {
            failures.push(format!(
                "{}: ours (V, F, comp, loops, chi) = {ours:?}, manifest {theirs:?}",
                row.file
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "disagreements with MANIFEST.md:\n{}",
        failures.join("\n")
    );
    assert!(
        checked >= 40,
        "only {checked} edge-manifold OBJ files were checked"
    );
}
