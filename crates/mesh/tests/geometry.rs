//! Geometry against closed forms: flat and developable surfaces have zero angle defect, the
//! sphere's defect is K·A with K = 1/R², Gauss–Bonnet holds exactly, mixed areas partition the
//! area, and the cotan Laplacian reproduces linear functions and the mean-curvature normal.

// Test code: unwrap is allowed (RULES), index loops mirror the formulas.
#![allow(clippy::unwrap_used, clippy::needless_range_loop)]

use std::f64::consts::{PI, TAU};

use flatcut_mesh::geometry::*;
use flatcut_mesh::shapes::*;
use flatcut_mesh::vec3::{add, cross, dot, norm, normalize, scale, sub};
use flatcut_mesh::{Topology, TriMesh, VertexId};
use proptest::prelude::*;

/// Σ_j w_ij (x_i − x_j) for a per-vertex vector field, from the cotan weights per edge.
fn cotan_laplacian(m: &TriMesh, t: &Topology, f: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let w = cotan_weights(&m.positions, &m.faces, t);
    let mut out = vec![[0.0; 3]; m.vertex_count()];
    for (e, &[i, j]) in t.edges().iter().enumerate() {
        let d = scale(sub(f[i as usize], f[j as usize]), w[e]);
        out[i as usize] = add(out[i as usize], d);
        out[j as usize] = sub(out[j as usize], d);
    }
    out
}

fn manifold_shapes() -> Vec<(&'static str, TriMesh)> {
    catalogue()
        .into_iter()
        .filter(|(n, _)| !n.starts_with("non_manifold"))
        .collect()
}

#[test]
fn gauss_bonnet_holds_on_every_shape() {
    // Σ_interior (2π − θ) + Σ_boundary (π − θ) = 2π χ, exactly for any triangle mesh.
    for (name, m) in manifold_shapes() {
        let t = Topology::build(&m).unwrap();
        let theta = angle_sums(&m.positions, &m.faces);
        let mut total = 0.0;
        for v in 0..m.vertex_count() {
            let vid = VertexId(v as u32);
            total += if t.is_boundary_vertex(vid) {
                PI - theta[v]
            } else {
                TAU - theta[v]
            };
        }
        let expected = TAU * t.euler_characteristic() as f64;
        assert!(
            (total - expected).abs() < 1e-9,
            "{name}: {total} vs {expected}"
        );
    }
    // A closed sphere: total defect 4π.
    let s = icosphere(37.0, 3);
    let t = Topology::build(&s).unwrap();
    let total: f64 = angle_defects(&s.positions, &s.faces, &t)
        .iter()
        .map(|d| d.unwrap())
        .sum();
    assert!((total - 2.0 * TAU).abs() < 1e-9, "{total}");
}

#[test]
fn developable_shapes_have_zero_interior_defect() {
    for m in [
        planar_disk(30.0, 6),
        patch_with_holes(50.0, 21),
        cylinder_patch(20.0, TAU, 30.0, 24, 7),
    ] {
        let t = Topology::build(&m).unwrap();
        let d = angle_defects(&m.positions, &m.faces, &t);
        let interior = d.iter().flatten().count();
        assert!(interior > 10);
        for x in d.iter().flatten() {
            assert!(x.abs() < 1e-12, "{x}");
        }
    }
    // A full cone: zero everywhere except the apex, whose defect is 2π(1 − r/s).
    let (r, h) = (40.0, 60.0);
    let m = cone_patch(r, h, TAU, 24, 6);
    let t = Topology::build(&m).unwrap();
    let d = angle_defects(&m.positions, &m.faces, &t);
    let apex = m.vertex_count() - 1;
    // The 24-gon cone's apex: each face has apex angle from its chord, not the smooth value.
    let slant = (r * r + h * h).sqrt();
    let exact = TAU * (1.0 - r / slant);
    assert!((d[apex].unwrap() - exact).abs() < 0.01 * exact);
    // Exactly: each apex face is isosceles with legs along rulings and a chord base.
    let chord = 2.0 * r * (PI / 24.0).sin();
    let face_apex = 2.0 * (0.5 * chord / slant).asin();
    assert!((d[apex].unwrap() - (TAU - 24.0 * face_apex)).abs() < 1e-12);
    for (v, x) in d.iter().enumerate() {
        if v != apex
            && let Some(x) = x
        {
            assert!(x.abs() < 1e-12);
        }
    }
}

