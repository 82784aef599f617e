//! A piece's holes filled for `HoleRims::Free`, so that the piece becomes a disk whose rim
//! vertices are interior: θ = 2π on the disk makes the fills flat, and a hole bounded by a
//! flat fill closes in the plane. The fills are dropped after the processing; their faces
//! only serve as constraints (their shape is not kept).
//!
//! Two fills, both triangulations of the rim's polygon seen on its mean plane (the plane
//! through the rim's centroid across the mean of its vertex normals), so that no fill face
//! is turned over:
//! * [`HoleFill::Ears`]: the polygon cut into ears, no vertex added;
//! * [`HoleFill::Fan`]: one vertex over the point of the polygon's kernel deepest inside it
//!   (the centroid where that is deep enough), lifted to continue the surface
//!   ([`fan_centre`]), and a triangle from it to every rim edge.
//!
//! A fan from the rim's centroid, the first fill (thirty-fifth session), turns a face over
//! wherever the centroid sees a rim edge from behind (a notched or bent hole); the turned
//! face's angle counts into the centre's sum (1.0–1.7 rad of excess on body patches), and
//! the filled piece stalled: 25 of 41 body patches closed their hole, against 38 with either
//! fill here and 40 with both in turn (docs/algorithms/flattenable.md, "Holes").

use flatcut_mesh::geometry::area_weighted_vertex_normals;
use flatcut_mesh::vec3::{add, cross, dot, normalize, scale, sub};
use flatcut_mesh::{TriMesh, VertexId};

use crate::hole_closure::Holes;

/// How a hole is filled for the processing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum HoleFill {
    /// Ears of the rim's polygon; a hole whose polygon has none (it overlaps itself on the
    /// mean plane) gets the fan.
    Ears,
    /// A fan from a lifted centre in the polygon's kernel; a hole whose kernel is empty gets
    /// the ears, and one with neither the fan from its centroid.
    Fan,
}

/// `piece` with every hole of `holes` filled by `fill`: the piece's vertices and faces first
/// and in their order, then the fills' centres (one per fan) and faces. Each fill face
/// across a rim edge runs along it backwards, the orientation of the piece's face there.
pub(crate) fn filled(piece: &TriMesh, holes: &Holes, fill: HoleFill) -> TriMesh {
    let mut positions = piece.positions.clone();
    let mut faces = piece.faces.clone();
    let normals = area_weighted_vertex_normals(&piece.positions, &piece.faces);
    for rim in holes.rims() {
        let plane = RimPlane::of(&piece.positions, &normals, rim);
        let ears = || plane.as_ref().and_then(|p| ears(p, rim));
        let fan = || {
            plane
                .as_ref()
                .and_then(|p| fan_centre(p, &piece.positions, &normals, rim))
        };
        let one = match fill {
            HoleFill::Ears => ears()
                .map(RimFill::Ears)
                .or_else(|| fan().map(RimFill::Fan)),
            HoleFill::Fan => fan()
                .map(RimFill::Fan)
                .or_else(|| ears().map(RimFill::Ears)),
        };
        match one.unwrap_or_else(|| RimFill::Fan(centroid(&piece.positions, rim))) {
            RimFill::Ears(tris) => faces.extend(tris),
            RimFill::Fan(centre) => {
                let c = positions.len() as u32;
                positions.push(centre);
                for j in 0..rim.len() {
                    let (a, b) = (rim[j].0, rim[(j + 1) % rim.len()].0);
                    faces.push([b, a, c]);
                }
            }
        }
    }
    TriMesh {
        positions,
        faces,
        attributes: Default::default(),
        face_labels: None,
    }
}

/// One rim's fill: its ears, or the centre of its fan.
enum RimFill {
    Ears(Vec<[u32; 3]>),
    Fan([f64; 3]),
}

