//! Pieces: the embedded mesh cut open along its line edges, split into connected pieces,
//! each named by the seed inside it, with its topology reported.
//!
//! Cutting duplicates vertices: the corners around each vertex are grouped into wedges
//! separated by cut edges (union–find over the corners across every uncut manifold edge);
//! each wedge becomes one vertex. Pieces are the face components across uncut edges. A line
//! that does not separate (a slit, or a seam of a tube cut open along its length) still opens
//! the surface: both sides then belong to the same piece.

use std::collections::HashMap;

use flatcut_mesh::{Topology, TriMesh, bvh::Bvh, geometry, vec3};

use crate::TrimError;
use crate::cuts::{Cuts, PieceSpec};
use crate::embed::Embedded;
use crate::lines::CutLine;
use crate::surface_point::SurfacePoint;

/// A seed closer than this to a cut line (relative to the mesh diagonal) is on the line: it
/// cannot say which side it means.
pub const SEED_ON_LINE_RELATIVE: f64 = 1e-6;

/// One piece of the cut surface.
#[derive(Clone, Debug)]
pub struct Piece {
    /// Its name (the seed's, or `unnamed-<k>`).
    pub name: String,
    /// The piece as a mesh (same units as the source).
    pub mesh: TriMesh,
    /// For each piece vertex, where it lies on the source surface.
    pub vertex_source: Vec<SurfacePoint>,
    /// For each piece face, the source face it lies in.
    pub face_source: Vec<u32>,
    /// Each piece face's index in the embedded mesh.
    pub embedded_face: Vec<u32>,
    /// Each piece vertex's index in the embedded mesh.
    pub embedded_vertex: Vec<u32>,
}

/// What became of one piece.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PieceReport {
    /// Name (`unnamed-<k>` when no seed names it).
    pub name: String,
    /// Named by a seed?
    pub named: bool,
    /// Kept (named, or unnamed with `keep_unnamed`)?
    pub kept: bool,
    /// Faces.
    pub faces: usize,
    /// Area, mm².
    pub area_mm2: f64,
    /// Boundary loops.
    pub boundary_loops: usize,
    /// Euler characteristic V − E + F.
    pub euler_characteristic: i64,
    /// Genus (handles): (2 − χ − loops) / 2.
    pub genus: i64,
    /// One boundary loop and no handle: a disk, flattenable without further cuts.
    pub disk: bool,
}

/// A mesh cut open along some of its edges (see [`split_along`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Split {
    /// For each face, its piece: the face components across uncut edges, numbered in order of
    /// their lowest face.
    pub face_piece: Vec<u32>,
    /// Number of pieces.
    pub piece_count: usize,
    /// For each corner `3·f + k` (vertex `k` of face `f`), its wedge: the corners around one
    /// vertex joined across every uncut interior edge. Wedges are numbered in order of their
    /// lowest corner; each becomes one vertex of the cut-open mesh.
    pub corner_vertex: Vec<u32>,
}

fn find(p: &mut [u32], mut x: u32) -> u32 {
    while p[x as usize] != x {
        p[x as usize] = p[p[x as usize] as usize];
        x = p[x as usize];
    }
    x
}

fn union(p: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(p, a), find(p, b));
    if ra != rb {
        p[ra.max(rb) as usize] = ra.min(rb);
    }
}

pub(crate) fn cut_edges(emb: &Embedded) -> HashMap<(u32, u32), usize> {
    let mut cut = HashMap::new();
    for (li, chain) in emb.line_vertices.iter().enumerate() {
        for w in chain.windows(2) {
            cut.insert((w[0].min(w[1]), w[0].max(w[1])), li);
        }
    }
    cut
}

pub(crate) fn split(emb: &Embedded, topo: &Topology, cut: &HashMap<(u32, u32), usize>) -> Split {
    split_along(emb.mesh.faces.len(), topo, |a, b| {
        cut.contains_key(&(a.min(b), a.max(b)))
    })
}

/// Cuts a mesh open along the edges `is_cut(a, b)` says (called with both orders of an
/// interior edge's end vertices; boundary edges are open already): groups corners into wedges
/// and faces into pieces by union–find across every uncut interior edge. Linear in the faces.
/// Shared by cutting lines and darts, so both open a surface the same way.
///
/// `face_count` and `topo` are the mesh's (`Topology::build` of it).
pub fn split_along(face_count: usize, topo: &Topology, is_cut: impl Fn(u32, u32) -> bool) -> Split {
    let nf = face_count;
    let mut fp: Vec<u32> = (0..nf as u32).collect();
    let mut cp: Vec<u32> = (0..3 * nf as u32).collect();
    for h in 0..3 * nf as u32 {
        let Some(t) = topo.twin(h) else { continue };
        if t < h {
            continue;
        }
        let (a, b) = (topo.from_vertex(h).0, topo.to_vertex(h).0);
        if is_cut(a, b) {
            continue;
        }
        union(&mut fp, h / 3, t / 3);
        // h: a → b in face h/3; t: b → a. Corner of a in t's face is next(t)'s start.
        union(&mut cp, h, Topology::next(t));
        union(&mut cp, Topology::next(h), t);
    }
    let mut piece_of_root = HashMap::new();
    let face_piece: Vec<u32> = (0..nf as u32)
        .map(|f| {
            let r = find(&mut fp, f);
            let n = piece_of_root.len() as u32;
            *piece_of_root.entry(r).or_insert(n)
        })
        .collect();
    let mut vertex_of_root = HashMap::new();
    let corner_vertex: Vec<u32> = (0..3 * nf as u32)
        .map(|c| {
            let r = find(&mut cp, c);
            let n = vertex_of_root.len() as u32;
            *vertex_of_root.entry(r).or_insert(n)
        })
        .collect();
    Split {
        piece_count: piece_of_root.len(),
        face_piece,
        corner_vertex,
    }
}

