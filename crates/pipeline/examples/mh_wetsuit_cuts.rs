//! Prints the `[[cut]]` and `[[piece]]` tables of pipelines/wetsuit-mh.toml (and, with
//! `--mm`, of pipelines/wetsuit-scan.toml): a wetsuit cut of the MakeHuman body
//! (`$FLATCUT_DATA/mh_body.obj`, decimetres) designed from its joint centres
//! (`mh_body_joints.csv`). Every landmark is the first surface hit of a ray from inside the
//! body, so the cut is reproducible:
//!
//! ```sh
//! FLATCUT_DATA=/work/shared/meshes cargo run -p flatcut_pipeline --example mh_wetsuit_cuts
//! FLATCUT_DATA=/work/shared/meshes cargo run -p flatcut_pipeline --example mh_wetsuit_cuts -- --mm
//! FLATCUT_DATA=/work/shared/meshes cargo run -p flatcut_pipeline --example mh_wetsuit_cuts -- --check
//! ```
//!
//! It is trim's cut (`fixtures/cuts/mh_body_wetsuit.toml`, made by
//! `cargo run -p flatcut_trim --example mh_body_wetsuit`) plus the seams a wetsuit maker adds
//! where the upper body is too curved for one flat panel: an armhole princess seam on each
//! front (armhole front → over the chest → waist) and a back princess seam over each
//! shoulder blade (armhole back → waist). With trim's cut the front and back upper pieces
//! carry the chest, shoulder blade and shoulder saddle together and did not become
//! flattenable (best θ_err 5.1e-4); split, every piece converges (docs/benchmarks.md).
//!
//! `--check` also cuts the body and prints each piece's faces and angle-defect totals
//! (Σ|2π − θ|, Σ(2π − θ), the Gauss–Bonnet content a flattenable piece must give up).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::HashMap;
use std::fmt::Write as _;