fn centroid(positions: &[[f64; 3]], rim: &[VertexId]) -> [f64; 3] {
    let k = rim.len() as f64;
    rim.iter()
        .fold([0.0; 3], |c, v| add(c, scale(positions[v.idx()], 1.0 / k)))
}

/// A rim seen on its mean plane: the plane through its centroid across the mean `n` of its
/// vertex normals, with axes `u`, `v` (u × v = n). Seen from `n`, the material lies left of
/// every rim edge and the hole right of it.
struct RimPlane {
    centroid: [f64; 3],
    n: [f64; 3],
    u: [f64; 3],
    v: [f64; 3],
    /// The rim's vertices on the plane, in rim order.
    points: Vec<[f64; 2]>,
}

impl RimPlane {
    /// `None` when the normals cancel (no side to see the rim from).
    fn of(positions: &[[f64; 3]], normals: &[[f64; 3]], rim: &[VertexId]) -> Option<Self> {
        let centroid = centroid(positions, rim);
        let n = normalize(rim.iter().fold([0.0; 3], |s, v| add(s, normals[v.idx()])));
        if !n.iter().all(|c| c.is_finite()) {
            return None;
        }
        let axis = if n[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let u = normalize(cross(n, axis));
        let v = cross(n, u);
        let points = rim
            .iter()
            .map(|r| {
                let d = sub(positions[r.idx()], centroid);
                [dot(d, u), dot(d, v)]
            })
            .collect();
        Some(Self {
            centroid,
            n,
            u,
            v,
            points,
        })
    }

    /// How far `p` lies inside the least of the rim edges' lines (negative outside one): a
    /// fan face [b, a, c] faces along n when c lies right of a → b.
    fn depth(&self, p: [f64; 2]) -> f64 {
        let q = &self.points;
        (0..q.len())
            .filter_map(|j| {
                let (a, b) = (q[j], q[(j + 1) % q.len()]);
                let e = [b[0] - a[0], b[1] - a[1]];
                let len = e[0].hypot(e[1]);
                (len > 0.0).then(|| (e[1] * (p[0] - a[0]) - e[0] * (p[1] - a[1])) / len)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The kernel's point deepest inside the rim (the centre of the largest circle in it):
    /// the best of a grid over the rim's extent, then a pattern search. `None` when the
    /// kernel is empty (no point sees every rim edge from the front).
    fn deepest(&self) -> Option<([f64; 2], f64)> {
        // Grid cells per side, and halvings of the search's step: a 24 × 24 grid is within
        // 3 % of the rim's extent of the best point, and 40 halvings take that below 1e-12.
        // The rounds (each a halving or a move) are bounded only against a ridge walked at a
        // tiny step.
        const GRID: usize = 24;
        const HALVINGS: usize = 40;
        const MAX_ROUNDS: usize = 1000;
        let (lo, hi) = self.points.iter().fold(
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
            |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1])],
                    [hi[0].max(p[0]), hi[1].max(p[1])],
                )
            },
        );
        let cell = [(hi[0] - lo[0]) / GRID as f64, (hi[1] - lo[1]) / GRID as f64];
        let mut best = ([0.0, 0.0], self.depth([0.0, 0.0]));
        for i in 0..=GRID {
            for j in 0..=GRID {
                let p = [lo[0] + i as f64 * cell[0], lo[1] + j as f64 * cell[1]];
                let d = self.depth(p);
                if d > best.1 {
                    best = (p, d);
                }
            }
        }
        let mut step = cell[0].max(cell[1]);
        let mut halvings = 0;
        for _ in 0..MAX_ROUNDS {
            if halvings == HALVINGS {
                break;
            }
            let mut moved = false;
            for (dx, dy) in [
                (1.0, 0.0),
                (-1.0, 0.0),
                (0.0, 1.0),
                (0.0, -1.0),
                (1.0, 1.0),
                (1.0, -1.0),
                (-1.0, 1.0),
                (-1.0, -1.0),
            ] {
                let p = [best.0[0] + dx * step, best.0[1] + dy * step];
                let d = self.depth(p);
                if d > best.1 {
                    best = (p, d);
                    moved = true;
                }
            }
            if !moved {
                step *= 0.5;
                halvings += 1;
            }
        }
        (best.1 > 0.0 && best.1.is_finite()).then_some(best)
    }

    fn lift(&self, p: [f64; 2]) -> [f64; 3] {
        add(self.centroid, add(scale(self.u, p[0]), scale(self.v, p[1])))
    }
}

