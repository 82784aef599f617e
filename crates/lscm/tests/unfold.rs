//! Exact unfolding: an isometry on developable pieces, a measurable mismatch elsewhere.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_lscm::{distortion, split_pieces, unfold};
use flatcut_mesh::{Topology, TriMesh};

fn unfold_mesh(mesh: &TriMesh) -> (f64, flatcut_lscm::DistortionReport) {
    let topo = Topology::build(mesh).unwrap();
    let piece = split_pieces(mesh, &topo).unwrap().remove(0);
    let u = unfold(&piece);
    let mut uv = vec![[0.0; 2]; mesh.vertex_count()];
    for (v, q) in piece.vertices.iter().zip(&u.uv) {
        uv[v.idx()] = *q;
    }
    (u.max_mismatch_mm, distortion(mesh, &topo, &uv))
}

#[test]
fn developable_pieces_unfold_isometrically() {
    for mesh in [
        common::planar(9),
        common::cylinder(20, 8),
        common::cone(20, 7),
    ] {
        let (mismatch, d) = unfold_mesh(&mesh);
        assert!(mismatch < 1e-9, "{mismatch}");
        assert!(d.max_edge_strain < 1e-9, "{}", d.max_edge_strain);
        assert!(d.e_r.max < 1e-9 && d.e_h.max < 1e-9);
        assert_eq!(d.flipped_faces, 0);
    }
}

#[test]
fn curved_pieces_show_a_mismatch() {
    let (mismatch, _) = unfold_mesh(&common::saddle(10));
    assert!(mismatch > 1e-3, "{mismatch}");
}
