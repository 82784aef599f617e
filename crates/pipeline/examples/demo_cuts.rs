//! Prints the `[[cut]]` and `[[piece]]` tables of pipelines/wetsuit-demo.toml: trim's
//! wetsuit cut of the demo's dress form (`flatcut_trim::dress_form_wetsuit`), points rounded
//! to 0.0001 mm (well inside the 5 mm landmark tolerance).
//!
//! `cargo run -p flatcut_pipeline --example demo_cuts`

use flatcut_mesh::shapes::{BodyMeasurements, dress_form};

fn main() {
    let m = BodyMeasurements {
        bust_mm: 920.0,
        waist_mm: 760.0,
        hip_mm: 980.0,
        height_mm: 1700.0,
        resolution: 48,
        ..Default::default()
    };
    let form = dress_form(&m);
    let cuts = match flatcut_trim::dress_form_wetsuit(&form, &m) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("demo_cuts: {e}");
            std::process::exit(1);
        }
    };
    let pt = |p: [f64; 3]| format!("[{:.4}, {:.4}, {:.4}]", p[0], p[1], p[2]);
    for c in &cuts.cuts {
        println!("[[cut]]\nname = {:?}", c.name);
        println!("points = [");
        for p in &c.points {
            println!("    {},", pt(*p));
        }
        println!("]\nclosed = {}\n", c.closed);
    }
    for p in &cuts.pieces {
        println!("[[piece]]\nname = {:?}\nseed = {}\n", p.name, pt(p.seed));
    }
}
