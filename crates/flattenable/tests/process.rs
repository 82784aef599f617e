//! [`process`]: several pieces, holes, trivial pieces, bad input and determinism.

#![allow(clippy::unwrap_used)]

mod common;

use flatcut_flattenable::{
    CREASE_DEFECT_NEUTRAL_RAD, CreaseKind, FlattenableError, Mode, ProcessOptions, Update, process,
};
use flatcut_mesh::TriMesh;

/// Concatenates meshes, shifting each by `dx · k` along x.
fn concat(parts: &[TriMesh], dx: f64) -> TriMesh {
    let mut out = TriMesh::default();
    for (k, m) in parts.iter().enumerate() {
        let base = out.positions.len() as u32;
        out.positions.extend(
            m.positions
                .iter()
                .map(|p| [p[0] + dx * k as f64, p[1], p[2]]),
        );
        out.faces.extend(
            m.faces
                .iter()
                .map(|f| [f[0] + base, f[1] + base, f[2] + base]),
        );
    }
    out
}

#[test]
fn pieces_are_processed_independently_and_deterministically() {
    let cap = common::sphere_cap(10);
    let saddle = common::saddle(9);
    let strip = common::grid(2, 0.3, |x, _| x * x); // no interior vertex
    let mesh = concat(&[cap.clone(), strip.clone(), saddle.clone()], 3.0);
    let opts = ProcessOptions::default();
    let all = process(&mesh, &opts).unwrap();
    assert_eq!(all.report.pieces.len(), 3);
    assert!(all.report.converged);
    // Each piece equals the piece processed alone, bit for bit.
    let alone_cap = process(&cap, &opts).unwrap();
    // (Shifted as in the mesh: the saddle's solution is sensitive to round-off, so the
    // comparison is made on the same coordinates.)
    let mut shifted = saddle.clone();
    for p in &mut shifted.positions {
        p[0] += 6.0;
    }
    let alone_saddle = process(&shifted, &opts).unwrap();
    let n0 = cap.vertex_count();
    let n1 = strip.vertex_count();
    for (v, p) in alone_cap.mesh.positions.iter().enumerate() {
        assert_eq!(all.mesh.positions[v], *p);
    }
    for (v, p) in alone_saddle.mesh.positions.iter().enumerate() {
        assert_eq!(all.mesh.positions[n0 + n1 + v], *p);
    }
    // The strip has no interior vertex: unchanged, and said so.
    let strip_rep = &all.report.pieces[1];
    assert_eq!(strip_rep.interior_vertices, 0);
    assert!(
        strip_rep
            .messages
            .iter()
            .any(|m| m.contains("no interior vertex"))
    );
    assert_eq!(
        &all.mesh.positions[n0..n0 + n1],
        &mesh.positions[n0..n0 + n1]
    );
    // Report aggregation.
    assert_eq!(
        all.report.iterations,
        all.report
            .pieces
            .iter()
            .map(|p| p.iterations)
            .max()
            .unwrap()
    );
    assert_eq!(all.report.theta_err.len(), all.report.iterations + 1);
    // Same result on 1 and 2 threads.
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let r = pool.install(|| process(&mesh, &opts).unwrap());
        assert_eq!(r.mesh.positions, all.mesh.positions);
    }
}

#[test]
fn piece_with_holes_keeps_every_loop_fixed() {
    let mut mesh = flatcut_mesh::shapes::patch_with_holes(2.0, 13);
    for p in &mut mesh.positions {
        p[2] = (4.0 - p[0] * p[0] - p[1] * p[1]).sqrt();
    }
    let r = process(&mesh, &ProcessOptions::default()).unwrap();
    assert_eq!(r.report.pieces[0].boundary_loops, 3);
    assert!(r.report.converged && r.report.final_theta_err <= 1e-9);
    assert_eq!(r.report.folded_faces, 0);
    assert_eq!(common::boundary_changed(&mesh, &r.mesh), 0);
    assert!(r.report.max_displacement_mm > 0.0);
}

