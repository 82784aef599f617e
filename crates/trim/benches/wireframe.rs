//! Time of `wireframe_surface` on the seat saddle (500 × 450 mm, z = ±40 mm, four curves) at
//! target edges of 20, 10 and 5 mm (~2k, ~8k, ~33k faces), and on the steep saddle (z = ±200 mm)
//! where one conformal re-parametrisation pass runs. Face counts are printed once per case.
//!
//! `cargo bench -p flatcut_trim --bench wireframe`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_trim::wireframe::{WireCurve, WireFrame, WireframeOptions, wireframe_surface};

fn saddle(amp: f64, target_edge_mm: f64) -> WireFrame {
    let (a, b) = (250.0, 225.0);
    let p = move |x: f64, y: f64| [x, y, amp * (x * x / (a * a) - y * y / (b * b))];
    let side = |name: &str, f: &dyn Fn(f64) -> [f64; 3]| WireCurve {
        name: name.to_string(),
        points: (0..=25).map(|i| f(i as f64 / 25.0)).collect(),
    };
    WireFrame {
        units: "mm".to_string(),
        target_edge_mm,
        curve: vec![
            side("front", &|s| p(-a + 2.0 * a * s, -b)),
            side("right", &|s| p(a, -b + 2.0 * b * s)),
            side("back", &|s| p(a - 2.0 * a * s, b)),
            side("left", &|s| p(-a, b - 2.0 * b * s)),
        ],
        guide: Vec::new(),
        options: WireframeOptions::default(),
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("wireframe");
    group.sample_size(10);
    for (amp, h) in [(40.0, 20.0), (40.0, 10.0), (40.0, 5.0), (200.0, 10.0)] {
        let wire = saddle(amp, h);
        let opts = WireframeOptions::default();
        let r = wireframe_surface(&wire, &opts).map(|p| p.report);
        if let Ok(r) = &r {
            eprintln!(
                "saddle ±{amp} mm, h = {h} mm: {} faces, min angle {:.2}°, {} passes",
                r.faces, r.min_angle_3d_deg, r.reparam_passes
            );
        }
        group.bench_function(format!("saddle_{amp}mm_h{h}mm"), |bch| {
            bch.iter(|| black_box(wireframe_surface(black_box(&wire), &opts).is_ok()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
