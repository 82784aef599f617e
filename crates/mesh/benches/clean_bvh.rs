//! clean() on a 1M-face triangle soup (the STL case: every face with its own three
//! vertices, welded back exactly), Bvh::build on 1M faces and 10k closest-point queries.
//!
//! `cargo bench -p flatcut_mesh --bench clean_bvh`

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_mesh::TriMesh;
use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::clean::{CleanOptions, clean};
use flatcut_mesh::shapes::grid_patch;

fn bench(c: &mut Criterion) {
    let grid = grid_patch(708, 708, 1000.0, |x, y| 0.001 * x * y);
    let mut positions = Vec::with_capacity(3 * grid.face_count());
    let mut faces = Vec::with_capacity(grid.face_count());
    for f in &grid.faces {
        let i = positions.len() as u32;
        positions.extend(f.map(|v| grid.positions[v as usize]));
        faces.push([i, i + 1, i + 2]);
    }
    let soup = TriMesh::new(positions, faces).unwrap();
    let mut group = c.benchmark_group("mesh_1M_faces");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    group.bench_function("clean_soup_exact_weld", |b| {
        b.iter(|| clean(black_box(&soup), &CleanOptions::default()).unwrap())
    });
    let tol = CleanOptions {
        weld_tolerance_mm: 0.01,
        ..Default::default()
    };
    group.bench_function("clean_soup_weld_0.01mm", |b| {
        b.iter(|| clean(black_box(&soup), &tol).unwrap())
    });
    group.bench_function("bvh_build", |b| b.iter(|| Bvh::build(black_box(&grid))));
    let bvh = Bvh::build(&grid);
    let queries: Vec<[f64; 3]> = (0..10_000)
        .map(|i| {
            let t = i as f64 * 0.618_033_988_749_895;
            [
                1000.0 * (t.fract() - 0.5),
                1000.0 * ((t * 1.3).fract() - 0.5),
                50.0 * ((t * 2.7).fract() - 0.5),
            ]
        })
        .collect();
    group.bench_function("closest_point_10k", |b| {
        b.iter(|| {
            queries
                .iter()
                .map(|&q| bvh.closest_point(q).unwrap().distance)
                .sum::<f64>()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
