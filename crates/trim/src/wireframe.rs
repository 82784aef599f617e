//! Surface from a wire-frame: a triangulated patch inside a closed loop of 3D boundary
//! curves (and through optional interior guide curves).
//!
//! 1. The curves are joined end to end into one closed loop ([`WireframeOptions::join_tolerance_mm`];
//!    `join.rs`).
//! 2. Parameter domain: the loop projected to its best-fit (PCA) plane when that projection is
//!    a simple polygon (`domain.rs`, `geom.rs`); otherwise the loop laid around a circle by arc
//!    length (always simple, convex; used only without guide curves). See
//!    docs/algorithms/wireframe_surface.md.
//! 3. The boundary is resampled at the target edge length keeping every input point
//!    (`sampling.rs`); spade's constrained Delaunay refinement fills the domain (minimum angle,
//!    maximum area); vertices it inserts on constraint edges are mapped back onto the 3D
//!    segment they split (`cdt.rs`).
//! 4. Lift: boundary and guide vertices sit at their 3D points; the interior solves the
//!    discrete Laplace equation (cotan weights of the domain triangulation, `flatcut_sparse`'s
//!    Cholesky; `lift.rs`). In the plane domain only the height over the plane is solved (the
//!    in-plane coordinates are linear, so the cotan Laplacian reproduces them exactly).
//! 5. The 3D triangle quality is measured (`measure.rs`); where lifting squeezes triangles
//!    below [`WireframeOptions::min_angle_3d_deg`], the patch is flattened conformally (LSCM),
//!    the same boundary and guide samples are re-triangulated in that flattening (where 2D
//!    angles are close to 3D angles), and lifted again (all three coordinates harmonic in the
//!    new domain); a few passes, keeping the best (`reparam.rs`).
//!
//! The input types and their checks are in `input.rs`, the error in `error.rs`; every public
//! item is re-exported here (`flatcut_trim::wireframe::*`).

mod cdt;
mod domain;
mod error;
mod geom;
mod input;
mod join;
mod lift;
mod measure;
mod reparam;
mod sampling;

use flatcut_mesh::vec3::dist;
use flatcut_mesh::{TriMesh, VertexAttributes};
use serde::Serialize;

pub use error::WireframeError;
pub use input::{DomainChoice, WireCurve, WireFrame, WireframeOptions};

use cdt::{Meshed, triangulate};
use domain::Frame;
use geom::{diagonal, first_crossing, signed_area};
use input::{check_options, check_polyline};
use join::{check_loop_in_3d, join_loop, nearest_on_loop};
use lift::{Lift, lift};
use measure::{boundary_order, deviation, min_angle_deg};
use reparam::reparametrise;
use sampling::{add_guide, sample_boundary};

/// Projected loop segments closer than this × the loop's diagonal count as touching: the
/// projection is then not a usable simple polygon (the CDT would get slivers or overlaps).
const TOUCH_RELATIVE: f64 = 1e-6;

/// The parameter domain that was used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DomainKind {
    /// Orthogonal projection to the loop's best-fit (PCA) plane.
    Plane,
    /// Loop laid around a circle of the loop's length by arc length.
    Circle,
}

/// Where a patch vertex comes from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum VertexOrigin {
    /// Exactly input point `point` of boundary curve `curve` (indices into `WireFrame::curve`).
    CurvePoint { curve: usize, point: usize },
    /// On boundary curve `curve`'s segment from point `segment` to `segment + 1`, at
    /// parameter `t` ∈ (0, 1) measured from point `segment`.
    OnCurve {
        curve: usize,
        segment: usize,
        t: f64,
    },
    /// Exactly input point `point` of guide `guide`.
    GuidePoint { guide: usize, point: usize },
    /// On guide `guide`'s segment `segment`→`segment + 1` at parameter `t`.
    OnGuide {
        guide: usize,
        segment: usize,
        t: f64,
    },
    /// An interior vertex placed by the refinement and the harmonic lift.
    Interior,
}

/// Measurements of a patch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WireframeReport {
    /// The first parameter domain (see `conformal_domain` for the one kept).
    pub domain: DomainKind,
    /// Triangles.
    pub faces: usize,
    /// Vertices.
    pub vertices: usize,
    /// Vertices on the boundary loop.
    pub boundary_vertices: usize,
    /// Length of the joined boundary loop (mm).
    pub loop_length_mm: f64,
    /// Largest gap closed when joining curve ends (mm).
    pub max_join_gap_mm: f64,
    /// Smallest triangle angle in the domain (degrees).
    pub min_angle_domain_deg: f64,
    /// Smallest triangle angle of the 3D patch after the first lift, before any
    /// re-parametrisation pass (degrees).
    pub min_angle_lifted_deg: f64,
    /// Smallest triangle angle of the final 3D patch (degrees).
    pub min_angle_3d_deg: f64,
    /// Re-parametrisation passes made (conformal flattening of the lifted patch, re-mesh,
    /// re-lift); the best pass is kept.
    pub reparam_passes: usize,
    /// True when the kept patch comes from a re-parametrisation pass: its domain (the mesh's
    /// texture coordinates) is then a conformal flattening, not `domain`.
    pub conformal_domain: bool,
    /// Largest distance of a boundary or guide vertex from the input segment it comes from (mm).
    pub max_boundary_deviation_mm: f64,
    /// Patch area (mm²).
    pub area_mm2: f64,
    /// Warnings (e.g. the 3D minimum angle stayed below the goal).
    pub warnings: Vec<String>,
}

