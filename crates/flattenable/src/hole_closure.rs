//! Whether the holes of a piece close in the plane, and the three constraints per hole that
//! say so.
//!
//! The paper's theorem is for a piece with one boundary loop: θ = 2π at every interior
//! vertex and it develops into the plane without stretch. A piece with holes needs more. Its
//! flat metric develops around each hole with a rigid motion of the plane (the holonomy),
//! and the pattern only exists when that motion is the identity: developed with its edge
//! lengths and the angles of the material at its vertices, the hole's polygon must turn by
//! exactly −2π (the material on the left) and end where it began. A sheet with two holes on
//! a sphere, processed to θ_err 1e-9, flattened with 1.3 % stretch around them; a band cut
//! from a cylinder (or a ring around a cone's apex) is flat at every interior vertex and
//! cannot be laid flat at all without a cut.
//!
//! For a hole with vertices v_0 … v_{k−1} (boundary order: material on the left), material
//! angle β_j (the summed corner angles at v_j), edges l_j = |v_{j+1} − v_j| and length
//! L = Σ l_j, the development has headings φ_0 = 0, φ_j = Σ_{m=1..j} (π − β_m) and end
//! point P = Σ_j l_j e^{iφ_j}. The constraints, all in radians so that they weigh like
//! θ − 2π:
//!
//! - turning: Σ_j (π − β_j) + 2π = 0;
//! - closure: Re P / L = 0 and Im P / L = 0 (the gap over the hole's length).
//!
//! With the rims held (`HoleRims::Fixed`) the l_j are constants and only the β_j move,
//! through the interior vertices next to the hole (`angle_gradient::angle_sum_gradient` at a boundary
//! vertex): ∂P/∂β_m = −i Σ_{j≥m} l_j e^{iφ_j} for m ≥ 1.
//!
//! Which loop is the outer one is not a property of the surface (a band has two equal
//! candidates); the longest loop in 3D is taken, as a pattern's outline encloses its holes.
//! With θ = 2π everywhere and every hole closed, the outer loop closes too (Gauss–Bonnet and
//! a simply connected development), so it carries no constraint.

use std::f64::consts::{PI, TAU};

use flatcut_mesh::vec3::dist;
use flatcut_mesh::{INVALID, Topology, VertexId};
use serde::Serialize;

use crate::angle_gradient::angle_sum_gradient;
use crate::least_norm::Layout;

/// Constraints per hole: turning, and the closure gap's two components.
pub const ROWS_PER_HOLE: usize = 3;

/// How one hole of a result develops in the plane (the report's `holes`).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct HoleClosure {
    /// The hole's boundary loop (index into the piece's loops, in the topology's order).
    pub loop_index: usize,
    /// Its vertices.
    pub vertices: usize,
    /// Its length (mm).
    pub length_mm: f64,
    /// Σ (π − β) + 2π over its vertices (rad): how far the hole's development is from
    /// turning once; 0 when it closes. By Gauss–Bonnet, the Gaussian curvature the hole
    /// encloses (positive on a sphere).
    pub turning_residual_rad: f64,
    /// |P|: how far the developed polygon ends from where it began (mm).
    pub gap_mm: f64,
}

impl HoleClosure {
    /// The larger of |turning residual| and gap / length (rad): the hole's constraint error,
    /// compared with the tolerance like θ_err.
    pub fn error_rad(&self) -> f64 {
        self.turning_residual_rad
            .abs()
            .max(self.gap_mm / self.length_mm.max(f64::MIN_POSITIVE))
    }

    /// Whether the hole closes, for a result whose θ is within `tolerance_rad` of 2π: its
    /// error is at most (vertices + 1) · `tolerance_rad`. A hole closed through a flat fill
    /// of its own (`HoleRims::Free`) turns by 2π − θ(centre) plus the sum of the rim
    /// vertices' residuals, and each heading of its development carries those of the rim
    /// before it, so that much round-off of θ = 2π reaches it.
    pub fn closes(&self, tolerance_rad: f64) -> bool {
        self.error_rad() <= tolerance_rad * (self.vertices + 1) as f64
    }
}

