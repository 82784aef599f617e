//! One connected component prepared for processing: local arrays, topology and the
//! least-norm layout built once, vertex weights, the fold guard, and the measures that go
//! into its report.

use std::f64::consts::TAU;

use flatcut_mesh::geometry::{corner_angles, face_areas, face_normals};
use flatcut_mesh::vec3::{angle, cross, dot, sub};
use flatcut_mesh::{Topology, TriMesh};

use crate::hole_closure::{HoleClosure, Holes};
use crate::least_norm::Layout;
use crate::report::PieceReport;

/// A piece ready for the iteration.
pub struct Piece {
    /// Component number.
    pub index: usize,
    /// Input vertex of each local vertex.
    pub vertex_map: Vec<u32>,
    /// Local faces.
    pub faces: Vec<[u32; 3]>,
    /// Local input positions.
    pub pos0: Vec<[f64; 3]>,
    /// Topology of the piece, built once.
    pub topo: Topology,
    /// Least-norm layout, built once.
    pub layout: Layout,
    /// w per interior vertex.
    pub weights: Vec<f64>,
    /// Every boundary loop but the outline: what must close besides θ = 2π.
    pub holes: Holes,
    guard: Guard,
}

/// Rejects folded geometry: a face whose normal turned by 90° or more against the input,
/// or a corner newly below the angle floor (a corner already below the floor in the input
/// may shrink to half its input value, so that scan slivers do not freeze the piece).
struct Guard {
    normals0: Vec<[f64; 3]>,
    /// cos of the smallest angle each corner may take: the floor, or half the input angle
    /// for a corner already below the floor. Compared as cosines (no atan2 in the hot loop).
    cos_limit: Vec<[f64; 3]>,
}

/// The fold test of a block of faces (their points coordinate by coordinate, their input
/// normals and corner limits): the loop of [`Piece::offending_faces`], run by `pulp` in a
/// function compiled for the CPU's widest vectors (see `least_norm::CornerAngles`).
struct FoldTests<'a, const B: usize> {
    points: &'a [[[f64; B]; 3]; 3],
    normals0: &'a [[f64; 3]],
    cos_limit: &'a [[f64; 3]],
    folded: &'a mut [bool],
    /// The faces' (f1 − f0) × (f2 − f0), x, y, z rows: what [`Piece::interior_normals`]
    /// sums, kept for an accepted trial's next step.
    normals: &'a mut [[f64; B]; 3],
}

impl<const B: usize> pulp::WithSimd for FoldTests<'_, B> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let points = self.points;
        for (j, folded) in self.folded.iter_mut().enumerate() {
            let p = [0, 1, 2].map(|k| [points[k][0][j], points[k][1][j], points[k][2][j]]);
            let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            for c in 0..3 {
                self.normals[c][j] = n[c];
            }
            let mut out_of_bounds = dot(n, self.normals0[j]) <= 0.0;
            // Corner k below its limit ⇔ cos(corner) > cos(limit) (cos falls on [0, π]); a
            // zero-length edge gives NaN and counts as folded.
            for k in 0..3 {
                let u = sub(p[(k + 1) % 3], p[k]);
                let w = sub(p[(k + 2) % 3], p[k]);
                let c = dot(u, w) / (dot(u, u) * dot(w, w)).sqrt();
                out_of_bounds |= c.is_nan() | (c > self.cos_limit[j][k]);
            }
            *folded = out_of_bounds;
        }
    }
}

impl Piece {
    /// Prepares a piece from its local mesh (validated by the caller). `weights_local`
    /// gives w per local vertex.
    pub fn new(
        index: usize,
        vertex_map: Vec<u32>,
        local: &TriMesh,
        topo: Topology,
        weights_local: &[f64],
        min_angle_deg: f64,
    ) -> Result<Self, crate::least_norm::FactorError> {
        let layout = Layout::build(&topo, &local.faces)?;
        let weights = layout
            .interior
            .iter()
            .map(|&p| weights_local[p as usize])
            .collect();
        let floor = min_angle_deg.to_radians();
        let guard = Guard {
            normals0: face_normals(&local.positions, &local.faces),
            cos_limit: corner_angles(&local.positions, &local.faces)
                .iter()
                .map(|a| a.map(|a0| if a0 >= floor { floor } else { 0.5 * a0 }.cos()))
                .collect(),
        };
        Ok(Self {
            index,
            vertex_map,
            faces: local.faces.clone(),
            pos0: local.positions.clone(),
            holes: Holes::of(&topo, &local.positions),
            topo,
            layout,
            weights,
            guard,
        })
    }

