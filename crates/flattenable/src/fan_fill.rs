//! A piece's holes filled by fans (`HoleRims::Free`): one vertex at each rim's centroid and a
//! triangle from it to every rim edge, so that the piece becomes a disk whose rim vertices are
//! interior. θ = 2π on the disk makes the fills flat, and a hole bounded by a flat fill closes
//! in the plane; the fills are dropped after the processing. A fan needs no triangulation of
//! the rim's polygon, and its faces only serve as constraints (their shape is not kept).
//!
//! The centre continues the surface over the hole ([`fill_centre`]): a fan from the rim's
//! centroid lies below a dome and above a bowl, which puts a cone of angle defect at the
//! centre and a kink at every rim vertex that the processing must first undo (measured on a
//! 570-face chest patch of the MakeHuman body with a 16-vertex hole: θ_err 0.79 rad at the
//! filled input, and the run stalled at 7e-2 with creases).

use flatcut_mesh::geometry::area_weighted_vertex_normals;
use flatcut_mesh::vec3::{add, dot, normalize, scale, sub};
use flatcut_mesh::{TriMesh, VertexId};

use crate::hole_closure::Holes;

/// `piece` with every hole of `holes` filled: the piece's vertices and faces first and in
/// their order, then one centroid vertex per hole and its fan. Each fan face runs along its
/// rim edge backwards, the orientation of the face across that edge.
pub(crate) fn fan_filled(piece: &TriMesh, holes: &Holes) -> TriMesh {
    let mut positions = piece.positions.clone();
    let mut faces = piece.faces.clone();
    let normals = area_weighted_vertex_normals(&piece.positions, &piece.faces);
    for rim in holes.rims() {
        let c = positions.len() as u32;
        positions.push(fill_centre(&piece.positions, &normals, rim));
        for j in 0..rim.len() {
            let (a, b) = (rim[j].0, rim[(j + 1) % rim.len()].0);
            faces.push([b, a, c]);
        }
    }
    TriMesh {
        positions,
        faces,
        attributes: Default::default(),
        face_labels: None,
    }
}

/// The fill's centre for `rim`: its centroid g moved along the rims' mean normal n by half
/// the height h at which the rim vertices' tangent planes meet best (least squares,
/// h = −Σ (n_v · n)(n_v · (g − v)) / Σ (n_v · n)², n_v the area-weighted vertex normals). On
/// a sphere the tangent planes of a circle meet on its axis at (sec φ − cos φ) R above the
/// circle's plane, and the sphere at (1 − cos φ) R, a ratio cos φ / (1 + cos φ) → ½: half is
/// the surface over the hole to second order. The centroid itself where the normals give no
/// height (a rim whose normals are all across n).
fn fill_centre(positions: &[[f64; 3]], normals: &[[f64; 3]], rim: &[VertexId]) -> [f64; 3] {
    let k = rim.len() as f64;
    let centroid = rim
        .iter()
        .fold([0.0; 3], |c, v| add(c, scale(positions[v.idx()], 1.0 / k)));
    let n = normalize(rim.iter().fold([0.0; 3], |s, v| add(s, normals[v.idx()])));
    let (mut num, mut den) = (0.0, 0.0);
    for v in rim {
        let nv = normalize(normals[v.idx()]);
        let a = dot(nv, n);
        num -= a * dot(nv, sub(centroid, positions[v.idx()]));
        den += a * a;
    }
    let h = 0.5 * num / den;
    if h.is_finite() && n.iter().all(|c| c.is_finite()) {
        add(centroid, scale(n, h))
    } else {
        centroid
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flatcut_mesh::Topology;

    #[test]
    fn the_fill_centre_lies_on_the_sphere_its_rim_was_cut_from() {
        let radius = 400.0;
        let sheet = flatcut_mesh::shapes::patch_with_holes_on_sphere(200.0, 25, radius);
        let topo = Topology::build(&sheet).unwrap();
        let holes = Holes::of(&topo, &sheet.positions);
        let filled = fan_filled(&sheet, &holes);
        assert_eq!(filled.vertex_count(), sheet.vertex_count() + 2);
        let normals = area_weighted_vertex_normals(&sheet.positions, &sheet.faces);
        for (k, rim) in holes.rims().enumerate() {
            let centre = filled.positions[sheet.vertex_count() + k];
            assert_eq!(centre, fill_centre(&sheet.positions, &normals, rim));
            let centroid = rim.iter().fold([0.0; 3], |c, v| {
                add(c, scale(sheet.positions[v.idx()], 1.0 / rim.len() as f64))
            });
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
        // Every fan face runs along its rim edge backwards: the filled piece is a disk.
        let filled_topo = Topology::build(&filled).unwrap();
        assert_eq!(filled_topo.boundary_loops().len(), 1);
        assert!(filled_topo.inconsistent_edges().is_empty());
    }
}