/// Defect against K·A_mixed on the grid cap: (worst relative error over interior vertices in
/// the inner 3/4 of the square grid, Σ|defect − K·A| / Σ K·A over all interior vertices).
/// The inner region excludes the four square corners, where the square-to-disk map is
/// singular (a 90° corner opens to 180°) and the triangles are distorted at every resolution.
fn cap_defect_error(n: usize) -> (f64, f64) {
    let r = 100.0;
    let m = sphere_cap_grid(n, PI / 3.0, r);
    let t = Topology::build(&m).unwrap();
    let d = angle_defects(&m.positions, &m.faces, &t);
    let a = mixed_areas(&m.positions, &m.faces);
    let (mut inner, mut sum_err, mut sum_k) = (0.0f64, 0.0, 0.0);
    for v in 0..m.vertex_count() {
        if let Some(x) = d[v] {
            let predicted = a[v] / (r * r);
            let (i, j) = ((v % n) as f64, (v / n) as f64);
            let c = 0.5 * (n - 1) as f64;
            if (i - c).abs().max((j - c).abs()) < 0.75 * c {
                inner = inner.max((x - predicted).abs() / predicted);
            }
            sum_err += (x - predicted).abs();
            sum_k += predicted;
        }
    }
    (inner, sum_err / sum_k)
}

#[test]
fn sphere_cap_defect_is_gaussian_curvature_times_mixed_area() {
    // Measured (conformal grid map): inner worst 2.7e-2, 1.1e-2, 3.7e-3 (ratios 0.41, 0.34 per
    // halving of h: the conformal map grades the triangle sizes, so pointwise convergence is
    // between first and second order); L1 2.3e-2, 6.2e-3, 1.6e-3 (ratios 0.27, 0.25: second order).
    let (e1, e2, e3) = (
        cap_defect_error(9),
        cap_defect_error(17),
        cap_defect_error(33),
    );
    assert!(e3.0 < 5e-3 && e3.1 < 2e-3, "{e1:?} {e2:?} {e3:?}");
    assert!(
        e2.0 < 0.5 * e1.0 && e3.0 < 0.5 * e2.0,
        "{e1:?} {e2:?} {e3:?}"
    );
    assert!(
        e2.1 < 0.35 * e1.1 && e3.1 < 0.35 * e2.1,
        "{e1:?} {e2:?} {e3:?}"
    );
    // Summed over the icosphere, defect = 4π and K·ΣA = 4π·(area/4πR²): a second identity.
    let s = icosphere(10.0, 3);
    let t = Topology::build(&s).unwrap();
    let d = angle_defects(&s.positions, &s.faces, &t);
    let a = mixed_areas(&s.positions, &s.faces);
    for v in 0..s.vertex_count() {
        let (x, k) = (d[v].unwrap(), a[v] / 100.0);
        assert!((x - k).abs() < 0.1 * k, "{v}: {x} vs {k}");
    }
}

#[test]
fn mixed_areas_partition_the_area_even_with_obtuse_triangles() {
    let mut meshes: Vec<TriMesh> = manifold_shapes().into_iter().map(|(_, m)| m).collect();
    // A sheared grid: every triangle obtuse.
    meshes.push(grid_patch(9, 9, 10.0, |_, _| 0.0));
    let last = meshes.last_mut().unwrap();
    for p in &mut last.positions {
        p[0] += 3.0 * p[1];
    }
    let angles = corner_angles(&last.positions, &last.faces);
    assert!(angles.iter().all(|a| a.iter().any(|&x| x > PI / 2.0)));
    for m in &meshes {
        let total: f64 = face_areas(&m.positions, &m.faces).iter().sum();
        let mixed: f64 = mixed_areas(&m.positions, &m.faces).iter().sum();
        assert!((mixed - total).abs() < 1e-12 * total, "{mixed} vs {total}");
        assert!(
            mixed_areas(&m.positions, &m.faces)
                .iter()
                .all(|&a| a >= 0.0)
        );
    }
}

