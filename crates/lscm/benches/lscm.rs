//! LSCM and LSCM + isometric refinement on generated grids (~2k, 20k, 200k faces) and, when
//! FLATCUT_DATA is set, on the real disk meshes.
//!
//! `cargo bench -p flatcut_lscm --bench lscm` (`FLATCUT_BENCH_LARGE=1` adds 2M faces)
//! (`FLATCUT_DATA=/work/shared/meshes cargo bench -p flatcut_lscm --bench lscm` adds the
//! real meshes). Timings include topology, component split and checks, as a caller sees them.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_lscm::{FlattenOptions, LscmOptions, Method, flatten, lscm};
use flatcut_mesh::TriMesh;

/// A saddle height field z = (x² − y²)/(2R), R = 200 mm, over a 200 mm square, n × n
/// vertices (2 (n − 1)² faces).
fn saddle(n: usize) -> TriMesh {
    flatcut_mesh::shapes::grid_patch(n, n, 200.0, |x, y| (x * x - y * y) / 400.0)
}

fn bench_pair(c: &mut Criterion, name: &str, mesh: &TriMesh, samples: usize) {
    let mut g = c.benchmark_group(name);
    g.sample_size(samples);
    g.warm_up_time(Duration::from_millis(500));
    g.bench_function("lscm", |b| {
        b.iter(|| black_box(lscm(black_box(mesh), &LscmOptions::default()).ok()))
    });
    let opts = FlattenOptions {
        method: Method::LscmArap,
        ..Default::default()
    };
    g.bench_function("lscm+arap", |b| {
        b.iter(|| black_box(flatten(black_box(mesh), &opts).ok()))
    });
    g.finish();
}

fn generated(c: &mut Criterion) {
    let mut sizes = vec![(33, 50), (101, 20), (317, 10)];
    // 2M faces takes minutes per sample set: only on request.
    if std::env::var_os("FLATCUT_BENCH_LARGE").is_some() {
        sizes.push((1001, 10));
    }
    for (n, samples) in sizes {
        let mesh = saddle(n);
        bench_pair(
            c,
            &format!("saddle_{}k_faces", mesh.faces.len() / 1000),
            &mesh,
            samples,
        );
    }
}

fn real(c: &mut Criterion) {
    let Some(dir) = std::env::var_os("FLATCUT_DATA") else {
        eprintln!("FLATCUT_DATA unset: skipping the real meshes");
        return;
    };
    for name in ["igl_camelhead.obj", "igl_face.obj", "mountain_disk.obj"] {
        let path = std::path::Path::new(&dir).join(name);
        let mesh = match flatcut_io::read_mesh(&path, flatcut_io::Units::Mm) {
            Ok(m) => m.mesh,
            Err(e) => panic!(
                "FLATCUT_DATA is set but {} cannot be read: {e}",
                path.display()
            ),
        };
        bench_pair(c, name.trim_end_matches(".obj"), &mesh, 10);
    }
}

criterion_group!(benches, generated, real);
criterion_main!(benches);