#[test]
fn bad_input_gives_named_errors() {
    let opts = ProcessOptions::default();
    // Closed.
    let sphere = flatcut_mesh::shapes::icosphere(1.0, 1);
    assert!(matches!(
        process(&sphere, &opts),
        Err(FlattenableError::ClosedPiece { piece: 0 })
    ));
    // Non-manifold edge and vertex.
    let fin = flatcut_mesh::shapes::non_manifold_fin();
    assert!(matches!(
        process(&fin, &opts),
        Err(FlattenableError::NonManifoldEdge { .. })
    ));
    let bowtie = flatcut_mesh::shapes::non_manifold_bowtie();
    let e = process(&bowtie, &opts).unwrap_err();
    assert!(
        matches!(e, FlattenableError::NonManifoldVertex { .. }),
        "{e}"
    );
    // Degenerate face: collapse one interior face of a grid onto a point.
    let mut degenerate = common::sphere_cap(6);
    let [a, b, c] = degenerate.faces[12];
    degenerate.positions[b as usize] = degenerate.positions[a as usize];
    degenerate.positions[c as usize] = degenerate.positions[a as usize];
    let e = process(&degenerate, &opts).unwrap_err();
    assert!(matches!(e, FlattenableError::DegenerateFace { .. }), "{e}");
    assert!(e.to_string().contains("face"));
    // NaN.
    let mut nan = common::sphere_cap(6);
    nan.positions[7][1] = f64::NAN;
    let e = process(&nan, &opts).unwrap_err();
    assert!(matches!(e, FlattenableError::Mesh(_)));
    assert!(e.to_string().contains("vertex 7"), "{e}");
    // Inconsistent orientation.
    let mut flipped = common::sphere_cap(6);
    flipped.faces[10].swap(1, 2);
    let e = process(&flipped, &opts).unwrap_err();
    assert!(
        matches!(e, FlattenableError::InconsistentOrientation { .. }),
        "{e}"
    );
    // Options.
    let cap = common::sphere_cap(6);
    let bad = ProcessOptions {
        weights: Some(vec![1.0; 3]),
        ..Default::default()
    };
    assert!(matches!(
        process(&cap, &bad),
        Err(FlattenableError::InvalidOption { .. })
    ));
    let bad = ProcessOptions {
        tolerance_rad: f64::NAN,
        ..Default::default()
    };
    assert!(matches!(
        process(&cap, &bad),
        Err(FlattenableError::InvalidOption { .. })
    ));
    // Empty mesh: nothing to do.
    let r = process(&TriMesh::default(), &opts).unwrap();
    assert!(r.report.pieces.is_empty());
}

/// Within the extents the solver works in (1e-50 to 1e50) a piece scaled by a power of two
/// comes back scaled, bit for bit, up to the ends of the range; beyond them it is refused by
/// name with its extent, where before a 2^300-wide cap ran on overflowed angles (θ_err π,
/// "did not converge") and a 1e300-wide one read as already flattenable (NaN angles).
#[test]
fn pieces_beyond_the_solvers_range_are_refused_and_those_within_scale_bit_for_bit() {
    let opts = ProcessOptions::default();
    let cap = common::sphere_cap(8);
    let base = process(&cap, &opts).unwrap().mesh;
    let scaled = |mesh: &TriMesh, s: f64| {
        let mut m = mesh.clone();
        for p in &mut m.positions {
            *p = p.map(|x| x * s);
        }
        m
    };
    // The cap's diagonal is 1.44: 2^±160 puts it at 2.1e48 and 9.9e-49.
    for k in [-160, 160] {
        let s = 2f64.powi(k);
        let out = process(&scaled(&cap, s), &opts).unwrap().mesh;
        assert_eq!(out.positions, scaled(&base, s).positions, "2^{k}");
    }
    for (k, shown) in [
        (-200, "spans 8.981"),
        (200, "spans 2.319"),
        (1000, "spans 1.54"),
    ] {
        let e = process(&scaled(&cap, 2f64.powi(k)), &opts).unwrap_err();
        assert!(
            matches!(e, FlattenableError::ExtentOutOfRange { piece: 0, .. }),
            "2^{k}: {e}"
        );
        assert!(e.to_string().contains(shown), "2^{k}: {e}");
    }
    // Coordinates of 1e300 (a square's diagonal beyond f64 when squared).
    let e = process(&scaled(&cap, 1e300), &opts).unwrap_err();
    assert!(e.to_string().contains("spans 1.44"), "{e}");
}