/// The fan's centre for `rim`: a base point b on the mean plane, moved along n by half the
/// height h at which the rim vertices' tangent planes meet best over it (least squares,
/// h = −Σ (n_v · n)(n_v · (b − v)) / Σ (n_v · n)², n_v the area-weighted vertex normals). On
/// a sphere the tangent planes of a circle meet on its axis at (sec φ − cos φ) R above the
/// circle's plane, and the sphere at (1 − cos φ) R, a ratio cos φ / (1 + cos φ) → ½: half is
/// the surface over the hole to second order. The base is the centroid when it lies at least
/// half as deep inside the rim as the kernel's deepest point, else that point. `None` when
/// the kernel is empty.
fn fan_centre(
    plane: &RimPlane,
    positions: &[[f64; 3]],
    normals: &[[f64; 3]],
    rim: &[VertexId],
) -> Option<[f64; 3]> {
    let (deepest, depth) = plane.deepest()?;
    let base = if plane.depth([0.0, 0.0]) >= 0.5 * depth {
        plane.centroid
    } else {
        plane.lift(deepest)
    };
    let (mut num, mut den) = (0.0, 0.0);
    for v in rim {
        let nv = normalize(normals[v.idx()]);
        let a = dot(nv, plane.n);
        num -= a * dot(nv, sub(base, positions[v.idx()]));
        den += a * a;
    }
    let h = 0.5 * num / den;
    Some(if h.is_finite() {
        add(base, scale(plane.n, h))
    } else {
        base
    })
}

/// The rim's polygon on its mean plane cut into ears, the roundest ear first (the largest
/// twice-area over the sum of its squared sides), so that the fill has no needless slivers.
/// `None` when at some point no ear is left (the rim overlaps itself on the plane).
fn ears(plane: &RimPlane, rim: &[VertexId]) -> Option<Vec<[u32; 3]>> {
    if rim.len() < 3 {
        return None;
    }
    // Seen from n the hole lies right of the rim: reversed, the polygon runs
    // counter-clockwise, and an ear (a, b, c) of it is a face along n whose edges of the rim
    // run backwards.
    let mut polygon: Vec<usize> = (0..rim.len()).rev().collect();
    let q = &plane.points;
    let turn = |a: usize, b: usize, c: usize| {
        (q[b][0] - q[a][0]) * (q[c][1] - q[a][1]) - (q[b][1] - q[a][1]) * (q[c][0] - q[a][0])
    };
    let mut tris = Vec::with_capacity(rim.len().saturating_sub(2));
    while polygon.len() > 3 {
        let m = polygon.len();
        let corner = |i: usize| (polygon[(i + m - 1) % m], polygon[i], polygon[(i + 1) % m]);
        // Only a reflex vertex can lie inside a convex corner's triangle.
        let reflex: Vec<usize> = (0..m)
            .filter(|&i| {
                let (a, b, c) = corner(i);
                turn(a, b, c) <= 0.0
            })
            .map(|i| polygon[i])
            .collect();
        let mut best: Option<(usize, f64)> = None;
        for i in 0..m {
            let (a, b, c) = corner(i);
            let twice_area = turn(a, b, c);
            if twice_area <= 0.0 {
                continue;
            }
            let blocked = reflex.iter().any(|&p| {
                p != a
                    && p != c
                    && turn(a, b, p) >= 0.0
                    && turn(b, c, p) >= 0.0
                    && turn(c, a, p) >= 0.0
            });
            if blocked {
                continue;
            }
            let side2 =
                |s: usize, t: usize| (q[t][0] - q[s][0]).powi(2) + (q[t][1] - q[s][1]).powi(2);
            let roundness = twice_area / (side2(a, b) + side2(b, c) + side2(c, a));
            if best.is_none_or(|(_, r)| roundness > r) {
                best = Some((i, roundness));
            }
        }
        let (i, _) = best?;
        let m = polygon.len();
        tris.push([
            rim[polygon[(i + m - 1) % m]].0,
            rim[polygon[i]].0,
            rim[polygon[(i + 1) % m]].0,
        ]);
        polygon.remove(i);
    }
    if polygon.len() == 3 {
        if turn(polygon[0], polygon[1], polygon[2]) <= 0.0 {
            return None;
        }
        tris.push([rim[polygon[0]].0, rim[polygon[1]].0, rim[polygon[2]].0]);
    }
    Some(tris)
}

