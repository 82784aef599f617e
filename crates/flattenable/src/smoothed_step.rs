//! The smoothed Gauss–Newton step: how a shallow piece at scan resolution leaves the plateau
//! its damped steps stall on.
//!
//! On a shallow piece (the paraboloid z = 0.1 (x² + y²) on [−1, 1]² at 160×160 vertices) the
//! damped steps stop gaining near θ = 2π: what is left of θ − 2π is smooth over the whole
//! piece, and so is the displacement that removes it (about one edge length). The undamped
//! least-norm step contains that displacement, but also rough components (normal bumps of
//! nearly flat stars, where the rows of A nearly vanish) whose second-order terms raise the
//! merit 1e7-fold; the damping that keeps them out keeps the smooth part out too, and each
//! damped step then gains 0.001–0.01 % of ‖θ − 2π‖². Low-pass filtering the undamped step,
//! (I + t L)⁻¹ d with L the graph Laplacian of the interior vertices (boundary vertices fixed
//! at zero displacement), removes the rough part and keeps the smooth one: scaled to the
//! linear model's optimum, one such step gained 40 % where the damped one gained 0.003 %
//! (docs/algorithms/flattenable.md, "Shallow pieces: a smoothed step").
//!
//! Which smoothing length suits depends on the piece and the stage (the filtered steps of the
//! 225×225 paraboloid gained most at t = 16 early and t = 1 late), so several stiffnesses t
//! are tried and the best result kept. L depends only on the connectivity, so its
//! factorisations are computed once per run.

use flatcut_sparse::{SpdFactor, SpdPattern, Triplets};

use crate::least_norm::Layout;

/// The stiffnesses t of the filters (I + t L)⁻¹ tried, in graph-Laplacian units: on a
/// valence-6 grid of 21×21 vertices t = 1 keeps 11 % of a field alternating in sign and 91 % of
/// the smoothest sine bump, t = 256 0.05 % and 4 % (`rough_fields_are_damped_more_…`). Measured on the paraboloid battery (`SHAPE=para`, A =
/// 0.01–0.3, N = 130–225): 1, 4, 16 and 64 each gave the best step at some stage; a fixed
/// single filter (50 Jacobi passes) converged some sizes and stalled others.
pub(crate) const FILTER_STIFFNESS: [f64; 5] = [1.0, 4.0, 16.0, 64.0, 256.0];

/// The filter of a smoothed jump, an index into `FILTER_STIFFNESS` (t = 16): it both smooths
/// the step and measures the residual's smooth part ([`smooth_part_scale`]). On the jittered
/// paraboloid z = 0.03 (x² + y²) at 200×200 (`JITTER=0.3 SHAPE=para … measure -- saddles`),
/// which stalled at 1.9e-8, whole jumps (not the quarter taken now) with t = 16 and t = 64
/// both converged (75 and 77 iterations); t = 16 leaves 13 % of the smooth residual in the
/// model, t = 64 3 %, and raises the merit less (docs/algorithms/flattenable.md, "Irregular
/// shallow pieces: a smoothed jump").
pub(crate) const JUMP_FILTER: usize = 2;

/// I + t L for a piece's interior vertices (L its graph Laplacian with the boundary held at
/// zero, [`Layout::graph_triplets`]): the pattern, analysed once.
pub(crate) struct Filters {
    pattern: SpdPattern,
}

/// I + t L as triplets.
fn screened_laplacian(layout: &Layout, stiffness: f64) -> Triplets {
    layout.graph_triplets(|valence| 1.0 + stiffness * valence, -stiffness)
}

impl Filters {
    /// The pattern of `layout`'s interior graph; `None` only when its symbolic factorisation
    /// cannot be allocated.
    pub(crate) fn new(layout: &Layout) -> Option<Self> {
        let pattern = screened_laplacian(layout, 1.0).pattern().ok()?;
        Some(Self { pattern })
    }