    /// Number of folded faces at `positions` (see [`PieceReport::folded_faces`]); non-finite
    /// positions count every face.
    pub fn folded_faces(&self, positions: &[[f64; 3]]) -> usize {
        self.offending_faces(positions).len()
    }

    /// The folded faces at `positions` (every face if a position is not finite). The faces
    /// go in blocks: their corners gathered first, then the tests in a loop without branches,
    /// which vectorises (the guard runs on every trial and correction).
    pub fn offending_faces(&self, positions: &[[f64; 3]]) -> Vec<usize> {
        self.offending_faces_with_normals(positions, None)
    }

    /// [`Piece::offending_faces`], also writing every face's (f1 − f0) × (f2 − f0) into
    /// `face_normals` (one per face) when given and the positions are finite (the sums of
    /// [`Piece::interior_normals_from_faces`], bit for bit those of
    /// [`Piece::interior_normals`] at the same positions).
    pub fn offending_faces_with_normals(
        &self,
        positions: &[[f64; 3]],
        mut face_normals: Option<&mut [[f64; 3]]>,
    ) -> Vec<usize> {
        const BLOCK: usize = 256;
        if positions.iter().flatten().any(|c| !c.is_finite()) {
            return (0..self.faces.len()).collect();
        }
        // Per face of a block: its three points, coordinate by coordinate.
        let mut points = [[[0.0f64; BLOCK]; 3]; 3];
        let mut normals = [[0.0f64; BLOCK]; 3];
        let mut folded = [false; BLOCK];
        let mut out = Vec::new();
        let arch = pulp::Arch::new();
        for start in (0..self.faces.len()).step_by(BLOCK) {
            let len = BLOCK.min(self.faces.len() - start);
            for (j, face) in self.faces[start..start + len].iter().enumerate() {
                for (k, &v) in face.iter().enumerate() {
                    for c in 0..3 {
                        points[k][c][j] = positions[v as usize][c];
                    }
                }
            }
            arch.dispatch(FoldTests {
                points: &points,
                normals0: &self.guard.normals0[start..start + len],
                cos_limit: &self.guard.cos_limit[start..start + len],
                folded: &mut folded[..len],
                normals: &mut normals,
            });
            if let Some(out) = face_normals.as_deref_mut() {
                for (j, n) in out[start..start + len].iter_mut().enumerate() {
                    *n = [normals[0][j], normals[1][j], normals[2][j]];
                }
            }
            out.extend((0..len).filter(|&j| folded[j]).map(|j| start + j));
        }
        out
    }

    /// Positions with the interior vertices replaced.
    pub fn with_interior(&self, base: &[[f64; 3]], interior: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut out = base.to_vec();
        for (i, &p) in self.layout.interior.iter().enumerate() {
            out[p as usize] = interior[i];
        }
        out
    }

    /// Interior positions of a full position array.
    pub fn interior_of(&self, positions: &[[f64; 3]]) -> Vec<[f64; 3]> {
        self.layout
            .interior
            .iter()
            .map(|&p| positions[p as usize])
            .collect()
    }

    /// θ_err = max |θ − 2π| and the squared residual ‖θ − 2π‖² from interior θ.
    pub fn errors(theta: &[f64]) -> (f64, f64) {
        Self::merit(theta, 0.0)
    }

