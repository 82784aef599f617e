//! Pieces of the cleaned surface: its connected components, named by the `[[piece]]` seeds
//! (or `piece-0`, `piece-1`, … in order of first face when the file names none).

use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::{SeamLedger, Topology, TriMesh, submesh};

use crate::spec::Pipeline;
use crate::{PipelineError, SEED_TOLERANCE_MM};

/// One piece as its own mesh.
#[derive(Clone, Debug)]
pub struct PieceMesh {
    /// Its name.
    pub name: String,
    /// Index of its `[[piece]]` entry, if it has one.
    pub spec: Option<usize>,
    /// The piece (mm), vertices numbered by first use.
    pub mesh: TriMesh,
    /// For each piece vertex, the vertex of the cleaned surface it came from (empty for
    /// pieces cut by lines, whose vertices may lie inside source faces).
    pub source_vertex: Vec<u32>,
    /// For each piece face, the face of the cleaned surface.
    pub source_face: Vec<u32>,
    /// Names of the darts cut into the piece (empty until [`crate::pieces`]' darts stage).
    pub darts: Vec<String>,
    /// Feature curves as vertex chains of `mesh` (after darts).
    pub features: Vec<Vec<u32>>,
}

/// A component (or cut piece) that no seed named, reported and left out.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DroppedComponent {
    /// Component number (order of first face), or the cut piece's index in trim's report.
    pub component: usize,
    /// Its faces.
    pub faces: usize,
}

/// Splits `mesh` into pieces. With `[[piece]]` entries, each seed (in `units_to_mm` units)
/// picks the component holding its closest surface point; the point must lie within
/// [`SEED_TOLERANCE_MM`], and no two seeds may pick one component. Unnamed components are
/// returned as dropped.
pub fn split(
    p: &Pipeline,
    mesh: &TriMesh,
    topo: &Topology,
    units_to_mm: f64,
) -> Result<(Vec<PieceMesh>, Vec<DroppedComponent>), PipelineError> {
    let comps = topo.component_count();
    let mut comp_faces: Vec<Vec<u32>> = vec![Vec::new(); comps];
    for (f, &c) in topo.face_components().iter().enumerate() {
        comp_faces[c as usize].push(f as u32);
    }
    let make = |name: String, spec: Option<usize>, faces: &[u32]| {
        let (m, source_vertex) = submesh(mesh, faces);
        PieceMesh {
            name,
            spec,
            mesh: m,
            source_vertex,
            source_face: faces.to_vec(),
            darts: Vec::new(),
            features: Vec::new(),
        }
    };
    if p.spec.pieces.is_empty() {
        let pieces = comp_faces
            .iter()
            .enumerate()
            .map(|(c, faces)| make(format!("piece-{c}"), None, faces))
            .collect();
        return Ok((pieces, Vec::new()));
    }
    let bvh = Bvh::build(mesh);
    let mut owner: Vec<Option<usize>> = vec![None; comps];
    let mut pieces = Vec::with_capacity(p.spec.pieces.len());
    for (i, ps) in p.spec.pieces.iter().enumerate() {
        let ps = ps.get_ref();
        let seed = ps.seed.get_ref().map(|c| c * units_to_mm);
        let hit = bvh.closest_point(seed);
        let Some(hit) = hit.filter(|h| h.distance <= SEED_TOLERANCE_MM) else {
            let d = hit.map_or(f64::INFINITY, |h| h.distance);
            return Err(p.invalid(
                ps.seed.span(),
                "piece.seed",
                format!(
                    "the seed of piece {:?} is {d:.3} mm from the surface (at most {SEED_TOLERANCE_MM} mm allowed): it lies in no piece; put it on the piece (coordinates in the file's units)",
                    ps.name.get_ref()
                ),
            ));
        };
        let c = topo.face_components()[hit.face.idx()] as usize;
        if let Some(j) = owner[c] {
            let other = p.spec.pieces[j].get_ref();
            let (line, _) = crate::spec::line_col(&p.text, other.seed.span().start);
            return Err(p.invalid(
                ps.seed.span(),
                "piece.seed",
                format!(
                    "the seed of piece {:?} lies in the same piece as the seed of {:?} (line {line}); one piece cannot have two names",
                    ps.name.get_ref(),
                    other.name.get_ref()
                ),
            ));
        }
        owner[c] = Some(i);
        pieces.push(make(ps.name.get_ref().clone(), Some(i), &comp_faces[c]));
    }
    let dropped = (0..comps)
        .filter(|&c| owner[c].is_none())
        .map(|c| DroppedComponent {
            component: c,
            faces: comp_faces[c].len(),
        })
        .collect();
    Ok((pieces, dropped))
}

