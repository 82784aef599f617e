//! Pattern pieces from hand-made flattened pieces and ledgers: matching notches on mates,
//! darts, grain, shrink, layout without overlap, and the refusals.

#![allow(clippy::unwrap_used)]

mod common;

use common::{flat_piece, grid, polyline_arc_of};
use flatcut_mesh::{Seam, SeamKind, SeamLedger, SeamSide, TriMesh};
use flatcut_pattern::geom::{point_in_polygon, segment_intersection, signed_area};
use flatcut_pattern::{
    LayoutOptions, PatternError, PatternOptions, PieceInput, PieceMeta, build_pieces, layout,
};

fn seam(id: &str, kind: SeamKind, a: (&str, Vec<u32>), b: (&str, Vec<u32>)) -> Seam {
    Seam {
        id: id.into(),
        line: id.split('/').next().unwrap_or(id).into(),
        kind,
        a: SeamSide {
            piece: a.0.into(),
            vertices: a.1,
        },
        b: SeamSide {
            piece: b.0.into(),
            vertices: b.1,
        },
        length_3d_mm: 0.0,
        start_mm: [0.0; 3],
        end_mm: [0.0; 3],
    }
}

/// Two halves of a cylinder (radius 80 mm, height 300 mm), each unrolled exactly
/// (u = R·θ, v = z); the back half is stretched 1 % along the seams so the mates differ.
fn cylinder_halves() -> (Vec<PieceInput>, SeamLedger) {
    let (r, h, nu, nz) = (80.0, 300.0, 13usize, 21usize);
    let half = |name: &str, theta0: f64, stretch: f64| {
        let mut positions = Vec::new();
        let mut uv = Vec::new();
        for j in 0..nz {
            // Uneven rows, so arc length and vertex count disagree.
            let t = j as f64 / (nz - 1) as f64;
            let z = h * (t + 0.08 * (std::f64::consts::PI * t).sin() * t);
            for i in 0..nu {
                let th = theta0 + std::f64::consts::PI * i as f64 / (nu - 1) as f64;
                positions.push([r * th.cos(), r * th.sin(), z]);
                uv.push([r * (th - theta0), z * stretch]);
            }
        }
        let mesh = grid(0.0, 1.0, 1.0, nu, nz);
        let mesh = TriMesh { positions, ..mesh };
        PieceInput {
            uv,
            ..flat_piece(name, mesh)
        }
    };
    let front = half("front", 0.0, 1.0);
    let back = half("back", std::f64::consts::PI, 1.01);
    // Seam at θ = π: front column nu−1, back column 0; at θ = 0 (= 2π): front column 0, back nu−1.
    let col = |c: usize| (0..nz).map(|j| (j * nu + c) as u32).collect::<Vec<_>>();
    let mut ledger = SeamLedger::new(vec!["front".into(), "back".into()]);
    ledger.seams.push(seam(
        "side-left/0",
        SeamKind::Seam,
        ("front", col(nu - 1)),
        ("back", col(0)),
    ));
    ledger.seams.push(seam(
        "side-right/0",
        SeamKind::Seam,
        ("front", col(0)),
        ("back", col(nu - 1)),
    ));
    (vec![front, back], ledger)
}

#[test]
fn mates_carry_the_same_notches() {
    let (pieces, ledger) = cylinder_halves();
    let opts = PatternOptions {
        notch_spacing_mm: 60.0,
        ..Default::default()
    };
    let out = build_pieces(&pieces, Some(&ledger), &opts).unwrap();
    for s in &ledger.seams {
        // Arc positions measured independently: each notch's sew point projected onto its
        // piece's own chain.
        let arcs = |piece: &str, chain: &[u32]| {
            let p = out.iter().find(|p| p.name == piece).unwrap();
            let pts: Vec<[f64; 2]> = chain.iter().map(|&v| p.uv[v as usize]).collect();
            let mut a: Vec<f64> = p
                .notches
                .iter()
                .filter(|n| n.seam == s.id)
                .map(|n| {
                    let (d, arc) = polyline_arc_of(n.at, &pts);
                    assert!(d < 1e-9, "notch on its seam");
                    // The notch runs from the cut line inward along the outward normal.
                    assert!(point_in_polygon(n.inner, &p.cut_line));
                    assert!(!point_in_polygon(n.inner, &p.sew_line));
                    arc
                })
                .collect();
            a.sort_by(f64::total_cmp);
            (a, flatcut_pattern::geom::polyline_length(&pts))
        };
        let (a, la) = arcs("front", &s.a.vertices);
        let (b, lb) = arcs("back", &s.b.vertices);
        assert!(
            (lb / la - 1.01).abs() < 1e-9,
            "the back is 1 % longer: {la} {lb}"
        );
        // 300 mm at ≤ 60 mm spacing: start, 4 intermediate, end.
        assert_eq!(a.len(), b.len());
        assert_eq!(a.len(), 6, "{a:?}");
        for k in 0..a.len() - 1 {
            assert!(
                (a[k] - b[k]).abs() <= 0.1,
                "notch {k}: {} vs {}",
                a[k],
                b[k]
            );
        }
        assert!((a[a.len() - 1] - la).abs() < 1e-9 && (b[b.len() - 1] - lb).abs() < 1e-9);
        let sp = out[0].seams.iter().find(|x| x.id == s.id).unwrap();
        assert!((sp.mate_length_2d_mm - lb).abs() < 1e-9);
    }
}

