//! Darts: a slit from a piece's boundary to a tip inside it, cut open so that the two legs
//! become boundary while the tip stays one vertex.
//!
//! 1. The start snaps to the closest point of the piece's boundary (within
//!    [`DartOptions::boundary_tolerance_mm`]); the tip to the closest surface point (within
//!    [`DartOptions::tip_tolerance_mm`]), or it is found by walking the straightest geodesic
//!    from the start in the given direction for the given length ([`crate::trace`]).
//! 2. Start and tip are joined by the exact geodesic (flatcut_trim's solver), and every dart
//!    is embedded exactly into the piece by flatcut_trim's [`embed`] (new vertices where the
//!    path crosses edges; nothing moves).
//! 3. The piece is opened along the dart edges: the corners around each vertex are grouped
//!    into wedges separated by dart edges (union–find across every uncut edge) and each wedge
//!    becomes a vertex. A vertex inside a leg has two wedges, the start on the boundary two,
//!    the tip — one dart edge in a closed fan — one: it stays one vertex.

use std::collections::HashMap;

use flatcut_mesh::{FaceLabels, Topology, TriMesh, VertexId, bvh::Bvh, vec3};
use flatcut_trim::{
    CutLine, GeodesicOptions, GeodesicSolver, SurfacePoint, SurfacePointOptions, TrimError,
    closest_on_halfedges, embed, split_along, surface_point,
};
use serde::{Deserialize, Serialize};

use crate::DartError;
use crate::trace::{Traced, trace};

/// Default largest distance from a dart's start to the piece's boundary, mm: as far as a
/// landmark may lie off a surface in flatcut_trim (a click on a scan's rim is a few mm off).
/// A tip closer than this to the boundary counts as on it.
pub const DEFAULT_BOUNDARY_TOLERANCE_MM: f64 = 5.0;

/// Default largest distance from a dart's tip to the piece's surface, mm (as for landmarks).
pub const DEFAULT_TIP_TOLERANCE_MM: f64 = 5.0;

/// One dart as the user gives it: a start on the boundary and either a tip, or a direction
/// and a length. Coordinates in the piece's units (mm inside flatcut).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DartSpec {
    /// Name, used in errors and as the seam id (`<name>`). Empty: `dart-<k>` (1-based).
    #[serde(default)]
    pub name: String,
    /// The start, on (or within the boundary tolerance of) the piece's boundary.
    pub from: [f64; 3],
    /// The tip, inside the piece. Give this, or `direction` and `length_mm`.
    #[serde(default)]
    pub tip: Option<[f64; 3]>,
    /// The direction at the start (3D, projected onto the surface there; need not be unit).
    #[serde(default)]
    pub direction: Option<[f64; 3]>,
    /// The length along the surface, mm.
    #[serde(default)]
    pub length_mm: Option<f64>,
}

impl DartSpec {
    /// A dart from `from` to `tip`.
    pub fn to_tip(name: &str, from: [f64; 3], tip: [f64; 3]) -> Self {
        Self {
            name: name.to_string(),
            from,
            tip: Some(tip),
            direction: None,
            length_mm: None,
        }
    }

    /// A dart from `from` in `direction` for `length_mm` along the surface.
    pub fn along(name: &str, from: [f64; 3], direction: [f64; 3], length_mm: f64) -> Self {
        Self {
            name: name.to_string(),
            from,
            tip: None,
            direction: Some(direction),
            length_mm: Some(length_mm),
        }
    }
}

/// Options of [`dart`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DartOptions {
    /// Largest distance from a start to the boundary, and smallest from a tip to it, mm.
    /// Default [`DEFAULT_BOUNDARY_TOLERANCE_MM`] (5).
    pub boundary_tolerance_mm: f64,
    /// Largest distance from a tip to the surface, mm. Default [`DEFAULT_TIP_TOLERANCE_MM`] (5).
    pub tip_tolerance_mm: f64,
    /// Most strip updates per geodesic (flatcut_trim's guard against rounding cycles).
    /// Default 100 000.
    pub max_strip_updates: usize,
}

impl Default for DartOptions {
    fn default() -> Self {
        Self {
            boundary_tolerance_mm: DEFAULT_BOUNDARY_TOLERANCE_MM,
            tip_tolerance_mm: DEFAULT_TIP_TOLERANCE_MM,
            max_strip_updates: GeodesicOptions::default().max_strip_updates,
        }
    }
}

