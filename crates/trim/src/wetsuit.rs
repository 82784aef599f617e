//! A wetsuit-style cut of the generated dress form ([`flatcut_mesh::shapes::dress_form`]):
//! the form already has neck, arm and bottom openings; this adds the seams a close-fitting
//! bodice and skirt would have — centre front and back, side seams, shoulder seams and a
//! waist seam — so that it falls into eight disks (front/back × left/right × upper/lower).
//! The bundled demo pipeline cuts the form with it.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use flatcut_mesh::shapes::{BodyMeasurements, landmarks};
use flatcut_mesh::{Topology, TriMesh, bvh::Bvh};

use crate::TrimError;
use crate::cuts::{CutSpec, Cuts, PieceSpec};

/// The cut of `form` (made by `dress_form(m)`, in mm) into eight disk pieces named
/// `{front,back}-{left,right}-{upper,lower}`; lines `waist` (closed), `centre-front`,
/// `centre-back`, `side-left`, `side-right`, `shoulder-left`, `shoulder-right`. Left is the
/// form's left (+x), front is +z. Landmarks are found on the mesh itself (rays from the axis,
/// boundary-loop vertices), so the cut fits any measurements and resolution.
pub fn dress_form_wetsuit(form: &TriMesh, m: &BodyMeasurements) -> Result<Cuts, TrimError> {
    let h = if m.height_mm.is_finite() && m.height_mm > 0.0 {
        m.height_mm
    } else {
        BodyMeasurements::default().height_mm
    };
    let bvh = Bvh::build(form);
    let topo = Topology::build(form)?;
    let at = |theta: f64, frac: f64| -> Result<[f64; 3], TrimError> {
        let (o, d) = ([0.0, frac * h, 0.0], [theta.cos(), 0.0, theta.sin()]);
        let hit = bvh
            .ray_intersect(o, d, 10.0 * h)
            .ok_or_else(|| TrimError::NoLandmark {
                what: format!("at angle {theta:.3} rad, height {:.3} of the form", frac),
            })?;
        Ok([o[0] + hit.t * d[0], o[1], o[2] + hit.t * d[2]])
    };
    // Boundary loops: neck (highest), bottom (lowest), arm holes (by side).
    let loops: Vec<Vec<[f64; 3]>> = topo
        .boundary_loops()
        .iter()
        .map(|l| l.iter().map(|v| form.positions[v.idx()]).collect())
        .collect();
    let centre = |l: &[[f64; 3]]| {
        let n = l.len() as f64;
        [0, 1, 2].map(|k| l.iter().map(|p| p[k]).sum::<f64>() / n)
    };
    let find = |what: &str, pick: &dyn Fn([f64; 3]) -> bool| -> Result<&Vec<[f64; 3]>, TrimError> {
        loops
            .iter()
            .find(|l| pick(centre(l)))
            .ok_or_else(|| TrimError::NoLandmark { what: what.into() })
    };
    let neck = find("neck opening", &|c| c[1] > 0.84 * h)?;
    let bottom = find("bottom opening", &|c| c[1] < 0.46 * h)?;
    let arm_l = find("left arm hole", &|c| {
        c[0] > 0.0 && c[1] > 0.7 * h && c[1] < 0.84 * h
    })?;
    let arm_r = find("right arm hole", &|c| {
        c[0] < 0.0 && c[1] > 0.7 * h && c[1] < 0.84 * h
    })?;
    // The loop vertex farthest in direction `d` (x, z) or highest/lowest.
    let toward = |l: &[[f64; 3]], score: &dyn Fn([f64; 3]) -> f64| -> [f64; 3] {
        *l.iter()
            .max_by(|a, b| score(**a).total_cmp(&score(**b)))
            .unwrap_or(&[0.0; 3])
    };
    let dir = |theta: f64| move |p: [f64; 3]| p[0] * theta.cos() + p[2] * theta.sin();
    let (front, back, left, right) = (FRAC_PI_2, 3.0 * FRAC_PI_2, 0.0, PI);
    let (waist, hip, bust) = (landmarks::WAIST, landmarks::HIP, landmarks::BUST);

    let waist_pts: Vec<[f64; 3]> = (0..8)
        .map(|k| at(k as f64 * FRAC_PI_4, waist))
        .collect::<Result<_, _>>()?;
    let line = |name: &str, points: Vec<[f64; 3]>, closed: bool| CutSpec {
        name: name.into(),
        points,
        vertices: Vec::new(),
        closed,
    };
    let mut cuts = vec![line("waist", waist_pts, true)];
    for (name, theta) in [("centre-front", front), ("centre-back", back)] {
        cuts.push(line(
            name,
            vec![
                toward(neck, &dir(theta)),
                at(theta, bust)?,
                at(theta, waist)?,
                at(theta, hip)?,
                toward(bottom, &dir(theta)),
            ],
            false,
        ));
    }
    for (name, theta, arm) in [("side-left", left, arm_l), ("side-right", right, arm_r)] {
        cuts.push(line(
            name,
            vec![
                toward(arm, &|p| -p[1]),
                at(theta, waist)?,
                at(theta, hip)?,
                toward(bottom, &dir(theta)),
            ],
            false,
        ));
    }
    for (name, theta, arm) in [
        ("shoulder-left", left, arm_l),
        ("shoulder-right", right, arm_r),
    ] {
        cuts.push(line(
            name,
            vec![toward(neck, &dir(theta)), toward(arm, &|p| p[1])],
            false,
        ));
    }
    let mut pieces = Vec::new();
    for (side, theta) in [
        ("front-left", FRAC_PI_4),
        ("front-right", 3.0 * FRAC_PI_4),
        ("back-right", 5.0 * FRAC_PI_4),
        ("back-left", 7.0 * FRAC_PI_4),
    ] {
        for (part, frac) in [("upper", 0.69), ("lower", 0.55)] {
            pieces.push(PieceSpec {
                name: format!("{side}-{part}"),
                seed: at(theta, frac)?,
            });
        }
    }
    Ok(Cuts {
        units: Some("mm".into()),
        cuts,
        pieces,
        options: Default::default(),
    })
}