/// Cuts `mesh` (mm) along the file's `[[cut]]` lines into the `[[piece]]` pieces with
/// crates/trim; returns the pieces, the seam ledger and the unnamed pieces trim dropped.
pub fn cut(
    p: &Pipeline,
    mesh: &TriMesh,
    units_to_mm: f64,
) -> Result<(Vec<PieceMesh>, SeamLedger, Vec<DroppedComponent>), PipelineError> {
    let mut cuts = flatcut_trim::Cuts {
        units: None,
        cuts: p.spec.cuts.iter().map(|c| c.get_ref().clone()).collect(),
        pieces: p
            .spec
            .pieces
            .iter()
            .map(|ps| {
                let ps = ps.get_ref();
                flatcut_trim::PieceSpec {
                    name: ps.name.get_ref().clone(),
                    seed: *ps.seed.get_ref(),
                }
            })
            .collect(),
        options: p.spec.trim.clone(),
    };
    cuts.scale(units_to_mm);
    let trimmed = flatcut_trim::trim(mesh, &cuts).map_err(|e| locate_trim_error(p, e))?;
    let spec_of = |name: &str| {
        p.spec
            .pieces
            .iter()
            .position(|ps| ps.get_ref().name.get_ref() == name)
    };
    let pieces = trimmed
        .pieces
        .into_iter()
        .map(|tp| PieceMesh {
            spec: spec_of(&tp.name),
            name: tp.name,
            source_vertex: Vec::new(),
            source_face: tp.face_source,
            mesh: tp.mesh,
            darts: Vec::new(),
            features: Vec::new(),
        })
        .collect();
    let dropped = trimmed
        .report
        .pieces
        .iter()
        .enumerate()
        .filter(|(_, r)| !r.kept)
        .map(|(i, r)| DroppedComponent {
            component: i,
            faces: r.faces,
        })
        .collect();
    Ok((pieces, trimmed.ledger, dropped))
}

/// A trim error located at the `[[cut]]` or `[[piece]]` whose name it quotes (else the first
/// `[[cut]]`).
fn locate_trim_error(p: &Pipeline, e: flatcut_trim::TrimError) -> PipelineError {
    let msg = e.to_string();
    let quoted = |n: &str| msg.contains(&format!("{n:?}"));
    let (span, key) = if let Some(c) = p.spec.cuts.iter().find(|c| quoted(&c.get_ref().name)) {
        (c.span(), "cut")
    } else if let Some(ps) = p
        .spec
        .pieces
        .iter()
        .find(|ps| quoted(ps.get_ref().name.get_ref()))
    {
        (ps.span(), "piece")
    } else {
        (p.spec.cuts.first().map_or(0..0, |c| c.span()), "cut")
    };
    p.invalid(span, key, msg)
}

/// Cuts the `[[piece]]`'s darts into `piece` (flatcut_dart, points in `units_to_mm` units)
/// and places its feature curves on the darted piece. Returns the darted result, if any, for
/// the seam ledger. Errors are located at the dart or feature curve they concern.
pub fn darts_and_features(
    p: &Pipeline,
    piece: &mut PieceMesh,
    units_to_mm: f64,
    seam_vertices: &std::collections::BTreeSet<u32>,
) -> Result<Option<flatcut_dart::Darted>, PipelineError> {
    let Some(ps) = piece.spec.map(|i| p.spec.pieces[i].get_ref()) else {
        return Ok(None);
    };
    let mut darted = None;
    if !ps.darts.is_empty() {
        let specs: Vec<flatcut_dart::DartSpec> = ps
            .darts
            .iter()
            .map(|d| {
                let mut d = d.get_ref().clone();
                d.from = d.from.map(|c| c * units_to_mm);
                d.tip = d.tip.map(|t| t.map(|c| c * units_to_mm));
                if let Some(v) = snap_to_seam_vertex(
                    &piece.mesh,
                    d.from,
                    seam_vertices,
                    p.spec.dart.boundary_tolerance_mm,
                ) {
                    d.from = v;
                }
                d
            })
            .collect();
        let d = flatcut_dart::dart(&piece.mesh, &specs, &p.spec.dart)
            .map_err(|e| dart_error(p, ps, e))?;
        piece.mesh = d.mesh.clone();
        piece.darts = d.darts.iter().map(|l| l.name.clone()).collect();
        // The darted piece has new vertices; the map back to the cleaned surface's vertices
        // no longer applies (faces keep theirs through the dart's face provenance).
        piece.source_vertex = Vec::new();
        piece.source_face = d
            .face_source
            .iter()
            .map(|&f| piece.source_face.get(f as usize).copied().unwrap_or(f))
            .collect();
        darted = Some(d);
    }
    if !ps.features.is_empty() {
        let bvh = Bvh::build(&piece.mesh);
        for (k, f) in ps.features.iter().enumerate() {
            let pts: Vec<[f64; 3]> = f
                .get_ref()
                .iter()
                .map(|x| x.map(|c| c * units_to_mm))
                .collect();
            let chain = crate::features::feature_chain(&piece.mesh, &bvh, &pts, SEED_TOLERANCE_MM)
                .map_err(|e| {
                    let message = match e {
                        crate::features::FeatureError::OffPiece {
                            landmark,
                            distance_mm,
                        } => format!(
                            "piece {:?}: landmark {landmark} of feature curve {k} is {distance_mm:.3} mm from the piece (at most {SEED_TOLERANCE_MM} mm allowed); put it on this piece (coordinates in the file's units)",
                            ps.name.get_ref()
                        ),
                        crate::features::FeatureError::NoPath { landmark } => format!(
                            "piece {:?}: no path on the piece joins landmarks {} and {landmark} of feature curve {k}",
                            ps.name.get_ref(),
                            landmark - 1
                        ),
                    };
                    p.invalid(f.span(), "piece.features", message)
                })?;
            piece.features.push(chain);
        }
    }
    Ok(darted)
}