/// One hole: its boundary loop and vertices in boundary order.
#[derive(Clone, Debug)]
struct Hole {
    loop_index: usize,
    vertices: Vec<VertexId>,
}

/// The holes of a piece: every boundary loop but the longest.
#[derive(Clone, Debug, Default)]
pub struct Holes {
    holes: Vec<Hole>,
}

/// The development of a hole at one set of positions.
struct Development {
    /// L (mm).
    length_mm: f64,
    turning_residual_rad: f64,
    /// P (mm).
    end: [f64; 2],
    /// Σ_{j≥m} l_j e^{iφ_j} per vertex m (mm), the suffix sums of the gradient.
    suffix: Vec<[f64; 2]>,
}

impl Holes {
    /// The holes of a piece with topology `topo`, the outline chosen at `positions` (its
    /// input).
    pub fn of(topo: &Topology, positions: &[[f64; 3]]) -> Self {
        let loops = topo.boundary_loops();
        let lengths: Vec<Vec<f64>> = loops
            .iter()
            .map(|l| {
                (0..l.len())
                    .map(|j| dist(positions[l[j].idx()], positions[l[(j + 1) % l.len()].idx()]))
                    .collect()
            })
            .collect();
        let total = |e: &[f64]| e.iter().sum::<f64>();
        // The longest loop is the outline; ties go to the first.
        let outer = (0..loops.len()).fold(None::<usize>, |best, i| match best {
            Some(b) if total(&lengths[b]) >= total(&lengths[i]) => Some(b),
            _ => Some(i),
        });
        let holes = loops
            .iter()
            .zip(lengths)
            .enumerate()
            .filter(|&(i, _)| Some(i) != outer)
            .map(|(loop_index, (l, _))| Hole {
                loop_index,
                vertices: l.clone(),
            })
            .collect();
        Self { holes }
    }

    /// Every hole's rim: its boundary loop's vertices, in boundary order (the material on
    /// the left).
    pub fn rims(&self) -> impl Iterator<Item = &[VertexId]> {
        self.holes.iter().map(|h| h.vertices.as_slice())
    }

    /// Number of holes.
    pub fn len(&self) -> usize {
        self.holes.len()
    }

    /// No hole: a disk (or a piece without boundary).
    pub fn is_empty(&self) -> bool {
        self.holes.is_empty()
    }

    /// Number of constraints, [`ROWS_PER_HOLE`] per hole.
    pub fn rows(&self) -> usize {
        ROWS_PER_HOLE * self.holes.len()
    }

    /// How every hole develops at `positions`.
    pub fn closures(
        &self,
        positions: &[[f64; 3]],
        faces: &[[u32; 3]],
        topo: &Topology,
    ) -> Vec<HoleClosure> {
        self.holes
            .iter()
            .map(|h| {
                let dev = h.develop(positions, faces, topo);
                HoleClosure {
                    loop_index: h.loop_index,
                    vertices: h.vertices.len(),
                    length_mm: dev.length_mm,
                    turning_residual_rad: dev.turning_residual_rad,
                    gap_mm: dev.end[0].hypot(dev.end[1]),
                }
            })
            .collect()
    }

