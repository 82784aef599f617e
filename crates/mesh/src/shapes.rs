//! Procedural surfaces for tests, benchmarks and the demo.
//!
//! Every function is deterministic, returns positions in millimetres and faces
//! counter-clockwise seen from the outside (or from +z for patches lying over the xy plane),
//! so face normals point outward / up. Shapes with a closed form for their curvature
//! (sphere, cylinder, cone, plane) are what the geometry tests check against.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use crate::TriMesh;
use crate::vec3::{add, normalize, scale};

fn mesh(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> TriMesh {
    TriMesh {
        positions,
        faces,
        ..Default::default()
    }
}

/// Triangulates an `nx × ny` vertex grid whose vertex `(i, j)` has index `i + nx·j`, with `i`
/// running along +u and `j` along +v (so the faces are counter-clockwise seen from u × v).
///
/// Each quad is split along the diagonal that points away from the grid centre ("union jack"),
/// so the pattern is symmetric under the grid's mirror symmetries and the four corner quads
/// are split through the corner vertex (which keeps corner triangles well shaped when the
/// square is mapped onto a disk).
fn grid_faces(nx: usize, ny: usize) -> Vec<[u32; 3]> {
    let mut faces = Vec::with_capacity(2 * nx.saturating_sub(1) * ny.saturating_sub(1));
    let id = |i: usize, j: usize| (i + nx * j) as u32;
    for j in 0..ny.saturating_sub(1) {
        for i in 0..nx.saturating_sub(1) {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            // Quad centre relative to the grid centre, in index units (doubled to stay integer).
            let cx = (2 * i + 1) as i64 - (nx as i64 - 1);
            let cy = (2 * j + 1) as i64 - (ny as i64 - 1);
            if (cx >= 0) == (cy >= 0) {
                // Diagonal a–c (along +u+v).
                faces.push([a, b, c]);
                faces.push([a, c, d]);
            } else {
                // Diagonal b–d (along +u−v).
                faces.push([a, b, d]);
                faces.push([b, c, d]);
            }
        }
    }
    faces
}

/// A height field over the square `[-size/2, size/2]²`: `nx × ny` vertices (at least 2 × 2),
/// vertex `(i, j)` at index `i + nx·j` with `x` growing with `i` and `y` with `j`, and
/// `z = height(x, y)`. Faces are counter-clockwise seen from +z (normals up); the quads are
/// split along the diagonal pointing away from the centre (see the module's grid pattern).
pub fn grid_patch(nx: usize, ny: usize, size_mm: f64, height: impl Fn(f64, f64) -> f64) -> TriMesh {
    let (nx, ny) = (nx.max(2), ny.max(2));
    let mut positions = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        let y = size_mm * (j as f64 / (ny - 1) as f64 - 0.5);
        for i in 0..nx {
            let x = size_mm * (i as f64 / (nx - 1) as f64 - 0.5);
            positions.push([x, y, height(x, y)]);
        }
    }
    mesh(positions, grid_faces(nx, ny))
}

/// The saddle of the flattenable-mesh issue: `z = 0.3 (x² − y²)` on `[−1, 1]²` with `n × n`
/// vertices (coordinates taken as millimetres, exactly as the issue states them).
pub fn saddle_grid(n: usize) -> TriMesh {
    grid_patch(n, n, 2.0, |x, y| 0.3 * (x * x - y * y))
}