#[test]
fn cotan_laplacian_of_linear_functions_vanishes_on_flat_meshes() {
    for m in [
        planar_disk(30.0, 6),
        patch_with_holes(50.0, 21),
        grid_patch(8, 11, 5.0, |_, _| 0.0),
    ] {
        let t = Topology::build(&m).unwrap();
        // Jitter interior vertices in-plane so the test is not only about regular grids.
        let mut m = m;
        for v in 0..m.vertex_count() {
            if t.is_interior_vertex(VertexId(v as u32)) {
                let s = (v as f64 * 12.9898).sin() * 43758.5453;
                let j = s - s.floor() - 0.5;
                m.positions[v][0] += 0.2 * j * (30.0 / 6.0) * 0.5;
                m.positions[v][1] -= 0.15 * j * (30.0 / 6.0) * 0.5;
            }
        }
        let f: Vec<[f64; 3]> = m
            .positions
            .iter()
            .map(|p| [2.0 * p[0] - 3.0 * p[1] + 1.0, p[0], 0.0])
            .collect();
        let lap = cotan_laplacian(&m, &t, &f);
        let scale_f = 200.0;
        for v in 0..m.vertex_count() {
            if t.is_interior_vertex(VertexId(v as u32)) {
                assert!(norm(lap[v]) < 1e-10 * scale_f, "{v}: {:?}", lap[v]);
            }
        }
    }
}

#[test]
fn cotan_laplacian_of_positions_is_the_mean_curvature_normal() {
    // Σ w_ij (x_i − x_j) = 2 H n A with H = 1/R on a sphere of radius R.
    let worst = |sub: usize| {
        let r = 10.0;
        let s = icosphere(r, sub);
        let t = Topology::build(&s).unwrap();
        let lap = cotan_laplacian(&s, &t, &s.positions);
        let a = mixed_areas(&s.positions, &s.faces);
        (0..s.vertex_count())
            .map(|v| {
                let expected = scale(normalize(s.positions[v]), 2.0 * a[v] / r);
                norm(sub_v(lap[v], expected)) / norm(expected)
            })
            .fold(0.0f64, f64::max)
    };
    fn sub_v(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        sub(a, b)
    }
    let (e2, e3, e4) = (worst(2), worst(3), worst(4));
    assert!(e4 < 0.05, "{e2} {e3} {e4}");
    assert!(e3 < e2 && e4 < e3, "{e2} {e3} {e4}");
}

#[test]
fn angles_sum_to_pi_and_stay_accurate_on_needles() {
    for (_, m) in catalogue() {
        for a in corner_angles(&m.positions, &m.faces) {
            assert!((a.iter().sum::<f64>() - PI).abs() < 1e-12);
        }
    }
    // A needle with a 1e-9 rad apex: acos would lose it, atan2 keeps 6+ digits.
    // Right angle at p1, apex atan(1e-9) = 1e-9 − 3e-28 at p0 (exact coordinates).
    let eps: f64 = 1e-9;
    let a = triangle_angles([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, eps, 0.0]);
    assert!((a[0] - eps).abs() < 1e-24, "{}", a[0]);
    assert!((a[1] - PI / 2.0).abs() < 1e-15);
    assert!((a[2] - (PI / 2.0 - eps)).abs() < 1e-15);
    // acos of the normalised dot product gives 0 here: the reason for atan2.
    let c = 1.0 / (1.0 + eps * eps).sqrt();
    assert_eq!(c.acos(), 0.0);
    // A flat triangle: the middle corner is π.
    let a = triangle_angles([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]);
    assert_eq!(a, [0.0, PI, 0.0]);
    // Areas and normals of a known triangle.
    assert_eq!(
        triangle_area([0.0; 3], [2.0, 0.0, 0.0], [0.0, 3.0, 0.0]),
        3.0
    );
    let n = face_normals(&[[0.0; 3], [2.0, 0.0, 0.0], [0.0, 3.0, 0.0]], &[[0, 1, 2]]);
    assert_eq!(n[0], [0.0, 0.0, 1.0]);
    assert!(dot(cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]) == 1.0);
}