#[test]
fn rectangle_cut_in_two_with_a_dart_and_an_override() {
    // Left [0,100]×[0,60], right [100,200]×[0,60] (6 × 4 vertices each).
    let left = flat_piece("left", grid(0.0, 100.0, 60.0, 6, 4));
    let right = flat_piece("right", grid(100.0, 100.0, 60.0, 6, 4));
    let mut ledger = SeamLedger::new(vec!["left".into(), "right".into()]);
    ledger.seams.push(seam(
        "centre/0",
        SeamKind::Seam,
        ("left", vec![5, 11, 17, 23]),
        ("right", vec![0, 6, 12, 18]),
    ));
    let mut opts = PatternOptions::default();
    opts.seam_overrides.insert("centre/0".into(), 15.0);
    let out = build_pieces(&[left, right], Some(&ledger), &opts).unwrap();
    let l = &out[0];
    let b = flatcut_pattern::geom::bbox(&l.cut_line);
    assert!(
        (b[1][0] - 115.0).abs() < 1e-5 && (b[0][0] + 10.0).abs() < 1e-5,
        "{b:?}"
    );
    assert_eq!(l.notches.len(), 2, "60 mm seam: end notches only");
    assert!(l.notches.iter().all(|n| (n.cut[0] - 115.0).abs() < 1e-5));
    assert!(
        l.notches.iter().all(|n| (n.inner[0] - 109.0).abs() < 1e-5),
        "6 mm deep"
    );
    assert_eq!(l.label.lines, vec!["left".to_string(), "cut 1".to_string()]);
    assert!(point_in_polygon(l.grain_line[0], &l.sew_line));
    assert!(l.grain_line[1][1] > l.grain_line[0][1]);

    // A dart: a V cut into the top of a piece, legs from the tip (50, 30).
    let mesh = TriMesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [100.0, 0.0, 0.0],
            [100.0, 60.0, 0.0],
            [55.0, 60.0, 0.0],
            [50.0, 30.0, 0.0],
            [45.0, 60.0, 0.0],
            [0.0, 60.0, 0.0],
        ],
        faces: vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [0, 4, 6], [4, 5, 6]],
        ..Default::default()
    };
    let p = flat_piece("bodice", mesh);
    let mut ledger = SeamLedger::new(vec!["bodice".into()]);
    ledger.seams.push(seam(
        "dart/0",
        SeamKind::Dart,
        ("bodice", vec![4, 3]),
        ("bodice", vec![4, 5]),
    ));
    let out = build_pieces(&[p], Some(&ledger), &PatternOptions::default()).unwrap();
    let d = &out[0].darts[0];
    assert_eq!(d.tip, [50.0, 30.0]);
    assert_eq!(d.legs[0].last(), Some(&[55.0, 60.0]));
    assert_eq!(d.legs[1].last(), Some(&[45.0, 60.0]));
    assert_eq!(out[0].notches.len(), 2, "a notch at each leg's mouth");
    assert!(signed_area(&out[0].cut_line) > 100.0 * 60.0);
}

