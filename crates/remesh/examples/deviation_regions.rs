//! Where do the face centroids of a remeshed scan leave the input surface? Remeshes
//! mh_body_scanlike.obj at 8 mm and prints, per body region, how many face centroids lie
//! farther than the bound from the input, and splits each deviation into the part the clean
//! body's curvature explains and the part the scan noise adds (mh_body.obj ×100 is the
//! noise-free surface the scan-like mesh was made from).
//!
//! `FLATCUT_DATA=/work/shared/meshes cargo run --release -p flatcut_remesh --example deviation_regions [bound_mm [target_edge_mm]]`
//! counts centroids farther than `bound_mm` (default 0.5) at `target_edge_mm` (default 8).
//! Environment: `CLEAN=1` remeshes mh_body_subdiv2.obj (×100, noise-free) instead of the
//! scan; `DEV=x` sets the remesh's `max_deviation_mm` (default 0.5; 0 turns refinement off);
//! `MIN=a MAX=b` set `min_edge_mm`/`max_edge_mm` (curvature adaptivity, and the refinement
//! floor `a`).

#![allow(clippy::unwrap_used)]

use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::vec3::{add, dist, scale};
use flatcut_mesh::{Topology, TriMesh};
use flatcut_remesh::{RemeshOptions, remesh};

fn load(dir: &std::path::Path, name: &str, units: flatcut_io::Units) -> TriMesh {
    flatcut_io::read_mesh(&dir.join(name), units)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .mesh
}