/// A patch made by [`wireframe_surface`].
#[derive(Clone, Debug)]
pub struct WireframePatch {
    /// The triangulated surface (mm), faces counter-clockwise in the domain.
    pub mesh: TriMesh,
    /// Each vertex's position in the parameter domain (mm).
    pub domain: Vec<[f64; 2]>,
    /// Each vertex's origin.
    pub origins: Vec<VertexOrigin>,
    /// The boundary loop's vertices in order, following the joined curves.
    pub boundary: Vec<u32>,
    /// Measurements.
    pub report: WireframeReport,
}

/// Makes a triangulated patch spanning a wire-frame whose points are in millimetres (use
/// [`WireFrame::scaled`] first if `wire.units` is not mm).
///
/// # Errors
/// [`WireframeError`] naming the curve, guide or point at fault.
pub fn wireframe_surface(
    wire: &WireFrame,
    opts: &WireframeOptions,
) -> Result<WireframePatch, WireframeError> {
    check_options(opts)?;
    if wire.curve.is_empty() {
        return Err(WireframeError::NoCurves);
    }
    for c in &wire.curve {
        check_polyline("curve", c, 2)?;
    }
    for g in &wire.guide {
        check_polyline("guide", g, 2)?;
    }
    let (segs, max_join_gap_mm) = join_loop(&wire.curve, opts.join_tolerance_mm)?;
    let loop_length_mm: f64 = segs.iter().map(|s| dist(s.p0, s.p1)).sum();
    let h = wire.target_edge_mm;
    if !(h.is_finite() && h > 0.0 && 3.0 * h <= loop_length_mm) {
        return Err(WireframeError::BadTargetEdge {
            target_edge_mm: h,
            loop_length_mm,
        });
    }
    // Samples the boundary and guides will need, checked before anything is allocated (a
    // tiny target edge or astronomically large coordinates must not hang or exhaust memory).
    let guide_length: f64 = wire
        .guide
        .iter()
        .flat_map(|g| g.points.windows(2).map(|w| dist(w[0], w[1])))
        .sum();
    let samples = (loop_length_mm + guide_length) / h + (segs.len() + wire.guide.len()) as f64;
    if !(samples.is_finite() && samples <= opts.max_vertices as f64) {
        return Err(WireframeError::TooManyVertices {
            needed: if samples.is_finite() {
                samples as usize
            } else {
                usize::MAX
            },
            max: opts.max_vertices,
        });
    }
    let diag = diagonal(segs.iter().map(|s| s.p0));
    check_loop_in_3d(&segs, &wire.curve, diag, opts.join_tolerance_mm)?;

    // Domain.
    let frame = Frame::pca(&segs);
    let projected: Vec<[f64; 2]> = segs.iter().map(|s| frame.project(s.p0)).collect();
    let crossing = first_crossing(&projected, TOUCH_RELATIVE * diag);
    let kind = match (opts.domain, crossing) {
        (DomainChoice::Circle, _) => DomainKind::Circle,
        (DomainChoice::Auto | DomainChoice::Plane, None) => DomainKind::Plane,
        (DomainChoice::Auto, Some(_)) => DomainKind::Circle,
        (DomainChoice::Plane, Some((a, b))) => {
            return Err(WireframeError::SelfIntersectingProjection {
                curve_a: wire.curve[segs[a].curve].name.clone(),
                point_a: segs[a].i0,
                curve_b: wire.curve[segs[b].curve].name.clone(),
                point_b: segs[b].i0,
            });
        }
    };
    if kind == DomainKind::Circle {
        if let Some(g) = wire.guide.first() {
            return Err(WireframeError::GuidesNeedPlane {
                guide: g.name.clone(),
            });
        }
    }
    // Orient the plane domain counter-clockwise (faces then face along the frame normal).
    let frame = if kind == DomainKind::Plane && signed_area(&projected) < 0.0 {
        frame.flipped()
    } else {
        frame
    };

    // Guide ends on the boundary (within the join tolerance of a segment's interior) become
    // boundary samples, so the guide meets the boundary at a vertex.
    let mut breaks: Vec<Vec<f64>> = vec![Vec::new(); segs.len()];
    for g in &wire.guide {
        for end in [g.points[0], g.points[g.points.len() - 1]] {
            if let Some((si, t)) = nearest_on_loop(&segs, end, opts.join_tolerance_mm) {
                if t > 0.0 && t < 1.0 {
                    breaks[si].push(t);
                }
            }
        }
    }
    // Boundary samples: every input point, plus points on each segment at ≤ h spacing.
    let (mut nodes, mut edge_info) =
        sample_boundary(&segs, &breaks, kind, &frame, h, loop_length_mm);
    let n_boundary = nodes.len();
    let mut edges: Vec<[usize; 2]> = (0..n_boundary).map(|i| [i, (i + 1) % n_boundary]).collect();
    let boundary_poly: Vec<[f64; 2]> = nodes.iter().map(|n| n.p2).collect();
    for (gi, g) in wire.guide.iter().enumerate() {
        add_guide(
            gi,
            g,
            &frame,
            h,
            opts.join_tolerance_mm,
            &boundary_poly,
            &mut nodes,
            &mut edges,
            &mut edge_info,
        )?;
    }

    // Estimated size: boundary samples + interior at the equilateral density of h.
    let domain_area = signed_area(&boundary_poly).abs();
    let tri_area = 3f64.sqrt() / 4.0 * h * h;
    let estimate = nodes.len() + (domain_area / tri_area).ceil() as usize;
    if estimate > opts.max_vertices {
        return Err(WireframeError::TooManyVertices {
            needed: estimate,
            max: opts.max_vertices,
        });
    }

    let meshed = triangulate(
        &nodes,
        n_boundary,
        &edges,
        &edge_info,
        tri_area,
        opts.domain_min_angle_deg,
        opts.max_vertices,
        &wire.guide,
    )?;
    let first_lift = match kind {
        DomainKind::Plane => Lift::Height(frame),
        DomainKind::Circle => Lift::Xyz,
    };
    let positions = lift(&meshed.domain, &meshed.faces, &meshed.fixed3, first_lift)?;
    let min_angle_lifted_deg = min_angle_deg(&positions, &meshed.faces);
    let mut best = (meshed.clone(), positions, min_angle_lifted_deg);
    let mut conformal_domain = false;
    let mut current = best.clone();
    let mut reparam_passes = 0;
    // Where the lift squeezed triangles, re-mesh in a conformal flattening of the lifted
    // surface (angles there ≈ angles on the surface) and lift again; keep the best pass.
    while best.2 < opts.min_angle_3d_deg && reparam_passes < opts.reparam_passes {
        let Some(next) = reparametrise(
            &current.0,
            &current.1,
            &nodes,
            n_boundary,
            &edges,
            &edge_info,
            tri_area,
            opts,
            &wire.guide,
        ) else {
            break;
        };
        reparam_passes += 1;
        current = next;
        if current.2 > best.2 {
            best = current.clone();
            conformal_domain = true;
        }
    }
    let (meshed, positions, min3) = best;
    let Meshed {
        faces,
        domain,
        origins,
        ..
    } = meshed;
    let min_angle_domain_deg = min_angle_deg(
        &domain.iter().map(|p| [p[0], p[1], 0.0]).collect::<Vec<_>>(),
        &faces,
    );
    let mut warnings = Vec::new();
    if min3 < opts.min_angle_3d_deg {
        warnings.push(format!(
            "the smallest 3D triangle angle is {min3:.2}° (goal {}°): the surface bends too much for its domain; lower target_edge_mm or split the loop",
            opts.min_angle_3d_deg
        ));
    }

    let mesh = TriMesh {
        positions,
        faces,
        attributes: VertexAttributes {
            texcoords: Some(domain.clone()),
            ..Default::default()
        },
        face_labels: None,
    };
    let boundary = boundary_order(&mesh, &origins);
    let max_boundary_deviation_mm = origins
        .iter()
        .zip(&mesh.positions)
        .filter_map(|(o, p)| deviation(*o, *p, &wire.curve, &wire.guide))
        .fold(0.0, f64::max);
    let area_mm2 = flatcut_mesh::geometry::total_area(&mesh);
    let report = WireframeReport {
        domain: kind,
        faces: mesh.faces.len(),
        vertices: mesh.positions.len(),
        boundary_vertices: boundary.len(),
        loop_length_mm,
        max_join_gap_mm,
        min_angle_domain_deg,
        min_angle_lifted_deg,
        min_angle_3d_deg: min3,
        reparam_passes,
        conformal_domain,
        max_boundary_deviation_mm,
        area_mm2,
        warnings,
    };
    Ok(WireframePatch {
        mesh,
        domain,
        origins,
        boundary,
        report,
    })
}