/// One dart in the darted piece.
#[derive(Clone, Debug, PartialEq)]
pub struct DartLegs {
    /// Its name.
    pub name: String,
    /// The tip vertex (one vertex, shared by both legs).
    pub tip: u32,
    /// Leg A: from the tip to the boundary, the faces on its left (walking from the tip,
    /// seen from the side the normals point to).
    pub leg_a: Vec<u32>,
    /// Leg B: from the tip to the boundary, the faces on its right. `leg_a[k]` and
    /// `leg_b[k]` are copies of one source point; `leg_a[0] == leg_b[0] == tip`.
    pub leg_b: Vec<u32>,
    /// Length of the dart on the source surface (each leg's 3D length), mm.
    pub length_mm: f64,
    /// The start on the source boundary.
    pub start: SurfacePoint,
    /// The tip on the source.
    pub tip_point: SurfacePoint,
    /// The start, mm.
    pub start_mm: [f64; 3],
    /// The tip, mm.
    pub tip_mm: [f64; 3],
}

/// The result of [`dart`]: the piece cut open along its darts, with provenance.
#[derive(Clone, Debug)]
pub struct Darted {
    /// The darted piece. Vertices: the input's (same indices), then the points the darts
    /// added, then the copies made by opening. Face labels carried over; other per-vertex
    /// attributes are dropped (they do not survive new vertices unchanged).
    pub mesh: TriMesh,
    /// For each vertex, where it lies on the input piece.
    pub vertex_source: Vec<SurfacePoint>,
    /// For each face, the input face it lies in.
    pub face_source: Vec<u32>,
    /// For each vertex, the vertex it is a copy of before opening (itself if not a copy);
    /// values below the input's vertex count are input vertices.
    pub split_from: Vec<u32>,
    /// The darts, in the order given.
    pub darts: Vec<DartLegs>,
}

/// Closest point of the piece's boundary (edges without a twin) to `x`: (distance, point).
pub(crate) fn closest_on_boundary(
    mesh: &TriMesh,
    topo: &Topology,
    x: [f64; 3],
) -> Option<(f64, SurfacePoint)> {
    let boundary = (0..3 * mesh.faces.len() as u32).filter(|&h| topo.twin(h).is_none());
    closest_on_halfedges(mesh, boundary, x)
}

/// A dart resolved on the input piece: its line from start to tip.
struct Resolved {
    name: String,
    line: CutLine,
}

fn finite(p: [f64; 3]) -> bool {
    p.iter().all(|c| c.is_finite())
}

/// Cuts `darts` into `piece` (a manifold, oriented piece with a boundary; mm).
pub fn dart(piece: &TriMesh, darts: &[DartSpec], opts: &DartOptions) -> Result<Darted, DartError> {
    piece.validate()?;
    if piece.faces.is_empty() {
        return Err(DartError::BadPiece {
            reason: "has no faces".into(),
        });
    }
    let solver = GeodesicSolver::new(
        piece,
        &GeodesicOptions {
            max_strip_updates: opts.max_strip_updates,
        },
    )
    .map_err(trim_mesh_error)?;
    let topo = solver.topology();
    if !topo.non_manifold_edges().is_empty() || !topo.inconsistent_edges().is_empty() {
        return Err(DartError::BadPiece {
            reason: "has non-manifold or inconsistently oriented edges (run `flatcut clean`)"
                .into(),
        });
    }
    if topo.boundary_loops().is_empty() {
        return Err(DartError::BadPiece {
            reason: "has no boundary (a closed surface)".into(),
        });
    }
    let bvh = Bvh::build(piece);

    // Names.
    let names: Vec<String> = darts
        .iter()
        .enumerate()
        .map(|(i, d)| {
            if d.name.is_empty() {
                format!("dart-{}", i + 1)
            } else {
                d.name.clone()
            }
        })
        .collect();
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, n) in names.iter().enumerate() {
        if let Some(&first) = seen.get(n.as_str()) {
            return Err(DartError::DuplicateName {
                name: n.clone(),
                first,
                second: i,
            });
        }
        seen.insert(n, i);
    }

    let mut resolved = Vec::with_capacity(darts.len());
    for (i, spec) in darts.iter().enumerate() {
        resolved.push(resolve(
            piece, topo, &solver, &bvh, i, &names[i], spec, opts,
        )?);
    }
    open(piece, &resolved)
}

