//! Whether the holes of a piece close in the plane.
//!
//! The paper's theorem is for a piece with one boundary loop: θ = 2π at every interior
//! vertex and it develops into the plane without stretch. A piece with holes needs more. Its
//! flat metric develops around each hole with a rigid motion of the plane (the holonomy),
//! and the pattern only exists when that motion is the identity: developed with its edge
//! lengths and the angles of the material at its vertices, the hole's polygon must turn by
//! exactly −2π (the material on the left) and end where it began. A sheet with two holes on
//! a sphere, processed to θ_err 1e-9, flattened with 1.2 % stretch around them; a band cut
//! from a cylinder (or a ring around a cone's apex) is flat at every interior vertex and
//! cannot be laid flat at all without a cut.
//!
//! For a hole with vertices v_0 … v_{k−1} (boundary order: material on the left), material
//! angle β_j (the summed corner angles at v_j), edges l_j = |v_{j+1} − v_j| and length
//! L = Σ l_j, the development has headings φ_0 = 0, φ_j = Σ_{m=1..j} (π − β_m) and end
//! point P = Σ_j l_j e^{iφ_j}. The hole closes when Σ_j (π − β_j) + 2π = 0 and P = 0; both
//! are measured ([`HoleClosure`]). (A step that held them as constraints, with
//! ∂P/∂β_m = −i Σ_{j≥m} l_j e^{iφ_j}, was tried in the thirty-fifth session and not kept:
//! docs/algorithms/flattenable.md, "Holes: θ = 2π does not close them".)
//!
//! Which loop is the outer one is not a property of the surface (a band has two equal
//! candidates); the longest loop in 3D is taken, as a pattern's outline encloses its holes.
//! With θ = 2π everywhere and every hole closed, the outer loop closes too (Gauss–Bonnet and
//! a simply connected development).

use std::f64::consts::{PI, TAU};

use flatcut_mesh::geometry::{angle_sums, loop_length};
use flatcut_mesh::vec3::dist;
use flatcut_mesh::{Topology, VertexId};
use serde::Serialize;

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

/// The least closed of `holes` (the largest [`HoleClosure::error_rad`]), if any.
pub fn least_closed<'a>(
    holes: impl IntoIterator<Item = &'a HoleClosure>,
) -> Option<&'a HoleClosure> {
    holes
        .into_iter()
        .max_by(|a, b| a.error_rad().total_cmp(&b.error_rad()))
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

impl Holes {
    /// The holes of a piece with topology `topo`, the outline chosen at `positions` (its
    /// input).
    pub fn of(topo: &Topology, positions: &[[f64; 3]]) -> Self {
        let loops = topo.boundary_loops();
        let lengths: Vec<f64> = loops.iter().map(|l| loop_length(positions, l)).collect();
        // The longest loop is the outline; ties go to the first.
        let outer = (0..loops.len()).fold(None::<usize>, |best, i| match best {
            Some(b) if lengths[b] >= lengths[i] => Some(b),
            _ => Some(i),
        });
        let holes = loops
            .iter()
            .enumerate()
            .filter(|&(i, _)| Some(i) != outer)
            .map(|(loop_index, l)| Hole {
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

    /// How every hole develops at `positions` (of the piece with faces `faces`).
    pub fn closures(&self, positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<HoleClosure> {
        if self.holes.is_empty() {
            return Vec::new();
        }
        let beta = angle_sums(positions, faces);
        self.holes
            .iter()
            .map(|h| h.develop(positions, &beta))
            .collect()
    }
}

impl Hole {
    /// Its development with the material angles `beta` (per vertex).
    fn develop(&self, positions: &[[f64; 3]], beta: &[f64]) -> HoleClosure {
        let k = self.vertices.len();
        let (mut heading, mut end) = (0.0, [0.0; 2]);
        for j in 0..k {
            if j > 0 {
                heading += PI - beta[self.vertices[j].idx()];
            }
            let l = dist(
                positions[self.vertices[j].idx()],
                positions[self.vertices[(j + 1) % k].idx()],
            );
            end = [end[0] + l * heading.cos(), end[1] + l * heading.sin()];
        }
        let turning: f64 = self.vertices.iter().map(|v| PI - beta[v.idx()]).sum();
        HoleClosure {
            loop_index: self.loop_index,
            vertices: k,
            length_mm: loop_length(positions, &self.vertices),
            turning_residual_rad: turning + TAU,
            gap_mm: end[0].hypot(end[1]),
        }
    }
}
