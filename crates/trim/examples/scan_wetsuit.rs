//! Cuts the wetsuit plan of pipelines/wetsuit-scan.toml on $FLATCUT_DATA/mh_body_scanlike.obj
//! cleaned (largest component) and remeshed to a given edge length, as `flatcut run` does, and
//! prints the trim result or error. The remeshed mesh is cached as an OBJ under the system
//! temporary folder so that repeated runs only cut.
//!   FLATCUT_DATA=/work/shared/meshes cargo run --release -p flatcut_trim --example scan_wetsuit -- 8

use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let edge_mm: f64 = std::env::args().nth(1).unwrap_or("8".into()).parse()?;
    let dir = PathBuf::from(std::env::var_os("FLATCUT_DATA").ok_or("set FLATCUT_DATA")?);
    let plan = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../pipelines/wetsuit-scan.toml"
    );
    let v: toml::Value = toml::from_str(&std::fs::read_to_string(plan)?)?;
    // Second argument: the crease angle (the plan's 180 when absent; 45 is the remesh default).
    let feature: Option<f64> = std::env::args().nth(2).map(|a| a.parse()).transpose()?;
    let cache = std::env::temp_dir().join(format!(
        "flatcut_scan_remesh_{edge_mm}_{}.obj",
        feature.unwrap_or(180.0)
    ));
    let t = std::time::Instant::now();
    let mesh = if cache.exists() {
        flatcut_io::read_mesh(&cache, flatcut_io::Units::Mm)?.mesh
    } else {
        let raw =
            flatcut_io::read_mesh(&dir.join("mh_body_scanlike.obj"), flatcut_io::Units::Mm)?.mesh;
        let clean = flatcut_mesh::clean::CleanOptions {
            keep: flatcut_mesh::clean::Keep::Largest,
            ..Default::default()
        };
        let (m, _, _) = flatcut_mesh::clean::clean(&raw, &clean)?;
        let mut ro: flatcut_remesh::RemeshOptions = v["input"]["remesh"].clone().try_into()?;
        ro.target_edge_mm = edge_mm;
        if let Some(f) = feature {
            ro.feature_angle_deg = f;
        }
        let m = flatcut_remesh::remesh(&m, &ro)?.mesh;
        flatcut_io::write_mesh(&cache, &m, &Default::default())?;
        m
    };
    eprintln!(
        "mesh {} faces in {:.1} s",
        mesh.faces.len(),
        t.elapsed().as_secs_f64()
    );
    let mut c = toml::Table::new();
    c.insert("cut".into(), v["cut"].clone());
    c.insert("piece".into(), v["piece"].clone());
    c.insert("options".into(), v["trim"].clone());
    let cuts: flatcut_trim::Cuts = toml::Value::Table(c).try_into()?;
    let t = std::time::Instant::now();
    match flatcut_trim::trim(&mesh, &cuts) {
        Ok(tr) => {
            println!(
                "trim ok in {:.2} s: {} pieces, {} seams",
                t.elapsed().as_secs_f64(),
                tr.pieces.len(),
                tr.ledger.seams.len()
            );
            for p in &tr.report.pieces {
                println!(
                    "  {} faces {} disk {} kept {}",
                    p.name, p.faces, p.disk, p.kept
                );
            }
        }
        Err(e) => {
            println!("trim error: {e}");
            let at = match &e {
                flatcut_trim::TrimError::OverlappingLines { point_mm, .. }
                | flatcut_trim::TrimError::SelfCrossing { point_mm, .. } => *point_mm,
                _ => return Ok(()),
            };
            let lines = flatcut_trim::cut_lines(&mesh, &cuts)?;
            for l in &lines {
                for (i, p) in l.points.iter().enumerate() {
                    let x = p.position(&mesh);
                    let d = flatcut_mesh::vec3::dist(x, at);
                    if d < 25.0 {
                        println!(
                            "  {} #{i}/{} {:?} at {:.3?} d {:.2}",
                            l.name,
                            l.points.len(),
                            p.location(&mesh),
                            x,
                            d
                        );
                    }
                }
            }
        }
    }
    Ok(())
}
