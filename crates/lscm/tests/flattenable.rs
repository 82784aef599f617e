//! A piece made flattenable by flatcut_flattenable (θ = 2π at every interior vertex to
//! 1e-9) flattens with lscm+arap to a near-isometry: max edge strain ≤ 1e-6.

#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;

use flatcut_flattenable::{ProcessOptions, process};
use flatcut_lscm::{FlattenOptions, Method, distortion, flatten};
use flatcut_mesh::{Topology, shapes};

#[test]
fn processed_pieces_flatten_isometrically() {
    for (name, mesh) in [
        ("saddle_grid", shapes::saddle_grid(9)),
        (
            "sphere_cap_grid",
            shapes::sphere_cap_grid(9, PI / 3.0, 100.0),
        ),
    ] {
        let processed = process(&mesh, &ProcessOptions::default()).unwrap();
        let theta_err = processed.report.final_theta_err;
        assert!(theta_err <= 1e-9, "{name}: θ_err {theta_err}");
        let flat_mesh = processed.mesh;
        let topo = Topology::build(&flat_mesh).unwrap();
        // Before processing the same piece cannot be flattened isometrically.
        let before = flatten(&mesh, &FlattenOptions::default()).unwrap();
        let d0 = distortion(
            &mesh,
            &Topology::build(&mesh).unwrap(),
            &before.flattening.uv,
        );
        assert!(d0.max_edge_strain > 1e-3, "{name}: {}", d0.max_edge_strain);
        let out = flatten(
            &flat_mesh,
            &FlattenOptions {
                method: Method::LscmArap,
                ..Default::default()
            },
        )
        .unwrap();
        let d = distortion(&flat_mesh, &topo, &out.flattening.uv);
        eprintln!(
            "{name}: θ_err {theta_err:e}, max edge strain {:e} (before processing {:e}), E_h max {:e}, E_r max {:e}",
            d.max_edge_strain, d0.max_edge_strain, d.e_h.max, d.e_r.max
        );
        assert!(d.max_edge_strain <= 1e-6, "{name}: {}", d.max_edge_strain);
        assert_eq!(d.flipped_faces, 0);
    }
}