/// An `n × n` vertex grid laid onto a spherical cap of radius `radius_mm`.
///
/// `cap_angle_rad` is the cap's full opening angle seen from the sphere centre, so the polar
/// half-angle is `cap_angle_rad / 2`; "a 60° sphere cap" is `cap_angle_rad = 60°`, i.e. points
/// up to 30° from the pole. This is the definition under which the claim holds: the
/// flat disk spanning the cap boundary has area π R² sin²α against the cap's 2π R² (1 − cos α),
/// a ratio (1 + cos α) / 2 = 0.933 for α = 30° (6.7 % less; with α = 60° it would be 25 %).
///
/// The square `[−1, 1]²` is mapped onto the unit disk conformally
/// ([`conformal_square_to_disk`]) and the disk onto the cap by the inverse stereographic
/// projection (ρ ↦ polar angle 2 atan(ρ tan(α/2))), also conformal: every grid triangle keeps
/// its shape up to scale (minimum corner angle 45° in the limit), except at the four square
/// corners, where the 90° corner opens to the rim's 180° and is split into two 90° angles by
/// the grid's diagonal. The sphere is centred at the origin and the cap sits around the +z
/// pole; normals point outward (up).
pub fn sphere_cap_grid(n: usize, cap_angle_rad: f64, radius_mm: f64) -> TriMesh {
    let t = (0.25 * cap_angle_rad).tan();
    let mut m = grid_patch(n, n, 2.0, |_, _| 0.0);
    for p in &mut m.positions {
        let [u, v] = conformal_square_to_disk(p[0], p[1]);
        let rho = u.hypot(v).min(1.0);
        let psi = v.atan2(u);
        let phi = 2.0 * (rho * t).atan();
        *p = [
            radius_mm * phi.sin() * psi.cos(),
            radius_mm * phi.sin() * psi.sin(),
            radius_mm * phi.cos(),
        ];
    }
    m
}

/// The conformal map of the square `[−1, 1]²` onto the unit disk (Schwarz–Christoffel; Fong
/// 2015, "Analytical methods for squaring the disc"):
/// `w = (1 − i)/√2 · cn(K (1 + i)/2 · (x + i y) − K, 1/√2)`, with K = K(1/√2) the complete
/// elliptic integral. Centre to centre, edges onto the circle, corners `(±1, ±1)` onto
/// `(±1, ±1)/√2`. Inputs outside the square are clamped onto it.
pub fn conformal_square_to_disk(x: f64, y: f64) -> [f64; 2] {
    // K(k = 1/√2) = Γ(1/4)² / (4 √π).
    const K: f64 = 1.854_074_677_301_372;
    let (x, y) = (x.clamp(-1.0, 1.0), y.clamp(-1.0, 1.0));
    let re = 0.5 * K * (x - y) - K;
    let im = 0.5 * K * (x + y);
    // cn(re + i im | m) by Abramowitz & Stegun 16.21.3; here m = m' = 1/2.
    let (s, c, d) = jacobi_sn_cn_dn(re, 0.5);
    let (s1, c1, d1) = jacobi_sn_cn_dn(im, 0.5);
    let den = c1 * c1 + 0.5 * s * s * s1 * s1;
    let (cr, ci) = (c * c1 / den, -s * d * s1 * d1 / den);
    // Multiply by (1 − i)/√2.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    [h * (cr + ci), h * (ci - cr)]
}

/// Jacobi elliptic functions sn, cn, dn of real `u` with parameter `m = k²` ∈ [0, 1), by the
/// arithmetic–geometric mean (Abramowitz & Stegun 16.4).
fn jacobi_sn_cn_dn(u: f64, m: f64) -> (f64, f64, f64) {
    let mut a = vec![1.0f64];
    let mut c = vec![m.sqrt()];
    let mut b = (1.0 - m).sqrt();
    while c.last().is_some_and(|&x| x.abs() > 1e-16) && a.len() < 32 {
        let (an, bn) = (a[a.len() - 1], b);
        a.push(0.5 * (an + bn));
        c.push(0.5 * (an - bn));
        b = (an * bn).sqrt();
    }
    let n = a.len() - 1;
    let mut phi = (1u64 << n) as f64 * a[n] * u;
    for k in (1..=n).rev() {
        phi = 0.5 * (phi + (c[k] / a[k] * phi.sin()).asin());
    }
    let (sn, cn) = phi.sin_cos();
    // dn > 0 for real u and m < 1; this form stays exact where cos φ₀ → 0 (sn = ±1), unlike
    // A&S's cos φ₀ / cos(φ₁ − φ₀).
    let dn = (1.0 - m * sn * sn).sqrt();
    (sn, cn, dn)
}

