//! Remeshing and decimation of the 428k-triangle body (mh_body_subdiv2.obj, decimetres,
//! scaled ×100 to mm) through FLATCUT_DATA: remesh to 8 mm, decimate to 50k faces. Without
//! FLATCUT_DATA a procedural stand-in of similar size runs: an icosphere of radius 400 mm
//! with 327k faces. The quality numbers of one run are printed beside the timing.
//!
//! `FLATCUT_DATA=/work/shared/meshes cargo bench -p flatcut_remesh --bench remesh`

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_mesh::TriMesh;
use flatcut_remesh::{DecimateOptions, RemeshOptions, decimate, remesh};

fn input() -> (String, TriMesh) {
    match std::env::var_os("FLATCUT_DATA") {
        Some(dir) => {
            let path = std::path::Path::new(&dir).join("mh_body_subdiv2.obj");
            let m = flatcut_io::read_mesh(&path, flatcut_io::Units::Dm)
                .unwrap_or_else(|e| panic!("FLATCUT_DATA is set but {}: {e}", path.display()))
                .mesh;
            ("mh_body_subdiv2".into(), m)
        }
        None => (
            "icosphere_r400_s7".into(),
            flatcut_mesh::shapes::icosphere(400.0, 7),
        ),
    }
}

fn bench(c: &mut Criterion) {
    let (name, mesh) = input();
    let faces = mesh.faces.len();
    let ropts = RemeshOptions {
        target_edge_mm: 8.0,
        ..RemeshOptions::default()
    };
    let dopts = DecimateOptions {
        target_faces: 50_000,
    };
    let t = Instant::now();
    match remesh(&mesh, &ropts) {
        Ok(r) => {
            let q = &r.report;
            eprintln!(
                "{name} ({faces} faces) remesh 8 mm: {:.2} s, {} faces, {:.2} % edges in [0.5,1.5]L, {:.2} % faces ≥ 25°, min angle {:.1}°, centroid max {:.3} mm, input→output max {:.3} mm",
                t.elapsed().as_secs_f64(),
                q.faces,
                100.0 * q.edges_within_half_to_1_5,
                100.0 * q.faces_min_angle_at_least_25_deg,
                q.min_angle_deg,
                q.centroid_to_input.max_mm,
                q.input_to_output.max_mm
            );
        }
        Err(e) => panic!("{name}: {e}"),
    }
    let t = Instant::now();
    match decimate(&mesh, &dopts) {
        Ok(d) => eprintln!(
            "{name} ({faces} faces) decimate to 50k: {:.2} s, {} faces, Hausdorff {:.3} mm, RMS {:.3} mm",
            t.elapsed().as_secs_f64(),
            d.report.faces,
            d.report.hausdorff_mm,
            d.report.rms_mm
        ),
        Err(e) => panic!("{name}: {e}"),
    }
    let mut group = c.benchmark_group("remesh");
    group.sample_size(10);
    group.bench_function(format!("{name}_remesh_8mm"), |b| {
        b.iter(|| black_box(remesh(black_box(&mesh), &ropts)))
    });
    group.bench_function(format!("{name}_decimate_50k"), |b| {
        b.iter(|| black_box(decimate(black_box(&mesh), &dopts)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
