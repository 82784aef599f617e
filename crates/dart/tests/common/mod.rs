//! Shared test shapes.

#![allow(dead_code)]

use flatcut_mesh::{TriMesh, shapes};

/// The bump z = h·exp(−r²/σ²) over the disk of radius `radius_mm`: flatcut_mesh's polar
/// disk (a centre vertex, ring k of 6k vertices) lifted. The top is vertex 0.
pub fn bump(rings: usize, radius_mm: f64, h_mm: f64, sigma_mm: f64) -> TriMesh {
    let mut m = shapes::planar_disk(radius_mm, rings);
    for p in &mut m.positions {
        let r2 = p[0] * p[0] + p[1] * p[1];
        p[2] = h_mm * (-r2 / (sigma_mm * sigma_mm)).exp();
    }
    m
}

/// Ring index of every vertex of [`bump`] (0 at the top): ring k holds 6k vertices.
pub fn ring_of(v: u32) -> usize {
    let mut k = 0usize;
    let mut first = 0u32;
    loop {
        let count = if k == 0 { 1 } else { 6 * k as u32 };
        if v < first + count {
            return k;
        }
        first += count;
        k += 1;
    }
}
