//! Measurements behind docs/algorithms/flattenable.md: `cargo run --release -p
//! flatcut_flattenable --example measure -- table` (or probe with env N = grid size,
//! W = cap|saddle, PAPER/LS/TAN to add variants; probe_weights; probe_targets).

#![allow(clippy::unwrap_used)]

#[path = "../tests/common/mod.rs"]
mod common;
use flatcut_flattenable::*;

fn show(name: &str, mesh: &flatcut_mesh::TriMesh, opts: &ProcessOptions) {
    let t = std::time::Instant::now();
    let r = process(mesh, opts);
    let (rep, ok) = match &r {
        Ok(p) => (p.report.clone(), "ok".to_string()),
        Err(FlattenableError::NotConverged { partial, .. }) => {
            (partial.report.clone(), "NOTCONV".into())
        }
        Err(e) => {
            println!("{name}: ERR {e}");
            return;
        }
    };
    let p = &rep.pieces[0];
    println!(
        "{name}: {ok} it={} err={:.2e} rms={:.2e} minang={:.1} area={:.2}% rmsd={:.4} maxd={:.4} rej={} folded={} t={:.2}s stop={} msgs={:?}",
        rep.iterations,
        rep.final_theta_err,
        rep.final_theta_rms,
        p.min_angle_deg,
        rep.area_change_percent,
        rep.rms_displacement_mm,
        rep.max_displacement_mm,
        p.rejected_steps,
        rep.folded_faces,
        t.elapsed().as_secs_f64(),
        p.stop_reason,
        p.messages
    );
}

