//! `trim` cost: 20 cutting lines on the scan-like MakeHuman body (148k triangles, mm, holes
//! and debris) — the wetsuit fixture's 18 lines plus a chest and a hip loop. Without
//! FLATCUT_DATA, the same kind of cut on a generated dress form of similar size.
//!
//! ```sh
//! FLATCUT_DATA=/work/shared/meshes cargo bench -p flatcut_trim --bench trim
//! ```

#![allow(clippy::unwrap_used, clippy::expect_used)]

use criterion::{Criterion, criterion_group, criterion_main};
use flatcut_mesh::{TriMesh, bvh::Bvh, shapes};
use flatcut_trim::{CutSpec, Cuts, trim};

/// A horizontal loop of eight ray hits round the point `c` (inside the body).
fn loop_at(bvh: &Bvh, name: &str, c: [f64; 3]) -> CutSpec {
    let points = (0..8)
        .map(|k| {
            let a = k as f64 * std::f64::consts::FRAC_PI_4 + 0.1;
            let d = [a.cos(), 0.0, a.sin()];
            let h = bvh.ray_intersect(c, d, 1e5).expect("ray hits the body");
            [c[0] + h.t * d[0], c[1], c[2] + h.t * d[2]]
        })
        .collect();
    CutSpec {
        name: name.into(),
        points,
        vertices: Vec::new(),
        closed: true,
    }
}

fn case() -> (String, TriMesh, Cuts) {
    if let Some(dir) = std::env::var_os("FLATCUT_DATA") {
        let dir = std::path::PathBuf::from(dir);
        let mesh = flatcut_io::read_mesh(&dir.join("mh_body_scanlike.obj"), flatcut_io::Units::Mm)
            .expect("FLATCUT_DATA is set but mh_body_scanlike.obj is missing")
            .mesh;
        let fixture = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/cuts/mh_body_wetsuit.toml"
        );
        let mut cuts: Cuts = toml::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
        cuts.scale(100.0); // dm → mm
        // The scan's noise and holes (one at the crotch, 23 mm from the template's surface
        // point) move the surface from the template's.
        cuts.options.landmark_tolerance_mm = 30.0;
        cuts.options.end_snap_mm = 30.0;
        cuts.options.keep_unnamed = true;
        // The underarm lines leave the arm-hole loop past a hole of the scan 4.8 mm away and
        // both wrap its corner: they overlap there, which `trim` refuses (tested). Loops
        // round the chest, belly, hip and thighs take their place: 15 + 5 = 20 lines.
        cuts.cuts.retain(|c| !c.name.starts_with("underarm"));
        let bvh = Bvh::build(&mesh);
        cuts.cuts.push(loop_at(&bvh, "chest", [0.0, 360.0, 20.0]));
        cuts.cuts.push(loop_at(&bvh, "belly", [0.0, 300.0, 20.0]));
        cuts.cuts.push(loop_at(&bvh, "hip", [0.0, 80.0, 10.0]));
        cuts.cuts
            .push(loop_at(&bvh, "thigh-left", [134.0, -160.0, 22.0]));
        cuts.cuts
            .push(loop_at(&bvh, "thigh-right", [-134.0, -160.0, 22.0]));
        assert_eq!(cuts.cuts.len(), 20);
        cuts.pieces.clear();
        ("mh_body_scanlike (148k tris), 20 lines".into(), mesh, cuts)
    } else {
        let m = shapes::BodyMeasurements {
            resolution: 256,
            ..Default::default()
        };
        let form = shapes::dress_form(&m);
        let mut cuts = flatcut_trim::dress_form_wetsuit(&form, &m).unwrap();
        let bvh = Bvh::build(&form);
        let h = m.height_mm;
        for (k, f) in [
            0.47, 0.52, 0.57, 0.60, 0.66, 0.69, 0.72, 0.74, 0.56, 0.58, 0.64, 0.68, 0.70,
        ]
        .iter()
        .enumerate()
        {
            cuts.cuts
                .push(loop_at(&bvh, &format!("ring-{k}"), [0.0, f * h, 0.0]));
        }
        cuts.pieces.clear();
        cuts.options.keep_unnamed = true;
        (
            format!(
                "dress_form res 256 ({} tris), {} lines",
                form.faces.len(),
                cuts.cuts.len()
            ),
            form,
            cuts,
        )
    }
}

fn bench(c: &mut Criterion) {
    let (name, mesh, cuts) = case();
    let t = trim(&mesh, &cuts).expect("the benchmark cut is valid");
    eprintln!(
        "{name}: {} pieces, {} seams, {} embedded faces",
        t.report.pieces.len(),
        t.ledger.seams.len(),
        t.embedded.mesh.faces.len()
    );
    let mut g = c.benchmark_group("trim");
    g.sample_size(10);
    g.bench_function(name, |b| b.iter(|| trim(&mesh, &cuts).unwrap()));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