fn rotate(p: [f64; 3], axis: [f64; 3], angle: f64) -> [f64; 3] {
    // Rodrigues.
    let k = normalize(axis);
    let (c, s) = (angle.cos(), angle.sin());
    add(
        add(scale(p, c), scale(cross(k, p), s)),
        scale(k, dot(k, p) * (1.0 - c)),
    )
}

proptest! {
    #[test]
    fn angles_and_areas_are_rigid_invariants(
        ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in 0.1f64..1.0, angle in -3.0f64..3.0,
        tx in -100.0f64..100.0, ty in -100.0f64..100.0, tz in -100.0f64..100.0, s in 0.01f64..100.0,
    ) {
        let m = saddle_grid(6);
        let moved: Vec<[f64; 3]> = m.positions.iter().map(|&p| add(rotate(p, [ax, ay, az], angle), [tx, ty, tz])).collect();
        let a0 = corner_angles(&m.positions, &m.faces);
        let a1 = corner_angles(&moved, &m.faces);
        for (x, y) in a0.iter().flatten().zip(a1.iter().flatten()) {
            prop_assert!((x - y).abs() < 1e-9);
        }
        let f0 = face_areas(&m.positions, &m.faces);
        let f1 = face_areas(&moved, &m.faces);
        for (x, y) in f0.iter().zip(&f1) {
            prop_assert!((x - y).abs() < 1e-9 * x.max(1.0));
        }
        let scaled: Vec<[f64; 3]> = moved.iter().map(|&p| scale(p, s)).collect();
        let f2 = face_areas(&scaled, &m.faces);
        let m0 = mixed_areas(&m.positions, &m.faces);
        let m2 = mixed_areas(&scaled, &m.faces);
        for (x, y) in f0.iter().zip(&f2) {
            prop_assert!((y - s * s * x).abs() < 1e-9 * s * s * x);
        }
        for (x, y) in m0.iter().zip(&m2) {
            prop_assert!((y - s * s * x).abs() < 1e-9 * s * s * x);
        }
    }
}

/// Closed forms: the foot of the perpendicular inside the segment, beyond either end (the
/// distance to that end point), and a degenerate segment (the distance to its point).
#[test]
fn point_segment_distance_closed_forms() {
    use flatcut_mesh::vec3::point_segment_distance;
    let (a, b) = ([1.0, 2.0, 3.0], [4.0, 6.0, 3.0]); // length 5 along (0.6, 0.8, 0)
    // 2 above the midpoint along z.
    assert!((point_segment_distance([2.5, 4.0, 5.0], a, b) - 2.0).abs() < 1e-15);
    // 3 past b along the segment and 4 off it: distance to b is 5.
    let past_b = [4.0 + 1.8 - 3.2, 6.0 + 2.4 + 2.4, 3.0];
    assert!((point_segment_distance(past_b, a, b) - 5.0).abs() < 1e-12);
    // Before a along the segment: distance to a.
    assert!((point_segment_distance([1.0 - 0.6, 2.0 - 0.8, 3.0], a, b) - 1.0).abs() < 1e-15);
    assert!((point_segment_distance([1.0, 2.0, 7.0], a, a) - 4.0).abs() < 1e-15);
}

#[test]
fn area_gradient_matches_central_differences() {
    // A doubly curved, irregular patch: the cap with every vertex jittered.
    let mut m = sphere_cap_grid(7, PI / 3.0, 2.0);
    for (i, p) in m.positions.iter_mut().enumerate() {
        let s = (i as f64 * 0.37).sin();
        *p = add(
            *p,
            [0.03 * s, -0.02 * (i as f64 * 1.3).cos(), 0.025 * s * s],
        );
    }
    let g = area_gradient(&m.positions, &m.faces);
    let h = 1e-6;
    let mut worst = 0.0f64;
    for v in 0..m.vertex_count() {
        for c in 0..3 {
            let mut plus = m.positions.clone();
            let mut minus = m.positions.clone();
            plus[v][c] += h;
            minus[v][c] -= h;
            let a_plus: f64 = face_areas(&plus, &m.faces).iter().sum();
            let a_minus: f64 = face_areas(&minus, &m.faces).iter().sum();
            let fd = (a_plus - a_minus) / (2.0 * h);
            worst = worst.max((fd - g[v][c]).abs() / norm(g[v]).max(1e-3));
        }
    }
    assert!(worst < 1e-6, "relative error {worst:e}");
    // Translation invariance: the gradients sum to zero (Σ ∂A/∂v = ∂A/∂(shift) = 0).
    let sum = g.iter().fold([0.0; 3], |s, v| add(s, *v));
    assert!(norm(sum) < 1e-12, "{sum:?}");
}