/// Joins two rings of vertices (indices, each listed counter-clockwise around +z with the
/// angular position of every vertex as a fraction of the full turn, first entry the smallest)
/// into a strip of triangles, always advancing on the ring whose next vertex comes first. For
/// `closed` rings the strip wraps around; otherwise it stops at the last vertices.
/// The strip is oriented with `inner` on the left of the walking direction, i.e. faces are
/// counter-clockwise seen from +z when `inner` lies closer to the axis.
fn zip_rings(inner: &[(u32, f64)], outer: &[(u32, f64)], closed: bool, faces: &mut Vec<[u32; 3]>) {
    let (ni, no) = (inner.len(), outer.len());
    let (mut i, mut o) = (0usize, 0usize);
    let (ei, eo) = if closed { (ni, no) } else { (ni - 1, no - 1) };
    let at = |ring: &[(u32, f64)], k: usize| {
        let n = ring.len();
        (ring[k % n].0, ring[k % n].1 + (k / n) as f64)
    };
    while i < ei || o < eo {
        let (vi, _) = at(inner, i);
        let (vo, _) = at(outer, o);
        let next_i = at(inner, i + 1);
        let next_o = at(outer, o + 1);
        let advance_inner = if i >= ei {
            false
        } else if o >= eo {
            true
        } else {
            next_i.1 < next_o.1
        };
        if advance_inner {
            faces.push([vi, vo, next_i.0]);
            i += 1;
        } else {
            faces.push([vi, vo, next_o.0]);
            o += 1;
        }
    }
}

/// Polar triangulation of a disk-like surface of revolution: one centre vertex at `centre`,
/// then `rings` rings with `6k` vertices on ring `k`, ring `k` at `point(k / rings, angle)`.
fn polar_disk(rings: usize, point: impl Fn(f64, f64) -> [f64; 3]) -> TriMesh {
    let rings = rings.max(1);
    let mut positions = vec![point(0.0, 0.0)];
    let mut faces = Vec::new();
    let mut prev: Vec<(u32, f64)> = vec![(0, 0.0)];
    for k in 1..=rings {
        let count = 6 * k;
        let mut ring = Vec::with_capacity(count);
        for s in 0..count {
            let frac = s as f64 / count as f64;
            ring.push((positions.len() as u32, frac));
            positions.push(point(k as f64 / rings as f64, TAU * frac));
        }
        if k == 1 {
            for s in 0..count {
                faces.push([0, ring[s].0, ring[(s + 1) % count].0]);
            }
        } else {
            zip_rings(&prev, &ring, true, &mut faces);
        }
        prev = ring;
    }
    mesh(positions, faces)
}

/// A spherical cap of radius `radius_mm` around the +z pole, points up to the polar angle
/// `half_angle_rad` (π gives a sphere with a single boundary point missing — use
/// [`icosphere`] for closed spheres). Polar triangulation: a pole vertex and `rings` rings of
/// `6k` vertices at equal polar steps. Sphere centred at the origin; normals outward.
pub fn sphere_cap(radius_mm: f64, half_angle_rad: f64, rings: usize) -> TriMesh {
    polar_disk(rings, |t, a| {
        let phi = t * half_angle_rad;
        [
            radius_mm * phi.sin() * a.cos(),
            radius_mm * phi.sin() * a.sin(),
            radius_mm * phi.cos(),
        ]
    })
}

/// A flat disk of radius `radius_mm` in the plane z = 0, polar triangulation with `rings`
/// rings of `6k` vertices; normals +z.
pub fn planar_disk(radius_mm: f64, rings: usize) -> TriMesh {
    polar_disk(rings, |t, a| {
        [radius_mm * t * a.cos(), radius_mm * t * a.sin(), 0.0]
    })
}

/// A piece of the cylinder of radius `radius_mm` around the y axis: the angle range
/// `[0, angle_rad]` measured from +x towards −z, heights `[0, height_mm]`, `n_around × n_up`
/// vertices (at least 2 × 2). With `angle_rad ≥ 2π` the piece closes into a tube
/// (`n_around` vertices per ring, two boundary loops). Normals point away from the axis.
/// Every strip between two rulings is a planar rectangle, so interior angle defects are zero.
pub fn cylinder_patch(
    radius_mm: f64,
    angle_rad: f64,
    height_mm: f64,
    n_around: usize,
    n_up: usize,
) -> TriMesh {
    surface_of_revolution(angle_rad, n_around, n_up, |_, t| (radius_mm, t * height_mm))
}