#[test]
fn hems_take_their_own_width_and_mirrored_corners() {
    // A skirt panel, wider at the hem: side seams slant outward to the hem at y = 0.
    let mesh = TriMesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [200.0, 0.0, 0.0],
            [170.0, 150.0, 0.0],
            [30.0, 150.0, 0.0],
        ],
        faces: vec![[0, 1, 2], [0, 2, 3]],
        ..Default::default()
    };
    let p = flat_piece("skirt", mesh.clone());
    let mut ledger = SeamLedger::new(vec!["skirt".into(), "other".into()]);
    let other = flat_piece("other", grid(300.0, 100.0, 150.0, 2, 2));
    ledger.seams.push(seam(
        "side/0",
        SeamKind::Seam,
        ("skirt", vec![1, 2]),
        ("other", vec![0, 2]),
    ));
    let opts = PatternOptions {
        free_edge_allowance_mm: Some(30.0),
        hem_corner: Some(flatcut_pattern::CornerRule::Mirrored),
        ..Default::default()
    };
    let out = build_pieces(&[p, other], Some(&ledger), &opts).unwrap();
    let cut = &out[0].cut_line;
    // The hem (free) gets 30 mm: the cut line reaches y = −30.
    let lo = cut.iter().map(|q| q[1]).fold(f64::MAX, f64::min);
    assert!((lo + 30.0).abs() < 1e-5, "{lo}");
    // At (200, 0) the side seam (10 mm) meets the hem: the hem allowance's right end is the
    // mirror about y = 0 of the side seam's cut line, so it lies on that mirrored line.
    let d = flatcut_pattern::geom::unit([170.0 - 200.0, 150.0]);
    let n = [d[1], -d[0]];
    let on_mirror = |q: [f64; 2]| {
        let r = [q[0] - 200.0, -q[1]];
        (r[0] * n[0] + r[1] * n[1] - 10.0).abs() < 1e-5
    };
    assert!(
        cut.iter()
            .any(|q| q[1] < -1.0 && q[0] > 200.0 && on_mirror(*q)),
        "{cut:?}"
    );
}

#[test]
fn grain_and_shrink() {
    // A flat piece whose 3D grain runs along x: the pattern turns it to +y.
    let mut p = flat_piece("panel", grid(0.0, 200.0, 50.0, 5, 3));
    p.meta = PieceMeta {
        grain_3d: Some([1.0, 0.0, 0.0]),
        shrink_along_grain: 0.0,
        shrink_across_grain: -0.05,
        ..Default::default()
    };
    let out = build_pieces(&[p], None, &PatternOptions::default()).unwrap();
    let b = flatcut_pattern::geom::bbox(&out[0].sew_line);
    assert!(
        (b[1][1] - b[0][1] - 200.0).abs() < 1e-9,
        "200 mm now along y: {b:?}"
    );
    assert!(
        (b[1][0] - b[0][0] - 50.0 * 0.95).abs() < 1e-9,
        "−5 % across: {b:?}"
    );
    let s = out[0].shrink;
    assert!((s.area_before_mm2 - 10_000.0).abs() < 1e-6);
    assert!((s.area_after_mm2 - 9_500.0).abs() < 1e-6);
}

#[test]
fn layout_places_every_copy_without_overlap() {
    let mut pieces = Vec::new();
    for (k, (w, h)) in [(300.0, 200.0), (150.0, 400.0), (500.0, 120.0), (80.0, 80.0)]
        .into_iter()
        .enumerate()
    {
        let mut p = flat_piece(&format!("p{k}"), grid(0.0, w, h, 3, 3));
        p.meta.quantity = 2;
        p.meta.mirror = k % 2 == 0;
        pieces.push(p);
    }
    let out = build_pieces(&pieces, None, &PatternOptions::default()).unwrap();
    let opts = LayoutOptions {
        sheet_width_mm: 900.0,
        ..Default::default()
    };
    let lay = layout(&out, &opts).unwrap();
    assert_eq!(lay.placements.len(), 8);
    assert_eq!(lay.placements.iter().filter(|p| p.mirrored).count(), 2);
    let polys: Vec<Vec<[f64; 2]>> = lay
        .placements
        .iter()
        .map(|pl| out[pl.piece].cut_line.iter().map(|p| pl.map(*p)).collect())
        .collect();
    let ts = lay.test_square;
    for (i, a) in polys.iter().enumerate() {
        for p in a {
            assert!(p[0] >= -1e-9 && p[0] <= 900.0 + 1e-9 && p[1] >= 0.0 && p[1] <= lay.height_mm);
            assert!(!(p[0] > ts[0] && p[0] < ts[0] + 50.0 && p[1] > ts[1] && p[1] < ts[1] + 50.0));
        }
        for b in &polys[i + 1..] {
            assert!(!point_in_polygon(a[0], b) && !point_in_polygon(b[0], a));
            for s in 0..a.len() {
                for t in 0..b.len() {
                    let hit = segment_intersection(
                        a[s],
                        a[(s + 1) % a.len()],
                        b[t],
                        b[(t + 1) % b.len()],
                    );
                    assert!(hit.is_none(), "placements {i} overlap");
                }
            }
        }
    }
    // A mirrored copy is the piece reflected left–right.
    let m = lay.placements.iter().find(|p| p.mirrored).unwrap();
    let q = m.map([10.0, 20.0]);
    assert!(
        (q[0] - (m.offset[0] - 10.0)).abs() < 1e-12 && (q[1] - (m.offset[1] + 20.0)).abs() < 1e-12
    );
}

