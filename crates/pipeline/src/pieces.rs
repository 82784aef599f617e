//! Pieces of the cleaned surface: its connected components, named by the `[[piece]]` seeds
//! (or `piece-0`, `piece-1`, … in order of first face when the file names none).

use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::{Topology, TriMesh, submesh};

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
    /// For each piece vertex, the vertex of the cleaned surface it came from.
    pub source_vertex: Vec<u32>,
    /// For each piece face, the face of the cleaned surface.
    pub source_face: Vec<u32>,
}

/// A component that no seed named, reported and left out.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DroppedComponent {
    /// Component number (order of first face).
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
