//! One decimation of mh_body_subdiv2 (FLATCUT_DATA) to 50k faces, with the phase it ends in
//! timed: `FLATCUT_DATA=../shared/meshes cargo run --release -p flatcut_remesh --example decimate_once [REPS]`.
fn main() {
    let dir = std::env::var_os("FLATCUT_DATA").expect("set FLATCUT_DATA to the shared meshes");
    let path = std::path::Path::new(&dir).join("mh_body_subdiv2.obj");
    let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Dm)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .mesh;
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let opts = flatcut_remesh::DecimateOptions {
        target_faces: 50_000,
    };
    for _ in 0..reps {
        let t = std::time::Instant::now();
        let d = flatcut_remesh::decimate(&mesh, &opts).expect("decimate");
        println!(
            "{} → {} faces in {:.3} s, Hausdorff {:.3} mm, RMS {:.3} mm",
            mesh.faces.len(),
            d.report.faces,
            t.elapsed().as_secs_f64(),
            d.report.hausdorff_mm,
            d.report.rms_mm
        );
    }
}