fn pct(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

fn main() {
    let Some(dir) = std::env::var_os("FLATCUT_DATA") else {
        eprintln!("set FLATCUT_DATA to the real-mesh folder");
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    let scan = if std::env::var_os("CLEAN").is_some() {
        load(&dir, "mh_body_subdiv2.obj", flatcut_io::Units::Dm)
    } else {
        load(&dir, "mh_body_scanlike.obj", flatcut_io::Units::Mm)
    };
    let clean = load(&dir, "mh_body.obj", flatcut_io::Units::Dm);
    let cbvh = Bvh::build(&clean);
    let sbvh = Bvh::build(&scan);
    // The input: edge lengths and noise (distance of scan vertices to the clean body).
    let st = Topology::build(&scan).unwrap();
    let mut el: Vec<f64> = st
        .edges()
        .iter()
        .map(|e| dist(scan.positions[e[0] as usize], scan.positions[e[1] as usize]))
        .collect();
    let used = scan.referenced_vertices();
    let mut noise: Vec<f64> = (0..scan.positions.len())
        .filter(|&v| used[v])
        .map(|v| cbvh.closest_point(scan.positions[v]).unwrap().distance)
        .collect();
    println!(
        "input: {} faces; edges p10 {:.2} p50 {:.2} p90 {:.2} mm; vertex to clean body p50 {:.2} p90 {:.2} p99 {:.2} max {:.2} mm",
        scan.faces.len(),
        pct(&mut el, 0.1),
        pct(&mut el, 0.5),
        pct(&mut el, 0.9),
        pct(&mut noise, 0.5),
        pct(&mut noise, 0.9),
        pct(&mut noise, 0.99),
        pct(&mut noise, 1.0)
    );
    let bound: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.5);
    let target: f64 = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(8.0);
    let opts = RemeshOptions {
        target_edge_mm: target,
        max_deviation_mm: std::env::var("DEV").map_or(0.5, |s| s.parse().unwrap()),
        min_edge_mm: std::env::var("MIN").ok().map(|s| s.parse().unwrap()),
        max_edge_mm: std::env::var("MAX").ok().map(|s| s.parse().unwrap()),
        fill_holes_perimeter_mm: 200.0,
        ..RemeshOptions::default()
    };
    let t = std::time::Instant::now();
    let r = remesh(&scan, &opts).unwrap();
    let q = &r.report;
    println!(
        "remesh: {:.2} s, {} faces, {:.3} % edges in [0.5,1.5]L, {:.3} % faces ≥ 25°, centroid max {:.3} rms {:.3} mm, vertex max {:.2e}, degenerate {}, non-manifold {}",
        t.elapsed().as_secs_f64(),
        q.faces,
        100.0 * q.edges_within_half_to_1_5,
        100.0 * q.faces_min_angle_at_least_25_deg,
        q.centroid_to_input.max_mm,
        q.centroid_to_input.rms_mm,
        q.vertex_to_input.max_mm,
        q.degenerate_faces,
        q.non_manifold_edges
    );
    println!(
        "samples over {} mm: {}; rough input area {:.2} %; input→output max {:.2} mm",
        q.max_deviation_mm,
        q.samples_over_deviation,
        100.0 * q.rough_input_fraction,
        q.input_to_output.max_mm
    );
    let m = &r.mesh;
    // Distance of every output face to the nearest input boundary vertex (open or filled).
    let bverts: Vec<[f64; 3]> = st
        .boundary_loops()
        .iter()
        .flatten()
        .map(|v| scan.positions[v.idx()])
        .collect();
    let regions = ["hand", "foot", "head", "near boundary", "rest"];
    let mut bad = vec![Vec::new(); regions.len()];
    let mut total = vec![0usize; regions.len()];
    let mut curv_part = vec![Vec::new(); regions.len()];
    for f in &m.faces {
        if f.iter().any(|&v| r.provenance[v as usize].filled) {
            continue;
        }
        let p = f.map(|v| m.positions[v as usize]);
        let c = scale(add(add(p[0], p[1]), p[2]), 1.0 / 3.0);
        let d = sbvh.closest_point(c).unwrap().distance;
        let near_b = bverts.iter().any(|&b| dist(b, c) < 16.0);
        // mm, y up, wrists at |x| ≈ 431, ankles at y ≈ −745, neck at y ≈ 589.
        let k = if c[0].abs() > 420.0 {
            0
        } else if c[1] < -700.0 {
            1
        } else if c[1] > 620.0 {
            2
        } else if near_b {
            3
        } else {
            4
        };
        total[k] += 1;
        if d > bound {
            // The same triangle with its corners on the clean body: how far its centroid is
            // from the clean body is what curvature alone explains.
            let pc = p.map(|x| cbvh.closest_point(x).unwrap().point);
            let cc = scale(add(add(pc[0], pc[1]), pc[2]), 1.0 / 3.0);
            curv_part[k].push(cbvh.closest_point(cc).unwrap().distance);
            bad[k].push(d);
        }
    }
    let mut worst: Vec<(f64, [f64; 3], [f64; 3])> = m
        .faces
        .iter()
        .map(|f| {
            let p = f.map(|v| m.positions[v as usize]);
            let c = scale(add(add(p[0], p[1]), p[2]), 1.0 / 3.0);
            let l = [dist(p[0], p[1]), dist(p[1], p[2]), dist(p[2], p[0])];
            (sbvh.closest_point(c).unwrap().distance, c, l)
        })
        .collect();
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    for w in worst.iter().take(12) {
        println!(
            "  worst {:.2} mm at ({:.0}, {:.0}, {:.0}), edges {:.1} {:.1} {:.1}",
            w.0, w.1[0], w.1[1], w.1[2], w.2[0], w.2[1], w.2[2]
        );
    }
    let all: usize = total.iter().sum();
    let nbad: usize = bad.iter().map(|b| b.len()).sum();
    println!(
        "faces outside filled holes {all}; centroid > {bound} mm: {nbad} ({:.2} %)",
        100.0 * nbad as f64 / all as f64
    );
    println!(
        "region | faces | over bound | % of region | p50 / max dev mm | curvature part p50 / max mm"
    );
    for k in 0..regions.len() {
        let n = bad[k].len();
        println!(
            "{} | {} | {} | {:.2} | {:.2} / {:.2} | {:.2} / {:.2}",
            regions[k],
            total[k],
            n,
            100.0 * n as f64 / total[k].max(1) as f64,
            pct(&mut bad[k], 0.5),
            pct(&mut bad[k], 1.0),
            pct(&mut curv_part[k], 0.5),
            pct(&mut curv_part[k], 1.0)
        );
    }
}