/// A piece of the cone with its apex at `(0, height_mm, 0)` and base circle of radius
/// `radius_mm` in the plane y = 0: angle range `[0, angle_rad]` (from +x towards −z; ≥ 2π
/// closes it), `n_around` vertices per ring and `n_up` rings from the base up to (excluding)
/// the apex (at least 2), plus the apex vertex. A full cone is a disk whose apex carries the angle defect
/// 2π (1 − r / √(r² + h²)); every other interior vertex has defect zero (the strips between
/// rulings are planar). Normals point away from the axis.
pub fn cone_patch(
    radius_mm: f64,
    height_mm: f64,
    angle_rad: f64,
    n_around: usize,
    n_up: usize,
) -> TriMesh {
    let n_up = n_up.max(2);
    let (n_around, wrap) = around_count(angle_rad, n_around);
    let mut m = surface_of_revolution(angle_rad, n_around, n_up, |_, t| {
        let s = t * (n_up - 1) as f64 / n_up as f64;
        (radius_mm * (1.0 - s), s * height_mm)
    });
    let apex = m.positions.len() as u32;
    m.positions.push([0.0, height_mm, 0.0]);
    let top = (n_up - 1) * n_around;
    let cols = if wrap { n_around } else { n_around - 1 };
    for i in 0..cols {
        let a = (top + i) as u32;
        let b = (top + (i + 1) % n_around) as u32;
        m.faces.push([a, b, apex]);
    }
    m
}

fn around_count(angle_rad: f64, n_around: usize) -> (usize, bool) {
    let wrap = angle_rad >= TAU - 1e-12;
    (n_around.max(if wrap { 3 } else { 2 }), wrap)
}

/// Grid over (angle, height) of a surface of revolution about +y; `profile(angle, t)` gives
/// (radius, y) for t ∈ [0, 1]. Faces oriented so normals point away from the axis.
fn surface_of_revolution(
    angle_rad: f64,
    n_around: usize,
    n_up: usize,
    profile: impl Fn(f64, f64) -> (f64, f64),
) -> TriMesh {
    let (n_around, wrap) = around_count(angle_rad, n_around);
    let n_up = n_up.max(2);
    let step = if wrap {
        TAU / n_around as f64
    } else {
        angle_rad / (n_around - 1) as f64
    };
    let mut positions = Vec::with_capacity(n_around * n_up);
    for j in 0..n_up {
        let t = j as f64 / (n_up - 1) as f64;
        for i in 0..n_around {
            let a = i as f64 * step;
            let (r, y) = profile(a, t);
            // Angle from +x towards −z: with y up, (around, up) is then a right-handed frame
            // whose cross product points outward.
            positions.push([r * a.cos(), y, -r * a.sin()]);
        }
    }
    let mut faces = Vec::new();
    let cols = if wrap { n_around } else { n_around - 1 };
    let id = |i: usize, j: usize| (i % n_around + n_around * j) as u32;
    for j in 0..n_up - 1 {
        for i in 0..cols {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    mesh(positions, faces)
}

/// A flat square sheet `[−size/2, size/2]²` in z = 0 (`n × n` vertex grid, normals +z) with two
/// round holes of radius `size/8` centred at `(∓size/4, 0)`: three boundary loops, one
/// component, χ = −1. A hole removes every grid quad whose centre lies inside its circle; by
/// the British flag theorem a disk can never contain two diagonal quad centres without one of
/// the other two, so the holes never leave a bowtie vertex. Needs `n ≥ 9` for holes to appear.
pub fn patch_with_holes(size_mm: f64, n: usize) -> TriMesh {
    let r = size_mm / 8.0;
    let centres = [[-size_mm / 4.0, 0.0], [size_mm / 4.0, 0.0]];
    grid_patch_with_holes(
        n,
        size_mm,
        |_, _| 0.0,
        |x, y| {
            centres
                .iter()
                .any(|h| (x - h[0]).powi(2) + (y - h[1]).powi(2) <= r * r)
        },
    )
}

/// [`grid_patch`]`(n, n, size_mm, height)` without the cells (grid quads) whose centre (x, y)
/// `in_hole` takes, the vertices no face keeps dropped (the others in order): a patch with
/// holes of any outline drawn by the caller. Two removed cells meeting only at a corner leave a
/// bowtie vertex there, which the caller's outline must avoid.
pub fn grid_patch_with_holes(
    n: usize,
    size_mm: f64,
    height: impl Fn(f64, f64) -> f64,
    in_hole: impl Fn(f64, f64) -> bool,
) -> TriMesh {
    let n = n.max(2);
    let grid = grid_patch(n, n, size_mm, height);
    let mut faces = Vec::with_capacity(grid.faces.len());
    // grid_faces emits the two triangles of each quad consecutively.
    for pair in grid.faces.chunks(2) {
        let quad: Vec<u32> = {
            let mut q: Vec<u32> = pair.iter().flatten().copied().collect();
            q.sort_unstable();
            q.dedup();
            q
        };
        let c = quad.iter().fold([0.0, 0.0], |s, &v| {
            let p = grid.positions[v as usize];
            [s[0] + p[0] / 4.0, s[1] + p[1] / 4.0]
        });
        if !in_hole(c[0], c[1]) {
            faces.extend_from_slice(pair);
        }
    }
    compact(grid.positions, faces)
}

/// [`patch_with_holes`] lifted onto the sphere of radius `radius_mm` about the origin (the
/// upper half, z = √(r² − x² − y²), clamped at z = 0 for a radius below the sheet's half
/// diagonal): a doubly curved sheet whose holes each enclose Gaussian curvature, so that θ = 2π
/// at its interior vertices does not close them in the plane.
pub fn patch_with_holes_on_sphere(size_mm: f64, n: usize, radius_mm: f64) -> TriMesh {
    let mut sheet = patch_with_holes(size_mm, n);
    for p in &mut sheet.positions {
        p[2] = (radius_mm * radius_mm - p[0] * p[0] - p[1] * p[1])
            .max(0.0)
            .sqrt();
    }
    sheet
}

/// Two triangles sharing only vertex 0: the smallest non-manifold ("bowtie") vertex.
pub fn non_manifold_bowtie() -> TriMesh {
    mesh(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.5, 0.0],
            [1.0, -0.5, 0.0],
            [-1.0, -0.5, 0.0],
            [-1.0, 0.5, 0.0],
        ],
        vec![[0, 2, 1], [0, 4, 3]],
    )
}