#[cfg(test)]
mod tests {
    use super::*;
    use flatcut_mesh::Topology;
    use flatcut_mesh::geometry::{angle_sums, face_areas};

    /// A 200 mm sheet on a 21 × 21 grid (10 mm cells) without the cells `hole` takes, flat.
    fn sheet_with_hole(hole: impl Fn(f64, f64) -> bool) -> TriMesh {
        flatcut_mesh::shapes::grid_patch_with_holes(21, 200.0, |_, _| 0.0, hole)
    }

    /// An L of two 20 mm arms, 80 mm long: its rim's centroid lies in the L's inner corner,
    /// outside it, and its kernel is the 20 mm square where the arms meet.
    fn l_hole(x: f64, y: f64) -> bool {
        let arm = |s: f64| (-40.0..=-20.0).contains(&s);
        let span = |s: f64| (-40.0..=40.0).contains(&s);
        (arm(y) && span(x)) || (arm(x) && span(y))
    }

    /// A U opening to +y: no point sees both inner walls from the front.
    fn u_hole(x: f64, y: f64) -> bool {
        let bottom = (-40.0..=-20.0).contains(&y) && (-40.0..=40.0).contains(&x);
        let wall = |x0: f64| (x0..=x0 + 20.0).contains(&x) && (-40.0..=40.0).contains(&y);
        bottom || wall(-40.0) || wall(20.0)
    }

    /// Checks that `filled` is `sheet` filled into a disk of consistent orientation whose
    /// fill faces all face +z (the sheet is flat), and returns the number of vertices added
    /// and the fill's area (mm²).
    fn check_flat_fill(sheet: &TriMesh, filled: &TriMesh) -> (usize, f64) {
        assert_eq!(&filled.faces[..sheet.face_count()], &sheet.faces[..]);
        let topo = Topology::build(filled).unwrap();
        assert_eq!(topo.boundary_loops().len(), 1);
        assert!(topo.inconsistent_edges().is_empty());
        for f in &filled.faces[sheet.face_count()..] {
            let [a, b, c] = f.map(|v| filled.positions[v as usize]);
            let normal = cross(sub(b, a), sub(c, a));
            assert!(normal[2] > 0.0, "fill face {f:?} turned over: {normal:?}");
        }
        let area = face_areas(&filled.positions, &filled.faces)[sheet.face_count()..]
            .iter()
            .sum();
        (filled.vertex_count() - sheet.vertex_count(), area)
    }

