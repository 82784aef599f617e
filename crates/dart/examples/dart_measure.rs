//! Measures what a dart buys: flattenable processing (robust mode) of a piece with and
//! without a dart at its largest concentrated curvature, then flattening; prints a table for
//! docs/algorithms/darts.md.
//!
//! `cargo run --release -p flatcut_dart --example dart_measure` (bumps), with FLATCUT_DATA set
//! also the back-left-upper piece of the mh_body wetsuit cut (fixtures/cuts/mh_body_wetsuit.toml).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use flatcut_dart::{DartSpec, SuggestOptions, dart, suggest};
use flatcut_flattenable::{FlattenableError, ProcessOptions, Processed, process};
use flatcut_lscm::{FlattenOptions, flatten};
use flatcut_mesh::{Topology, TriMesh, VertexId, shapes, vec3};

fn bump(rings: usize, radius: f64, h: f64, sigma: f64) -> TriMesh {
    let mut m = shapes::planar_disk(radius, rings);
    for p in &mut m.positions {
        p[2] = h * (-(p[0] * p[0] + p[1] * p[1]) / (sigma * sigma)).exp();
    }
    m
}

fn rms_on_input(src: &TriMesh, out: &TriMesh) -> f64 {
    let topo = Topology::build(src).unwrap();
    let (mut s, mut n) = (0.0, 0);
    for v in 0..src.positions.len() {
        if topo.is_interior_vertex(VertexId(v as u32)) {
            s += vec3::norm2(vec3::sub(out.positions[v], src.positions[v]));
            n += 1;
        }
    }
    (s / n as f64).sqrt()
}

fn run(m: &TriMesh) -> (Processed, bool) {
    match process(m, &ProcessOptions::default()) {
        Ok(p) => (p, true),
        Err(FlattenableError::NotConverged { partial, .. }) => (*partial, false),
        Err(e) => panic!("{e}"),
    }
}

fn measure(label: &str, m: &TriMesh, specs: &[DartSpec]) {
    let t = std::time::Instant::now();
    let d = dart(m, specs, &Default::default()).unwrap();
    let dart_s = t.elapsed().as_secs_f64();
    let (p0, c0) = run(m);
    let (p1, c1) = run(&d.mesh);
    let (r0, r1) = (rms_on_input(m, &p0.mesh), rms_on_input(m, &p1.mesh));
    let mut legs = String::new();
    if c1 {
        let flat = flatten(&p1.mesh, &FlattenOptions::default()).unwrap();
        let uv = &flat.flattening.uv;
        for l in &d.darts {
            let len = |leg: &[u32]| -> f64 {
                leg.windows(2)
                    .map(|w| {
                        let (a, b) = (uv[w[0] as usize], uv[w[1] as usize]);
                        (a[0] - b[0]).hypot(a[1] - b[1])
                    })
                    .sum()
            };
            let (la, lb) = (len(&l.leg_a), len(&l.leg_b));
            legs += &format!(" {:.2e}", (la - lb).abs() / la);
        }
    }
    println!(
        "| {label} | {} | {} | {:.3} | {:.3} | {:.1} % | {}/{} | {:.1e}/{:.1e} | {:.2}/{:.2} | {}{} | {:.3} |",
        m.positions.len(),
        m.faces.len(),
        r0,
        r1,
        100.0 * (1.0 - r1 / r0),
        p0.report.iterations,
        p1.report.iterations,
        p0.report.final_theta_err,
        p1.report.final_theta_err,
        p0.report.area_change_percent,
        p1.report.area_change_percent,
        if c0 && c1 { "yes" } else { "NO" },
        legs,
        dart_s
    );
}

fn main() {
    println!(
        "| piece | V | F | RMS no dart (mm) | RMS dart (mm) | decrease | iterations | θ_err | area % | converged, legs |ΔL|/L | dart s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &(rings, h) in &[
        (8usize, 30.0),
        (12, 30.0),
        (16, 30.0),
        (24, 30.0),
        (12, 15.0),
        (12, 45.0),
    ] {
        let m = bump(rings, 100.0, h, 40.0);
        let rim = m.positions[1 + 3 * rings * (rings - 1)];
        measure(
            &format!("bump {rings} rings, h {h}"),
            &m,
            &[DartSpec::to_tip("d", rim, m.positions[0])],
        );
        let s = suggest(&m, 1, &SuggestOptions::default()).unwrap();
        measure(
            &format!(
                "bump {rings} rings, h {h}, suggested (tip v{})",
                s[0].tip_vertex
            ),
            &m,
            std::slice::from_ref(&s[0].spec),
        );
    }
    if let Some(dir) = std::env::var_os("FLATCUT_DATA") {
        let path = std::path::PathBuf::from(dir).join("mh_body.obj");
        let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Dm)
            .unwrap()
            .mesh;
        let fixture = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/cuts/mh_body_wetsuit.toml"
        );
        let mut cuts: flatcut_trim::Cuts =
            toml::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
        cuts.scale(100.0);
        let t = flatcut_trim::trim(&mesh, &cuts).unwrap();
        for name in ["back-left-upper", "back-right-upper", "front-left-upper"] {
            let p = t.pieces.iter().find(|p| p.name == name).unwrap();
            let s = suggest(&p.mesh, 3, &SuggestOptions::default()).unwrap();
            for x in &s {
                println!(
                    "{name}: suggestion {} tip {:?} from {:?} len {:.1} conc {:.4} abs {:.4} -> {:.4}",
                    x.spec.name,
                    x.spec.tip,
                    x.spec.from,
                    x.length_mm,
                    x.concentrated_defect_rad,
                    x.abs_defect_before_rad,
                    x.abs_defect_after_rad
                );
            }
            if let Some(x) = s.first() {
                measure(
                    &format!("mh_body {name}, suggested"),
                    &p.mesh,
                    std::slice::from_ref(&x.spec),
                );
            }
        }
    }
}