    /// θ_err = max |θ − 2π| and the merit Σ (|θ − 2π| − `dead_zone_rad`)₊²: residuals within
    /// the dead zone count zero; with a dead zone of 0 it is ‖θ − 2π‖², bit for bit.
    pub fn merit(theta: &[f64], dead_zone_rad: f64) -> (f64, f64) {
        theta.iter().fold((0.0f64, 0.0f64), |(m, s), &t| {
            let r = t - TAU;
            let q = beyond(r, dead_zone_rad);
            // A NaN θ is infinitely far from 2π: `f64::max` would skip it, and a piece whose
            // angles were all NaN would read as already flattenable.
            (m.max(distance_from_flat(t)), s + q * q)
        })
    }

    /// θ at every interior vertex of the input.
    pub fn input_theta(&self) -> Vec<f64> {
        let mut theta = vec![0.0; self.layout.n()];
        self.layout.theta(&self.pos0, &mut theta);
        theta
    }

    /// Fills the measured fields of a report for the final `positions`; `theta0` is
    /// [`Piece::input_theta`].
    pub fn measure(&self, positions: &[[f64; 3]], theta0: &[f64], report: &mut PieceReport) {
        let mut theta = vec![0.0; self.layout.n()];
        self.layout.theta(positions, &mut theta);
        let (err, sq) = Self::errors(&theta);
        let n = self.layout.n();
        report.final_theta_err = err;
        report.final_theta_rms = if n > 0 { (sq / n as f64).sqrt() } else { 0.0 };
        report.input_total_defect_rad = theta0.iter().map(|t| TAU - t).sum();
        report.input_theta_rms = if n > 0 {
            (Self::errors(theta0).1 / n as f64).sqrt()
        } else {
            0.0
        };
        let (mut max_d, mut sum_d2) = (0.0f64, 0.0);
        for &p in &self.layout.interior {
            let d = flatcut_mesh::vec3::dist(positions[p as usize], self.pos0[p as usize]);
            max_d = max_d.max(d);
            sum_d2 += d * d;
        }
        report.max_displacement_mm = max_d;
        report.rms_displacement_mm = if n > 0 {
            (sum_d2 / n as f64).sqrt()
        } else {
            0.0
        };
        let (a0, a1) = (self.total_area(&self.pos0), self.total_area(positions));
        report.area_change_percent = if a0 > 0.0 {
            100.0 * (a1 - a0) / a0
        } else {
            0.0
        };
        report.folded_faces = self.folded_faces(positions);
        report.holes = self.holes.closures(positions, &self.faces);
        report.final_hole_err = report
            .holes
            .iter()
            .map(HoleClosure::error_rad)
            .fold(0.0, f64::max);
        let normals = face_normals(positions, &self.faces);
        let n0 = &self.guard.normals0;
        // How far the surface turned: the largest angle between a face's normal and its
        // input normal.
        report.max_normal_turn_deg = n0
            .iter()
            .zip(&normals)
            .map(|(a, b)| angle(*a, *b))
            .fold(0.0, f64::max)
            .to_degrees();
        // Where it creased: interior edges whose bend (the angle between the normals of its
        // two faces) grew by more than CREASE_DEG over the input's.
        let crease = crate::report::CREASE_DEG.to_radians();
        let mut sharpest = (0.0f64, 0u32);
        report.creased_edges = 0;
        // The ends of creased edges, to sum the input's angle defect under the crease.
        let mut on_crease = vec![false; self.pos0.len()];
        for h in 0..3 * self.faces.len() as u32 {
            let Some(t) = self.topo.twin(h).filter(|&t| t > h) else {
                continue;
            };
            let (f, g) = (Topology::face(h).idx(), Topology::face(t).idx());
            let grown = angle(normals[f], normals[g]) - angle(n0[f], n0[g]);
            if grown > sharpest.0 {
                sharpest = (grown, self.topo.from_vertex(h).0);
            }
            if grown > crease {
                report.creased_edges += 1;
                on_crease[self.topo.from_vertex(h).idx()] = true;
                on_crease[self.topo.from_vertex(t).idx()] = true;
            }
        }
        report.max_crease_deg = sharpest.0.to_degrees();
        // (A float sum of nothing is −0.0, which would read "-0.0" in the JSON.)
        report.creased_defect_rad = if report.creased_edges == 0 {
            0.0
        } else {
            self.layout
                .interior
                .iter()
                .zip(theta0)
                .filter(|(p, _)| on_crease[**p as usize])
                .map(|(_, t)| TAU - t)
                .sum()
        };
        report.sharpest_crease_position_mm =
            (report.creased_edges > 0).then(|| self.pos0[sharpest.1 as usize]);
        if report.creased_edges > 0 {
            let at = self.vertex_map[sharpest.1 as usize];
            let [x, y, z] = self.pos0[sharpest.1 as usize];
            let kind = crate::report::CreaseKind::of(report.creased_defect_rad)
                .map_or(String::new(), |k| format!(" ({})", k.advice()));
            report.messages.push(format!(
                "{CREASE_NOTE}: {} edges bend by more than {:.0}° beyond the input's bend (up to {:.0}°, at input vertex {at} at ({x:.2}, {y:.2}, {z:.2}) mm), and the flattened piece folds there; the input's angle defect under the crease sums to {:+.3} rad{kind}",
                report.creased_edges,
                crate::report::CREASE_DEG,
                report.max_crease_deg,
                report.creased_defect_rad,
            ));
        }
        self.locate_residual(&theta, report);
        report.min_angle_deg = corner_angles(positions, &self.faces)
            .iter()
            .flatten()
            .fold(f64::INFINITY, |m, &a| m.min(a))
            .to_degrees();
    }

