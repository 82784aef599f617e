//! Measurements behind docs/algorithms/flattenable.md: `cargo run --release -p
//! flatcut_flattenable --example measure -- table` (or probe with env N = grid size,
//! W = cap|saddle, TARGET=zero, PAPER/LS/TAN to add variants; probe_weights; probe_targets
//! [ONLY=cap12,…]; real and bodies [BODY=mh_body_subdiv2] with FLATCUT_DATA; DIAG=1 shows
//! where the residual sits; speed [SIZES=…, REPS, TRACE=1, STEP_RATIO=1,
//! BEST_OF=20 (kernel timings), ONLY_TARGET=zero|detail|none, SOLVE_HASH=1 (the bits of one solve)]; saddles [SEEDS=…, DIAG=1], the
//! round-off robustness check; SHAPE=bcap for the bench cap, SHAPE=para [A=0.1, JITTER=0.3] for a shallow paraboloid; random [COUNT, NMIN, NMAX, SEED,
//! TARGET, ROUGH]: a corpus of random pieces); holes [K, R, H, NMAX, BODY, UNITS, MSG=1] with
//! FLATCUT_DATA: body patches with a hole, fixed against free rims).

#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

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
    if std::env::var("TRACE").is_ok() {
        let t: Vec<String> = p.theta_err.iter().map(|e| format!("{e:.1e}")).collect();
        println!("trace: {}", t.join(" "));
    }
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

/// `process`, with the best partial result when it does not converge: the result and "yes"
/// or "no"; other errors as they are.
fn process_or_partial(
    mesh: &flatcut_mesh::TriMesh,
    opts: &ProcessOptions,
) -> Result<(Processed, &'static str), FlattenableError> {
    match process(mesh, opts) {
        Ok(r) => Ok((r, "yes")),
        Err(FlattenableError::NotConverged { partial, .. }) => Ok((*partial, "no")),
        Err(e) => Err(e),
    }
}

/// The table cells every real-mesh table shares: total defect, converged, iterations, θ_err
/// of the input and at the end, smallest corner, area change.
fn outcome_cells(p: &PieceReport, ok: &str) -> String {
    format!(
        "{:+.3} | {ok} | {} | {:.2e} | {:.2e} | {:.1} | {:+.2}",
        p.input_total_defect_rad,
        p.iterations,
        p.theta_err[0],
        p.final_theta_err,
        p.min_angle_deg,
        p.area_change_percent
    )
}

/// The environment variable `name` parsed, or `default` when unset or unparsable.
fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// The comma-separated list in `name`, or `default` when unset.
fn env_list<T: std::str::FromStr>(name: &str, default: Vec<T>) -> Vec<T> {
    std::env::var(name)
        .map(|s| s.split(',').filter_map(|x| x.parse().ok()).collect())
        .unwrap_or(default)
}

/// Coarse-to-fine options from the environment: C2F=off|pos|disp (default: the library's),
/// C2F_MIN (min_faces), C2F_MAX (max_faces; unlimited when C2F=pos|disp), C2F_LEVELS,
/// C2F_RATIO, C2F_CTOL (coarse_tolerance_rad), C2F_RESCUE=0 (no rescue hierarchies),
/// PROLONG=positions (the prolongation alone, `max_faces` kept).
fn c2f_from_env() -> CoarseToFine {
    let mut c = CoarseToFine::default();
    match std::env::var("C2F").as_deref() {
        Ok("off") => c.levels = 0,
        Ok("pos") => {
            c.prolongation = Prolongation::Positions;
            c.max_faces = usize::MAX;
        }
        Ok("disp") => {
            c.prolongation = Prolongation::Displacement;
            c.max_faces = usize::MAX;
        }
        _ => {}
    }
    if let Some(v) = std::env::var("C2F_MIN").ok().and_then(|s| s.parse().ok()) {
        c.min_faces = v;
    }
    if let Some(v) = std::env::var("C2F_MAX").ok().and_then(|s| s.parse().ok()) {
        c.max_faces = v;
    }
    if let Some(v) = std::env::var("C2F_LEVELS")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        c.levels = v;
    }
    if let Some(v) = std::env::var("C2F_CTOL").ok().and_then(|s| s.parse().ok()) {
        c.coarse_tolerance_rad = v;
    }
    if let Some(v) = std::env::var("C2F_RATIO").ok().and_then(|s| s.parse().ok()) {
        c.ratio = v;
    }
    if std::env::var("PROLONG").as_deref() == Ok("positions") {
        c.prolongation = Prolongation::Positions;
    }
    if std::env::var("C2F_RESCUE").as_deref() == Ok("0") {
        c.rescue = false;
    }
    c
}

