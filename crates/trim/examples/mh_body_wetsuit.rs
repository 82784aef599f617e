//! Prints `fixtures/cuts/mh_body_wetsuit.toml`: a wetsuit cut of the MakeHuman body
//! (`$FLATCUT_DATA/mh_body.obj`, decimetres) designed from its joint centres
//! (`mh_body_joints.csv`). Every landmark is the first surface hit of a ray from inside the
//! body (a joint or a point on a limb axis), so the cut is reproducible:
//!
//! ```sh
//! FLATCUT_DATA=/work/shared/meshes cargo run -p flatcut_trim --example mh_body_wetsuit \
//!     > fixtures/cuts/mh_body_wetsuit.toml
//! ```
//!
//! Loops (closed): neck, arm holes, wrists, ankles, waist. Open lines: a centre line from the
//! neck down the front, through the crotch and up the back to the neck; shoulder seams
//! (neck → arm hole); side seams (arm hole → torso side → waist → hip → outer leg → ankle);
//! underarm seams (arm hole → wrist); inseams (crotch, a T-junction on the centre line →
//! inner leg → ankle). Pieces: front/back × left/right × upper/lower and two sleeves; head,
//! hands and feet are left unnamed and dropped.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::HashMap;
use std::fmt::Write as _;

use flatcut_mesh::{bvh::Bvh, vec3};

fn main() {
    let dir = std::path::PathBuf::from(std::env::var_os("FLATCUT_DATA").expect("set FLATCUT_DATA"));
    // Read in mm (×100); points are printed back in dm.
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
    // The part of `x` perpendicular to unit `a`.
    let reject =
        |x: [f64; 3], a: [f64; 3]| vec3::normalize(vec3::sub(x, vec3::scale(a, vec3::dot(x, a))));
    // Eight points round an axis through `c`: k = 0 along `u`, 2 along `v`, 4 along −u, 6 along −v.
    let ring = |c: [f64; 3], u: [f64; 3], v: [f64; 3]| -> Vec<[f64; 3]> {
        (0..8)
            .map(|k| {
                let p = k as f64 * std::f64::consts::FRAC_PI_4;
                hit(
                    c,
                    vec3::add(vec3::scale(u, p.cos()), vec3::scale(v, p.sin())),
                )
            })
            .collect()
    };
    let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let neg = |a: [f64; 3]| vec3::scale(a, -1.0);

    let mut lines: Vec<(String, Vec<[f64; 3]>, bool)> = Vec::new();
    let mut seeds: Vec<(String, [f64; 3])> = Vec::new();
    // Neck: k = 0 left (+x), 2 front, 4 right, 6 back.
    let neck = ring([0.0, 600.0, 8.0], x, z);
    // Waist, same layout.
    let waist_c = [0.0, 220.0, 20.0];
    let waist = ring(waist_c, x, z);
    lines.push(("neck".into(), neck.clone(), true));
    lines.push(("waist".into(), waist.clone(), true));
    // Crotch: straight down from the pelvis joint.
    let crotch = hit(j("pelvis"), neg(y));
    let centre = vec![
        neck[2],
        hit([0.0, 430.0, 0.0], z),
        waist[2],
        hit([0.0, 130.0, 10.0], z),
        crotch,
        hit([0.0, 130.0, 10.0], neg(z)),
        waist[6],
        hit([0.0, 430.0, 0.0], neg(z)),
        neck[6],
    ];
    lines.push(("centre".into(), centre, false));
    for (side, s) in [("left", 1.0), ("right", -1.0)] {
        let p = |n: &str| j(&format!("{}-{n}", &side[..1]));
        let inward = [-s, 0.0, 0.0];
        // Arm hole: a quarter of the way down the upper arm; k = 0 towards the armpit.
        let arm = vec3::normalize(vec3::sub(p("elbow"), p("shoulder")));
        let u_arm = reject(inward, arm);
        let arm_hole = ring(lerp(p("shoulder"), p("elbow"), 0.25), u_arm, reject(z, arm));
        // Wrist: near the hand along the forearm; k = 0 on the underarm side.
        let fore = vec3::normalize(vec3::sub(p("hand"), p("elbow")));
        let u_fore = reject(u_arm, fore);
        let wrist = ring(
            lerp(p("elbow"), p("hand"), 0.8),
            u_fore,
            vec3::cross(fore, u_fore),
        );
        // Ankle: above the ankle joint along the shin; k = 0 on the inner side.
        let shin = vec3::normalize(vec3::sub(p("ankle"), p("knee")));
        let u_leg = reject(inward, shin);
        let ankle = ring(lerp(p("knee"), p("ankle"), 0.85), u_leg, reject(z, shin));
        let thigh = vec3::normalize(vec3::sub(p("knee"), p("upper-leg")));
        let u_thigh = reject(inward, thigh);
        let thigh_at = |t: f64| lerp(p("upper-leg"), p("knee"), t);
        let waist_side = if s > 0.0 { waist[0] } else { waist[4] };
        let neck_side = if s > 0.0 { neck[0] } else { neck[4] };
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
            vec![arm_hole[0], hit(p("elbow"), u_fore), wrist[0]],
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
        seeds.push((
            format!("front-{side}-upper"),
            hit([s * 80.0, 350.0, 20.0], z),
        ));
        seeds.push((
            format!("back-{side}-upper"),
            hit([s * 80.0, 350.0, 20.0], neg(z)),
        ));
        seeds.push((format!("front-{side}-lower"), hit(thigh_at(0.5), z)));
        seeds.push((format!("back-{side}-lower"), hit(thigh_at(0.5), neg(z))));
        seeds.push((
            format!("sleeve-{side}"),
            hit(lerp(p("shoulder"), p("elbow"), 0.6), z),
        ));
    }

    let dm = |p: [f64; 3]| {
        format!(
            "[{:.4}, {:.4}, {:.4}]",
            p[0] / 100.0,
            p[1] / 100.0,
            p[2] / 100.0
        )
    };
    let mut o = String::new();
    writeln!(o, "# A wetsuit cut of the MakeHuman body (mh_body.obj, decimetres, y up, +z front, left = +x).").unwrap();
    writeln!(o, "# Generated by `cargo run -p flatcut_trim --example mh_body_wetsuit`: landmarks are ray hits").unwrap();
    writeln!(o, "# from the joint centres of mh_body_joints.csv. Head, hands and feet stay unnamed (dropped).").unwrap();
    writeln!(o, "units = \"dm\"\n").unwrap();
    for (name, pts, closed) in &lines {
        writeln!(o, "[[cut]]\nname = \"{name}\"").unwrap();
        let list: Vec<String> = pts.iter().map(|&p| dm(p)).collect();
        writeln!(o, "points = [\n    {},\n]", list.join(",\n    ")).unwrap();
        if *closed {
            writeln!(o, "closed = true").unwrap();
        }
        writeln!(o).unwrap();
    }
    for (name, p) in &seeds {
        writeln!(o, "[[piece]]\nname = \"{name}\"\nseed = {}\n", dm(*p)).unwrap();
    }
    print!("{o}");
}
