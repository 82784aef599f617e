//! Real meshes from $FLATCUT_DATA, cross-checked against tobj (an independent OBJ reader)
//! and against the counts in the data set's MANIFEST.md (measured independently).
//! Skipped when FLATCUT_DATA is unset; a missing file FAILS when it is set.

#![allow(clippy::unwrap_used)] // helpers outside #[test] fns unwrap too

use std::path::PathBuf;

use flatcut_io::{Units, read_mesh};

/// (file, triangles after fan triangulation, referenced vertices) from MANIFEST.md.
const MESHES: &[(&str, usize, usize)] = &[
    ("mh_proxy741.obj", 1460, 741),
    ("igl_snail.obj", 1653, 871),
    ("garment_tee_sim.obj", 5691, 2904),
    ("mh_body.obj", 26756, 13380),
    ("mh_base_hm08_full.obj", 36972, 19158),
];

fn data_file(name: &str) -> Option<PathBuf> {
    let Ok(dir) = std::env::var("FLATCUT_DATA") else {
        println!("FLATCUT_DATA is not set: skipping real-mesh test for {name}");
        return None;
    };
    let path = PathBuf::from(dir).join(name);
    assert!(
        path.is_file(),
        "FLATCUT_DATA is set but {} is missing",
        path.display()
    );
    Some(path)
}

#[test]
fn real_objs_match_tobj_and_manifest() {
    for &(name, tris, verts) in MESHES {
        let Some(path) = data_file(name) else {
            continue;
        };
        let ours = read_mesh(&path, Units::Mm).unwrap_or_else(|e| panic!("{e}"));
        let m = &ours.mesh;
        assert_eq!(m.faces.len(), tris, "{name}: triangles vs MANIFEST");
        let referenced = m.referenced_vertices().iter().filter(|u| **u).count();
        assert_eq!(referenced, verts, "{name}: referenced vertices vs MANIFEST");

        let opts = tobj::LoadOptions {
            triangulate: true,
            single_index: false,
            ..Default::default()
        };
        let (models, _materials) = tobj::load_obj(&path, &opts).unwrap();
        let tobj_tris: usize = models.iter().map(|md| md.mesh.indices.len() / 3).sum();
        assert_eq!(m.faces.len(), tobj_tris, "{name}: triangle count vs tobj");
        // tobj re-indexes per model, so compare corner by corner: both readers keep the file's
        // face order and fan-triangulate from the first corner. tobj stores f32.
        let mut f = 0;
        for md in &models {
            let p = &md.mesh.positions;
            for t in md.mesh.indices.chunks_exact(3) {
                for (k, &ti) in t.iter().enumerate() {
                    let i = ti as usize;
                    let theirs = [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
                    let mine = m.positions[m.faces[f][k] as usize].map(|x| x as f32);
                    assert_eq!(mine, theirs, "{name}: triangle {f} corner {k}");
                }
                f += 1;
            }
        }
        if models.len() > 1 {
            let labels = m.face_labels.as_ref().unwrap();
            assert!(
                labels.names.len() >= 2,
                "{name}: tobj sees {} groups, we keep labels",
                models.len()
            );
        }
        println!(
            "{name}: {} triangles, {} vertices, {} tobj models, {} labels, warnings {:?}",
            m.faces.len(),
            m.positions.len(),
            models.len(),
            m.face_labels.as_ref().map_or(0, |l| l.names.len()),
            ours.source.warnings
        );
    }
}

/// Groups become labels without splitting shared vertices (tobj duplicates them per group).
#[test]
fn groups_keep_global_vertex_identity() {
    let Some(path) = data_file("mh_base_hm08_full.obj") else {
        return;
    };
    let text = std::fs::read_to_string(&path).unwrap();
    let v_lines = text.lines().filter(|l| l.starts_with("v ")).count();
    let mut groups: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("g "))
        .map(str::trim)
        .collect();
    groups.sort_unstable();
    groups.dedup();
    let m = read_mesh(&path, Units::Mm).unwrap().mesh;
    assert_eq!(m.positions.len(), v_lines, "one vertex per 'v' line");
    let labels = m.face_labels.as_ref().unwrap();
    assert!(
        labels.names.len() >= groups.len() && labels.names.len() <= groups.len() + 1,
        "{} labels, {} groups",
        labels.names.len(),
        groups.len()
    );
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(&path, &opts).unwrap();
    let tobj_positions: usize = models.iter().map(|md| md.mesh.positions.len() / 3).sum();
    println!(
        "{}: ours {} vertices, {} labels; tobj {} models holding {} positions",
        path.display(),
        m.positions.len(),
        labels.names.len(),
        models.len(),
        tobj_positions
    );
}