fn probe() {
    let n: usize = env_or("N", 12);
    let which = std::env::var("W").unwrap_or("all".into());
    let meshes = [
        ("cap", common::sphere_cap(n)),
        ("saddle", common::saddle(n)),
        // The bench's cap (alternating diagonals).
        ("bcap", common::bench_cap(n)),
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
        let target = match std::env::var("TARGET").as_deref() {
            Ok("zero") => Target::Zero,
            _ => Target::Detail,
        };
        show(
            &format!("{name} robust direct {target:?}"),
            m,
            &ProcessOptions {
                target,
                coarse_to_fine: c2f_from_env(),
                ..Default::default()
            },
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
        ("cap100".into(), common::sphere_cap(100)),
        ("saddle50".into(), common::saddle(50)),
        ("saddle100".into(), common::saddle(100)),
    ];
    let only = std::env::var("ONLY").ok();
    for (name, m) in &cases {
        if only
            .as_ref()
            .is_some_and(|o| !o.split(',').any(|x| x == name))
        {
            continue;
        }
        for (mode, base) in [
            (
                "robust LS",
                ProcessOptions {
                    update: Update::LeastSquare,
                    ..Default::default()
                },
            ),
            ("robust direct", ProcessOptions::default()),
            ("paper LS", ProcessOptions::paper(Update::LeastSquare)),
        ] {
            if mode.starts_with("paper") && m.vertex_count() > 700 {
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
        let (r, ok) = match process_or_partial(m, opts) {
            Ok(r) => r,
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
            let zero = ProcessOptions {
                target: Target::Zero,
                ..Default::default()
            };
            row(&name, "robust, zero target", &m, &zero);
            if n <= 50 {
                row(&name, "robust, isotropic metric", &m, &iso);
            }
        }
    }
}

/// The real-disk table: FLATCUT_DATA meshes, default options (env TARGET=zero for the zero
/// target, ONLY=a,b to restrict).
fn real() {
    let dir = std::env::var("FLATCUT_DATA").expect("set FLATCUT_DATA");
    let target = match std::env::var("TARGET").as_deref() {
        Ok("zero") => Target::Zero,
        _ => Target::Detail,
    };
    let only = std::env::var("ONLY").ok();
    for name in [
        "igl_snail",
        "smpl_hand_lowres",
        "igl_camel_b",
        "igl_inspired_mesh",
        "igl_lilium",
        "bust_demosthenes",
        "igl_lion",
        "igl_camelhead",
        "mountain_disk",
        "igl_face",
    ] {
        if only
            .as_ref()
            .is_some_and(|o| !o.split(',').any(|x| x == name))
        {
            continue;
        }
        let path = std::path::Path::new(&dir).join(format!("{name}.obj"));
        let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
            .unwrap()
            .mesh;
        let opts = ProcessOptions {
            target,
            coarse_to_fine: c2f_from_env(),
            ..Default::default()
        };
        let t = std::time::Instant::now();
        let (r, ok) = match process_or_partial(&mesh, &opts) {
            Ok(r) => r,
            Err(e) => {
                println!("| {name} | error: {e} |");
                continue;
            }
        };
        let p = &r.report.pieces[0];
        println!(
            "| {name} | {} | {} | {} | {:.4} | {} | {:.1} | {} |",
            p.faces,
            p.interior_vertices,
            outcome_cells(p, ok),
            p.max_displacement_mm,
            p.folded_faces,
            t.elapsed().as_secs_f64(),
            p.stop_reason
        );
        if std::env::var("C2F").is_ok() {
            println!("    {:?}", p.messages);
        }
        if let (false, Some(v), Some(at)) =
            (p.converged, p.worst_vertex, p.worst_vertex_position_mm)
        {
            // Where it resists, against the piece's size (the bounding box's diagonal).
            let diagonal = mesh.diagonal();
            println!(
                "    least flat at vertex {v} ({:.2}, {:.2}, {:.2}); half of ‖θ − 2π‖² on {} of {} interior vertices ({:.1} %), within {:.2} mm = {:.0} % of the diagonal",
                at[0],
                at[1],
                at[2],
                p.vertices_holding_half_residual,
                p.interior_vertices,
                100.0 * p.vertices_holding_half_residual as f64 / p.interior_vertices.max(1) as f64,
                p.half_residual_radius_mm,
                100.0 * p.half_residual_radius_mm / diagonal
            );
        }
        if std::env::var("DIAG").is_ok() {
            diag(&mesh, &r.mesh);
        }
    }
}

/// Where the residual of a result sits (`DIAG=1` with `real` or `bodies`): how many interior
/// vertices are above 1e-4, and the worst twelve with their input residual, valence, ring
/// distance to each boundary loop and smallest corner in their star.
fn diag(input: &flatcut_mesh::TriMesh, out: &flatcut_mesh::TriMesh) {
    use flatcut_mesh::geometry::{angle_sums, corner_angles};
    let topo = flatcut_mesh::Topology::build(out).unwrap();
    let sums = angle_sums(&out.positions, &out.faces);
    let sums0 = angle_sums(&input.positions, &input.faces);
    let n = out.vertex_count();
    // ring distance from each loop
    let loops = topo.boundary_loops();
    let mut dist = vec![vec![usize::MAX; n]; loops.len()];
    for (l, lp) in loops.iter().enumerate() {
        let mut q = std::collections::VecDeque::new();
        for &v in lp {
            dist[l][v.0 as usize] = 0;
            q.push_back(v.0);
        }
        while let Some(v) = q.pop_front() {
            for &h in topo.outgoing(flatcut_mesh::VertexId(v)) {
                let w = topo.to_vertex(h).0 as usize;
                if dist[l][w] == usize::MAX {
                    dist[l][w] = dist[l][v as usize] + 1;
                    q.push_back(w as u32);
                }
            }
        }
    }
    let ca = corner_angles(&out.positions, &out.faces);
    let mut minang = vec![f64::INFINITY; n];
    for (f, c) in out.faces.iter().zip(&ca) {
        for k in 0..3 {
            for j in 0..3 {
                let v = c[j];
                let m = &mut minang[f[k] as usize];
                *m = m.min(v);
            }
        }
    }
    let mut idx: Vec<usize> = (0..n)
        .filter(|&v| topo.is_interior_vertex(flatcut_mesh::VertexId(v as u32)))
        .collect();
    idx.sort_by(|&a, &b| {
        (sums[b] - std::f64::consts::TAU)
            .abs()
            .total_cmp(&(sums[a] - std::f64::consts::TAU).abs())
    });
    let over = idx
        .iter()
        .filter(|&&v| (sums[v] - std::f64::consts::TAU).abs() > 1e-4)
        .count();
    println!(
        "    loops {:?}; {} interior > 1e-4",
        loops.iter().map(|l| l.len()).collect::<Vec<_>>(),
        over
    );
    for &v in idx.iter().take(12) {
        let d: Vec<usize> = dist.iter().map(|d| d[v]).collect();
        println!(
            "    v{v}: θ−2π {:+.2e} (input {:+.2e}) valence {} ring dist {:?} min star angle {:.2}°",
            sums[v] - std::f64::consts::TAU,
            sums0[v] - std::f64::consts::TAU,
            topo.outgoing(flatcut_mesh::VertexId(v as u32)).len(),
            d,
            minang[v].to_degrees()
        );
    }
}

/// `DAMPING=graph-laplacian`: the damping shaped like the graph Laplacian (the default
/// otherwise).
fn damping_from_env() -> flatcut_flattenable::Damping {
    match std::env::var("DAMPING").as_deref() {
        Ok("graph-laplacian") => flatcut_flattenable::Damping::GraphLaplacian,
        _ => flatcut_flattenable::Damping::Identity,
    }
}

/// Pieces cut from the MakeHuman body (decimetres, y up, +z front; MANIFEST landmarks):
/// upper back, chest, left shoulder cap, left front thigh; on mh_body and on its 2×
/// subdivision (BODY=mh_body_subdiv2); DAMPING as `damping_from_env`.
fn bodies() {
    let dir = std::env::var("FLATCUT_DATA").expect("set FLATCUT_DATA");
    let body = std::env::var("BODY").unwrap_or("mh_body".into());
    let target = match std::env::var("TARGET").as_deref() {
        Ok("zero") => Target::Zero,
        _ => Target::Detail,
    };
    // BODY may also be a path (e.g. a remeshed scan); SCALE maps its units to the boxes'
    // decimetres (100 for mh_body_scanlike, which is in millimetres).
    let path = if body.contains('/') {
        std::path::PathBuf::from(&body)
    } else {
        std::path::Path::new(&dir).join(format!("{body}.obj"))
    };
    let scale: f64 = std::env::var("SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let mut mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
        .unwrap()
        .mesh;
    for p in &mut mesh.positions {
        for c in p.iter_mut() {
            *c /= scale;
        }
    }
    // LOOP=k: each piece Loop-subdivided k times (4^k × the faces): pieces at scan
    // resolution, smooth, from the same cuts.
    let loops_of_subdivision: usize = env_or("LOOP", 0);
    let only = std::env::var("ONLY").ok();
    for (name, mut piece) in common::body_pieces(&mesh) {
        if only
            .as_ref()
            .is_some_and(|o| !o.split(',').any(|x| x == name))
        {
            continue;
        }
        for _ in 0..loops_of_subdivision {
            piece = common::loop_subdivide(&piece);
        }
        let topo = flatcut_mesh::Topology::build(&piece).unwrap();
        let loops = topo.boundary_loops().len();
        let opts = ProcessOptions {
            target,
            coarse_to_fine: c2f_from_env(),
            damping: damping_from_env(),
            ..Default::default()
        };
        let t = std::time::Instant::now();
        let (r, ok) = match process_or_partial(&piece, &opts) {
            Ok(r) => r,
            Err(e) => {
                println!("| {body} {name} | error: {e} |");
                continue;
            }
        };
        let p = &r.report.pieces[0];
        println!(
            "| {body} {name} | {} | {} | {loops} | {} | {:.4} | {:.4} | {} | {:.1} |",
            p.faces,
            p.interior_vertices,
            outcome_cells(p, ok),
            p.rms_displacement_mm,
            p.max_displacement_mm,
            p.folded_faces,
            t.elapsed().as_secs_f64(),
        );
        if std::env::var("C2F").is_ok() {
            println!("    {:?}", p.messages);
        }
        if std::env::var("TRACE").is_ok() {
            let t: Vec<String> = p.theta_err.iter().map(|e| format!("{e:.1e}")).collect();
            println!("    θ_err: {}", t.join(" "));
        }
        if std::env::var("DIAG").is_ok() {
            diag(&piece, &r.mesh);
        }
    }
}

/// `patches`: geodesic balls cut from the bodies of FLATCUT_DATA (env BODIES, comma-separated
/// names; K centres each by farthest-point sampling; RADIUS as a fraction of the body's
/// height, default 0.1, i.e. a disk ~1/5 of the body tall; LOOP=k Loop-subdivides each patch k
/// times, to scan resolution), each processed with the default options: one table row per
/// patch.
fn patches() {
    let dir = std::env::var("FLATCUT_DATA").expect("set FLATCUT_DATA");
    let bodies: Vec<String> = env_list(
        "BODIES",
        vec![
            "smpl_man".to_string(),
            "smpl_woman".into(),
            "smpl_female_TApose".into(),
            "mh_female_generic".into(),
            "mh_male_generic".into(),
            "mh_body".into(),
        ],
    );
    let k: usize = env_or("K", 10);
    let fraction: f64 = env_or("RADIUS", 0.1);
    let loops_of_subdivision: usize = env_or("LOOP", 0);
    for body in bodies {
        let path = std::path::Path::new(&dir).join(format!("{body}.obj"));
        let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
            .unwrap()
            .mesh;
        let height = common::largest_side(&mesh);
        for centre in common::spread_vertices(&mesh, k) {
            let mut piece = common::geodesic_ball(&mesh, centre, fraction * height);
            for _ in 0..loops_of_subdivision {
                piece = common::loop_subdivide(&piece);
            }
            let t = std::time::Instant::now();
            let (r, ok) = match process_or_partial(&piece, &ProcessOptions::default()) {
                Ok(r) => r,
                Err(e) => {
                    println!("| {body} v{centre} | {} | error: {e} |", piece.face_count());
                    continue;
                }
            };
            let p = &r.report.pieces[0];
            let loops = flatcut_mesh::Topology::build(&piece)
                .map(|t| t.boundary_loops().len())
                .unwrap_or(0);
            // The crease's kind (docs/algorithms/flattenable.md, "Creases"): what the
            // neutral band `CREASE_DEFECT_NEUTRAL_RAD` is judged on.
            let kind = flatcut_flattenable::CreaseKind::of(p.creased_defect_rad)
                .filter(|_| p.creased_edges > 0)
                .map_or("-".to_string(), |k| format!("{k:?}"));
            println!(
                "| {body} v{centre} | {} | {loops} | {} | {:.4} | {:.0} | {} | {:+.3} {kind} | {} | {:.1} |",
                p.faces,
                outcome_cells(p, ok),
                p.rms_displacement_mm / (fraction * height),
                p.max_crease_deg,
                p.creased_edges,
                p.creased_defect_rad,
                p.folded_faces,
                t.elapsed().as_secs_f64(),
            );
            if std::env::var("MSG").is_ok() {
                println!("    {} {:?}", p.stop_reason, p.messages);
            }
        }
    }
}

/// Speed on the bench caps (the criterion bench's pieces): per size and target, iterations,
/// rejected trials, factorisations, pull-backs, best of `REPS` (default 3) wall times, and
/// that time over one numeric Cholesky of A Aᵀ at the input. SIZES=12,24,… to restrict.
/// CPU time of this process so far (ns; Linux, summed over threads from
/// /proc/self/task/*/schedstat; 0 elsewhere): on the shared machine wall time mostly
/// measures the other agents' load.
fn cpu_ns() -> u64 {
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return 0;
    };
    dir.filter_map(|e| e.ok())
        .filter_map(|e| std::fs::read_to_string(e.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum()
}

/// `speed`: per grid size (env `SIZES`, comma-separated n of n×n caps; `REPS` runs each) the
/// kernel timings and both targets' runs with their messages; `TRACE=1` adds θ_err per
/// iteration, `C2F_LEVELS=0` solves without coarse-to-fine, `C2F_MAX` raises its largest
/// piece (all knobs of `c2f_from_env`), `ONLY_TARGET=zero|detail` runs one target
/// (`none`: the kernels' times only).
fn speed() {
    let reps: usize = env_or("REPS", 3);
    let sizes: Vec<usize> = env_list("SIZES", vec![12, 24, 33, 43, 72]);
    // Totals per target over the sizes (factorisations, best CPU, unconverged runs): what the
    // sweeps in docs/algorithms/flattenable.md compare.
    let mut totals = [
        (Target::Detail, 0usize, 0.0f64, 0usize),
        (Target::Zero, 0, 0.0, 0),
    ];
    for n in sizes {
        let mesh = common::bench_cap(n);
        let at_input = common::AtInput::new(&mesh);
        let common::AtInput {
            layout,
            theta,
            grad,
            mean_diagonal: m,
            ..
        } = &at_input;
        let m = *m;
        // A copy to assemble into (the step cost below factors the input's).
        let mut normal = at_input.normal.clone();
        let metric = at_input.metric();
        // Best of 20, or BEST_OF (the machine is shared: the minimum is the least disturbed).
        let best_of_count: usize = env_or("BEST_OF", 20);
        let best_of = |f: &mut dyn FnMut()| {
            (0..best_of_count)
                .map(|_| {
                    let t = std::time::Instant::now();
                    f();
                    t.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min)
        };
        // Into buffers made once, as a run refactors (`Layout::factor` would also allocate
        // and page in L's values every time: ~15 % of a 3.5k factorisation).
        let mut fac = layout.new_factor().unwrap();
        let faer_chol = best_of(&mut || {
            layout
                .refactor_with_faer(&mut fac, &normal, 1e-3 * m, None)
                .unwrap();
        });
        let chol = best_of(&mut || {
            layout.refactor(&mut fac, &normal, 1e-3 * m, None).unwrap();
        });
        if std::env::var_os("SOLVE_HASH").is_some() {
            // The bits of one solve with this factor: equal hashes, equal factor and solve.
            let mut x = theta.clone();
            layout.solve(&fac, &mut x, 1);
            let hash = x
                .iter()
                .fold(0u64, |h, v| (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3));
            println!("{} faces: solve hash {hash:016x}", mesh.faces.len());
        }
        let mut x = theta.clone();
        let solve = best_of(&mut || layout.solve(&fac, &mut x, 1));
        let assemble = best_of(&mut || layout.normal_matrix(grad, &metric, &mut normal));
        // The run's metric: unit weights, the default tangential penalty, the input's
        // area-weighted vertex normals.
        let normals = at_input.interior_normals(&mesh);
        let tangential_metric = at_input.tangential_metric(&normals);
        let assemble_tangential =
            best_of(&mut || layout.normal_matrix(grad, &tangential_metric, &mut normal));
        let (mut th, mut gr) = (theta.clone(), grad.clone());
        let eval = best_of(&mut || layout.evaluate(&mesh.positions, &mut th, &mut gr));
        let theta_alone = best_of(&mut || layout.theta(&mesh.positions, &mut th));
        let grad_alone = best_of(&mut || layout.gradient(&mesh.positions, &mut gr));
        println!(
            "{} faces: Cholesky {:.2} µs (faer's {:.2} µs), solve {:.2} µs, assemble A G Aᵀ {:.2} µs (tangential metric {:.2} µs), θ+A {:.2} µs (θ {:.2} µs, A {:.2} µs)",
            mesh.faces.len(),
            chol * 1e6,
            faer_chol * 1e6,
            solve * 1e6,
            assemble * 1e6,
            assemble_tangential * 1e6,
            eval * 1e6,
            theta_alone * 1e6,
            grad_alone * 1e6
        );
        for target in [Target::Detail, Target::Zero] {
            // Experiment knobs: those of `c2f_from_env` (C2F_LEVELS=0 = direct solve, C2F_MAX,
            // C2F_CTOL, C2F_RESCUE=0, PROLONG=positions, …).
            // MAXIT=0: the piece's set-up alone (topology, layout, AMD, symbolic
            // factorisation, θ at the input, the report's measures), to split a run's time
            // into set-up and steps.
            let opts = ProcessOptions {
                target,
                coarse_to_fine: c2f_from_env(),
                max_iterations: std::env::var("MAXIT").ok().and_then(|s| s.parse().ok()),
                ..Default::default()
            };
            match std::env::var("ONLY_TARGET").as_deref() {
                Ok("zero") if target == Target::Detail => continue,
                Ok("detail") if target == Target::Zero => continue,
                Ok("none") => continue,
                _ => {}
            }
            let mut best = f64::INFINITY;
            let mut best_cpu = f64::INFINITY;
            let mut rep = None;
            for _ in 0..reps {
                let t = std::time::Instant::now();
                let c0 = cpu_ns();
                let r = process(&mesh, &opts);
                best = best.min(t.elapsed().as_secs_f64());
                best_cpu = best_cpu.min((cpu_ns() - c0) as f64 * 1e-9);
                rep = Some(match r {
                    Ok(p) => (p.report, "conv"),
                    Err(FlattenableError::NotConverged { partial, .. }) => {
                        (partial.report, "NOTCONV")
                    }
                    Err(e) => panic!("{e}"),
                });
            }
            let (r, ok) = rep.unwrap();
            let p = &r.pieces[0];
            // STEP_RATIO=1 (with C2F_LEVELS=0): what a step costs against one Cholesky
            // (`AtInput::step_cost`: the four timed in turn, their minima).
            if std::env::var_os("STEP_RATIO").is_some() && p.factorizations > 0 {
                let cost = at_input.step_cost(&mesh, &opts, reps);
                // Against faer's numeric factorisation (the "one sparse Cholesky")
                // and against the run's own.
                let per_step = cost.per_factorization(p.factorizations);
                println!(
                    "    interleaved minima: Cholesky {:.1} µs (faer's {:.1} µs), set-up {:.1} µs, run {:.1} µs; per factorisation after the set-up {:.1} µs = {:.2}x faer's Cholesky ({:.2}x the run's own)",
                    cost.cholesky * 1e6,
                    cost.faer_cholesky * 1e6,
                    cost.set_up * 1e6,
                    cost.run * 1e6,
                    per_step * 1e6,
                    per_step / cost.faer_cholesky,
                    per_step / cost.cholesky
                );
            }
            for t in totals.iter_mut().filter(|t| t.0 == target) {
                t.1 += p.factorizations;
                t.2 += best_cpu;
                t.3 += usize::from(ok != "conv");
            }
            println!(
                "{} faces {:?}: {ok} it={} rej={} fact={} pb={} err={:.1e} area={:+.3}% rmsd={:.4} turn={:.1}° crease={:.1}° creased={} | wall {:.1} ms, CPU {:.1} ms = {:.1} Cholesky ({:.3} ms); per factorisation {:.2}x; stop: {}",
                p.faces,
                target,
                p.iterations,
                p.rejected_steps,
                p.factorizations,
                p.pull_backs,
                p.final_theta_err,
                p.area_change_percent,
                p.rms_displacement_mm,
                p.max_normal_turn_deg,
                p.max_crease_deg,
                p.creased_edges,
                best * 1e3,
                best_cpu * 1e3,
                best_cpu / chol,
                chol * 1e3,
                best_cpu / chol / p.factorizations.max(1) as f64,
                p.stop_reason,
            );
            for m in &p.messages {
                println!("    {m}");
            }
            if std::env::var_os("TRACE").is_some() {
                let t: Vec<String> = p.theta_err.iter().map(|e| format!("{e:.1e}")).collect();
                println!("    θ_err: {}", t.join(" "));
            }
        }
    }
    for (target, fact, cpu, unconverged) in totals {
        println!(
            "total {target:?}: {fact} factorisations, CPU {:.2} s, {unconverged} not converged",
            cpu
        );
    }
}

/// The 100×100 saddle with its coordinates multiplied by 1 + k·2.2e-16, k ∈ {−1, 0, 1} per
/// coordinate from a xorshift sequence (seed 0: the exact grid): the robustness check for
/// anything that changes round-off (docs/algorithms/flattenable.md, "Double roots"). Seeds
/// 0–6 (SEEDS=…), two at a time; N for another size, TARGET=zero. `SHAPE=bcap` perturbs the
/// bench's sphere cap instead: how much a run's cost depends on round-off alone
/// (docs/benchmarks.md).
fn saddles() {
    let n: usize = env_or("N", 100);
    let seeds: Vec<u64> = env_list("SEEDS", (0..7).collect());
    let mut opts = ProcessOptions {
        coarse_to_fine: c2f_from_env(),
        damping: damping_from_env(),
        ..Default::default()
    };
    if std::env::var("TARGET").as_deref() == Ok("zero") {
        opts.target = Target::Zero;
    }
    if std::env::var_os("LS").is_some() {
        opts.update = Update::LeastSquare;
    }
    let run = |seed: u64| -> String {
        // `SHAPE=bcap`: the bench's sphere cap instead of the saddle; `SHAPE=para`: the
        // shallow paraboloid z = A (x² + y²) on [−1, 1]² (A=0.1 unless given), which stalled
        // at 160×160 before smoothed steps (docs/algorithms/flattenable.md, "Shallow pieces: a
        // smoothed step").
        let mut mesh = match std::env::var("SHAPE").as_deref() {
            Ok("bcap") => common::bench_cap(n),
            Ok("para") => {
                let a: f64 = env_or("A", 0.1);
                // JITTER=j: interior vertices moved in x and y by up to ±j of the spacing
                // (37 fixed pseudo-random pairs, cycled) before the height is taken: an
                // irregular triangulation of the same surface.
                let j: f64 = env_or("JITTER", 0.0);
                if j > 0.0 {
                    common::jittered_paraboloid(n, a, j)
                } else {
                    common::grid(n, 1.0, |x, y| a * (x * x + y * y))
                }
            }
            _ => common::saddle(n),
        };
        common::perturb_by_one_ulp(&mut mesh, seed);
        let t = std::time::Instant::now();
        let (rep, out) = match process(&mesh, &opts) {
            Ok(p) => (p.report, p.mesh),
            Err(FlattenableError::NotConverged { partial, .. }) => (partial.report, partial.mesh),
            Err(e) => return format!("seed {seed}: ERR {e}"),
        };
        if std::env::var_os("DIAG").is_some() {
            // Grid cells (column, row) of a face's corners.
            let cells = |f: usize| -> String {
                let cell = |v: u32| format!("({},{})", v as usize % n, v as usize / n);
                out.faces[f].map(cell).join(" ")
            };
            let smallest = |a: [f64; 3]| a.iter().cloned().fold(f64::INFINITY, f64::min);
            let n0 = flatcut_mesh::geometry::face_normals(&mesh.positions, &mesh.faces);
            let n1 = flatcut_mesh::geometry::face_normals(&out.positions, &out.faces);
            let mut turn: Vec<(f64, usize)> = n0
                .iter()
                .zip(&n1)
                .enumerate()
                .map(|(f, (a, b))| (flatcut_mesh::vec3::dot(*a, *b), f))
                .collect();
            turn.sort_by(|a, b| a.0.total_cmp(&b.0));
            for &(c, f) in turn.iter().take(4) {
                let deg = c.clamp(-1.0, 1.0).acos().to_degrees();
                eprintln!(
                    "  seed {seed} face {f} normal turned {deg:.1}° at {}",
                    cells(f)
                );
            }
            let ang = flatcut_mesh::geometry::corner_angles(&out.positions, &out.faces);
            let ang0 = flatcut_mesh::geometry::corner_angles(&mesh.positions, &mesh.faces);
            let mut worst: Vec<(f64, usize)> = ang
                .iter()
                .enumerate()
                .map(|(f, a)| (smallest(*a), f))
                .collect();
            worst.sort_by(|a, b| a.0.total_cmp(&b.0));
            for &(a, f) in worst.iter().take(3) {
                eprintln!(
                    "  seed {seed} face {f} min corner {:.2}° (input {:.1}°) at {}",
                    a.to_degrees(),
                    smallest(ang0[f]).to_degrees(),
                    cells(f)
                );
            }
            // Where the residual sits: the interior vertices farthest from θ = 2π.
            let theta = flatcut_mesh::geometry::angle_sums(&out.positions, &out.faces);
            let topo = flatcut_mesh::Topology::build(&out).unwrap();
            let mut far: Vec<(f64, usize)> = theta
                .iter()
                .enumerate()
                .filter(|&(v, _)| topo.is_interior_vertex(flatcut_mesh::VertexId(v as u32)))
                .map(|(v, t)| (t - std::f64::consts::TAU, v))
                .collect();
            far.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
            let above = far.iter().filter(|(e, _)| e.abs() > 1e-9).count();
            let listed: Vec<String> = far
                .iter()
                .take(6)
                .map(|&(e, v)| format!("({},{}) {e:+.1e}", v % n, v / n))
                .collect();
            eprintln!(
                "  seed {seed} {above} interior vertices beyond 1e-9 rad; farthest: {}",
                listed.join(", ")
            );
        }
        let p = &rep.pieces[0];
        let trace = if std::env::var_os("TRACE").is_some() {
            let t: Vec<String> = p.theta_err.iter().map(|e| format!("{e:.1e}")).collect();
            format!(
                "\n    {}\n    θ_err: {}",
                p.messages.join("\n    "),
                t.join(" ")
            )
        } else {
            String::new()
        };
        format!(
            "seed {seed}: {} it={} rej={} fact={} err={:.1e} rmsd={:.4} area={:+.3}% turn={:.1}° crease={:.1}° creased={} t={:.2}s stop={}{trace}",
            if rep.converged { "conv" } else { "NOTCONV" },
            p.iterations,
            p.rejected_steps,
            p.factorizations,
            p.final_theta_err,
            p.rms_displacement_mm,
            p.area_change_percent,
            p.max_normal_turn_deg,
            p.max_crease_deg,
            p.creased_edges,
            t.elapsed().as_secs_f64(),
            p.stop_reason
        )
    };
    for pair in seeds.chunks(2) {
        let out: Vec<String> = std::thread::scope(|sc| {
            let hs: Vec<_> = pair.iter().map(|&s| sc.spawn(move || run(s))).collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for line in out {
            println!("{line}");
        }
    }
}

/// The state where the tail begins: the bench cap N×N (zero target) stopped after IT
/// iterations; per interior vertex θ − 2π, the row norm of A times the mean edge, and the
/// star's distance from its best plane over the mean edge.
fn tail() {
    use flatcut_flattenable::angle_gradient::angle_sum_gradient;
    let n: usize = env_or("N", 100);
    let it: usize = env_or("IT", 23);
    let mesh = common::bench_cap(n);
    let opts = ProcessOptions {
        target: Target::Zero,
        max_iterations: Some(it),
        ..Default::default()
    };
    let out = match process(&mesh, &opts) {
        Ok(p) => p.mesh,
        Err(FlattenableError::NotConverged { partial, .. }) => partial.mesh,
        Err(e) => panic!("{e}"),
    };
    let topo = flatcut_mesh::Topology::build(&out).unwrap();
    let mut rows = Vec::new();
    for v in 0..out.vertex_count() as u32 {
        let vid = flatcut_mesh::VertexId(v);
        if !topo.is_interior_vertex(vid) {
            continue;
        }
        let (theta, grads) = angle_sum_gradient(&out.positions, &out.faces, &topo, vid);
        let ring = topo.one_ring(vid).unwrap();
        let p = out.positions[v as usize];
        let h: f64 = ring
            .iter()
            .map(|&q| flatcut_mesh::vec3::dist(p, out.positions[q as usize]))
            .sum::<f64>()
            / ring.len() as f64;
        let norm: f64 = grads
            .iter()
            .map(|(_, g)| g.iter().map(|c| c * c).sum::<f64>())
            .sum::<f64>()
            .sqrt();
        // Flatness: distance of the centre from the plane through the ring's centroid with
        // the area-weighted star normal, over h.
        let mut nrm = [0.0; 3];
        for k in 0..ring.len() {
            let a = out.positions[ring[k] as usize];
            let b = out.positions[ring[(k + 1) % ring.len()] as usize];
            let c = flatcut_mesh::vec3::cross(
                flatcut_mesh::vec3::sub(a, p),
                flatcut_mesh::vec3::sub(b, p),
            );
            nrm = flatcut_mesh::vec3::add(nrm, c);
        }
        let nl = flatcut_mesh::vec3::norm(nrm);
        let mut dev = 0.0f64;
        for &q in ring {
            let d =
                flatcut_mesh::vec3::dot(flatcut_mesh::vec3::sub(out.positions[q as usize], p), nrm)
                    / nl;
            dev = dev.max(d.abs());
        }
        rows.push((theta - std::f64::consts::TAU, norm * h, dev / h, v));
    }
    let total: f64 = rows.iter().map(|r| r.0 * r.0).sum();
    rows.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
    let mut norms: Vec<f64> = rows.iter().map(|r| r.1).collect();
    norms.sort_by(f64::total_cmp);
    println!(
        "f = {total:.3e}; row·h median {:.2e}, p10 {:.2e}, p1 {:.2e}",
        norms[norms.len() / 2],
        norms[norms.len() / 10],
        norms[norms.len() / 100]
    );
    let mut acc = 0.0;
    for (k, r) in rows.iter().enumerate() {
        acc += r.0 * r.0;
        if k < 15 || (k % 50 == 0 && acc < 0.99 * total) {
            println!(
                "  #{k} v{} ({},{}): θ−2π {:+.2e} row·h {:.2e} ring off-plane {:.2e} h; cum {:.3}",
                r.3,
                r.3 as usize % n,
                r.3 as usize / n,
                r.0,
                r.1,
                r.2,
                acc / total
            );
        }
    }
}

/// `cargo run --release -p flatcut_flattenable --example measure -- [table|probe|probe_weights|probe_targets|real|bodies|speed|saddles|tail]`
/// prints the measurement tables of docs/algorithms/flattenable.md (a tool, not a test: it asserts
/// nothing; the tests assert the numbers that must hold).
/// Time of one coarsening (to a quarter of the faces, as coarse-to-fine does) of the bench
/// caps in SIZES and of the saddle grid, best of REPS, with a fingerprint of the result
/// (faces and prolongation map, bit for bit) so that a faster coarsening can be checked to
/// give the same hierarchy.
fn coarsen_timing() {
    use std::hash::{Hash, Hasher};
    let reps: usize = env_or("REPS", 5);
    let sizes: Vec<usize> = env_list("SIZES", vec![33, 43, 72, 100, 160]);
    for n in sizes {
        for (name, mesh) in [("cap", common::bench_cap(n)), ("saddle", common::saddle(n))] {
            let target = mesh.face_count() / 4;
            let mut best = f64::INFINITY;
            let mut out = None;
            for _ in 0..reps {
                let t = std::time::Instant::now();
                let c = flatcut_flattenable::coarsen::coarsen(&mesh, target).unwrap();
                best = best.min(t.elapsed().as_secs_f64());
                out = Some(c);
            }
            let c = out.unwrap();
            let mut h = std::collections::hash_map::DefaultHasher::new();
            c.mesh.faces.hash(&mut h);
            c.fine_of_coarse.hash(&mut h);
            for l in &c.location {
                match *l {
                    flatcut_flattenable::coarsen::Location::Kept(k) => (0u8, k).hash(&mut h),
                    flatcut_flattenable::coarsen::Location::InFace { face, bary } => {
                        (1u8, face, bary.map(f64::to_bits)).hash(&mut h)
                    }
                }
            }
            println!(
                "{name} {} faces -> {}: {:.2} ms, fingerprint {:016x}",
                mesh.face_count(),
                c.mesh.face_count(),
                best * 1e3,
                h.finish()
            );
        }
    }
}

fn main() {
    match std::env::args().nth(1).as_deref().unwrap_or("table") {
        "probe" => probe(),
        "probe_weights" => probe_weights(),
        "probe_targets" => probe_targets(),
        "table" => table(),
        "real" => real(),
        "bodies" => bodies(),
        "patches" => patches(),
        "speed" => speed(),
        "saddles" => saddles(),
        "tail" => tail(),
        "coarsen" => coarsen_timing(),
        "random" => random(),
        "holes" => holes(),
        other => {
            eprintln!(
                "unknown table '{other}': use table, probe, probe_weights, probe_targets, real, bodies, patches, speed, saddles, tail, coarsen, random or holes"
            );
            std::process::exit(2);
        }
    }
}

/// `random`: a corpus of random pieces like `tests/properties.rs`'s (`common::random_piece`),
/// from a fixed xorshift sequence: `COUNT` pieces (default 60) of n×n vertices, n in
/// `NMIN..=NMAX` (default 33..=45: 2k–3.9k faces, through coarse-to-fine first), default
/// options, `TARGET=zero|detail` (default detail). Per piece one line (faces, converged,
/// iterations, factorisations, seconds, RMS displacement, area change, first message) and
/// the totals: how a change to the method does on pieces nobody chose. `ONLY=k`: piece k
/// alone, with its messages and θ_err per iteration. `ROUGH=a`: the same pieces with height
/// noise of up to a spacings per vertex, as `tests/properties.rs`'s rough pieces (scan noise:
/// median |2π − θ| above 0.1 rad from a ≈ 0.5), from a second sequence so that the corpus
/// is the same for every a.
fn random() {
    let count: usize = env_or("COUNT", 60);
    let (nmin, nmax): (usize, usize) = (env_or("NMIN", 33), env_or("NMAX", 45));
    let target = match std::env::var("TARGET").as_deref() {
        Ok("zero") => Target::Zero,
        _ => Target::Detail,
    };
    let opts = ProcessOptions {
        target,
        coarse_to_fine: c2f_from_env(),
        ..Default::default()
    };
    let rough: f64 = env_or("ROUGH", 0.0);
    let mut next = common::uniform(env_or("SEED", 0x2026_1127));
    // ONLY=k: piece k alone, with every message and its θ_err per iteration.
    let only: Option<usize> = std::env::var("ONLY").ok().and_then(|s| s.parse().ok());
    let (mut conv, mut its, mut facts, mut secs, mut rms) = (0usize, 0usize, 0usize, 0.0, 0.0);
    for k in 0..count {
        let n = nmin + ((next() * (nmax - nmin + 1) as f64) as usize).min(nmax - nmin);
        let jitter: Vec<(f64, f64)> = (0..1 + (next() * 39.0) as usize)
            .map(|_| (0.6 * next() - 0.3, 0.6 * next() - 0.3))
            .collect();
        let c: [f64; 7] = std::array::from_fn(|_| next() - 0.5);
        let mut mesh = common::random_piece(n, &jitter, c);
        let mut noise = common::uniform(0x5EED_0000 + k as u64);
        let h = 2.0 / (n - 1) as f64;
        for p in &mut mesh.positions {
            p[2] += rough * (2.0 * noise() - 1.0) * h;
        }
        if only.is_some_and(|only| only != k) {
            continue;
        }
        let t = std::time::Instant::now();
        let (r, ok) = match process(&mesh, &opts) {
            Ok(p) => (p.report, true),
            Err(FlattenableError::NotConverged { partial, .. }) => (partial.report, false),
            Err(e) => panic!("{e}"),
        };
        let dt = t.elapsed().as_secs_f64();
        let p = &r.pieces[0];
        conv += usize::from(ok);
        its += p.iterations;
        facts += p.factorizations;
        secs += dt;
        rms += p.rms_displacement_mm;
        println!(
            "{k:3} {} faces {} it={} fact={} {:.1} ms rmsd={:.5} area={:+.3}% | {}",
            p.faces,
            if ok { "conv" } else { "NOTCONV" },
            p.iterations,
            p.factorizations,
            dt * 1e3,
            p.rms_displacement_mm,
            p.area_change_percent,
            p.messages.first().map_or("", String::as_str)
        );
        if only.is_some() {
            println!(
                "    input θ_err {:.2e}, total defect {:.3} rad; stop: {}",
                p.theta_err[0], p.input_total_defect_rad, p.stop_reason
            );
            for m in &p.messages {
                println!("    {m}");
            }
            let t: Vec<String> = p.theta_err.iter().map(|e| format!("{e:.1e}")).collect();
            println!("    θ_err: {}", t.join(" "));
        }
    }
    println!(
        "total {target:?}: {conv}/{count} converged, {its} iterations, {facts} factorisations, {secs:.2} s, mean RMS displacement {:.5}",
        rms / count as f64
    );
}

/// `holes` (FLATCUT_DATA): body patches with a hole, processed with the rims fixed and with
/// `HoleRims::Free` (docs/algorithms/flattenable.md, "Holes"). Each patch is the geodesic
/// ball of radius `R` mm (default 150) around one of `K` spread vertices (default 60) of
/// `BODY` (default mh_male_generic, read in `UNITS` dm), without the faces whose centroids
/// lie within `H` mm (default 25) of that vertex (its largest part); kept when it has two boundary loops and at
/// most `NMAX` faces (default 1 500). One line per patch, then the counts: how many
/// converge with fixed rims, and with free rims by which fill (or back on the fixed run).
fn holes() {
    let dir = std::env::var("FLATCUT_DATA").expect("set FLATCUT_DATA");
    let body = std::env::var("BODY").unwrap_or("mh_male_generic".into());
    let units: flatcut_io::Units = std::env::var("UNITS")
        .ok()
        .and_then(|u| u.parse().ok())
        .unwrap_or(flatcut_io::Units::Dm);
    let k: usize = env_or("K", 60);
    let radius_mm: f64 = env_or("R", 150.0);
    let hole_mm: f64 = env_or("H", 25.0);
    let max_faces: usize = env_or("NMAX", 1500);
    let path = std::path::Path::new(&dir).join(format!("{body}.obj"));
    let mesh = flatcut_io::read_mesh(&path, units).unwrap().mesh;
    let (mut patches, mut fixed_ok, mut by_ears, mut by_fans, mut fell_back, mut lost) =
        (0, 0, 0, 0, 0, 0);
    for centre in common::spread_vertices(&mesh, k) {
        let Some(ring) = common::ball_with_hole(&mesh, centre, (radius_mm, hole_mm), max_faces)
        else {
            continue;
        };
        let run = |rims: HoleRims| {
            let opts = ProcessOptions {
                hole_rims: rims,
                ..Default::default()
            };
            let (r, ok) = process_or_partial(&ring, &opts).ok()?;
            Some((r.report.pieces[0].clone(), ok == "yes"))
        };
        let Some((fixed, fixed_conv)) = run(HoleRims::Fixed) else {
            continue;
        };
        let Some((free, free_conv)) = run(HoleRims::Free) else {
            continue;
        };
        patches += 1;
        let note = free
            .messages
            .iter()
            .find(|m| m.starts_with("hole rims free"))
            .cloned()
            .unwrap_or_default();
        let how = if !free_conv {
            "not converged"
        } else if note.contains("filled by ears") {
            "ears"
        } else if note.contains("filled by fans") {
            "fans"
        } else {
            "fixed rims (fallback)"
        };
        fixed_ok += usize::from(fixed_conv);
        match how {
            "ears" => by_ears += 1,
            "fans" => by_fans += 1,
            "fixed rims (fallback)" if fixed_conv => fell_back += 1,
            _ => lost += 1,
        }
        if std::env::var_os("MSG").is_some() && how != "ears" && how != "fans" {
            for m in &free.messages {
                println!("    {m}");
            }
        }
        let worst_hole =
            |p: &PieceReport| p.holes.iter().map(|h| h.error_rad()).fold(0.0, f64::max);
        println!(
            "v{centre}: {} faces, rim of {} vertices | fixed: {} θ_err {:.1e}, hole error {:.1e} | free: {how}, θ_err {:.1e}, hole error {:.1e}, {} iterations, RMS {:.3} mm, creased {}",
            ring.face_count(),
            fixed.holes.first().map_or(0, |h| h.vertices),
            if fixed_conv { "conv" } else { "NOTCONV" },
            fixed.final_theta_err,
            worst_hole(&fixed),
            free.final_theta_err,
            worst_hole(&free),
            free.iterations,
            free.rms_displacement_mm,
            free.creased_edges,
        );
    }
    println!(
        "{patches} patches: fixed rims converge on {fixed_ok}; free rims close by ears {by_ears}, by fans {by_fans}, fall back to the fixed run on {fell_back} of those that converge fixed; {lost} other"
    );
}