/// Names pieces by seeds: for each piece index, the seed index naming it.
pub(crate) fn name_pieces(
    emb: &Embedded,
    split: &Split,
    lines: &[CutLine],
    cut: &HashMap<(u32, u32), usize>,
    seeds: &[PieceSpec],
    cuts: &Cuts,
) -> Result<Vec<Option<usize>>, TrimError> {
    let mut named: Vec<Option<usize>> = vec![None; split.piece_count];
    if seeds.is_empty() {
        return Ok(named);
    }
    let mut names = std::collections::HashSet::new();
    for s in seeds {
        if !names.insert(s.name.as_str()) {
            return Err(TrimError::DuplicateName {
                what: "piece",
                name: s.name.clone(),
            });
        }
    }
    let bvh = Bvh::build(&emb.mesh);
    let diag = emb.mesh.diagonal();
    for (si, s) in seeds.iter().enumerate() {
        if !s.seed.iter().all(|c| c.is_finite()) {
            return Err(TrimError::NonFinitePoint {
                what: format!("piece {:?} seed", s.name),
            });
        }
        let cp = bvh.closest_point(s.seed).ok_or(TrimError::EmptyMesh)?;
        if cp.distance > cuts.options.landmark_tolerance_mm {
            return Err(TrimError::OffSurface {
                what: format!("piece {:?} seed", s.name),
                distance_mm: cp.distance,
                tolerance_mm: cuts.options.landmark_tolerance_mm,
            });
        }
        let face = emb.mesh.faces[cp.face.idx()];
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            if let Some(&li) = cut.get(&(a.min(b), a.max(b))) {
                let (pa, pb) = (
                    emb.mesh.positions[a as usize],
                    emb.mesh.positions[b as usize],
                );
                let dist = vec3::point_segment_distance(cp.point, pa, pb);
                if dist <= SEED_ON_LINE_RELATIVE * diag {
                    return Err(TrimError::SeedOnLine {
                        piece: s.name.clone(),
                        line: lines[li].name.clone(),
                    });
                }
            }
        }
        let p = split.face_piece[cp.face.idx()] as usize;
        if let Some(prev) = named[p] {
            // The nearest line, for the message.
            let (near_mm, near_line) = emb
                .line_vertices
                .iter()
                .enumerate()
                .flat_map(|(li, ch)| ch.windows(2).map(move |w| (li, w[0], w[1])))
                .map(|(li, a, b)| {
                    let (pa, pb) = (
                        emb.mesh.positions[a as usize],
                        emb.mesh.positions[b as usize],
                    );
                    (vec3::point_segment_distance(cp.point, pa, pb), li)
                })
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .map_or((f64::INFINITY, String::new()), |(d, li)| {
                    (d, lines[li].name.clone())
                });
            return Err(TrimError::SeedUsedTwice {
                first: seeds[prev].name.clone(),
                second: s.name.clone(),
                near_line,
                near_mm,
            });
        }
        named[p] = Some(si);
    }
    Ok(named)
}

/// Builds piece `p` as its own mesh; returns it and the local vertex of every corner of it.
pub(crate) fn build_piece(
    emb: &Embedded,
    split: &Split,
    faces: &[u32],
    name: String,
) -> (Piece, HashMap<u32, u32>) {
    let mut local: HashMap<u32, u32> = HashMap::new();
    let mut embedded_vertex = Vec::new();
    let mut pf = Vec::with_capacity(faces.len());
    for &f in faces {
        let mut tri = [0u32; 3];
        for (k, t) in tri.iter_mut().enumerate() {
            let sv = split.corner_vertex[3 * f as usize + k];
            *t = *local.entry(sv).or_insert_with(|| {
                embedded_vertex.push(emb.mesh.faces[f as usize][k]);
                (embedded_vertex.len() - 1) as u32
            });
        }
        pf.push(tri);
    }
    let piece = Piece {
        name,
        mesh: TriMesh {
            positions: embedded_vertex
                .iter()
                .map(|&v| emb.mesh.positions[v as usize])
                .collect(),
            faces: pf,
            ..Default::default()
        },
        vertex_source: embedded_vertex
            .iter()
            .map(|&v| emb.vertex_source[v as usize])
            .collect(),
        face_source: faces.iter().map(|&f| emb.face_source[f as usize]).collect(),
        embedded_face: faces.to_vec(),
        embedded_vertex,
    };
    (piece, local)
}

/// Topology counts of a piece.
pub(crate) fn report_of(piece: &Piece, named: bool, kept: bool) -> Result<PieceReport, TrimError> {
    let topo = Topology::build(&piece.mesh)?;
    let loops = topo.boundary_loops().len() + topo.open_boundary_chains().len();
    let chi = topo.euler_characteristic();
    let genus = (2 - chi - loops as i64) / 2;
    Ok(PieceReport {
        name: piece.name.clone(),
        named,
        kept,
        faces: piece.mesh.faces.len(),
        area_mm2: geometry::total_area(&piece.mesh),
        boundary_loops: loops,
        euler_characteristic: chi,
        genus,
        disk: loops == 1 && genus == 0 && topo.component_count() == 1,
    })
}
