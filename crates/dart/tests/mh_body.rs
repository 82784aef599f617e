//! A dart at the back of the shoulder (the paper's wetsuit, §5.2, Fig. 9e–f) on the
//! back-right-upper piece of the wetsuit cut of $FLATCUT_DATA/mh_body.obj
//! (fixtures/cuts/mh_body_wetsuit.toml). Skipped (passes) only when FLATCUT_DATA is unset.

#![allow(clippy::unwrap_used)]

use flatcut_dart::{SuggestOptions, append_dart_seams, dart, suggest};
use flatcut_flattenable::{ProcessOptions, process};
use flatcut_lscm::{FlattenOptions, flatten};
use flatcut_mesh::{SeamKind, Topology, VertexId, vec3};

#[test]
fn mh_body_back_shoulder_dart_lowers_displacement() {
    let Some(dir) = std::env::var_os("FLATCUT_DATA") else {
        eprintln!("FLATCUT_DATA unset: skipping mh_body");
        return;
    };
    let path = std::path::PathBuf::from(dir).join("mh_body.obj");
    assert!(
        path.exists(),
        "FLATCUT_DATA is set but {} is missing",
        path.display()
    );
    let mesh = flatcut_io::read_mesh(&path, flatcut_io::Units::Dm)
        .unwrap()
        .mesh;
    let fixture = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/cuts/mh_body_wetsuit.toml"
    );
    let mut cuts: flatcut_trim::Cuts =
        toml::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
    cuts.scale(100.0);
    let t = flatcut_trim::trim(&mesh, &cuts).unwrap();
    let name = "back-right-upper";
    let piece = &t.pieces.iter().find(|p| p.name == name).unwrap().mesh;

    // The first suggestion: tip on the shoulder blade (below the neck line at y = 600 mm,
    // right of the centre back, on the back), start on the centre back seam.
    let s = suggest(piece, 1, &SuggestOptions::default()).unwrap();
    let tip = s[0].spec.tip.unwrap();
    println!("suggested tip {tip:?} from {:?}", s[0].spec.from);
    assert!(
        tip[0] < -30.0 && tip[1] > 400.0 && tip[1] < 600.0 && tip[2] < 0.0,
        "{tip:?}"
    );
    let d = dart(piece, &[s[0].spec.clone()], &Default::default()).unwrap();
    let legs = &d.darts[0];
    assert_eq!(legs.leg_a[0], legs.tip);
    assert_eq!(
        d.split_from.iter().filter(|&&v| v == legs.tip).count(),
        1,
        "tip copied"
    );
    let topo = Topology::build(&d.mesh).unwrap();
    assert_eq!(topo.boundary_loops().len(), 1);

    // Processing needs less displacement with the dart (measured 5.750 → 4.943 mm RMS over
    // the piece's interior vertices, docs/algorithms/darts.md).
    let opts = ProcessOptions::default();
    let p0 = process(piece, &opts).unwrap();
    let p1 = process(&d.mesh, &opts).unwrap();
    let src_topo = Topology::build(piece).unwrap();
    let rms = |out: &flatcut_mesh::TriMesh| {
        let (mut s, mut n) = (0.0, 0);
        for v in 0..piece.positions.len() {
            if src_topo.is_interior_vertex(VertexId(v as u32)) {
                s += vec3::norm2(vec3::sub(out.positions[v], piece.positions[v]));
                n += 1;
            }
        }
        (s / n as f64).sqrt()
    };
    let (r0, r1) = (rms(&p0.mesh), rms(&p1.mesh));
    println!("{name}: RMS displacement {r0:.4} → {r1:.4} mm");
    assert!(r1 < 0.95 * r0, "{r1} vs {r0}");

    // Flattened, the legs have equal 2D length.
    let flat = flatten(&p1.mesh, &FlattenOptions::default()).unwrap();
    let uv = &flat.flattening.uv;
    let len = |leg: &[u32]| -> f64 {
        leg.windows(2)
            .map(|w| {
                let (a, b) = (uv[w[0] as usize], uv[w[1] as usize]);
                (a[0] - b[0]).hypot(a[1] - b[1])
            })
            .sum()
    };
    let (la, lb) = (len(&legs.leg_a), len(&legs.leg_b));
    assert!((la - lb).abs() <= 1e-6 * la, "{la} vs {lb}");

    // The dart joins trim's ledger; the centre-back seam through its start is split there.
    let mut ledger = t.ledger.clone();
    let before = ledger.seams.len();
    append_dart_seams(&mut ledger, name, &d).unwrap();
    ledger.check().unwrap();
    assert!(ledger.seams.len() > before);
    assert_eq!(
        ledger
            .seams
            .iter()
            .filter(|s| s.kind == SeamKind::Dart)
            .count(),
        1
    );
    let bset: std::collections::HashSet<(u32, u32)> = (0..3 * d.mesh.faces.len() as u32)
        .filter(|&h| topo.twin(h).is_none())
        .map(|h| {
            let (a, b) = (topo.from_vertex(h).0, topo.to_vertex(h).0);
            (a.min(b), a.max(b))
        })
        .collect();
    for seam in &ledger.seams {
        for side in [&seam.a, &seam.b] {
            if side.piece == name {
                for w in side.vertices.windows(2) {
                    assert!(
                        bset.contains(&(w[0].min(w[1]), w[0].max(w[1]))),
                        "{}",
                        seam.id
                    );
                }
            }
        }
    }
}