    /// Fills where the remaining residual of interior `theta` lies: the worst vertex, its
    /// input position, the fewest vertices holding half of ‖θ − 2π‖² and how far from the
    /// worst they reach (ties in |θ − 2π| broken by the lower local index, so the answer is
    /// deterministic).
    fn locate_residual(&self, theta: &[f64], report: &mut PieceReport) {
        let mut order: Vec<(f64, usize)> = theta
            .iter()
            .enumerate()
            .map(|(i, &t)| (distance_from_flat(t), i))
            .collect();
        order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let Some(&(_, worst)) = order.first() else {
            report.worst_vertex = None;
            report.worst_vertex_position_mm = None;
            report.vertices_holding_half_residual = 0;
            report.half_residual_radius_mm = 0.0;
            return;
        };
        let local = |i: usize| self.layout.interior[i] as usize;
        let at = self.pos0[local(worst)];
        report.worst_vertex = Some(self.vertex_map[local(worst)]);
        report.worst_vertex_position_mm = Some(at);
        let total: f64 = order.iter().map(|(r, _)| r * r).sum();
        let (mut held, mut count, mut radius) = (0.0, 0, 0.0f64);
        if total > 0.0 {
            for &(r, i) in &order {
                if held >= 0.5 * total {
                    break;
                }
                held += r * r;
                count += 1;
                radius = radius.max(flatcut_mesh::vec3::dist(self.pos0[local(i)], at));
            }
        }
        report.vertices_holding_half_residual = count;
        report.half_residual_radius_mm = radius;
    }

    /// Total area of the piece at `positions`.
    pub fn total_area(&self, positions: &[[f64; 3]]) -> f64 {
        face_areas(positions, &self.faces).iter().sum()
    }

    /// Mean length of each interior vertex's incident edges in the input (each edge is
    /// counted once per incident face, i.e. twice for an interior edge: same mean).
    pub fn interior_edge_lengths(&self) -> Vec<f64> {
        let mut sum = vec![0.0; self.pos0.len()];
        let mut count = vec![0u32; self.pos0.len()];
        for f in &self.faces {
            for k in 0..3 {
                let (a, b) = (f[k] as usize, f[(k + 1) % 3] as usize);
                let l = flatcut_mesh::vec3::dist(self.pos0[a], self.pos0[b]);
                for v in [a, b] {
                    sum[v] += l;
                    count[v] += 1;
                }
            }
        }
        self.layout
            .interior
            .iter()
            .map(|&p| sum[p as usize] / f64::from(count[p as usize].max(1)))
            .collect()
    }