    /// The numeric factorisations of I + t L for every t of `FILTER_STIFFNESS`, in that
    /// order (I + t L is strictly diagonally dominant, so each succeeds unless memory runs
    /// out; then `None`).
    pub(crate) fn factors(&self, layout: &Layout) -> Option<Vec<SpdFactor<'_>>> {
        FILTER_STIFFNESS
            .iter()
            .map(|&t| {
                self.pattern
                    .factor(screened_laplacian(layout, t).values())
                    .ok()
            })
            .collect()
    }
}

/// (I + t L)⁻¹ `field`, coordinate by coordinate; `None` if the solve fails or is not finite.
pub(crate) fn filtered(factor: &SpdFactor<'_>, field: &[[f64; 3]]) -> Option<Vec<[f64; 3]>> {
    let n = field.len();
    let mut rhs = vec![0.0; 3 * n];
    for (i, v) in field.iter().enumerate() {
        for c in 0..3 {
            rhs[c * n + i] = v[c];
        }
    }
    factor.solve_in_place(&mut rhs, 3).ok()?;
    let out: Vec<[f64; 3]> = (0..n)
        .map(|i| [rhs[i], rhs[n + i], rhs[2 * n + i]])
        .collect();
    out.iter()
        .all(|v| v.iter().all(|x| x.is_finite()))
        .then_some(out)
}

/// (I + t L)⁻¹ `field` for a scalar field (one value per interior vertex); `None` if the
/// solve fails or is not finite.
pub(crate) fn filtered_scalar(factor: &SpdFactor<'_>, field: &[f64]) -> Option<Vec<f64>> {
    let mut out = field.to_vec();
    factor.solve_in_place(&mut out, 1).ok()?;
    out.iter().all(|x| x.is_finite()).then_some(out)
}

/// The scale s that minimises ‖F (b − s A d)‖², F = (I + t L)⁻¹ the filter `factor`: the
/// linear model of the residual's smooth part along d, given A d. On an irregular
/// triangulation the angle sums answer a smooth displacement with a rough term as well (the
/// angle defect is a consistent curvature only summed over regions, not vertex by vertex),
/// which [`model_scale`] weighs as much as the smooth answer; this scale weighs only what
/// survives the filter. `None` when F A d vanishes or a solve fails.
pub(crate) fn smooth_part_scale(factor: &SpdFactor<'_>, b: &[f64], ad: &[f64]) -> Option<f64> {
    let (fb, fad) = (filtered_scalar(factor, b)?, filtered_scalar(factor, ad)?);
    let aa: f64 = fad.iter().map(|y| y * y).sum();
    (aa > 0.0).then(|| fb.iter().zip(&fad).map(|(x, y)| x * y).sum::<f64>() / aa)
}