/// Start, tip and geodesic of one dart.
#[allow(clippy::too_many_arguments)]
fn resolve(
    piece: &TriMesh,
    topo: &Topology,
    solver: &GeodesicSolver,
    bvh: &Bvh,
    index: usize,
    name: &str,
    spec: &DartSpec,
    opts: &DartOptions,
) -> Result<Resolved, DartError> {
    let bad = |reason: &str| DartError::BadSpec {
        index,
        name: name.to_string(),
        reason: reason.to_string(),
    };
    if !finite(spec.from) {
        return Err(bad("its start has a non-finite coordinate"));
    }
    let (d_start, start) = closest_on_boundary(piece, topo, spec.from)
        .ok_or_else(|| bad("the piece has no boundary edge"))?;
    if d_start > opts.boundary_tolerance_mm {
        return Err(DartError::StartOffBoundary {
            index,
            name: name.to_string(),
            distance_mm: d_start,
            tolerance_mm: opts.boundary_tolerance_mm,
        });
    }
    let tip = match (spec.tip, spec.direction, spec.length_mm) {
        (Some(t), None, None) => {
            if !finite(t) {
                return Err(bad("its tip has a non-finite coordinate"));
            }
            let sp_opts = SurfacePointOptions {
                tolerance_mm: opts.tip_tolerance_mm,
            };
            surface_point(bvh, t, name, &sp_opts).map_err(|e| match e {
                TrimError::OffSurface {
                    distance_mm,
                    tolerance_mm,
                    ..
                } => DartError::TipOffPiece {
                    index,
                    name: name.to_string(),
                    distance_mm,
                    tolerance_mm,
                },
                other => bad(&other.to_string()),
            })?
        }
        (None, Some(dir), Some(len)) => {
            if !finite(dir) || vec3::norm(dir) == 0.0 {
                return Err(bad("its direction must be a finite, non-zero vector"));
            }
            if !(len.is_finite() && len > 0.0) {
                return Err(bad("its length must be a positive number of mm"));
            }
            match trace(piece, topo, start, dir, len) {
                Traced::Tip(t) => t,
                Traced::LeftPiece(reach) => {
                    return Err(DartError::TooLong {
                        index,
                        name: name.to_string(),
                        length_mm: len,
                        reach_mm: reach,
                    });
                }
                Traced::Outward => {
                    return Err(DartError::DirectionOutward {
                        index,
                        name: name.to_string(),
                        direction: dir,
                    });
                }
            }
        }
        _ => {
            return Err(bad(
                "give either `tip`, or `direction` and `length_mm` (not both, not neither)",
            ));
        }
    };
    let tip_mm = tip.position(piece);
    let d_tip = closest_on_boundary(piece, topo, tip_mm).map_or(f64::INFINITY, |b| b.0);
    if d_tip <= opts.boundary_tolerance_mm {
        return Err(DartError::TipOnBoundary {
            index,
            name: name.to_string(),
            distance_mm: d_tip,
            tolerance_mm: opts.boundary_tolerance_mm,
        });
    }
    let g = solver.path(start, tip).ok_or(DartError::NoPath {
        index,
        name: name.to_string(),
    })?;
    Ok(Resolved {
        name: name.to_string(),
        line: CutLine {
            name: name.to_string(),
            closed: false,
            points: g.points,
            length: g.length,
        },
    })
}

fn trim_mesh_error(e: TrimError) -> DartError {
    match e {
        TrimError::Mesh(m) => DartError::Mesh(m),
        TrimError::EmptyMesh => DartError::BadPiece {
            reason: "has no faces".into(),
        },
        other => DartError::Embedding(other),
    }
}