    #[test]
    fn a_notched_hole_gets_a_fan_from_its_kernel_and_ears_that_tile_it() {
        let sheet = sheet_with_hole(l_hole);
        let topo = Topology::build(&sheet).unwrap();
        let holes = Holes::of(&topo, &sheet.positions);
        assert_eq!(holes.len(), 1);
        let rim = holes.rims().next().unwrap();
        let normals = area_weighted_vertex_normals(&sheet.positions, &sheet.faces);
        let plane = RimPlane::of(&sheet.positions, &normals, rim).unwrap();
        // The centroid fan of before: the centroid sees rim edges from behind.
        assert!(plane.depth([0.0, 0.0]) < 0.0);
        let (deepest, depth) = plane.deepest().unwrap();
        // The largest circle in the arms' 20 mm square: radius 10 mm, at its centre.
        assert!((depth - 10.0).abs() < 1e-9, "{depth}");
        let at = plane.lift(deepest);
        assert!(
            (at[0] + 30.0).abs() < 1e-6 && (at[1] + 30.0).abs() < 1e-6,
            "{at:?}"
        );

        let fan = filled(&sheet, &holes, HoleFill::Fan);
        assert_eq!(check_flat_fill(&sheet, &fan).0, 1);
        // A fan from inside the kernel of a flat polygon covers it once: 2π at its centre.
        let centre = sheet.vertex_count();
        let theta = angle_sums(&fan.positions, &fan.faces)[centre];
        assert!((theta - std::f64::consts::TAU).abs() < 1e-12, "{theta}");
        assert_eq!(fan.positions[centre][2], 0.0);

        let ears = filled(&sheet, &holes, HoleFill::Ears);
        let (added, area) = check_flat_fill(&sheet, &ears);
        assert_eq!(added, 0);
        assert_eq!(ears.face_count() - sheet.face_count(), rim.len() - 2);
        // The ears tile the L: 2 × 80 × 20 − 20 × 20 mm².
        assert!((area - 2800.0).abs() < 1e-9, "{area}");
    }

    #[test]
    fn a_hole_without_kernel_is_filled_by_ears_even_when_a_fan_is_asked_for() {
        let sheet = sheet_with_hole(u_hole);
        let topo = Topology::build(&sheet).unwrap();
        let holes = Holes::of(&topo, &sheet.positions);
        let rim = holes.rims().next().unwrap();
        let normals = area_weighted_vertex_normals(&sheet.positions, &sheet.faces);
        assert!(
            RimPlane::of(&sheet.positions, &normals, rim)
                .unwrap()
                .deepest()
                .is_none()
        );
        let fan = filled(&sheet, &holes, HoleFill::Fan);
        assert_eq!(fan, filled(&sheet, &holes, HoleFill::Ears));
        let (added, area) = check_flat_fill(&sheet, &fan);
        assert_eq!(added, 0);
        // 80 × 20 + 2 × 60 × 20 mm².
        assert!((area - 4000.0).abs() < 1e-9, "{area}");
    }

    #[test]
    fn the_fan_centre_lies_on_the_sphere_its_rim_was_cut_from() {
        let radius = 400.0;
        let sheet = flatcut_mesh::shapes::patch_with_holes_on_sphere(200.0, 25, radius);
        let topo = Topology::build(&sheet).unwrap();
        let holes = Holes::of(&topo, &sheet.positions);
        let filled = filled(&sheet, &holes, HoleFill::Fan);
        assert_eq!(filled.vertex_count(), sheet.vertex_count() + 2);
        for (k, rim) in holes.rims().enumerate() {
            let centre = filled.positions[sheet.vertex_count() + k];
            let centroid = centroid(&sheet.positions, rim);
            // The centroid sits a sagitta inside the sphere; the centre is on it to within a
            // fifth of that (measured 13 %: the rim's vertex normals come from one-sided fans,
            // and the rim is the grid's jagged loop, not a circle).
            let off = |p: [f64; 3]| (dot(p, p).sqrt() - radius).abs();
            let sagitta = off(centroid);
            assert!(sagitta > 0.5, "{sagitta}");
            assert!(
                off(centre) < 0.2 * sagitta,
                "{} against {sagitta}",
                off(centre)
            );
        }
        let filled_topo = Topology::build(&filled).unwrap();
        assert_eq!(filled_topo.boundary_loops().len(), 1);
        assert!(filled_topo.inconsistent_edges().is_empty());
    }
}
