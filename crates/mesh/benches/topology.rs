//! Topology::build on a generated 1M-face grid (and on mh_body_subdiv2.obj when FLATCUT_DATA
//! is set, read with a minimal v/f parser since the mesh crate cannot use flatcut_io).
//! Target: < 1 s for 1M faces; Topology + TriMesh < 400 bytes per face.
//! Also prints the memory: bytes per face from the arrays' capacities, and the process's
//! peak resident set growth while building (Linux VmHWM).
//!
//! `cargo bench -p flatcut_mesh --bench topology`

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_mesh::shapes::grid_patch;
use flatcut_mesh::{Topology, TriMesh};

/// Peak resident set size of this process in kB (VmHWM), if readable.
fn peak_rss_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn report_memory(name: &str, mesh: &TriMesh) {
    let before = peak_rss_kb();
    let t = Topology::build(mesh).unwrap();
    let after = peak_rss_kb();
    let f = mesh.face_count() as f64;
    let (mb, tb) = (mesh.heap_bytes(), t.heap_bytes());
    eprintln!(
        "{name}: {} faces, TriMesh {:.0} B/face + Topology {:.0} B/face = {:.0} B/face (capacities)",
        mesh.face_count(),
        mb as f64 / f,
        tb as f64 / f,
        (mb + tb) as f64 / f
    );
    if let (Some(b), Some(a)) = (before, after) {
        // Only meaningful the first time the process reaches this size.
        eprintln!(
            "{name}: peak RSS growth during build {:.0} B/face (VmHWM {b} → {a} kB)",
            (a - b) as f64 * 1024.0 / f
        );
    }
}

/// Minimal OBJ reader: `v` and `f` lines, polygons fanned, `v/vt/vn` references, negative
/// indices. Enough for the benchmark; the real reader lives in flatcut_io.
fn read_obj(path: &std::path::Path) -> TriMesh {
    let text = std::fs::read_to_string(path).unwrap();
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.take(3).map(|x| x.parse().unwrap()).collect();
                positions.push([c[0], c[1], c[2]]);
            }
            Some("f") => {
                let idx: Vec<u32> = it
                    .map(|x| {
                        let i: i64 = x.split('/').next().unwrap().parse().unwrap();
                        if i < 0 {
                            (positions.len() as i64 + i) as u32
                        } else {
                            (i - 1) as u32
                        }
                    })
                    .collect();
                for k in 1..idx.len() - 1 {
                    faces.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

fn bench(c: &mut Criterion) {
    // 708 × 708 vertices: 2 · 707² = 999 698 faces.
    let grid = grid_patch(708, 708, 1000.0, |x, y| 0.001 * x * y);
    report_memory("grid 1M", &grid);
    let mut group = c.benchmark_group("topology_build");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(15));
    group.bench_function("grid_1M_faces", |b| {
        b.iter(|| Topology::build(black_box(&grid)).unwrap())
    });
    if let Ok(dir) = std::env::var("FLATCUT_DATA") {
        let path = std::path::Path::new(&dir).join("mh_body_subdiv2.obj");
        assert!(
            path.exists(),
            "FLATCUT_DATA is set but {} is missing",
            path.display()
        );
        let body = read_obj(&path);
        report_memory("mh_body_subdiv2", &body);
        group.bench_function("mh_body_subdiv2", |b| {
            b.iter(|| Topology::build(black_box(&body)).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
