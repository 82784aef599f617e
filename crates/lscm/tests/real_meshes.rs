//! LSCM on real meshes against libigl's `igl::lscm`.
//!
//! Reference numbers were produced by `python crates/lscm/tests/reference/igl_lscm_reference.py
//! /work/shared/meshes` with libigl 2.6.3 and numpy 2.4.6 from PyPI (Python 3.11): same
//! pins (the boundary diameter pair, at (0, 0) and (d, 0)), metrics computed in numpy with
//! its SVD. Needs FLATCUT_DATA (the shared meshes folder): skipped when unset, failing when
//! set and a file is missing.

#![allow(clippy::unwrap_used, clippy::excessive_precision)] // reference values as printed (%.17g)

use std::path::PathBuf;

use flatcut_lscm::{LscmOptions, Pins, distortion, lscm};
use flatcut_mesh::{Topology, VertexId};

fn data(name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("FLATCUT_DATA")?;
    let path = PathBuf::from(dir).join(name);
    assert!(
        path.is_file(),
        "FLATCUT_DATA is set but {} is missing",
        path.display()
    );
    Some(path)
}

struct Reference {
    file: &'static str,
    pins: [u32; 2],
    mean_e_r: f64,
    mean_e_h: f64,
    /// xᵀQx with libigl's Q, = 2 E_C.
    x_q_x: f64,
}

const REFERENCES: [Reference; 2] = [
    Reference {
        file: "igl_camelhead.obj",
        pins: [6091, 9797],
        mean_e_r: 0.066144714268106974,
        mean_e_h: 0.92506281369938537,
        x_q_x: 0.0010972003875596666,
    },
    Reference {
        file: "igl_face.obj",
        pins: [4434, 12539],
        mean_e_r: 0.027992948388441984,
        mean_e_h: 0.78573653031389235,
        x_q_x: 0.32555532365135131,
    },
];

#[test]
fn lscm_matches_libigl() {
    for r in &REFERENCES {
        let Some(path) = data(r.file) else {
            eprintln!("FLATCUT_DATA unset: skipping {}", r.file);
            continue;
        };
        let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
            .unwrap()
            .mesh;
        let topo = Topology::build(&mesh).unwrap();
        let opts = LscmOptions {
            pins: Pins::Given([VertexId(r.pins[0]), VertexId(r.pins[1])]),
            ..Default::default()
        };
        let flat = lscm(&mesh, &opts).unwrap();
        let d = distortion(&mesh, &topo, &flat.uv);
        eprintln!(
            "{}: mean E_r {:.17} (libigl {:.17}), mean E_h {:.17} (libigl {:.17}), 2 E_C {:.17e} (libigl {:.17e})",
            r.file,
            d.e_r.mean,
            r.mean_e_r,
            d.e_h.mean,
            r.mean_e_h,
            2.0 * flat.pieces[0].conformal_energy,
            r.x_q_x
        );
        assert!((d.e_r.mean - r.mean_e_r).abs() <= 1e-6, "{}", r.file);
        assert!((d.e_h.mean - r.mean_e_h).abs() <= 1e-6, "{}", r.file);
        let e = 2.0 * flat.pieces[0].conformal_energy;
        assert!(
            (e - r.x_q_x).abs() <= 1e-6 * r.x_q_x,
            "{}: {e} vs {}",
            r.file,
            r.x_q_x
        );
        assert_eq!(d.flipped_faces, 0);
        // The automatic pins are the same diameter pair the reference script chose.
        let auto = lscm(&mesh, &LscmOptions::default()).unwrap();
        let mut pins = auto.pieces[0].pins.map(|v| v.0);
        pins.sort_unstable();
        assert_eq!(pins, r.pins, "{}", r.file);
    }
}

#[test]
fn real_disks_flatten_unfolded_and_refinement_lowers_the_area_error() {
    for file in ["igl_camelhead.obj", "igl_face.obj", "mountain_disk.obj"] {
        let Some(path) = data(file) else {
            eprintln!("FLATCUT_DATA unset: skipping {file}");
            continue;
        };
        let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
            .unwrap()
            .mesh;
        let topo = Topology::build(&mesh).unwrap();
        let conformal = flatcut_lscm::flatten(
            &mesh,
            &flatcut_lscm::FlattenOptions {
                method: flatcut_lscm::Method::Lscm,
                ..Default::default()
            },
        )
        .unwrap();
        let refined = flatcut_lscm::flatten(&mesh, &Default::default()).unwrap();
        let d0 = distortion(&mesh, &topo, &conformal.flattening.uv);
        let d1 = distortion(&mesh, &topo, &refined.flattening.uv);
        eprintln!(
            "{file}: lscm strain {:.3e} E_h mean {:.3e} flipped {} | lscm+arap strain {:.3e} E_h mean {:.3e} E_r mean {:.3e} flipped {}",
            d0.max_edge_strain,
            d0.e_h.mean,
            d0.flipped_faces,
            d1.max_edge_strain,
            d1.e_h.mean,
            d1.e_r.mean,
            d1.flipped_faces
        );
        assert_eq!(d0.flipped_faces, 0, "{file}");
        assert_eq!(d1.flipped_faces, 0, "{file}");
        // These scans are far from developable: no flattening is close to isometric, and the
        // max strain is not monotone; the refinement must lower the ARAP energy and the mean
        // area error without adding a fold.
        assert!(d1.e_h.mean < d0.e_h.mean, "{file}");
        let r = &refined.refine[0].arap;
        assert!(r.energy_after < r.energy_before, "{file}");
        assert!(
            refined
                .flattening
                .uv
                .iter()
                .flatten()
                .all(|x| x.is_finite())
        );
    }
}