/// Three triangles on the edge 0–1: the smallest non-manifold edge.
pub fn non_manifold_fin() -> TriMesh {
    mesh(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.0],
            [0.5, 0.0, 1.0],
        ],
        vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    )
}

/// A closed icosphere of radius `radius_mm` centred at the origin: the icosahedron with every
/// triangle split into four `subdivisions` times, new vertices projected onto the sphere
/// (12 + 10 (4^s − 1) vertices, 20 · 4^s faces). χ = 2, normals outward.
pub fn icosphere(radius_mm: f64, subdivisions: usize) -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| normalize(p))
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoint = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<[f64; 3]>| -> u32 {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let p = normalize(scale(
                    add(positions[a as usize], positions[b as usize]),
                    0.5,
                ));
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    for p in &mut positions {
        *p = scale(*p, radius_mm);
    }
    mesh(positions, faces)
}

/// A closed torus around the y axis: tube centre circle of radius `major_mm`, tube radius
/// `minor_mm`, `n_major × n_minor` vertices (each at least 3). χ = 0, genus 1, normals outward.
pub fn torus(major_mm: f64, minor_mm: f64, n_major: usize, n_minor: usize) -> TriMesh {
    let (nu, nv) = (n_major.max(3), n_minor.max(3));
    let mut positions = Vec::with_capacity(nu * nv);
    for j in 0..nv {
        let b = TAU * j as f64 / nv as f64;
        for i in 0..nu {
            let a = TAU * i as f64 / nu as f64;
            let r = major_mm + minor_mm * b.cos();
            positions.push([r * a.cos(), minor_mm * b.sin(), -r * a.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) + nu * (j % nv)) as u32;
    let mut faces = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    mesh(positions, faces)
}

/// Small versions of every shape, by name, for tests that run an algorithm over all of them.
/// Includes the non-manifold examples; filter on the name if an algorithm needs manifolds.
pub fn catalogue() -> Vec<(&'static str, TriMesh)> {
    vec![
        ("saddle_grid", saddle_grid(9)),
        ("grid_patch_flat", grid_patch(7, 5, 10.0, |_, _| 0.0)),
        ("sphere_cap_grid", sphere_cap_grid(9, PI / 3.0, 100.0)),
        ("sphere_cap", sphere_cap(100.0, PI / 4.0, 5)),
        ("hemisphere", sphere_cap(50.0, FRAC_PI_2, 6)),
        ("cylinder_patch", cylinder_patch(50.0, PI / 2.0, 80.0, 8, 6)),
        ("cylinder_tube", cylinder_patch(50.0, TAU, 80.0, 16, 6)),
        ("cone_patch", cone_patch(40.0, 60.0, PI, 9, 5)),
        ("cone_full", cone_patch(40.0, 60.0, TAU, 16, 5)),
        ("planar_disk", planar_disk(30.0, 5)),
        ("patch_with_holes", patch_with_holes(100.0, 17)),
        ("icosphere", icosphere(50.0, 2)),
        ("torus", torus(60.0, 20.0, 16, 8)),
        ("non_manifold_bowtie", non_manifold_bowtie()),
        ("non_manifold_fin", non_manifold_fin()),
        (
            "dress_form",
            dress_form(&BodyMeasurements {
                resolution: 24,
                ..Default::default()
            }),
        ),
    ]
}

/// Body measurements for [`dress_form`], all in millimetres; circumferences are measured
/// horizontally. `Default` is a standard women's size (EU 38, height 168 cm).
#[derive(Clone, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct BodyMeasurements {
    /// Body height, floor to crown (default 1680 mm); places the landmarks vertically.
    pub height_mm: f64,
    /// Bust circumference at the bust points (default 880 mm). `chest_mm` is accepted for it
    /// (the same girth on a men's size chart).
    #[serde(alias = "chest_mm")]
    pub bust_mm: f64,
    /// Natural waist circumference (default 700 mm).
    pub waist_mm: f64,
    /// Hip circumference at the fullest part of the seat (default 960 mm).
    pub hip_mm: f64,
    /// Neck base circumference (default 340 mm).
    pub neck_mm: f64,
    /// Shoulder width, shoulder tip to shoulder tip in a straight line (default 390 mm).
    pub shoulder_width_mm: f64,
    /// Vertices around each horizontal ring (default 96, at least 16); rings are spaced so
    /// triangles are close to equilateral, so the face count grows with its square
    /// (96 gives about 18k faces).
    pub resolution: usize,
}

impl Default for BodyMeasurements {
    fn default() -> Self {
        Self {
            height_mm: 1680.0,
            bust_mm: 880.0,
            waist_mm: 700.0,
            hip_mm: 960.0,
            neck_mm: 340.0,
            shoulder_width_mm: 390.0,
            resolution: 96,
        }
    }
}

/// Landmark heights of [`dress_form`] as fractions of body height: the rings at these heights
/// have exactly the measured circumferences.
pub mod landmarks {
    /// Fullest hip.
    pub const HIP: f64 = 0.50;
    /// Natural waist.
    pub const WAIST: f64 = 0.625;
    /// Bust points.
    pub const BUST: f64 = 0.71;
    /// Bottom opening of the form.
    pub const BOTTOM: f64 = 0.44;
    /// Top of the neck stub.
    pub const NECK_TOP: f64 = 0.875;
}

/// One horizontal key section of the torso: height, half-width (x), half-depth (z),
/// superellipse exponent, and the circumference it must have if it is a measurement.
struct Section {
    y: f64,
    a: f64,
    b: f64,
    p: f64,
    circumference: Option<f64>,
}

/// A dress form: the torso from below the hips to the neck, y up, +z front, x to the
/// form's left, the floor at y = 0.
///
/// Horizontal rings of `m.resolution` vertices are superellipses |x/a|^p + |z/b|^p = 1 whose
/// half-axes and exponent are interpolated (smoothstep, so each key section is a local
/// extreme) between key sections: bottom opening, hip, waist, bust (with two front bust
/// bulges), armpit, shoulder line (as wide as `shoulder_width_mm`, shallow), neck base and
/// neck top. Above the armpits the rings widen to the shoulders and then shrink to the neck
/// circle, so the shoulders close over the top. Each ring is scaled so that the polygon
/// perimeter of the hip, waist and bust rings equals the measurement exactly (the scale is
/// interpolated between key sections). Rings are spaced so that the vertical edge length
/// matches the horizontal one. The arm holes remove the quads whose centre lies in an ellipse
/// (in angle and height) on each side between armpit and shoulder.
///
/// The result is one connected, manifold, consistently outward-oriented open surface with four
/// boundary loops (neck, two arm holes, bottom): χ = −2. Non-finite or non-positive
/// measurements are replaced by the defaults.
pub fn dress_form(m: &BodyMeasurements) -> TriMesh {
    let d = BodyMeasurements::default();
    let pick = |v: f64, dv: f64| if v.is_finite() && v > 0.0 { v } else { dv };
    let h = pick(m.height_mm, d.height_mm);
    let bust = pick(m.bust_mm, d.bust_mm);
    let waist = pick(m.waist_mm, d.waist_mm);
    let hip = pick(m.hip_mm, d.hip_mm);
    let neck = pick(m.neck_mm, d.neck_mm);
    let shoulder = pick(m.shoulder_width_mm, d.shoulder_width_mm);
    let n = m.resolution.max(16);

    // Half-axes from a circumference c and an aspect ratio k = a/b (perimeter ≈ π(a + b);
    // the exact scale comes from the ring perimeter afterwards).
    let from_c = |y: f64, c: f64, k: f64, p: f64, measured: bool| {
        let b = c / (PI * (k + 1.0));
        Section {
            y: y * h,
            a: k * b,
            b,
            p,
            circumference: measured.then_some(c),
        }
    };
    let sections = [
        from_c(landmarks::BOTTOM, 0.95 * hip, 1.30, 2.4, false),
        from_c(landmarks::HIP, hip, 1.38, 2.6, true),
        from_c(landmarks::WAIST, waist, 1.38, 2.4, true),
        from_c(landmarks::BUST, bust, 1.22, 2.4, true),
        from_c(0.745, 0.97 * bust, 1.35, 2.6, false),
        Section {
            y: 0.815 * h,
            a: 0.5 * shoulder,
            b: 0.075 * bust,
            p: 3.0,
            circumference: None,
        },
        from_c(0.845, neck, 1.15, 2.0, false),
        from_c(landmarks::NECK_TOP, neck, 1.15, 2.0, false),
    ];
    let bust_y = landmarks::BUST * h;
    let bulge = 0.035 * bust;

    // Ring before scaling at height y, lying in segment `s` (sections s and s + 1).
    let raw_ring = |s: usize, y: f64| -> Vec<[f64; 2]> {
        let (lo, hi) = (&sections[s], &sections[s + 1]);
        let t = ((y - lo.y) / (hi.y - lo.y)).clamp(0.0, 1.0);
        let w = t * t * (3.0 - 2.0 * t);
        let a = lo.a + w * (hi.a - lo.a);
        let b = lo.b + w * (hi.b - lo.b);
        let p = lo.p + w * (hi.p - lo.p);
        let gy = (-((y - bust_y) / (0.035 * h)).powi(2)).exp();
        (0..n)
            .map(|i| {
                let th = TAU * i as f64 / n as f64;
                let (c, sn) = (th.cos(), th.sin());
                // The point at polar angle θ, so that a vertex moves radially from ring to ring
                // (a superellipse parameter would slide it sideways where the shape changes
                // fast, over the shoulders, and shear the quads into slivers).
                let r = ((c.abs() / a).powf(p) + (sn.abs() / b).powf(p)).powf(-1.0 / p);
                let (x, z) = (r * c, r * sn);
                // Bust bulges on the front, either side of the centre front (θ = π/2).
                let mut g = 0.0;
                for centre in [FRAC_PI_2 - 0.42, FRAC_PI_2 + 0.42] {
                    g += (-((th - centre) / 0.32).powi(2)).exp();
                }
                let r = (x * x + z * z).sqrt();
                let push = if r > 0.0 {
                    1.0 + bulge * gy * g / r
                } else {
                    1.0
                };
                [x * push, z * push]
            })
            .collect()
    };
    let perimeter = |ring: &[[f64; 2]]| -> f64 {
        (0..ring.len())
            .map(|i| {
                let (p, q) = (ring[i], ring[(i + 1) % ring.len()]);
                (q[0] - p[0]).hypot(q[1] - p[1])
            })
            .sum()
    };
    // Scale per key section: exact circumference at measured ones, 1 elsewhere.
    let key_scale: Vec<f64> = sections
        .iter()
        .enumerate()
        .map(|(k, sec)| match sec.circumference {
            Some(c) => {
                let s = k.min(sections.len() - 2);
                c / perimeter(&raw_ring(s, sec.y))
            }
            None => 1.0,
        })
        .collect();
    let ring = |s: usize, y: f64| -> Vec<[f64; 2]> {
        let (lo, hi) = (&sections[s], &sections[s + 1]);
        let t = ((y - lo.y) / (hi.y - lo.y)).clamp(0.0, 1.0);
        let w = t * t * (3.0 - 2.0 * t);
        let sc = key_scale[s] + w * (key_scale[s + 1] - key_scale[s]);
        raw_ring(s, y)
            .into_iter()
            .map(|[x, z]| [sc * x, sc * z])
            .collect()
    };

    // Ring heights: within each segment, uniform in τ = ∫ ds / (perimeter / n), where ds
    // is the largest displacement of a ring vertex, so vertical edges match horizontal ones.
    const SAMPLES: usize = 200;
    let mut heights = vec![sections[0].y];
    for s in 0..sections.len() - 1 {
        let (y0, y1) = (sections[s].y, sections[s + 1].y);
        let mut tau = vec![0.0];
        let mut prev = ring(s, y0);
        for k in 1..=SAMPLES {
            let y = y0 + (y1 - y0) * k as f64 / SAMPLES as f64;
            let cur = ring(s, y);
            let dy = (y1 - y0) / SAMPLES as f64;
            let dmax = prev
                .iter()
                .zip(&cur)
                .map(|(p, q)| (q[0] - p[0]).hypot(q[1] - p[1]))
                .fold(0.0, f64::max);
            let edge = 0.5 * (perimeter(&prev) + perimeter(&cur)) / n as f64;
            tau.push(tau[k - 1] + dy.hypot(dmax) / edge);
            prev = cur;
        }
        let total = tau[SAMPLES];
        let count = (total.round() as usize).max(1);
        let mut k = 0;
        for r in 1..=count {
            let target = total * r as f64 / count as f64;
            if r == count {
                heights.push(y1);
                break;
            }
            while k < SAMPLES - 1 && tau[k + 1] < target {
                k += 1;
            }
            let f = (target - tau[k]) / (tau[k + 1] - tau[k]);
            heights.push(y0 + (y1 - y0) * (k as f64 + f) / SAMPLES as f64);
        }
    }

    let mut positions = Vec::with_capacity(heights.len() * n);
    let mut seg = 0;
    for &y in &heights {
        while seg + 2 < sections.len() && y > sections[seg + 1].y {
            seg += 1;
        }
        for [x, z] in ring(seg, y) {
            positions.push([x, y, z]);
        }
    }

    // Arm holes: an ellipse in (angle, height) around each side (θ = 0 and π).
    let hole_y = 0.78 * h;
    let (hole_dy, hole_dth) = (0.03 * h, 0.5);
    let in_hole = |th: f64, y: f64| {
        [0.0, PI].iter().any(|&c| {
            let mut dth = (th - c).rem_euclid(TAU);
            if dth > PI {
                dth -= TAU;
            }
            (dth / hole_dth).powi(2) + ((y - hole_y) / hole_dy).powi(2) <= 1.0
        })
    };
    let id = |i: usize, j: usize| ((i % n) + n * j) as u32;
    let mut faces = Vec::with_capacity(2 * n * heights.len());
    for j in 0..heights.len() - 1 {
        let ym = 0.5 * (heights[j] + heights[j + 1]);
        for i in 0..n {
            let th = TAU * (i as f64 + 0.5) / n as f64;
            if in_hole(th, ym) {
                continue;
            }
            let (a, b, c, dd) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            // θ runs from +x towards +z (counter-clockwise seen from below), so (up, around)
            // is the outward frame: triangles go a → d → c.
            faces.push([a, c, b]);
            faces.push([a, dd, c]);
        }
    }
    compact(positions, faces)
}

/// Drops unreferenced vertices, keeping order.
fn compact(positions: Vec<[f64; 3]>, mut faces: Vec<[u32; 3]>) -> TriMesh {
    let mut remap = vec![u32::MAX; positions.len()];
    for f in &faces {
        for &v in f {
            remap[v as usize] = 0;
        }
    }
    let mut kept = Vec::with_capacity(positions.len());
    for (v, p) in positions.into_iter().enumerate() {
        if remap[v] == 0 {
            remap[v] = kept.len() as u32;
            kept.push(p);
        }
    }
    for f in &mut faces {
        for v in f.iter_mut() {
            *v = remap[*v as usize];
        }
    }
    mesh(kept, faces)
}