    /// The constraint values at `positions`: per hole the turning residual, Re P / L and
    /// Im P / L (rad; all 0 when every hole closes).
    pub fn residuals(
        &self,
        positions: &[[f64; 3]],
        faces: &[[u32; 3]],
        topo: &Topology,
    ) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.rows());
        for h in &self.holes {
            out.extend(h.develop(positions, faces, topo).constraints());
        }
        out
    }

    /// The constraint values and their gradients with respect to the interior vertices
    /// (`layout`'s order; one field per constraint, in the order of [`Holes::residuals`]),
    /// with the rims held (their edge lengths are then constants): the rows a step holding
    /// the holes would add to A (tried in the thirty-fifth session and not kept; see
    /// docs/algorithms/flattenable.md, "Holes: θ = 2π does not close them").
    pub fn residuals_and_gradients(
        &self,
        positions: &[[f64; 3]],
        faces: &[[u32; 3]],
        topo: &Topology,
        layout: &Layout,
    ) -> (Vec<f64>, Vec<Vec<[f64; 3]>>) {
        let mut values = Vec::with_capacity(self.rows());
        let mut rows = Vec::with_capacity(self.rows());
        for h in &self.holes {
            let dev = h.develop(positions, faces, topo);
            values.extend(dev.constraints());
            let mut turning = vec![[0.0; 3]; layout.n()];
            let mut gap_x = vec![[0.0; 3]; layout.n()];
            let mut gap_y = vec![[0.0; 3]; layout.n()];
            for (m, &v) in h.vertices.iter().enumerate() {
                // ∂/∂β_m of the three constraints: −1; Im S_m / L and −Re S_m / L (m ≥ 1,
                // β_0 only sets the turning: P's frame starts on edge 0).
                let s = if m == 0 { [0.0; 2] } else { dev.suffix[m] };
                let coefficient = [-1.0, s[1] / dev.length_mm, -s[0] / dev.length_mm];
                let (_, grad) = angle_sum_gradient(positions, faces, topo, v);
                for (q, g) in grad {
                    let i = layout.index_of[q.idx()];
                    if i == INVALID {
                        continue;
                    }
                    for (row, c) in [&mut turning, &mut gap_x, &mut gap_y]
                        .into_iter()
                        .zip(coefficient)
                    {
                        for k in 0..3 {
                            row[i as usize][k] += c * g[k];
                        }
                    }
                }
            }
            rows.extend([turning, gap_x, gap_y]);
        }
        (values, rows)
    }
}

impl Development {
    /// The hole's three constraint values: turning residual, Re P / L, Im P / L (rad).
    fn constraints(&self) -> [f64; ROWS_PER_HOLE] {
        [
            self.turning_residual_rad,
            self.end[0] / self.length_mm,
            self.end[1] / self.length_mm,
        ]
    }
}

impl Hole {
    fn develop(&self, positions: &[[f64; 3]], faces: &[[u32; 3]], topo: &Topology) -> Development {
        let k = self.vertices.len();
        let turn: Vec<f64> = self
            .vertices
            .iter()
            .map(|&v| PI - material_angle(positions, faces, topo, v))
            .collect();
        // Headings φ_j and the terms l_j e^{iφ_j}; then their suffix sums.
        let edges: Vec<f64> = (0..k)
            .map(|j| {
                dist(
                    positions[self.vertices[j].idx()],
                    positions[self.vertices[(j + 1) % k].idx()],
                )
            })
            .collect();
        let mut heading = 0.0;
        let mut terms = Vec::with_capacity(k);
        for j in 0..k {
            if j > 0 {
                heading += turn[j];
            }
            terms.push([edges[j] * heading.cos(), edges[j] * heading.sin()]);
        }
        let mut suffix = vec![[0.0; 2]; k];
        let mut acc = [0.0; 2];
        for j in (0..k).rev() {
            acc = [acc[0] + terms[j][0], acc[1] + terms[j][1]];
            suffix[j] = acc;
        }
        Development {
            length_mm: edges.iter().sum(),
            turning_residual_rad: turn.iter().sum::<f64>() + TAU,
            end: suffix.first().copied().unwrap_or([0.0; 2]),
            suffix,
        }
    }
}

/// β(v): the summed corner angles of the faces at `v`.
fn material_angle(positions: &[[f64; 3]], faces: &[[u32; 3]], topo: &Topology, v: VertexId) -> f64 {
    topo.outgoing(v)
        .iter()
        .map(|&h| {
            let f = faces[Topology::face(h).idx()];
            let k = (h % 3) as usize;
            let (a, b) = (f[(k + 1) % 3], f[(k + 2) % 3]);
            flatcut_mesh::vec3::angle(
                flatcut_mesh::vec3::sub(positions[a as usize], positions[v.idx()]),
                flatcut_mesh::vec3::sub(positions[b as usize], positions[v.idx()]),
            )
        })
        .sum()
}