#[test]
fn options_read_from_toml_like_json_with_documented_defaults() {
    let o: ProcessOptions =
        serde_json::from_str(r#"{"mode":"paper","update":"least-square"}"#).unwrap();
    assert_eq!(o.mode, Mode::Paper);
    assert_eq!(o.update, Update::LeastSquare);
    assert_eq!(o.tolerance_rad, 1e-9);
    assert!(serde_json::from_str::<ProcessOptions>(r#"{"bogus":1}"#).is_err());
}

/// A piece that stops unconverged names its cause by its input: a rough one (median
/// |2π − θ| above 0.1 rad: scan noise) is told to smooth the scan, and the Gauss–Bonnet
/// reading of its total defect is left out; a smooth one keeps that reading, and so does a
/// coarse cup of nine interior vertices, whose large defects are its curvature over few
/// vertices, not noise. All are cut off by the iteration limit so that they stop.
#[test]
fn an_unconverged_rough_piece_is_called_rough_and_a_smooth_one_is_not() {
    use flatcut_flattenable::FlattenableError;
    let rough = noisy_saddle();
    let smooth = common::saddle(12);
    let opts = cut_off_after(1);
    let messages = |mesh| match process(mesh, &opts) {
        Err(FlattenableError::NotConverged { partial, .. }) => {
            partial.report.pieces[0].messages.clone()
        }
        other => panic!("expected NotConverged, got {:?}", other.map(|_| ())),
    };
    let r = messages(&rough);
    assert!(
        r.iter().any(|m| m.contains("the surface is rough")),
        "{r:?}"
    );
    assert!(
        !r.iter().any(|m| m.contains("total angle defect of")),
        "{r:?}"
    );
    let s = messages(&smooth);
    assert!(!s.iter().any(|m| m.contains("rough")), "{s:?}");
    assert!(
        s.iter().any(|m| m.contains("negative total angle defect")),
        "{s:?}"
    );
    // 5×5 vertices, slopes up to 3 at the rim: total defect ~4 rad, median ~0.5 rad.
    let cup = common::grid(5, 0.5, |x, y| 3.0 * (x * x + y * y));
    let c = messages(&cup);
    assert!(!c.iter().any(|m| m.contains("rough")), "{c:?}");
    assert!(
        c.iter().any(|m| m.contains("total angle defect of")),
        "{c:?}"
    );
}

/// Largest growth of an interior edge's bend (angle between its faces' normals) from
/// `input` to `output`, in degrees, computed here with acos of the normals' dot product
/// (the library uses atan2), and the number of edges grown by more than `limit_deg`.
/// The default options with a direct solve cut off after `iterations`, so that a piece stops
/// unconverged.
/// The 12×12 saddle z = 0.3 (x² − y²) on [−0.5, 0.5]² with height noise of ±0.15 on its
/// 1/11 spacing (a deterministic hash): median |2π − θ| ~0.4 rad, rough by any measure.
fn noisy_saddle() -> TriMesh {
    let noise = |x: f64, y: f64| {
        let h = ((x * 12.9898 + y * 78.233).sin() * 43_758.545).fract();
        0.15 * (2.0 * h.abs() - 1.0)
    };
    common::grid(12, 0.5, |x, y| 0.3 * (x * x - y * y) + noise(x, y))
}

/// A rough piece too small for the coarse-to-fine hierarchies (the noisy 12×12 saddle, 242
/// faces) converges through the direct solve under the graph-Laplacian damping, the last
/// attempt on a rough piece: the mesh crate's angle sums (not the solver's) are 2π to the
/// tolerance and no face flips. Without the rescue, the direct solve alone stalls far from
/// θ = 2π (measured 6.3e-2).
#[test]
fn a_small_rough_piece_converges_through_the_shaped_direct_solve() {
    let rough = noisy_saddle();
    let r = process(&rough, &ProcessOptions::default()).unwrap();
    let p = &r.report.pieces[0];
    assert!(
        p.messages
            .iter()
            .any(|m| m == "solved again from the input with graph-Laplacian damping"),
        "{:?}",
        p.messages
    );
    let topo = flatcut_mesh::Topology::build(&r.mesh).unwrap();
    let worst = flatcut_mesh::geometry::angle_defects(&r.mesh.positions, &r.mesh.faces, &topo)
        .iter()
        .flatten()
        .map(|d| d.abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-9, "max |2π − θ| {worst}");
    assert_eq!(p.folded_faces, 0);
    assert_eq!(common::boundary_changed(&rough, &r.mesh), 0);
    let direct_alone = ProcessOptions {
        coarse_to_fine: flatcut_flattenable::CoarseToFine {
            rescue: false,
            ..Default::default()
        },
        ..Default::default()
    };
    match process(&rough, &direct_alone) {
        Err(flatcut_flattenable::FlattenableError::NotConverged { best_theta_err, .. }) => {
            assert!(best_theta_err > 1e-3, "{best_theta_err}")
        }
        other => panic!("expected NotConverged, got {:?}", other.map(|_| ())),
    }
}

fn cut_off_after(iterations: usize) -> ProcessOptions {
    ProcessOptions {
        max_iterations: Some(iterations),
        coarse_to_fine: flatcut_flattenable::CoarseToFine {
            levels: 0,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Per interior edge, the growth of its bend from `input` to `output` (degrees, by acos of
/// the normals' dot product) and its two ends.
fn bend_growths(
    input: &TriMesh,
    topo: &flatcut_mesh::Topology,
    output: &TriMesh,
) -> Vec<(f64, [usize; 2])> {
    use flatcut_mesh::geometry::face_normals;
    let (n0, n1) = (
        face_normals(&input.positions, &input.faces),
        face_normals(&output.positions, &output.faces),
    );
    let bend = |n: &[[f64; 3]], f: usize, g: usize| {
        flatcut_mesh::vec3::dot(n[f], n[g])
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees()
    };
    (0..3 * input.faces.len() as u32)
        .filter_map(|h| {
            let t = topo.twin(h).filter(|&t| t > h)?;
            let (f, g) = (
                flatcut_mesh::Topology::face(h).idx(),
                flatcut_mesh::Topology::face(t).idx(),
            );
            let ends = [topo.from_vertex(h).idx(), topo.from_vertex(t).idx()];
            Some((bend(&n1, f, g) - bend(&n0, f, g), ends))
        })
        .collect()
}

/// The largest growth of an interior edge's bend (degrees), the edges grown by more than
/// `limit_deg`, and the input angle defect summed over those edges' interior ends (the mesh
/// crate's `angle_defects`).
fn crease_growth(input: &TriMesh, output: &TriMesh, limit_deg: f64) -> (f64, usize, f64) {
    let topo = flatcut_mesh::Topology::build(input).unwrap();
    let growths = bend_growths(input, &topo, output);
    let max = growths.iter().map(|g| g.0).fold(0.0, f64::max);
    let creased: Vec<_> = growths.iter().filter(|g| g.0 > limit_deg).collect();
    let ends: std::collections::BTreeSet<usize> = creased.iter().flat_map(|g| g.1).collect();
    let defects = flatcut_mesh::geometry::angle_defects(&input.positions, &input.faces, &topo);
    let defect = ends.iter().filter_map(|&v| defects[v]).sum();
    (max, creased.len(), defect)
}

#[test]
fn creases_of_the_result_are_measured_and_named() {
    // The cap's flattenable neighbour is smooth (edges bend ≤ 9° more than in the input on
    // the grids measured); the saddle's is pleated (bends grown by 115–155°), and so is a
    // cup too steep for its boundary (z = 2 r², which does not converge and crumples): the
    // report says so, where, and in what surface, and its numbers equal an independent
    // recount.
    let steep_cup = common::grid(12, 0.5, |x, y| 2.0 * (x * x + y * y));
    for (name, mesh, kind) in [
        ("cap", common::sphere_cap(12), None),
        ("saddle", common::saddle(12), Some(CreaseKind::SaddleLike)),
        ("steep cup", steep_cup, Some(CreaseKind::DomeLike)),
    ] {
        let r = match process(&mesh, &ProcessOptions::default()) {
            Ok(r) => r,
            Err(FlattenableError::NotConverged { partial, .. }) if name == "steep cup" => *partial,
            Err(e) => panic!("{name}: {e}"),
        };
        let p = &r.report.pieces[0];
        let (max, count, defect) = crease_growth(&mesh, &r.mesh, flatcut_flattenable::CREASE_DEG);
        assert!(
            (p.creased_defect_rad - defect).abs() < 1e-12,
            "{name}: {} vs {defect}",
            p.creased_defect_rad
        );
        assert!(
            (p.max_crease_deg - max).abs() < 1e-6,
            "{name}: {} vs {max}",
            p.max_crease_deg
        );
        assert_eq!(p.creased_edges, count);
        assert_eq!(r.report.creased_edges, count);
        let named = p
            .messages
            .iter()
            .any(|m| m.contains("creases") && m.contains("input vertex"));
        match kind {
            Some(kind) => {
                assert!(
                    max > 30.0 && count >= 2,
                    "{name}: {max}° over {count} edges"
                );
                assert!(named, "{:?}", p.messages);
                // The saddle creases where its input has an angle excess, where a dart would
                // take surface out where there is too much already; the cup where it has a
                // deficit, which a dart takes out. The message says which.
                assert!(
                    defect.abs() >= CREASE_DEFECT_NEUTRAL_RAD,
                    "{name}: {defect}"
                );
                assert_eq!(CreaseKind::of(defect), Some(kind), "{name}: {defect}");
                assert_eq!(defect < 0.0, kind == CreaseKind::SaddleLike);
                assert!(
                    p.messages.iter().any(|m| m.contains(kind.advice())),
                    "{:?}",
                    p.messages
                );
                assert_sharpest_crease_position(&mesh, &r.mesh, p.sharpest_crease_position_mm);
            }
            None => {
                assert!(max < 15.0 && count == 0, "cap: {max}° over {count} edges");
                assert!(!named, "{:?}", p.messages);
                assert_eq!(p.creased_defect_rad.to_bits(), 0.0f64.to_bits());
                assert_eq!(p.sharpest_crease_position_mm, None);
            }
        }
        if name == "saddle" {
            assert!(
                max > 90.0 && count > 10,
                "saddle: {max}° over {count} edges"
            );
        }
        // The turn of the normals against the input, the other measure: the cap's faces
        // turn by ~22°, the saddle's by more than the crease limit.
        assert!(p.max_normal_turn_deg > 5.0 && p.max_normal_turn_deg < 90.0);
    }
}

/// The sharpest crease's position is an input end of an edge whose growth of bend is the
/// largest (within 1e-9°, ties taken on either side).
fn assert_sharpest_crease_position(input: &TriMesh, output: &TriMesh, at: Option<[f64; 3]>) {
    let at = at.expect("a creased piece names its sharpest crease");
    let topo = flatcut_mesh::Topology::build(input).unwrap();
    let growths = bend_growths(input, &topo, output);
    let max = growths.iter().map(|g| g.0).fold(f64::MIN, f64::max);
    assert!(
        growths.iter().any(|(grown, ends)| {
            *grown >= max - 1e-9 && ends.iter().any(|&v| input.positions[v] == at)
        }),
        "{at:?} is not an end of an edge grown by the most ({max}°)"
    );
}

/// A piece that does not converge names where it is least flat: the interior vertex of
/// largest |θ − 2π| (in input numbering, on the second of two pieces), its input position,
/// and the fewest vertices holding half of the remaining ‖θ − 2π‖², all recounted here from
/// the returned mesh's angle sums (the mesh crate's, not the solver's).
#[test]
fn an_unconverged_piece_names_where_it_is_least_flat() {
    // A flat disk first (already flattenable: converged after no iteration), so that the
    // error is the saddle's and its vertices are numbered after the disk's.
    let disk = flatcut_mesh::shapes::planar_disk(1.0, 6);
    let saddle = common::saddle(14);
    let mesh = concat(&[disk.clone(), saddle], 3.0);
    let opts = cut_off_after(2);
    let error = process(&mesh, &opts).err().unwrap();
    let message = error.to_string();
    let FlattenableError::NotConverged { partial, .. } = error else {
        panic!("two iterations do not flatten these pieces: {message}");
    };
    let p = &partial.report.pieces[1];
    let topo = flatcut_mesh::Topology::build(&partial.mesh).unwrap();
    let defects =
        flatcut_mesh::geometry::angle_defects(&partial.mesh.positions, &partial.mesh.faces, &topo);
    // |θ − 2π| per interior vertex of the second piece (global numbering).
    let first = disk.vertex_count();
    let mut residual: Vec<(f64, usize)> = defects
        .iter()
        .enumerate()
        .skip(first)
        .filter_map(|(v, d)| d.map(|d| (d.abs(), v)))
        .collect();
    assert_eq!(residual.len(), p.interior_vertices);
    residual.sort_by(|a, b| b.0.total_cmp(&a.0));
    let worst = p.worst_vertex.unwrap() as usize;
    // The solver's θ and the mesh crate's differ in round-off only.
    assert!(worst >= first, "{worst} is not on the second piece");
    assert!(
        (defects[worst].unwrap().abs() - residual[0].0).abs() <= 1e-12,
        "{worst}: {:?} vs {:?}",
        defects[worst],
        residual[0]
    );
    assert!((residual[0].0 - p.final_theta_err).abs() <= 1e-12);
    assert_eq!(p.worst_vertex_position_mm, Some(mesh.positions[worst]));
    // The fewest vertices holding half of the squared residual.
    let total: f64 = residual.iter().map(|r| r.0 * r.0).sum();
    let mut held = 0.0;
    let k = residual
        .iter()
        .position(|r| {
            held += r.0 * r.0;
            held >= 0.5 * total
        })
        .unwrap()
        + 1;
    assert!(
        p.vertices_holding_half_residual.abs_diff(k) <= 1,
        "{} vs {k}",
        p.vertices_holding_half_residual
    );
    assert!(k > 1 && k < p.interior_vertices / 2, "{k}");
    // Their reach from the worst vertex, bracketed by the recount with a vertex more or less
    // (round-off may order near-ties differently).
    let at = mesh.positions[worst];
    let reach = |n: usize| {
        residual[..n]
            .iter()
            .map(|r| flatcut_mesh::vec3::dist(mesh.positions[r.1], at))
            .fold(0.0, f64::max)
    };
    assert!(
        p.half_residual_radius_mm >= reach(k - 1) - 1e-12
            && p.half_residual_radius_mm <= reach(k + 1) + 1e-12,
        "{} not in [{}, {}]",
        p.half_residual_radius_mm,
        reach(k - 1),
        reach(k + 1)
    );
    assert!(
        message.contains(&format!("least flat at input vertex {worst} at (")),
        "{message}"
    );
    assert!(
        message.contains(&format!(
            "on {} of {} interior vertices",
            p.vertices_holding_half_residual, p.interior_vertices
        )),
        "{message}"
    );
}

/// A piece whose input already has θ = 2π within the tolerance (a cylinder strip, a planar
/// disk: developable polyhedra) comes back bit for bit, after no iteration, and says so; a
/// curved piece beside it is processed as usual.
#[test]
fn an_already_flattenable_piece_is_returned_unchanged_without_iterations() {
    let cyl = flatcut_mesh::shapes::cylinder_patch(30.0, 2.0, 40.0, 9, 7);
    let disk = flatcut_mesh::shapes::planar_disk(50.0, 6);
    let cap = common::sphere_cap(10);
    let opts = ProcessOptions::default();
    for flat in [&cyl, &disk] {
        // Independent evidence that it is flattenable: the mesh crate's angle defects.
        let topo = flatcut_mesh::Topology::build(flat).unwrap();
        let defects = flatcut_mesh::geometry::angle_defects(&flat.positions, &flat.faces, &topo);
        let worst = defects
            .iter()
            .flatten()
            .map(|d| d.abs())
            .fold(0.0, f64::max);
        assert!(defects.iter().flatten().count() > 10);
        assert!(worst <= 1e-12, "input defect {worst}");
        let r = process(flat, &opts).unwrap();
        assert_eq!(r.mesh.positions, flat.positions);
        assert_eq!(r.report.iterations, 0);
        let p = &r.report.pieces[0];
        assert!(p.converged && p.factorizations == 0);
        assert!(
            p.messages
                .iter()
                .any(|m| m.starts_with("already flattenable"))
        );
        assert_eq!(p.theta_err.len(), 1);
    }
    let both = concat(&[cyl.clone(), cap.clone()], 200.0);
    let r = process(&both, &opts).unwrap();
    assert_eq!(r.report.pieces[0].iterations, 0);
    assert!(r.report.pieces[1].iterations > 0);
    assert_eq!(&r.mesh.positions[..cyl.vertex_count()], &cyl.positions[..]);
}

#[test]
fn the_progress_hook_sees_every_iteration_and_changes_nothing() {
    use std::sync::{Arc, Mutex};
    // A cap and a saddle (two pieces, run in parallel), robust and paper mode.
    let mesh = concat(&[common::sphere_cap(12), common::saddle(10)], 3.0);
    for base in [
        ProcessOptions::default(),
        ProcessOptions::paper(Update::LeastSquare),
    ] {
        let seen = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&seen);
        let opts = ProcessOptions {
            progress: flatcut_flattenable::ProgressHook::new(move |e| {
                sink.lock().unwrap().push(*e);
            }),
            ..base.clone()
        };
        let quiet = process(&mesh, &base);
        let observed = process(&mesh, &opts);
        let (quiet, observed) = match (quiet, observed) {
            (Ok(a), Ok(b)) => (a, b),
            (
                Err(FlattenableError::NotConverged { partial: a, .. }),
                Err(FlattenableError::NotConverged { partial: b, .. }),
            ) => (*a, *b),
            (a, b) => panic!("{a:?} / {b:?}"),
        };
        assert_eq!(
            quiet.mesh.positions, observed.mesh.positions,
            "the hook changed the result"
        );
        let seen = seen.lock().unwrap();
        for p in &observed.report.pieces {
            // This piece's events, in order: iteration 0 (the input) and one per iteration,
            // with the report's θ_err.
            let events: Vec<(usize, f64)> = seen
                .iter()
                .filter(|e| e.piece == p.piece)
                .map(|e| {
                    assert_eq!(e.faces, p.faces);
                    (e.iteration, e.theta_err)
                })
                .collect();
            let expected: Vec<(usize, f64)> = p.theta_err.iter().copied().enumerate().collect();
            assert_eq!(events, expected, "piece {} ({:?})", p.piece, base.mode);
        }
    }
}
