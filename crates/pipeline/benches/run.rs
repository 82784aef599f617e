//! Time of a whole pipeline run in memory (`compute`: every stage, files encoded, no folder
//! written) on the bundled pipelines that need no data, and with FLATCUT_DATA set on
//! pipelines/wetsuit-mh.toml and pipelines/wetsuit-scan.toml (mh_body_scanlike.obj, 148k
//! triangles to a full pattern set: issue 8's target is < 10 s, release, 2 cores). The
//! per-stage times of one run are printed first.
//!
//! `[FLATCUT_DATA=/work/shared/meshes] cargo bench -p flatcut_pipeline --bench run`

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_pipeline::{Pipeline, Progress, compute};

fn bench(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../pipelines");
    let mut names = vec!["wetsuit-demo", "patch-demo"];
    if std::env::var_os("FLATCUT_DATA").is_some() {
        names.push("wetsuit-mh");
        names.push("wetsuit-scan");
    }
    let mut group = c.benchmark_group("pipeline");
    // One run of the scan takes seconds: the fewest samples criterion allows, time to take them.
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(60));
    for name in names {
        let path = dir.join(format!("{name}.toml"));
        if !path.is_file() {
            continue;
        }
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
                    "{name}: {} pieces, {faces} faces, {:.3} s: {}",
                    r.report.pieces.len(),
                    r.timings.total_seconds,
                    stages.join(", ")
                );
            }
            Err(e) => panic!("{name}: {e}"),
        }
        group.bench_function(name, |b| {
            b.iter(|| black_box(compute(&p, &Progress::hidden()).map(|r| r.files.len())))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