/// Embeds the darts, checks them against the boundary and each other, and opens the piece.
fn open(piece: &TriMesh, darts: &[Resolved]) -> Result<Darted, DartError> {
    let lines: Vec<CutLine> = darts.iter().map(|d| d.line.clone()).collect();
    let index_of = |n: &str| darts.iter().position(|d| d.name == n).unwrap_or(0);
    let emb = embed(piece, &lines).map_err(|e| match e {
        TrimError::OverlappingLines { a, b, point_mm } => DartError::Crossing {
            a: index_of(&a),
            a_name: a,
            b: index_of(&b),
            b_name: b,
            point_mm,
        },
        other => DartError::Embedding(other),
    })?;
    let mesh = &emb.mesh;
    let topo = Topology::build(mesh)?;

    // No dart touches the boundary between its ends, no two darts share a vertex.
    let mut owner: HashMap<u32, usize> = HashMap::new();
    for (i, chain) in emb.line_vertices.iter().enumerate() {
        for (k, &v) in chain.iter().enumerate() {
            if let Some(&j) = owner.get(&v)
                && j != i
            {
                return Err(DartError::Crossing {
                    a: j,
                    a_name: darts[j].name.clone(),
                    b: i,
                    b_name: darts[i].name.clone(),
                    point_mm: mesh.positions[v as usize],
                });
            }
            owner.insert(v, i);
            if k > 0 && topo.is_boundary_vertex(VertexId(v)) {
                return Err(DartError::TouchesBoundary {
                    index: i,
                    name: darts[i].name.clone(),
                    point_mm: mesh.positions[v as usize],
                });
            }
        }
        if chain.len() < 2 {
            return Err(DartError::BadSpec {
                index: i,
                name: darts[i].name.clone(),
                reason: "its start and tip are the same point".into(),
            });
        }
    }

    // Wedges: corners joined across every edge that is not a dart edge.
    let mut cut = std::collections::HashSet::new();
    for chain in &emb.line_vertices {
        for w in chain.windows(2) {
            cut.insert((w[0].min(w[1]), w[0].max(w[1])));
        }
    }
    let nf = mesh.faces.len();
    let wedges = split_along(nf, &topo, |a, b| cut.contains(&(a.min(b), a.max(b))));
    // The first wedge of a vertex (lowest corner) keeps its index; others are appended.
    let mut positions = mesh.positions.clone();
    let mut vertex_source = emb.vertex_source.clone();
    let mut split_from: Vec<u32> = (0..positions.len() as u32).collect();
    let mut vertex_of_root: HashMap<u32, u32> = HashMap::new();
    let mut has_first = vec![false; positions.len()];
    let mut corner_vertex = vec![0u32; 3 * nf];
    for c in 0..3 * nf as u32 {
        let v = mesh.faces[(c / 3) as usize][(c % 3) as usize];
        let r = wedges.corner_vertex[c as usize];
        let nv = *vertex_of_root.entry(r).or_insert_with(|| {
            if has_first[v as usize] {
                positions.push(mesh.positions[v as usize]);
                vertex_source.push(emb.vertex_source[v as usize]);
                split_from.push(v);
                (positions.len() - 1) as u32
            } else {
                has_first[v as usize] = true;
                v
            }
        });
        corner_vertex[c as usize] = nv;
    }
    let faces: Vec<[u32; 3]> = (0..nf)
        .map(|f| {
            [
                corner_vertex[3 * f],
                corner_vertex[3 * f + 1],
                corner_vertex[3 * f + 2],
            ]
        })
        .collect();

    // Legs, from the tip: the left face of tip-ward edge u → v holds halfedge u → v.
    let mut legs = Vec::with_capacity(darts.len());
    for (i, chain) in emb.line_vertices.iter().enumerate() {
        let from_tip: Vec<u32> = chain.iter().rev().copied().collect();
        let mut leg_a = Vec::with_capacity(from_tip.len());
        let mut leg_b = Vec::with_capacity(from_tip.len());
        for (k, w) in from_tip.windows(2).enumerate() {
            let (u, v) = (w[0], w[1]);
            let mut left = None;
            let mut right = None;
            for &h in topo.outgoing(VertexId(u)) {
                if topo.to_vertex(h).0 == v {
                    left = Some(h);
                }
            }
            for &h in topo.outgoing(VertexId(v)) {
                if topo.to_vertex(h).0 == u {
                    right = Some(h);
                }
            }
            let (Some(hl), Some(hr)) = (left, right) else {
                return Err(DartError::TouchesBoundary {
                    index: i,
                    name: darts[i].name.clone(),
                    point_mm: mesh.positions[u as usize],
                });
            };
            if k == 0 {
                leg_a.push(corner_vertex[hl as usize]);
                leg_b.push(corner_vertex[Topology::next(hr) as usize]);
            }
            leg_a.push(corner_vertex[Topology::next(hl) as usize]);
            leg_b.push(corner_vertex[hr as usize]);
        }
        let tip = leg_a[0];
        let start_v = chain[0];
        legs.push(DartLegs {
            name: darts[i].name.clone(),
            tip,
            leg_a,
            leg_b,
            length_mm: chain
                .windows(2)
                .map(|w| vec3::dist(mesh.positions[w[0] as usize], mesh.positions[w[1] as usize]))
                .sum(),
            start: emb.vertex_source[start_v as usize],
            tip_point: emb.vertex_source[tip as usize],
            start_mm: mesh.positions[start_v as usize],
            tip_mm: mesh.positions[tip as usize],
        });
    }

    let face_labels = piece.face_labels.as_ref().map(|l| FaceLabels {
        names: l.names.clone(),
        labels: emb
            .face_source
            .iter()
            .map(|&f| l.labels.get(f as usize).copied().unwrap_or(0))
            .collect(),
    });
    Ok(Darted {
        mesh: TriMesh {
            positions,
            faces,
            face_labels,
            ..Default::default()
        },
        vertex_source,
        face_source: emb.face_source,
        split_from,
        darts: legs,
    })
}
