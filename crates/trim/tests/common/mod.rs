//! Checks shared by the cutting tests.

#![allow(clippy::unwrap_used, dead_code)]

use flatcut_mesh::{TriMesh, geometry, vec3};
use flatcut_trim::Trimmed;

/// The acceptance checks every cut must pass.
pub fn check_conservation(mesh: &TriMesh, t: &Trimmed) {
    let diag = mesh.diagonal();
    // Area: the pieces (kept and dropped) sum to the source, face by face.
    let src_area = geometry::face_areas(&mesh.positions, &mesh.faces);
    let emb_area = geometry::face_areas(&t.embedded.mesh.positions, &t.embedded.mesh.faces);
    let mut per_face = vec![0.0; mesh.faces.len()];
    for (f, &s) in t.embedded.face_source.iter().enumerate() {
        per_face[s as usize] += emb_area[f];
    }
    for (f, (&a, &b)) in src_area.iter().zip(&per_face).enumerate() {
        assert!(
            (a - b).abs() <= 1e-9 * a.max(1e-300),
            "face {f}: {a} vs {b}"
        );
    }
    let total: f64 = src_area.iter().sum();
    let pieces: f64 = t.report.pieces.iter().map(|p| p.area_mm2).sum();
    assert!(
        (total - pieces).abs() <= 1e-9 * total,
        "{total} vs {pieces}"
    );
    // Every source face has a fate.
    assert!(t.report.face_fates.iter().all(|f| !f.is_empty()));
    // Each embedded line lies on its polyline.
    for (l, chain) in t.lines.iter().zip(&t.embedded.line_vertices) {
        let segs: Vec<([f64; 3], [f64; 3])> = l
            .points
            .windows(2)
            .map(|w| (w[0].position(mesh), w[1].position(mesh)))
            .collect();
        for &v in chain {
            let x = t.embedded.mesh.positions[v as usize];
            let d = segs
                .iter()
                .map(|&(a, b)| {
                    let e = vec3::sub(b, a);
                    let s = if vec3::norm2(e) > 0.0 {
                        (vec3::dot(vec3::sub(x, a), e) / vec3::norm2(e)).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    vec3::dist(x, vec3::add(a, vec3::scale(e, s)))
                })
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 1e-9 * diag, "line {} vertex {v} is {d} off", l.name);
        }
        // The embedded chain is exactly as long as the polyline.
        let len: f64 = chain
            .windows(2)
            .map(|w| {
                vec3::dist(
                    t.embedded.mesh.positions[w[0] as usize],
                    t.embedded.mesh.positions[w[1] as usize],
                )
            })
            .sum();
        assert!(
            (len - l.length).abs() <= 1e-9 * l.length,
            "{} {len} {}",
            l.name,
            l.length
        );
    }
    // Provenance: every piece vertex is where its source point is.
    for p in &t.pieces {
        for (v, sp) in p.vertex_source.iter().enumerate() {
            assert!(vec3::dist(p.mesh.positions[v], sp.position(mesh)) <= 1e-9 * diag);
        }
        assert_eq!(p.face_source.len(), p.mesh.faces.len());
    }
    // The ledger: valid, chains on piece boundaries, mates equal in 3D length.
    t.ledger.check().unwrap();
    for s in &t.ledger.seams {
        let piece = |n: &str| t.pieces.iter().find(|p| p.name == n).unwrap();
        let len = |side: &flatcut_mesh::SeamSide| -> f64 {
            let p = piece(&side.piece);
            side.vertices
                .windows(2)
                .map(|w| {
                    vec3::dist(
                        p.mesh.positions[w[0] as usize],
                        p.mesh.positions[w[1] as usize],
                    )
                })
                .sum()
        };
        let (la, lb) = (len(&s.a), len(&s.b));
        assert!((la - lb).abs() <= 1e-9 * la, "seam {}: {la} vs {lb}", s.id);
        assert!((la - s.length_3d_mm).abs() <= 1e-9 * la);
        // Same source points, k by k.
        let (pa, pb) = (piece(&s.a.piece), piece(&s.b.piece));
        for (&va, &vb) in s.a.vertices.iter().zip(&s.b.vertices) {
            assert_eq!(
                pa.mesh.positions[va as usize],
                pb.mesh.positions[vb as usize]
            );
        }
        // Consecutive chain vertices are joined by a boundary edge of the piece.
        for side in [&s.a, &s.b] {
            let p = piece(&side.piece);
            let topo = flatcut_mesh::Topology::build(&p.mesh).unwrap();
            for w in side.vertices.windows(2) {
                let e = (w[0].min(w[1]), w[0].max(w[1]));
                let k = topo
                    .edges()
                    .iter()
                    .position(|x| (x[0], x[1]) == e)
                    .expect("edge");
                assert_eq!(
                    topo.edge_face_counts()[k],
                    1,
                    "seam {} edge {e:?} not on boundary",
                    s.id
                );
            }
        }
    }
}