/// A dart that starts on a seam must start at one of the seam's vertices: a start inside a
/// seam edge would need the same new vertex on the seam's mate in another piece. When the
/// boundary edge closest to `from` (within `tolerance_mm`, else the dart crate reports the
/// start off the boundary) has both ends on seams, the start moves to its nearer end — at
/// most half an edge.
fn snap_to_seam_vertex(
    mesh: &TriMesh,
    from: [f64; 3],
    seam_vertices: &std::collections::BTreeSet<u32>,
    tolerance_mm: f64,
) -> Option<[f64; 3]> {
    use flatcut_mesh::vec3;
    if seam_vertices.is_empty() {
        return None;
    }
    let topo = Topology::build(mesh).ok()?;
    let mut best: Option<(f64, u32, u32)> = None;
    for lp in topo.boundary_loops() {
        for (k, a) in lp.iter().enumerate() {
            let b = lp[(k + 1) % lp.len()];
            let (pa, pb) = (mesh.positions[a.idx()], mesh.positions[b.idx()]);
            let ab = vec3::sub(pb, pa);
            let l2 = vec3::norm2(ab);
            let t = if l2 > 0.0 {
                (vec3::dot(vec3::sub(from, pa), ab) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let d = vec3::dist(from, vec3::add(pa, vec3::scale(ab, t)));
            if best.is_none_or(|(bd, _, _)| d < bd) {
                best = Some((d, a.0, b.0));
            }
        }
    }
    let (d, a, b) = best?;
    if d > tolerance_mm || !(seam_vertices.contains(&a) && seam_vertices.contains(&b)) {
        return None;
    }
    let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
    Some(if vec3::dist(from, pa) <= vec3::dist(from, pb) {
        pa
    } else {
        pb
    })
}

/// Index in the piece's `darts` of the dart a [`flatcut_dart::DartError`] is about.
fn dart_index(ps: &crate::spec::PieceSpec, e: &flatcut_dart::DartError) -> Option<usize> {
    use flatcut_dart::DartError as E;
    match e {
        E::BadSpec { index, .. }
        | E::StartOffBoundary { index, .. }
        | E::TipOffPiece { index, .. }
        | E::TipOnBoundary { index, .. }
        | E::TouchesBoundary { index, .. }
        | E::TooLong { index, .. }
        | E::DirectionOutward { index, .. }
        | E::NoPath { index, .. } => Some(*index),
        E::Crossing { b, .. } => Some(*b),
        E::DuplicateName { second, .. } => Some(*second),
        E::StartSplitsSeam { name, .. } | E::DuplicateSeam { seam: name } => {
            ps.darts.iter().enumerate().position(|(i, d)| {
                let n = &d.get_ref().name;
                let n = if n.is_empty() {
                    format!("dart-{}", i + 1)
                } else {
                    n.clone()
                };
                *name == n || *name == flatcut_dart::dart_seam_id(&n)
            })
        }
        _ => None,
    }
}

/// A dart error located at its dart in the TOML (else at the piece's first dart).
pub fn dart_error(
    p: &Pipeline,
    ps: &crate::spec::PieceSpec,
    e: flatcut_dart::DartError,
) -> PipelineError {
    let span = dart_index(ps, &e)
        .and_then(|i| ps.darts.get(i))
        .or(ps.darts.first())
        .map_or(ps.name.span(), |d| d.span());
    p.invalid(
        span,
        "piece.darts",
        format!("piece {:?}: {e}", ps.name.get_ref()),
    )
}