/// The scale s that minimises ‖b − s A d‖² (the linear model along d), given A d; 0 when
/// A d = 0.
pub(crate) fn model_scale(b: &[f64], ad: &[f64]) -> f64 {
    let aa: f64 = ad.iter().map(|y| y * y).sum();
    if aa > 0.0 {
        b.iter().zip(ad).map(|(x, y)| x * y).sum::<f64>() / aa
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::{
        FILTER_STIFFNESS, Filters, filtered, filtered_scalar, model_scale, screened_laplacian,
        smooth_part_scale,
    };
    use crate::least_norm::Layout;
    use flatcut_mesh::{Topology, TriMesh};

    /// An n×n grid of the unit square, split along one diagonal per cell.
    fn grid(n: usize) -> TriMesh {
        let mut positions = Vec::new();
        for j in 0..n {
            for i in 0..n {
                positions.push([i as f64, j as f64, 0.1 * ((i * j) % 3) as f64]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = (j * n + i) as u32;
                let n = n as u32;
                faces.push([v, v + 1, v + n + 1]);
                faces.push([v, v + n + 1, v + n]);
            }
        }
        TriMesh::new(positions, faces).unwrap()
    }

    fn layout(mesh: &TriMesh) -> Layout {
        let topo = Topology::build(mesh).unwrap();
        Layout::build(&topo, &mesh.faces).unwrap()
    }

    /// (I + t L) applied to a field, entry by entry from its triplets: the second formula
    /// the filter is checked against.
    fn apply(layout: &Layout, stiffness: f64, field: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let matrix = screened_laplacian(layout, stiffness);
        let mut out = vec![[0.0; 3]; field.len()];
        for (&(i, j), &v) in matrix.pairs().iter().zip(matrix.values()) {
            for c in 0..3 {
                out[i][c] += v * field[j][c];
                if i != j {
                    out[j][c] += v * field[i][c];
                }
            }
        }
        out
    }

    /// The filter inverts I + t L (checked with the matrix applied entry by entry), and on
    /// a valence-6 grid the degree of every interior vertex is 6, boundary neighbours
    /// included.
    #[test]
    fn filter_inverts_the_screened_laplacian() {
        let mesh = grid(9);
        let layout = layout(&mesh);
        let laplacian = screened_laplacian(&layout, 1.0);
        let degrees: Vec<f64> = laplacian
            .pairs()
            .iter()
            .zip(laplacian.values())
            .filter(|((i, j), _)| i == j)
            .map(|(_, v)| v - 1.0)
            .collect();
        assert_eq!(degrees.len(), layout.n());
        assert!(degrees.iter().all(|&k| k == 6.0), "{degrees:?}");
        let filters = Filters::new(&layout).unwrap();
        let field: Vec<[f64; 3]> = (0..layout.n())
            .map(|i| {
                let x = i as f64;
                [x.sin(), (0.3 * x).cos(), 1.0]
            })
            .collect();
        let factors = filters.factors(&layout).unwrap();
        assert_eq!(factors.len(), FILTER_STIFFNESS.len());
        for (factor, &t) in factors.iter().zip(&FILTER_STIFFNESS) {
            let smooth = filtered(factor, &field).unwrap();
            let back = apply(&layout, t, &smooth);
            for (a, b) in back.iter().zip(&field) {
                for c in 0..3 {
                    assert!((a[c] - b[c]).abs() < 1e-12, "t = {t}: {a:?} vs {b:?}");
                }
            }
        }
    }

    /// On the interior of the n×n `grid`: the smoothest Dirichlet mode
    /// sin(π i / h) sin(π j / h) and the field alternating in sign between neighbours along
    /// the rows and columns.
    fn bump_and_alternating(layout: &Layout, n: usize) -> (Vec<f64>, Vec<f64>) {
        let pi = std::f64::consts::PI;
        let h = (n - 1) as f64;
        layout
            .interior
            .iter()
            .map(|&v| {
                let (i, j) = ((v as usize % n) as f64, (v as usize / n) as f64);
                let alternating = if (i + j) as i64 % 2 == 0 { 1.0 } else { -1.0 };
                ((pi * i / h).sin() * (pi * j / h).sin(), alternating)
            })
            .unzip()
    }

    /// A scalar field as the first coordinate of a vector field.
    fn first_coordinate(field: &[f64]) -> Vec<[f64; 3]> {
        field.iter().map(|&x| [x, 0.0, 0.0]).collect()
    }

    /// A low-pass filter: a checkerboard-like field (alternating signs along the rows) loses
    /// far more of its norm than a smooth bump, and more at a larger stiffness.
    #[test]
    fn rough_fields_are_damped_more_than_smooth_ones() {
        let n = 21;
        let mesh = grid(n);
        let layout = layout(&mesh);
        let filters = Filters::new(&layout).unwrap();
        let factors = filters.factors(&layout).unwrap();
        let (bump, alternating) = bump_and_alternating(&layout, n);
        let (smooth, rough) = (first_coordinate(&bump), first_coordinate(&alternating));
        let norm = |f: &[[f64; 3]]| f.iter().map(|v| v[0] * v[0]).sum::<f64>().sqrt();
        let mut last_rough = f64::INFINITY;
        for factor in &factors {
            let kept_smooth = norm(&filtered(factor, &smooth).unwrap()) / norm(&smooth);
            let kept_rough = norm(&filtered(factor, &rough).unwrap()) / norm(&rough);
            assert!(
                kept_rough < 0.2 * kept_smooth,
                "{kept_rough} vs {kept_smooth}"
            );
            assert!(kept_rough < last_rough);
            last_rough = kept_rough;
        }
        // The smoothest Dirichlet mode keeps most of itself at t = 1 (0.912 measured: a
        // Rayleigh quotient of L near 0.1 on this grid), the alternating field 0.111.
        let kept = norm(&filtered(&factors[0], &smooth).unwrap()) / norm(&smooth);
        assert!(kept > 0.9, "{kept}");
    }

    /// The scalar filter is the vector one on a single coordinate, and the smooth part's
    /// scale minimises ‖F (b − s a)‖² (larger a little to either side); on a field whose
    /// rough part is the whole difference between b and a, it is the smooth part's own
    /// ratio, where the plain model's scale is pulled off by the rough part.
    #[test]
    fn smooth_part_scale_fits_what_survives_the_filter() {
        let n = 21;
        let mesh = grid(n);
        let layout = layout(&mesh);
        let filters = Filters::new(&layout).unwrap();
        let factors = filters.factors(&layout).unwrap();
        let filter = &factors[super::JUMP_FILTER];
        let (bump, alternating) = bump_and_alternating(&layout, n);
        // b = the bump; a = half the bump plus a large alternating field.
        let b = bump.clone();
        let a: Vec<f64> = bump
            .iter()
            .zip(&alternating)
            .map(|(x, r)| 0.5 * x + 2.0 * r)
            .collect();
        let by_vector = filtered(filter, &first_coordinate(&a)).unwrap();
        let by_scalar = filtered_scalar(filter, &a).unwrap();
        for (v, x) in by_vector.iter().zip(&by_scalar) {
            assert!((v[0] - x).abs() < 1e-14, "{v:?} vs {x}");
        }
        let s = smooth_part_scale(filter, &b, &a).unwrap();
        let smooth_model = |s: f64| {
            let r: Vec<f64> = b.iter().zip(&a).map(|(x, y)| x - s * y).collect();
            filtered_scalar(filter, &r)
                .unwrap()
                .iter()
                .map(|x| x * x)
                .sum::<f64>()
        };
        assert!(smooth_model(s) < smooth_model(s + 1e-3));
        assert!(smooth_model(s) < smooth_model(s - 1e-3));
        // The filter keeps little of the alternating field at t = 16, so the fit is near
        // the bump's ratio 2; the plain model, dominated by the alternating part, is not
        // (0.03: ½‖bump‖² / (¼‖bump‖² + 4‖alternating‖²)).
        assert!((s - 2.0).abs() < 0.1, "{s}");
        let plain = model_scale(&b, &a);
        assert!(plain < 0.2, "{plain}");
        assert_eq!(smooth_part_scale(filter, &b, &vec![0.0; b.len()]), None);
    }

    /// The scale minimises the model: ‖b − s a‖² is larger a little to either side.
    #[test]
    fn model_scale_minimises_the_linear_model() {
        let b = [1.0, -2.0, 0.5, 3.0];
        let a = [0.3, -1.0, 2.0, 1.5];
        let s = model_scale(&b, &a);
        let model = |s: f64| {
            b.iter()
                .zip(&a)
                .map(|(x, y)| (x - s * y).powi(2))
                .sum::<f64>()
        };
        assert!(model(s) < model(s + 1e-3) && model(s) < model(s - 1e-3));
        assert_eq!(model_scale(&b, &[0.0; 4]), 0.0);
    }
}