    /// Area-weighted unit vertex normals of the interior vertices at `positions`.
    pub fn interior_normals(&self, positions: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let face_normals: Vec<[f64; 3]> = self
            .faces
            .iter()
            .map(|f| {
                cross(
                    sub(positions[f[1] as usize], positions[f[0] as usize]),
                    sub(positions[f[2] as usize], positions[f[0] as usize]),
                )
            })
            .collect();
        self.interior_normals_from_faces(&face_normals)
    }

    /// [`Piece::interior_normals`] from the faces' (f1 − f0) × (f2 − f0), one per face.
    pub fn interior_normals_from_faces(&self, face_normals: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut acc = vec![[0.0; 3]; self.pos0.len()];
        for (f, &n) in self.faces.iter().zip(face_normals) {
            for &v in f {
                for c in 0..3 {
                    acc[v as usize][c] += n[c];
                }
            }
        }
        self.layout
            .interior
            .iter()
            .map(|&p| flatcut_mesh::vec3::normalize(acc[p as usize]))
            .collect()
    }
}

/// How [`Piece::measure`]'s note on creases begins: a measure taken again on other vertices
/// (the piece itself after its filled copy ran, `HoleRims::Free`) replaces the note by it.
pub(crate) const CREASE_NOTE: &str = "the processed surface creases";

/// Median |2π − θ| over the input's interior vertices (rad) above which a piece is rough (scan
/// noise): one that does not converge is called so in its error, instead of the Gauss–Bonnet
/// hints, and its attempts end with the direct solve under the shaped damping
/// (`coarse_to_fine::shaped_direct`). Measured: smooth real meshes 0.000–0.004 (igl_face,
/// mountain_disk, igl_lilium, igl_snail, igl_inspired_mesh), a coarse hand 0.042
/// (smpl_hand_lowres); the noisy scan remeshed to 8 mm 0.17 (its trimmed pieces
/// 0.155–0.164), 0.006 after ten Taubin steps. Noise makes the total defect a sum of
/// spikes (+4 to +11 rad on the scan's legs, +0.34 on the clean body's thigh), so the
/// cup/saddle reading of it would mislead.
const ROUGH_MEDIAN_DEFECT_RAD: f64 = 0.1;
/// …over at least this many interior vertices: over a handful the median is the shape's own
/// curvature, not noise (a cone's one interior vertex, a coarse cup's dozen: their defects are
/// large because their vertices are few), and the Gauss–Bonnet hints apply. The rough pieces
/// measured have thousands.
const ROUGH_MIN_INTERIOR: usize = 30;

/// The median |2π − θ| over the interior vertices of a piece's input (`theta0`, its
/// [`Piece::input_theta`]) where that says the surface is rough ([`ROUGH_MEDIAN_DEFECT_RAD`],
/// [`ROUGH_MIN_INTERIOR`]), else `None`.
pub fn rough_median(theta0: &[f64]) -> Option<f64> {
    if theta0.len() < ROUGH_MIN_INTERIOR {
        return None;
    }
    let mut d: Vec<f64> = theta0.iter().map(|t| (TAU - t).abs()).collect();
    let mid = d.len() / 2;
    let median = *d.select_nth_unstable_by(mid, f64::total_cmp).1;
    (median > ROUGH_MEDIAN_DEFECT_RAD).then_some(median)
}

/// |θ − 2π| of an interior angle sum, with NaN infinitely far (as in [`Piece::merit`]).
#[inline]
pub fn distance_from_flat(theta: f64) -> f64 {
    let r = theta - TAU;
    if r.is_nan() { f64::INFINITY } else { r.abs() }
}