/// Each component's bounding-box diagonal, with no overflow or underflow where its square
/// would leave f64: unit squares at scales 1, 1e300 and 1e-300 give √2 times the scale (the
/// naive formula gives infinity and 0 for the last two), and a group without faces gives 0.
#[test]
fn component_extents_are_diagonals_without_overflow() {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for (k, s) in [1.0, 1e300, 1e-300].into_iter().enumerate() {
        let o = 4 * k as u32;
        positions.extend([[0.0, 0.0, 0.0], [s, 0.0, 0.0], [s, s, 0.0], [0.0, s, 0.0]]);
        faces.extend([[o, o + 1, o + 2], [o, o + 2, o + 3]]);
    }
    let mesh = TriMesh::new(positions, faces).unwrap();
    let extents = component_extents(&mesh, &[0, 0, 1, 1, 2, 2], 4);
    let root2 = 2f64.sqrt();
    assert_eq!(extents, vec![root2, 1e300 * root2, 1e-300 * root2, 0.0]);
    let naive = |s: f64| (s * s + s * s).sqrt();
    assert_eq!((naive(1e300), naive(1e-300)), (f64::INFINITY, 0.0));
}

#[test]
fn area_weighted_vertex_normals_on_a_plane_and_a_sphere() {
    // A plane: each vertex's normal is +z times twice the area of its faces.
    let plane = grid_patch(7, 5, 60.0, |_, _| 0.0);
    let normals = area_weighted_vertex_normals(&plane.positions, &plane.faces);
    let mut twice_area = vec![0.0; plane.positions.len()];
    for (f, a) in plane
        .faces
        .iter()
        .zip(face_areas(&plane.positions, &plane.faces))
    {
        for &v in f {
            twice_area[v as usize] += 2.0 * a;
        }
    }
    for (n, a) in normals.iter().zip(&twice_area) {
        assert!(n[0].abs() < 1e-12 && n[1].abs() < 1e-12, "{n:?}");
        assert!((n[2] - a).abs() <= 1e-12 * a, "{} vs {a}", n[2]);
    }
    // A closed sphere: the normals point outwards along the radius, and they sum to zero
    // (three times the faces' area vectors, whose sum vanishes on a closed surface).
    let sphere = icosphere(50.0, 3);
    let normals = area_weighted_vertex_normals(&sphere.positions, &sphere.faces);
    let mut sum = [0.0; 3];
    for (n, p) in normals.iter().zip(&sphere.positions) {
        assert!(dot(normalize(*n), normalize(*p)) > 0.999, "{n:?} at {p:?}");
        sum = add(sum, *n);
    }
    let total: f64 = normals.iter().map(|n| norm(*n)).sum();
    assert!(norm(sum) < 1e-12 * total, "Σ = {sum:?}");
}

#[test]
fn loop_length_of_a_square_sheets_boundary_is_its_perimeter() {
    let sheet = grid_patch(9, 9, 120.0, |_, _| 0.0);
    let topo = Topology::build(&sheet).unwrap();
    let outline = &topo.boundary_loops()[0];
    assert_eq!(outline.len(), 32);
    assert!((loop_length(&sheet.positions, outline) - 480.0).abs() < 1e-12);
    // Three vertices of a 3-4-5 triangle: the closing edge counts.
    let p = [[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 4.0, 0.0]];
    assert_eq!(
        loop_length(&p, &[VertexId(0), VertexId(1), VertexId(2)]),
        12.0
    );
}