fn probe() {
    let n: usize = std::env::var("N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(12);
    let which = std::env::var("W").unwrap_or("all".into());
    let meshes = [
        ("cap", common::sphere_cap(n)),
        ("saddle", common::saddle(n)),
    ];
    for (name, m) in &meshes {
        if which != "all" && which != *name {
            continue;
        }
        if std::env::var("PAPER").is_ok() {
            show(
                &format!("{name} paper direct"),
                m,
                &ProcessOptions::paper(Update::Direct),
            );
            show(
                &format!("{name} paper ls cotan"),
                m,
                &ProcessOptions::paper(Update::LeastSquare),
            );
            show(
                &format!("{name} paper ls uniform"),
                m,
                &ProcessOptions {
                    laplacian: Laplacian::Uniform,
                    ..ProcessOptions::paper(Update::LeastSquare)
                },
            );
        }
        show(
            &format!("{name} robust direct"),
            m,
            &ProcessOptions::default(),
        );
        if std::env::var("LS").is_ok() {
            show(
                &format!("{name} robust ls zero"),
                m,
                &ProcessOptions {
                    update: Update::LeastSquare,
                    target: Target::Zero,
                    ..Default::default()
                },
            );
            show(
                &format!("{name} robust ls detail"),
                m,
                &ProcessOptions {
                    update: Update::LeastSquare,
                    target: Target::Detail,
                    ..Default::default()
                },
            );
        }
        if let Ok(t) = std::env::var("TAN") {
            show(
                &format!("{name} robust tan {t}"),
                m,
                &ProcessOptions {
                    tangential_penalty: t.parse().unwrap(),
                    ..Default::default()
                },
            );
        }
    }
}

fn probe_weights() {
    let mesh = common::sphere_cap(12);
    let row: Vec<u32> = (1..11).map(|i| 6 * 12 + i).collect();
    for tan in [1.0, 10.0] {
        for (fw, upd) in [
            (1.0, Update::Direct),
            (10.0, Update::Direct),
            (1.0, Update::LeastSquare),
            (10.0, Update::LeastSquare),
        ] {
            let opts = ProcessOptions {
                feature_curves: vec![row.clone()],
                feature_weight: fw,
                tangential_penalty: tan,
                update: upd,
                ..Default::default()
            };
            let r = match process(&mesh, &opts) {
                Ok(r) => r,
                Err(FlattenableError::NotConverged { partial, .. }) => {
                    println!("notconv");
                    *partial
                }
                Err(e) => panic!("{e}"),
            };
            let m: f64 = row
                .iter()
                .map(|&v| {
                    flatcut_mesh::vec3::dist(
                        mesh.positions[v as usize],
                        r.mesh.positions[v as usize],
                    )
                })
                .sum();
            println!(
                "tan {tan} fw {fw} {upd:?}: row moved {m:.4} it {}",
                r.report.iterations
            );
        }
    }
}

fn probe_targets() {
    let cases: Vec<(String, flatcut_mesh::TriMesh)> = vec![
        ("cap12".into(), common::sphere_cap(12)),
        ("cap25".into(), common::sphere_cap(25)),
        ("cap50".into(), common::sphere_cap(50)),
        ("saddle12".into(), common::saddle(12)),
        ("saddle25".into(), common::saddle(25)),
    ];
    for (name, m) in &cases {
        for (mode, base) in [
            (
                "robust",
                ProcessOptions {
                    update: Update::LeastSquare,
                    ..Default::default()
                },
            ),
            ("paper", ProcessOptions::paper(Update::LeastSquare)),
        ] {
            if mode == "paper" && m.vertex_count() > 700 {
                continue;
            }
            for target in [Target::Zero, Target::Detail] {
                let opts = ProcessOptions {
                    target,
                    ..base.clone()
                };
                let (r, ok) = match process(m, &opts) {
                    Ok(r) => (r, "conv"),
                    Err(FlattenableError::NotConverged { partial, .. }) => (*partial, "NOTCONV"),
                    Err(e) => {
                        println!("{name} {mode} {target:?}: {e}");
                        continue;
                    }
                };
                let p = &r.report.pieces[0];
                println!(
                    "| {name} | {mode} | {target:?} | {ok} | {} | {:.1e} | {:.3} | {:.4} | {:.4} | {:.1} | {} |",
                    r.report.iterations,
                    r.report.final_theta_err,
                    r.report.area_change_percent,
                    r.report.rms_displacement_mm,
                    r.report.max_displacement_mm,
                    p.min_angle_deg,
                    r.report.folded_faces
                );
            }
        }
    }
}

/// The convergence table of docs/algorithms/flattenable.md.
fn table() {
    let row = |name: &str, mode: &str, m: &flatcut_mesh::TriMesh, opts: &ProcessOptions| {
        let t = std::time::Instant::now();
        let (r, ok) = match process(m, opts) {
            Ok(r) => (r, "yes"),
            Err(FlattenableError::NotConverged { partial, .. }) => (*partial, "no"),
            Err(e) => {
                println!("| {name} | {mode} | error: {e} |");
                return;
            }
        };
        let p = &r.report.pieces[0];
        println!(
            "| {name} | {mode} | {ok} | {} | {:.1e} | {:.1e} | {:.1} | {:+.2} | {:.4} | {:.4} | {} | {:.2} |",
            r.report.iterations,
            r.report.final_theta_err,
            r.report.final_theta_rms,
            p.min_angle_deg,
            r.report.area_change_percent,
            r.report.rms_displacement_mm,
            r.report.max_displacement_mm,
            r.report.folded_faces,
            t.elapsed().as_secs_f64()
        );
    };
    let iso = ProcessOptions {
        tangential_penalty: 1.0,
        ..Default::default()
    };
    for n in [12usize, 25, 50, 100] {
        for (kind, m) in [
            ("cap", common::sphere_cap(n)),
            ("saddle", common::saddle(n)),
        ] {
            let name = format!("{kind} {n}×{n}");
            if n == 12 {
                row(
                    &name,
                    "paper direct",
                    &m,
                    &ProcessOptions::paper(Update::Direct),
                );
                row(
                    &name,
                    "paper LS cotan",
                    &m,
                    &ProcessOptions::paper(Update::LeastSquare),
                );
                let uni = ProcessOptions {
                    laplacian: Laplacian::Uniform,
                    ..ProcessOptions::paper(Update::LeastSquare)
                };
                row(&name, "paper LS uniform", &m, &uni);
            }
            row(&name, "robust (default)", &m, &ProcessOptions::default());
            if n <= 50 {
                row(&name, "robust, isotropic metric", &m, &iso);
            }
        }
    }
}

/// `cargo run --release -p flatcut_flattenable --example measure -- [table|probe|probe_weights|probe_targets]`
/// prints the measurement tables of docs/algorithms/flattenable.md (a tool, not a test: it asserts
/// nothing; the tests assert the numbers that must hold).
fn main() {
    match std::env::args().nth(1).as_deref().unwrap_or("table") {
        "probe" => probe(),
        "probe_weights" => probe_weights(),
        "probe_targets" => probe_targets(),
        "table" => table(),
        other => {
            eprintln!("unknown table '{other}': use table, probe, probe_weights or probe_targets");
            std::process::exit(2);
        }
    }
}