#[test]
fn refusals_name_the_problem() {
    // A folded outline: the top right corner pulled across the left edge.
    let mut p = flat_piece("folded", grid(0.0, 100.0, 60.0, 3, 3));
    p.uv[8] = [-30.0, 30.0];
    let e = build_pieces(&[p], None, &PatternOptions::default()).unwrap_err();
    assert!(matches!(e, PatternError::SelfIntersecting { .. }), "{e}");
    assert!(e.to_string().contains("crosses itself near"), "{e}");

    let p = flat_piece("small", grid(0.0, 30.0, 60.0, 3, 3));
    let opts = PatternOptions {
        seam_allowance_mm: 16.0,
        ..Default::default()
    };
    let e = build_pieces(std::slice::from_ref(&p), None, &opts).unwrap_err();
    assert!(
        matches!(e, PatternError::AllowanceTooLarge { half_mm, .. } if (half_mm - 15.0).abs() < 1e-9),
        "{e}"
    );

    let mut opts = PatternOptions::default();
    opts.seam_overrides.insert("x/0".into(), -1.0);
    let e = build_pieces(std::slice::from_ref(&p), None, &opts).unwrap_err();
    assert!(
        e.to_string().contains("seam_overrides[\"x/0\"] = -1"),
        "{e}"
    );

    let mut q = p.clone();
    q.meta.quantity = 3;
    q.meta.mirror = true;
    let e = build_pieces(&[q], None, &PatternOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("even number for mirrored pairs"),
        "{e}"
    );

    let mut q = p.clone();
    q.meta.shrink_across_grain = -5.0;
    assert!(matches!(
        build_pieces(&[q], None, &PatternOptions::default()),
        Err(PatternError::BadOption { .. })
    ));

    // Two parts in one piece would lose one of them: refused.
    let mut two = grid(0.0, 30.0, 60.0, 3, 3);
    let other = grid(100.0, 30.0, 60.0, 3, 3);
    let off = two.positions.len() as u32;
    two.positions.extend(other.positions);
    two.faces
        .extend(other.faces.iter().map(|f| f.map(|v| v + off)));
    let e = build_pieces(&[flat_piece("two", two)], None, &PatternOptions::default()).unwrap_err();
    assert!(e.to_string().contains("2 separate parts"), "{e}");

    let mut ledger = SeamLedger::new(vec!["small".into(), "ghost".into()]);
    ledger.seams.push(seam(
        "s/0",
        SeamKind::Seam,
        ("small", vec![0, 1]),
        ("ghost", vec![0, 1]),
    ));
    let e = build_pieces(
        std::slice::from_ref(&p),
        Some(&ledger),
        &PatternOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e, PatternError::MissingPiece { .. }), "{e}");

    let mut ledger = SeamLedger::new(vec!["small".into()]);
    ledger.seams.push(seam(
        "s/0",
        SeamKind::Seam,
        ("small", vec![0, 4]),
        ("small", vec![2, 5]),
    ));
    let e = build_pieces(&[p], Some(&ledger), &PatternOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .contains("vertex 4 is not on the piece's outer boundary"),
        "{e}"
    );
}

#[test]
fn grain_from_3d_on_a_curved_piece() {
    // The front cylinder half unrolled, then turned by 30° in the plane: with the grain along
    // the cylinder's axis (z), the pattern turns it back so the seams (3D lines along z) are
    // vertical again.
    let (mut pieces, _) = cylinder_halves();
    let mut front = pieces.remove(0);
    let (s, c) = 30f64.to_radians().sin_cos();
    for q in &mut front.uv {
        *q = [c * q[0] - s * q[1], s * q[0] + c * q[1]];
    }
    front.meta.grain_3d = Some([0.0, 0.0, 1.0]);
    let out = build_pieces(&[front], None, &PatternOptions::default()).unwrap();
    let p = &out[0];
    assert!(
        (p.rotation_rad + 30f64.to_radians()).abs() < 1e-9,
        "{}",
        p.rotation_rad
    );
    let (nu, nz) = (13usize, 21usize);
    for col in [0, nu - 1] {
        let a = p.uv[col];
        let b = p.uv[(nz - 1) * nu + col];
        assert!(
            (a[0] - b[0]).abs() < 1e-9 && b[1] - a[1] > 299.0,
            "{a:?} {b:?}"
        );
    }
    // A grain normal to the whole piece has no direction in the pattern.
    let flat = flat_piece("flat", grid(0.0, 10.0, 10.0, 2, 2));
    let mut f = flat.clone();
    f.meta.grain_3d = Some([0.0, 0.0, 1.0]);
    assert!(matches!(
        build_pieces(&[f], None, &PatternOptions::default()),
        Err(PatternError::GrainNormalToPiece { .. })
    ));
}
