//! Every shape of the mesh crate's catalogue: flattened without a mirrored piece (and, on
//! disks and planar pieces, without a single flipped face), isometric where the shape is
//! developable, refused with the right error where it cannot be flattened at all.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_lscm::{FlattenOptions, LscmError, Method, distortion, flatten};
use flatcut_mesh::{Topology, shapes};

#[test]
fn catalogue_never_mirrored_and_developable_shapes_isometric() {
    let developable = [
        "grid_patch_flat",
        "cylinder_patch",
        "cone_patch",
        "planar_disk",
    ];
    let planar_with_holes = ["patch_with_holes"];
    let mut flattened = 0;
    for (name, mesh) in shapes::catalogue() {
        let topo = Topology::build(&mesh).unwrap();
        let disk = topo.component_count() == 1 && topo.euler_characteristic() == 1;
        for method in [Method::Lscm, Method::LscmArap] {
            let opts = FlattenOptions {
                method,
                ..Default::default()
            };
            match flatten(&mesh, &opts) {
                Ok(out) => {
                    let uv = &out.flattening.uv;
                    let areas = common::signed_areas(&mesh, uv);
                    let d = distortion(&mesh, &topo, uv);
                    let negative = areas.iter().filter(|&&a| a < 0.0).count();
                    assert_eq!(d.flipped_faces, negative, "{name}");
                    // The piece as a whole is never mirrored.
                    assert!(d.area_2d_mm2 > 0.0, "{name} {method:?}");
                    if disk || planar_with_holes.contains(&name) {
                        let min = areas.iter().copied().fold(f64::INFINITY, f64::min);
                        assert!(min > 0.0, "{name} {method:?}: min signed area {min}");
                    } else {
                        // Not a disk and not planar (a tube, a body with openings): no
                        // fold-free flattening need exist; folds are reported, not hidden.
                        eprintln!(
                            "{name} {method:?}: {} flipped faces reported",
                            d.flipped_faces
                        );
                    }
                    if method == Method::LscmArap && developable.contains(&name) {
                        assert!(d.e_h.max < 1e-9, "{name}: E_h {}", d.e_h.max);
                        assert!(d.e_r.max < 1e-9, "{name}: E_r {}", d.e_r.max);
                        assert!(d.max_edge_strain < 1e-9, "{name}: {}", d.max_edge_strain);
                    }
                    flattened += 1;
                }
                Err(e) => match name {
                    "icosphere" | "torus" => {
                        assert!(
                            matches!(e, LscmError::ClosedComponent { .. }),
                            "{name}: {e}"
                        )
                    }
                    "non_manifold_bowtie" => {
                        assert!(
                            matches!(e, LscmError::NonManifoldVertex { .. }),
                            "{name}: {e}"
                        )
                    }
                    "non_manifold_fin" => {
                        assert!(
                            matches!(e, LscmError::NonManifoldEdge { .. }),
                            "{name}: {e}"
                        )
                    }
                    _ => panic!("{name} {method:?}: unexpected error {e}"),
                },
            }
        }
    }
    assert!(flattened >= 2 * 10, "only {flattened} flattenings");
}

#[test]
fn shapes_cylinder_and_cone_patches_become_isometries() {
    use std::f64::consts::PI;
    for mesh in [
        shapes::cylinder_patch(70.0, 2.0 * PI / 3.0, 150.0, 30, 20),
        shapes::cone_patch(60.0, 90.0, 1.5 * PI, 30, 12),
    ] {
        let topo = Topology::build(&mesh).unwrap();
        let out = flatten(&mesh, &FlattenOptions::default()).unwrap();
        let d = distortion(&mesh, &topo, &out.flattening.uv);
        assert!(
            d.e_h.max < 1e-9 && d.e_r.max < 1e-9,
            "{:?} {:?}",
            d.e_h,
            d.e_r
        );
        assert!(d.max_edge_strain < 1e-9, "{}", d.max_edge_strain);
        assert_eq!(d.flipped_faces, 0);
    }
}
