//! Small test surfaces made here (until flatcut_mesh::shapes lands): parametric grids with
//! faces counter-clockwise with respect to ∂u × ∂v.
#![allow(dead_code, clippy::unwrap_used)]

use flatcut_mesh::TriMesh;

/// An `nu × nv` vertex grid over (u, v) ∈ [0, 1]², vertex (i, j) at index i + nu·j, with
/// alternating diagonals (irregular enough that nothing is accidentally symmetric).
pub fn grid(nu: usize, nv: usize, f: impl Fn(f64, f64) -> [f64; 3]) -> TriMesh {
    let mut positions = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            positions.push(f(i as f64 / (nu - 1) as f64, j as f64 / (nv - 1) as f64));
        }
    }
    let id = |i: usize, j: usize| (i + nu * j) as u32;
    let mut faces = Vec::new();
    for j in 0..nv - 1 {
        for i in 0..nu - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                faces.push([a, b, c]);
                faces.push([a, c, d]);
            } else {
                faces.push([a, b, d]);
                faces.push([b, c, d]);
            }
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

/// A planar piece in a tilted plane, irregularly sampled (mm).
pub fn planar(n: usize) -> TriMesh {
    let e1 = [0.6, 0.8, 0.0];
    let e2 = [0.0, 0.0, 1.0];
    grid(n, n + 3, |u, v| {
        let x = 120.0 * u + 9.0 * (3.0 * v).sin();
        let y = 80.0 * v + 6.0 * (4.0 * u).sin() * v;
        [
            5.0 + x * e1[0] + y * e2[0],
            -3.0 + x * e1[1] + y * e2[1],
            7.0 + x * e1[2] + y * e2[2],
        ]
    })
}

/// A cylinder piece, radius 60 mm, 150° around, 120 mm tall (developable).
pub fn cylinder(nu: usize, nv: usize) -> TriMesh {
    let r = 60.0;
    let span = 150f64.to_radians();
    grid(nu, nv, |u, v| {
        let a = u * span;
        [r * a.cos(), 120.0 * v, -r * a.sin()]
    })
}

/// A truncated cone piece (no apex: developable), 200° around.
pub fn cone(nu: usize, nv: usize) -> TriMesh {
    let span = 200f64.to_radians();
    grid(nu, nv, |u, v| {
        let a = u * span;
        let s = 0.35 + 0.65 * (1.0 - v); // distance factor from the apex
        let (r, h) = (70.0 * s, 110.0 * (1.0 - s));
        [r * a.cos(), h, -r * a.sin()]
    })
}

/// A saddle z = (x² − y²)/150 over 100×100 mm (not developable).
pub fn saddle(n: usize) -> TriMesh {
    grid(n, n, |u, v| {
        let (x, y) = (100.0 * u - 50.0, 100.0 * v - 50.0);
        [x, y, (x * x - y * y) / 150.0]
    })
}

/// A spherical cap (not developable), radius 80 mm, up to 60° from the pole, as a grid
/// in polar coordinates with the pole row collapsed avoided (starts at 5°).
pub fn sphere_band(nu: usize, nv: usize) -> TriMesh {
    grid(nu, nv, |u, v| {
        let a = u * 4.0;
        let p = (5.0 + 55.0 * v).to_radians();
        [
            80.0 * p.sin() * a.cos(),
            80.0 * p.sin() * a.sin(),
            80.0 * p.cos(),
        ]
    })
}

/// A planar annulus (a piece with a hole), inner radius 30, outer 70 mm, closed around.
pub fn annulus(n_around: usize, n_radial: usize) -> TriMesh {
    let mut positions = Vec::new();
    for j in 0..n_radial {
        let r = 30.0 + 40.0 * j as f64 / (n_radial - 1) as f64;
        for i in 0..n_around {
            let a = std::f64::consts::TAU * i as f64 / n_around as f64;
            positions.push([r * a.cos(), r * a.sin(), 0.0]);
        }
    }
    let id = |i: usize, j: usize| ((i % n_around) + n_around * j) as u32;
    let mut faces = Vec::new();
    for j in 0..n_radial - 1 {
        for i in 0..n_around {
            // Counter-clockwise seen from +z: inner → outer → outer-next.
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, c, b]);
            faces.push([a, d, c]);
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

/// Two meshes as one (the second's indices shifted).
pub fn union(a: &TriMesh, b: &TriMesh) -> TriMesh {
    let mut positions = a.positions.clone();
    positions.extend_from_slice(&b.positions);
    let off = a.positions.len() as u32;
    let mut faces = a.faces.clone();
    faces.extend(b.faces.iter().map(|f| f.map(|v| v + off)));
    TriMesh::new(positions, faces).unwrap()
}

/// The signed area of every face in `uv`.
pub fn signed_areas(mesh: &TriMesh, uv: &[[f64; 2]]) -> Vec<f64> {
    mesh.faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| uv[v as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        })
        .collect()
}
