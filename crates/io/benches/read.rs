//! Read throughput on the 428k-triangle MakeHuman body (FLATCUT_DATA/mh_body_subdiv2.obj) as
//! OBJ, and the same mesh written at setup as binary PLY, binary STL and GLB.
//! Also `info`: read + `Topology::build` + `mesh_info`, what `flatcut info` does per file.
//! Run: `FLATCUT_DATA=... cargo bench -p flatcut_io --bench read`

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use flatcut_io::{Units, WriteOptions, read_mesh, write_mesh};

fn bench_read(c: &mut Criterion) {
    let Ok(dir) = std::env::var("FLATCUT_DATA") else {
        println!(
            "FLATCUT_DATA is not set: skipping the read benchmark (needs mh_body_subdiv2.obj)"
        );
        return;
    };
    let obj = PathBuf::from(dir).join("mh_body_subdiv2.obj");
    assert!(
        obj.is_file(),
        "FLATCUT_DATA is set but {} is missing",
        obj.display()
    );
    let mesh = read_mesh(&obj, Units::Mm).unwrap().mesh;
    let tmp = tempfile::tempdir().unwrap();
    let mut files = vec![obj.clone()];
    for ext in ["ply", "stl", "glb"] {
        let p = tmp.path().join(format!("body.{ext}"));
        write_mesh(
            &p,
            &mesh,
            &WriteOptions {
                units: Some(Units::Mm),
                ..Default::default()
            },
        )
        .unwrap();
        files.push(p);
    }
    let mut group = c.benchmark_group("read_mh_body_subdiv2");
    group.sample_size(20);
    for path in &files {
        let size = std::fs::metadata(path).unwrap().len();
        group.throughput(Throughput::Bytes(size));
        let name = path.extension().unwrap().to_string_lossy().into_owned();
        group.bench_function(name, |b| b.iter(|| read_mesh(path, Units::Mm).unwrap()));
    }
    group.finish();
    let mut group = c.benchmark_group("info_mh_body_subdiv2");
    group.sample_size(10);
    for path in &files {
        let name = path.extension().unwrap().to_string_lossy().into_owned();
        group.bench_function(name, |b| {
            b.iter(|| {
                let mesh = read_mesh(path, Units::Mm).unwrap().mesh;
                let topo = flatcut_mesh::Topology::build(&mesh).unwrap();
                flatcut_mesh::mesh_info(&mesh, &topo)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_read);
criterion_main!(benches);
