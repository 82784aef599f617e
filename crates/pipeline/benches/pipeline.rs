//! A 150k-triangle scan to a full pattern set: pipelines/wetsuit-scan.toml
//! (mh_body_scanlike.obj, 148k triangles: clean, remesh to 15 mm, cut into 16 pieces,
//! process, flatten, every output encoded in memory — `compute`, no folder written).
//! Issue 8's target is < 10 s (release, 2 cores). Needs FLATCUT_DATA; without it the bench
//! says so and measures nothing. The per-stage times of one run are printed first.
//!
//! `FLATCUT_DATA=/work/shared/meshes cargo bench -p flatcut_pipeline --bench pipeline`

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_pipeline::{Pipeline, Progress, compute};

fn bench(c: &mut Criterion) {
    if std::env::var_os("FLATCUT_DATA").is_none() {
        eprintln!("pipeline bench: FLATCUT_DATA is unset; wetsuit-scan needs mh_body_scanlike.obj");
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../pipelines/wetsuit-scan.toml");
    let p = match Pipeline::read(&path) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    match compute(&p, &Progress::hidden()) {
        Ok(r) => {
            let stages: Vec<String> = r
                .timings
                .stages
                .iter()
                .map(|s| format!("{} {:.3} s", s.stage, s.seconds))
                .collect();
            let faces: usize = r.report.pieces.iter().map(|p| p.faces).sum();
            eprintln!(
                "wetsuit-scan: {} pieces, {faces} faces, {:.3} s on {} threads: {}",
                r.report.pieces.len(),
                r.timings.total_seconds,
                r.timings.threads,
                stages.join(", ")
            );
        }
        Err(e) => panic!("wetsuit-scan: {e}"),
    }
    let mut group = c.benchmark_group("pipeline");
    // One run takes seconds: the fewest samples criterion allows.
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(60));
    group.bench_function("wetsuit-scan", |b| {
        b.iter(|| black_box(compute(&p, &Progress::hidden()).map(|r| r.files.len())))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