/// The part of a residual `r` beyond ±`dead_zone_rad` (0 inside it; `r` itself, bit for bit,
/// for a dead zone of 0, except that −0.0 becomes +0.0).
#[inline]
pub fn beyond(r: f64, dead_zone_rad: f64) -> f64 {
    r - r.clamp(-dead_zone_rad, dead_zone_rad)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A NaN angle is infinitely far from 2π, wherever it stands (`f64::max` alone skips it,
    /// so all-NaN angles read as θ_err 0); without NaN, the sums of the plain formula.
    #[test]
    fn a_nan_angle_counts_as_infinitely_far_from_two_pi() {
        for theta in [vec![f64::NAN; 3], vec![TAU, f64::NAN, TAU + 1e-3]] {
            let (err, merit) = Piece::errors(&theta);
            assert_eq!(err, f64::INFINITY);
            assert!(merit.is_nan());
        }
        let theta = [TAU - 0.25, TAU + 0.5, TAU];
        assert_eq!(Piece::errors(&theta), (0.5, 0.25 * 0.25 + 0.5 * 0.5));
    }

    /// The guard's block loop against the fold rule stated with the mesh crate's own
    /// normals and angles (acos of normalised vectors, not the guard's cosine comparison),
    /// on a grid of 882 faces (four blocks) with folds planted in several blocks.
    #[test]
    fn the_fold_guard_finds_the_faces_the_rule_names() {
        let mesh = flatcut_mesh::shapes::grid_patch(22, 22, 100.0, |x, y| 0.001 * x * y);
        let topo = Topology::build(&mesh).unwrap();
        let n = mesh.positions.len();
        let floor_deg = 0.5;
        let piece = Piece::new(
            0,
            (0..n as u32).collect(),
            &mesh,
            topo,
            &vec![1.0; n],
            floor_deg,
        )
        .unwrap();
        let rule = |pos: &[[f64; 3]]| -> Vec<usize> {
            let (normals0, normals) = (
                face_normals(&mesh.positions, &mesh.faces),
                face_normals(pos, &mesh.faces),
            );
            let (angles0, angles) = (
                corner_angles(&mesh.positions, &mesh.faces),
                corner_angles(pos, &mesh.faces),
            );
            let floor = f64::to_radians(floor_deg);
            (0..mesh.faces.len())
                .filter(|&f| {
                    dot(normals[f], normals0[f]) <= 0.0
                        || (0..3).any(|k| {
                            let limit = if angles0[f][k] >= floor {
                                floor
                            } else {
                                0.5 * angles0[f][k]
                            };
                            angles[f][k] < limit
                        })
                })
                .collect()
        };
        assert!(piece.offending_faces(&mesh.positions).is_empty());
        let mut pos = mesh.positions.clone();
        // A vertex pushed across its ring (flips), one pulled onto an edge of its ring
        // (slivers), in different blocks.
        let (a, b) = (5 * 22 + 5, 17 * 22 + 12);
        pos[a][0] += 12.0;
        let (p, q) = (pos[b - 1], pos[b + 22]);
        pos[b] = [
            0.5 * (p[0] + q[0]) + 1e-4,
            0.5 * (p[1] + q[1]),
            0.5 * (p[2] + q[2]),
        ];
        let found = piece.offending_faces(&pos);
        let expected = rule(&pos);
        assert!(expected.len() >= 3, "{expected:?}");
        assert!(expected.iter().any(|&f| f < 256) && expected.iter().any(|&f| f >= 512));
        assert_eq!(found, expected);
        assert_eq!(piece.folded_faces(&pos), expected.len());
        // A NaN counts every face.
        pos[7][2] = f64::NAN;
        assert_eq!(piece.folded_faces(&pos), mesh.faces.len());
    }

    /// The face normals the guard writes (four blocks of faces) give the metric's vertex
    /// normals bit for bit as `interior_normals` forms them, and those equal the mesh
    /// crate's area-weighted normals to round-off.
    #[test]
    fn the_guards_face_normals_give_the_interior_normals_bit_for_bit() {
        let mut mesh = flatcut_mesh::shapes::grid_patch(22, 22, 100.0, |x, y| 0.001 * x * y);
        for (i, p) in mesh.positions.iter_mut().enumerate() {
            p[2] += 0.3 * ((i * 7919 % 13) as f64 / 13.0 - 0.5);
        }
        let topo = Topology::build(&mesh).unwrap();
        let n = mesh.positions.len();
        let piece =
            Piece::new(0, (0..n as u32).collect(), &mesh, topo, &vec![1.0; n], 0.5).unwrap();
        let mut from_faces = vec![[f64::NAN; 3]; mesh.faces.len()];
        let offending = piece.offending_faces_with_normals(&mesh.positions, Some(&mut from_faces));
        assert!(offending.is_empty());
        assert!(mesh.faces.len() > 3 * 256, "the faces span several blocks");
        let from_guard = piece.interior_normals_from_faces(&from_faces);
        let direct = piece.interior_normals(&mesh.positions);
        assert_eq!(from_guard.len(), piece.layout.n());
        // Area-weighted from the mesh crate: Σ |cross| · unit normal over a vertex's faces.
        let reference =
            flatcut_mesh::geometry::area_weighted_vertex_normals(&mesh.positions, &mesh.faces);
        for (i, (g, d)) in from_guard.iter().zip(&direct).enumerate() {
            assert_eq!(
                g.map(f64::to_bits),
                d.map(f64::to_bits),
                "interior vertex {i}"
            );
            let r = flatcut_mesh::vec3::normalize(reference[piece.layout.interior[i] as usize]);
            assert!(
                dot(*g, r) > 1.0 - 1e-12,
                "interior vertex {i}: {g:?} vs {r:?}"
            );
        }
    }

    /// The median of |2π − θ| by hand: 31 interior vertices with defects 0, 0.01, …, 0.30
    /// rad, half of them of either sign, have the median 0.15 (rough); scaled to 0 … 0.06,
    /// the median 0.03 (smooth); 29 vertices are too few to tell noise from shape.
    #[test]
    fn rough_median_is_the_median_defect_over_enough_vertices() {
        let theta = |scale: f64, n: usize| -> Vec<f64> {
            (0..n)
                .map(|k| {
                    let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                    TAU - sign * scale * k as f64
                })
                .collect()
        };
        let median = rough_median(&theta(0.01, 31)).unwrap();
        assert!((median - 0.15).abs() < 1e-12, "{median}");
        assert_eq!(rough_median(&theta(0.002, 31)), None);
        assert_eq!(rough_median(&theta(0.01, ROUGH_MIN_INTERIOR - 1)), None);
        assert_eq!(rough_median(&vec![TAU; 100]), None);
    }

    #[test]
    fn the_merit_with_no_dead_zone_is_the_squared_residual_bit_for_bit() {
        let theta = [TAU + 3e-3, TAU - 1e-9, TAU + 2.5e-10, TAU, TAU - 0.7];
        let (mut max, mut sum) = (0.0f64, 0.0f64);
        for t in theta {
            max = max.max((t - TAU).abs());
            sum += (t - TAU) * (t - TAU);
        }
        let (err, f) = Piece::merit(&theta, 0.0);
        assert_eq!((err.to_bits(), f.to_bits()), (max.to_bits(), sum.to_bits()));
        // (−0.0 comes back as +0.0, the same value; 2π − θ is never −0.0.)
        for r in [3e-3, -1e-9, 0.0, 1e-300, -7.0] {
            assert_eq!(beyond(r, 0.0).to_bits(), r.to_bits());
        }
    }

    #[test]
    fn the_dead_zone_counts_only_what_lies_beyond_it() {
        let z = 5e-10;
        // Residuals θ − 2π of +2e-9, −2e-9 (beyond by 1.5e-9 each), +4e-10 and −5e-10 (inside).
        let theta = [TAU + 2e-9, TAU - 2e-9, TAU + 4e-10, TAU - 5e-10];
        let (err, f) = Piece::merit(&theta, z);
        assert_eq!(err, (theta[0] - TAU).abs().max((theta[1] - TAU).abs()));
        // Σ (|r| − z)₊² from the residuals as represented, against 2·(1.5e-9)².
        let expect: f64 = theta
            .iter()
            .map(|t| ((t - TAU).abs() - z).max(0.0).powi(2))
            .sum();
        assert!((f - expect).abs() <= 1e-12 * expect, "{f} vs {expect}");
        assert!((f - 2.0 * 1.5e-9f64.powi(2)).abs() < 1e-3 * f, "{f}");
        assert_eq!(beyond(4e-10, z), 0.0);
        assert_eq!(beyond(-3e-9, z), -3e-9 + z);
    }
}