use flatcut_mesh::{Topology, bvh::Bvh, geometry, vec3};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mm = args.iter().any(|a| a == "--mm");
    let check = args.iter().any(|a| a == "--check");
    let dir = std::path::PathBuf::from(std::env::var_os("FLATCUT_DATA").expect("set FLATCUT_DATA"));
    // Read in mm (×100); points are printed back in dm (or mm with --mm).
    let mesh = flatcut_io::read_mesh(&dir.join("mh_body.obj"), flatcut_io::Units::Dm)
        .expect("mh_body.obj")
        .mesh;
    let csv = std::fs::read_to_string(dir.join("mh_body_joints.csv")).expect("joints");
    let mut joint: HashMap<String, [f64; 3]> = HashMap::new();
    for l in csv.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let p = [1, 2, 3].map(|k| f[k].parse::<f64>().unwrap() * 100.0);
        joint.insert(f[0].to_string(), p);
    }
    let j = |n: &str| *joint.get(n).unwrap_or_else(|| panic!("joint {n}"));
    let bvh = Bvh::build(&mesh);
    let hit = |o: [f64; 3], d: [f64; 3]| -> [f64; 3] {
        let d = vec3::normalize(d);
        let h = bvh
            .ray_intersect(o, d, 1e5)
            .unwrap_or_else(|| panic!("no hit from {o:?} along {d:?}"));
        vec3::add(o, vec3::scale(d, h.t))
    };
    let lerp =
        |a: [f64; 3], b: [f64; 3], t: f64| vec3::add(vec3::scale(a, 1.0 - t), vec3::scale(b, t));
    let reject =
        |x: [f64; 3], a: [f64; 3]| vec3::normalize(vec3::sub(x, vec3::scale(a, vec3::dot(x, a))));
    // Points round an axis through `c` at the given angles (degrees, from `u` towards `v`).
    let ring_at = |c: [f64; 3], u: [f64; 3], v: [f64; 3], deg: &[f64]| -> Vec<[f64; 3]> {
        deg.iter()
            .map(|d| {
                let p = d.to_radians();
                hit(
                    c,
                    vec3::add(vec3::scale(u, p.cos()), vec3::scale(v, p.sin())),
                )
            })
            .collect()
    };
    // The point of the elbow (sign +1: the vertex of largest angle defect, the sharpest
    // convex point) or its crook (sign −1: the most saddle-like vertex) within
    // ELBOW_SEARCH_MM of a ray hit behind (in front of) the elbow joint.
    const ELBOW_SEARCH_MM: f64 = 20.0;
    let body_topo = Topology::build(&mesh).expect("mh_body topology");
    let body_defect = geometry::angle_defects(&mesh.positions, &mesh.faces, &body_topo);
    let elbow_point = |near: [f64; 3], sign: f64| -> [f64; 3] {
        let v = (0..mesh.positions.len())
            .filter(|&v| vec3::norm(vec3::sub(mesh.positions[v], near)) <= ELBOW_SEARCH_MM)
            .max_by(|&a, &b| {
                let (x, y) = (
                    body_defect[a].map_or(f64::NEG_INFINITY, |d| sign * d),
                    body_defect[b].map_or(f64::NEG_INFINITY, |d| sign * d),
                );
                x.total_cmp(&y)
            })
            .expect("a vertex near the elbow");
        mesh.positions[v]
    };
    let eight: Vec<f64> = (0..8).map(|k| k as f64 * 45.0).collect();
    let ring = |c, u, v| ring_at(c, u, v, &eight);
    let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let neg = |a: [f64; 3]| vec3::scale(a, -1.0);

    let mut lines: Vec<(String, Vec<[f64; 3]>, bool)> = Vec::new();
    let mut seeds: Vec<(String, [f64; 3])> = Vec::new();
    // Neck: k = 0 left (+x), 2 front, 4 right, 6 back.
    let neck = ring([0.0, 600.0, 8.0], x, z);
    // Waist: trim's front and side points, the four princess-seam ends and the centre back. Seen from the waist
    // centre (z = 20 mm) the front is ~123 mm away and the back ~45 mm, so the angles that
    // put the princess seams ~50 mm (front) and ~60 mm (back) from the centre line differ.
    const WAIST_FRONT_PRINCESS_DEG: f64 = 67.5;
    const WAIST_BACK_PRINCESS_DEG: f64 = 37.0;
    let waist_deg = [
        0.0,
        45.0,
        WAIST_FRONT_PRINCESS_DEG,
        90.0,
        180.0 - WAIST_FRONT_PRINCESS_DEG,
        135.0,
        180.0,
        180.0 + WAIST_BACK_PRINCESS_DEG,
        270.0,
        360.0 - WAIST_BACK_PRINCESS_DEG,
    ];
    let waist_c = [0.0, 220.0, 20.0];
    let waist = ring_at(waist_c, x, z, &waist_deg);
    let (w_left, w_front, w_right, w_back) = (waist[0], waist[3], waist[6], waist[8]);
    lines.push(("neck".into(), neck.clone(), true));
    lines.push(("waist".into(), waist.clone(), true));
    let crotch = hit(j("pelvis"), neg(y));
    let centre = vec![
        neck[2],
        hit([0.0, 430.0, 0.0], z),
        w_front,
        hit([0.0, 130.0, 10.0], z),
        crotch,
        hit([0.0, 130.0, 10.0], neg(z)),
        w_back,
        hit([0.0, 430.0, 0.0], neg(z)),
        neck[6],
    ];
    lines.push(("centre".into(), centre, false));
    for (side, s) in [("left", 1.0), ("right", -1.0)] {
        let p = |n: &str| j(&format!("{}-{n}", &side[..1]));
        let inward = [-s, 0.0, 0.0];
        let arm = vec3::normalize(vec3::sub(p("elbow"), p("shoulder")));
        let u_arm = reject(inward, arm);
        let arm_hole = ring(lerp(p("shoulder"), p("elbow"), 0.25), u_arm, reject(z, arm));
        let fore = vec3::normalize(vec3::sub(p("hand"), p("elbow")));
        let u_fore = reject(u_arm, fore);
        let wrist = ring(
            lerp(p("elbow"), p("hand"), 0.8),
            u_fore,
            vec3::cross(fore, u_fore),
        );
        let shin = vec3::normalize(vec3::sub(p("ankle"), p("knee")));
        let u_leg = reject(inward, shin);
        let ankle = ring(lerp(p("knee"), p("ankle"), 0.85), u_leg, reject(z, shin));
        let thigh = vec3::normalize(vec3::sub(p("knee"), p("upper-leg")));
        let u_thigh = reject(inward, thigh);
        let thigh_at = |t: f64| lerp(p("upper-leg"), p("knee"), t);
        let (waist_side, neck_side) = if s > 0.0 {
            (w_left, neck[0])
        } else {
            (w_right, neck[4])
        };
        // Princess-seam ends on the waist (left: 2 front, 9 back; right: 4 front, 7 back).
        let (w_front_princess, w_back_princess) = if s > 0.0 {
            (waist[2], waist[9])
        } else {
            (waist[4], waist[7])
        };
        lines.push((format!("arm-hole-{side}"), arm_hole.clone(), true));
        lines.push((format!("wrist-{side}"), wrist.clone(), true));
        lines.push((format!("ankle-{side}"), ankle.clone(), true));
        lines.push((
            format!("shoulder-{side}"),
            vec![neck_side, arm_hole[4]],
            false,
        ));
        lines.push((
            format!("side-{side}"),
            vec![
                arm_hole[0],
                hit([0.0, 390.0, 10.0], [s, 0.0, 0.0]),
                waist_side,
                hit([0.0, 90.0, 10.0], [s, 0.0, 0.0]),
                hit(thigh_at(0.4), neg(u_thigh)),
                hit(p("knee"), neg(u_leg)),
                ankle[4],
            ],
            false,
        ));
        lines.push((
            format!("underarm-{side}"),
            vec![arm_hole[0], elbow_point(hit(p("elbow"), z), -1.0), wrist[0]],
            false,
        ));
        lines.push((
            format!("inseam-{side}"),
            vec![
                crotch,
                hit(thigh_at(0.3), u_thigh),
                hit(p("knee"), u_leg),
                ankle[0],
            ],
            false,
        ));
        // Two-piece sleeve: a back seam from the armhole over the point of the elbow to the
        // wrist. One tube piece stalled at θ_err 1.7e-2, and so did its back half with the
        // seam beside the elbow: the elbow point (+0.19 rad) must lie on the seam.
        lines.push((
            format!("sleeve-back-{side}"),
            vec![
                arm_hole[5],
                elbow_point(hit(p("elbow"), neg(z)), 1.0),
                wrist[4],
            ],
            false,
        ));
        // Front princess: the armhole's front point, over the chest, to the waist.
        lines.push((
            format!("princess-front-{side}"),
            vec![
                arm_hole[2],
                hit([s * 80.0, 400.0, 20.0], z),
                w_front_princess,
            ],
            false,
        ));
        // Back princess: the armhole's back point, over the shoulder blade, to the waist.
        lines.push((
            format!("princess-back-{side}"),
            vec![
                arm_hole[6],
                hit([s * 85.0, 400.0, 0.0], neg(z)),
                w_back_princess,
            ],
            false,
        ));
        // Seeds: centre panels near the centre line, side panels between princess and side.
        seeds.push((
            format!("front-{side}-centre"),
            hit([s * 25.0, 330.0, 20.0], z),
        ));
        seeds.push((
            format!("front-{side}-side"),
            hit([s * 60.0, 300.0, 20.0], [s * 0.8, 0.0, 0.6]),
        ));
        seeds.push((
            format!("back-{side}-centre"),
            hit([s * 25.0, 330.0, 0.0], neg(z)),
        ));
        seeds.push((
            format!("back-{side}-side"),
            hit([s * 60.0, 300.0, 0.0], [s * 0.8, 0.0, -0.6]),
        ));
        seeds.push((format!("front-{side}-lower"), hit(thigh_at(0.5), z)));
        seeds.push((format!("back-{side}-lower"), hit(thigh_at(0.5), neg(z))));
        seeds.push((
            format!("sleeve-{side}-front"),
            hit(lerp(p("shoulder"), p("elbow"), 0.6), z),
        ));
        seeds.push((
            format!("sleeve-{side}-back"),
            hit(lerp(p("shoulder"), p("elbow"), 0.6), neg(z)),
        ));
    }

    let (div, digits) = if mm { (1.0, 2) } else { (100.0, 4) };
    let pt = |p: [f64; 3]| {
        format!(
            "[{:.d$}, {:.d$}, {:.d$}]",
            p[0] / div,
            p[1] / div,
            p[2] / div,
            d = digits
        )
    };
    let mut o = String::new();
    for (name, pts, closed) in &lines {
        writeln!(o, "[[cut]]\nname = {name:?}\npoints = [").unwrap();
        for p in pts {
            writeln!(o, "    {},", pt(*p)).unwrap();
        }
        writeln!(o, "]\nclosed = {closed}\n").unwrap();
    }
    for (name, s) in &seeds {
        writeln!(o, "[[piece]]\nname = {name:?}\nseed = {}\n", pt(*s)).unwrap();
    }
    print!("{o}");

    if check {
        let cuts = flatcut_trim::Cuts {
            units: None,
            cuts: lines
                .iter()
                .map(|(name, points, closed)| flatcut_trim::CutSpec {
                    name: name.clone(),
                    points: points.clone(),
                    vertices: Vec::new(),
                    closed: *closed,
                })
                .collect(),
            pieces: seeds
                .iter()
                .map(|(name, seed)| flatcut_trim::PieceSpec {
                    name: name.clone(),
                    seed: *seed,
                })
                .collect(),
            options: Default::default(),
        };
        let t = flatcut_trim::trim(&mesh, &cuts).unwrap_or_else(|e| panic!("{e}"));
        for piece in &t.pieces {
            let m = &piece.mesh;
            let topo = Topology::build(m).unwrap();
            let all = geometry::angle_defects(&m.positions, &m.faces, &topo);
            let worst = (0..all.len())
                .filter(|&v| all[v].is_some())
                .max_by(|&a, &b| {
                    let (x, y) = (all[a].unwrap_or(0.0).abs(), all[b].unwrap_or(0.0).abs());
                    x.total_cmp(&y)
                });
            let d: Vec<f64> = all.iter().flatten().copied().collect();
            let abs: f64 = d.iter().map(|x| x.abs()).sum();
            let sum: f64 = d.iter().sum();
            let (wv, wd) = worst.map_or(([f64::NAN; 3], f64::NAN), |v| {
                (m.positions[v], all[v].unwrap_or(f64::NAN))
            });
            eprintln!(
                "{:20} faces {:5} loops {} Σ|defect| {:.3} Σdefect {:+.3} rad, worst {:+.3} at {}",
                piece.name,
                m.faces.len(),
                topo.boundary_loops().len(),
                abs,
                sum,
                wd,
                pt(wv),
            );
        }
    }
}
