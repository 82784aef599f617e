//! Robust mode on the real disk patches of FLATCUT_DATA (skipped when the variable is unset;
//! a missing file fails). What must hold on every one: either θ_err ≤ 1e-9 with no fold, or
//! the clean `NotConverged` error whose partial result is unfolded, has bit-identical
//! boundary, and is better than the input. The numbers reached are in
//! docs/algorithms/flattenable.md.

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use flatcut_flattenable::{FlattenableError, ProcessOptions, Processed, process};
use flatcut_mesh::{Topology, TriMesh, VertexId};

fn data(name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("FLATCUT_DATA")?;
    let path = PathBuf::from(dir).join(name);
    assert!(
        path.exists(),
        "FLATCUT_DATA is set but {} is missing",
        path.display()
    );
    Some(path)
}

fn check(name: &str, max_iterations: usize) {
    check_with(name, max_iterations, false);
}

fn check_with(name: &str, max_iterations: usize, must_converge: bool) {
    let Some(path) = data(name) else {
        eprintln!("FLATCUT_DATA unset: skipping {name}");
        return;
    };
    let mesh: TriMesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Mm)
        .unwrap()
        .mesh;
    let opts = ProcessOptions {
        max_iterations: Some(max_iterations),
        ..Default::default()
    };
    let r: Processed = match process(&mesh, &opts) {
        Ok(r) => {
            assert!(r.report.final_theta_err <= 1e-9);
            r
        }
        Err(FlattenableError::NotConverged {
            best_theta_err,
            partial,
            ..
        }) => {
            eprintln!("{name}: not converged, best θ_err {best_theta_err:.3e}");
            assert!(
                !must_converge,
                "{name}: did not converge ({best_theta_err:.3e})"
            );
            assert!(best_theta_err > 1e-9);
            let p = &partial.report.pieces[0];
            // Best by the merit ‖θ − 2π‖: its RMS is below the input's.
            let mut theta0 = flatcut_mesh::geometry::angle_sums(&mesh.positions, &mesh.faces);
            let topo = Topology::build(&mesh).unwrap();
            let (mut s, mut n) = (0.0, 0usize);
            for (v, t) in theta0.iter_mut().enumerate() {
                if topo.is_interior_vertex(VertexId(v as u32)) {
                    s += (*t - std::f64::consts::TAU).powi(2);
                    n += 1;
                }
            }
            assert!(p.final_theta_rms < (s / n as f64).sqrt());
            *partial
        }
        Err(e) => panic!("{name}: {e}"),
    };
    assert_eq!(r.report.folded_faces, 0, "{name}");
    assert!(r.mesh.positions.iter().flatten().all(|c| c.is_finite()));
    let topo = Topology::build(&mesh).unwrap();
    for v in 0..mesh.vertex_count() {
        if topo.is_boundary_vertex(VertexId(v as u32)) {
            assert_eq!(
                mesh.positions[v], r.mesh.positions[v],
                "{name}: boundary moved"
            );
        }
    }
}

#[test]
fn igl_snail() {
    check("igl_snail.obj", 100);
}

#[test]
fn smpl_hand_lowres() {
    check("smpl_hand_lowres.obj", 100);
}

#[test]
#[ignore = "8k vertices: run in release"]
fn bust_demosthenes() {
    check("bust_demosthenes.obj", 500);
}

#[test]
#[ignore = "8k vertices: run in release"]
fn igl_lion() {
    check("igl_lion.obj", 500);
}

/// A disk-like relief (negative total defect −0.65 rad) that robust mode takes to 1e-9:
/// measured 85 iterations solved directly, 14 fine-level ones with the default coarse-to-fine
/// start (docs/algorithms/flattenable.md).
#[test]
#[ignore = "2k vertices: run in release"]
fn igl_inspired_mesh_converges() {
    check_with("igl_inspired_mesh.obj", 500, true);
}
