//! Constrained Delaunay triangulation of the domain with refinement (spade): minimum angle,
//! maximum area; vertices inserted on constraint edges are mapped back onto the 3D segment
//! they split.

use std::collections::{HashMap, HashSet};

use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, HasPosition, Point2, RefinementParameters,
    Triangulation,
};

use super::geom::{bbox2, dist2, lerp3, point_in_polygon, signed_area};
use super::sampling::{EdgeOnInput, Node};
use super::{VertexOrigin, WireCurve, WireframeError};

/// The tag of a vertex spade inserted during refinement (not one of ours).
const NEW_VERTEX: u32 = u32::MAX;

/// The tag of a bounding-box vertex (keeps the convex hull away from the loop, so that the
/// refinement's circumcentres never fall outside the hull and get skipped).
const BOX_VERTEX: u32 = u32::MAX - 1;

/// Padding of the bounding box around the domain, relative to the domain's extent: enough
/// to keep hull effects off the loop, small enough that refining the outside (needed when
/// guides make spade's own inside/outside test unusable) stays cheap.
const BOX_PAD_RELATIVE: f64 = 0.25;

/// The spade vertex: domain position and our tag.
#[derive(Clone, Copy, Debug)]
struct DomVertex {
    p: Point2<f64>,
    tag: u32,
}

impl HasPosition for DomVertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.p
    }
}

impl From<Point2<f64>> for DomVertex {
    fn from(p: Point2<f64>) -> Self {
        Self { p, tag: NEW_VERTEX }
    }
}

/// A triangulated domain with every vertex's origin and fixed 3D point (boundary and guide
/// vertices) or `None` (interior).
#[derive(Clone, Debug)]
pub(super) struct Meshed {
    pub(super) faces: Vec<[u32; 3]>,
    pub(super) domain: Vec<[f64; 2]>,
    pub(super) origins: Vec<VertexOrigin>,
    pub(super) fixed3: Vec<Option<[f64; 3]>>,
    /// The node each vertex is (None: inserted by the refinement).
    pub(super) node_of: Vec<Option<usize>>,
}

/// Constrained Delaunay triangulation with refinement of the domain spanned by `nodes`
/// (the first `n_boundary` are the boundary loop, counter-clockwise) and the constraint
/// `edges`; keeps the faces inside the loop and places vertices inserted on constraint edges
/// on the 3D segment between the edge's nodes.
#[allow(clippy::too_many_arguments)]
pub(super) fn triangulate(
    nodes: &[Node],
    n_boundary: usize,
    edges: &[[usize; 2]],
    edge_info: &[EdgeOnInput],
    tri_area: f64,
    min_angle_deg: f64,
    max_vertices: usize,
    guides: &[WireCurve],
) -> Result<Meshed, WireframeError> {
    let boundary_poly: Vec<[f64; 2]> = nodes[..n_boundary].iter().map(|n| n.p2).collect();
    // Constrained Delaunay triangulation inside a padding box.
    let mut verts: Vec<DomVertex> = nodes
        .iter()
        .enumerate()
        .map(|(i, n)| DomVertex {
            p: Point2::new(n.p2[0], n.p2[1]),
            tag: i as u32,
        })
        .collect();
    let (lo, hi) = bbox2(&boundary_poly);
    let pad = BOX_PAD_RELATIVE * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    for (x, y) in [
        (lo[0] - pad, lo[1] - pad),
        (hi[0] + pad, lo[1] - pad),
        (hi[0] + pad, hi[1] + pad),
        (lo[0] - pad, hi[1] + pad),
    ] {
        verts.push(DomVertex {
            p: Point2::new(x, y),
            tag: BOX_VERTEX,
        });
    }
    let n_in = verts.len();
    let mut conflicts = Vec::new();
    let mut cdt: ConstrainedDelaunayTriangulation<DomVertex> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(verts, edges.to_vec(), |e| {
            conflicts.push(e)
        })
        .map_err(|e| WireframeError::Triangulation(format!("{e:?}")))?;
    if cdt.num_vertices() != n_in {
        // A guide sample on top of another sample: the guides cross (or touch the boundary).
        let have: HashSet<u32> = cdt.vertices().map(|v| v.data().tag).collect();
        let lost = (0..nodes.len()).find(|&i| !have.contains(&(i as u32)));
        if let Some(VertexOrigin::GuidePoint { guide, .. } | VertexOrigin::OnGuide { guide, .. }) =
            lost.map(|i| nodes[i].origin)
        {
            return Err(WireframeError::GuideCrosses {
                guide: guides[guide].name.clone(),
            });
        }
        return Err(WireframeError::CoincidentDomainPoints {
            count: n_in - cdt.num_vertices(),
        });
    }
    if let Some(e) = conflicts.first() {
        // One of the two conflicting edges; boundary edges cannot conflict with each other
        // (the loop is simple), so a guide is involved: name this one's, or the first guide.
        let guide = edges
            .iter()
            .position(|x| x == e || *x == [e[1], e[0]])
            .filter(|&i| !edge_info[i].curve)
            .map_or(0, |i| edge_info[i].index);
        return Err(WireframeError::GuideCrosses {
            guide: guides
                .get(guide)
                .map_or_else(String::new, |g| g.name.clone()),
        });
    }
    let edge_lookup: HashMap<(usize, usize), usize> = edges
        .iter()
        .enumerate()
        .map(|(i, e)| ((e[0], e[1]), i))
        .collect();
    // spade tells inside from outside by the parity of constraint crossings, which guides
    // reaching the boundary break (a region beyond a guide counts as outside). With guides the
    // whole box is refined and the inside is found below from the boundary polygon alone.
    let exclude_outside = guides.is_empty();
    let box_area = (hi[0] - lo[0] + 2.0 * pad) * (hi[1] - lo[1] + 2.0 * pad);
    let refined_area = if exclude_outside {
        signed_area(&boundary_poly).abs()
    } else {
        box_area
    };
    let budget =
        (4 * (nodes.len() + (refined_area / tri_area).ceil() as usize) + 1000).min(max_vertices);
    let result = cdt.refine(
        RefinementParameters::<f64>::new()
            .exclude_outer_faces(exclude_outside)
            .with_angle_limit(AngleLimit::from_deg(min_angle_deg))
            .with_max_allowed_area(tri_area)
            .with_max_additional_vertices(budget),
    );
    if !result.refinement_complete {
        return Err(WireframeError::RefinementIncomplete { budget });
    }
    let excluded: HashSet<_> = result.excluded_faces.iter().copied().collect();
    // A face is inside when its centroid is inside the boundary polygon (faces never straddle
    // a constraint edge, so the centroid decides for the whole face).
    let inside = |f: &spade::handles::FaceHandle<
        '_,
        spade::handles::InnerTag,
        DomVertex,
        (),
        spade::CdtEdge<()>,
        (),
    >| {
        let [a, b, c] = f.positions();
        point_in_polygon(
            [(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0],
            &boundary_poly,
        )
    };

    // Extract the inside faces, number their vertices, and place every vertex in 3D.
    let mut index: HashMap<FixedVertexHandle, u32> = HashMap::new();
    let mut handles: Vec<FixedVertexHandle> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    for f in cdt.inner_faces() {
        if excluded.contains(&f.fix()) || !inside(&f) {
            continue;
        }
        let vs = f.vertices();
        let mut tri = [0u32; 3];
        for (k, v) in vs.iter().enumerate() {
            let next = handles.len() as u32;
            tri[k] = *index.entry(v.fix()).or_insert_with(|| {
                handles.push(v.fix());
                next
            });
        }
        faces.push(tri);
    }
    if faces.is_empty() {
        return Err(WireframeError::Solve("no triangle inside the loop"));
    }
    let nv = handles.len();
    let mut domain: Vec<[f64; 2]> = Vec::with_capacity(nv);
    let mut origins = Vec::with_capacity(nv);
    let mut fixed3: Vec<Option<[f64; 3]>> = Vec::with_capacity(nv);
    for &hdl in &handles {
        let v = cdt.vertex(hdl);
        let p = v.position();
        domain.push([p.x, p.y]);
        let tag = v.data().tag;
        if (tag as usize) < nodes.len() {
            let n = &nodes[tag as usize];
            origins.push(n.origin);
            fixed3.push(Some(n.p3));
        } else if tag == NEW_VERTEX {
            let on_edge = split_of(&cdt, hdl).and_then(|(a, b)| {
                let (i, flip) = match edge_lookup.get(&(a, b)) {
                    Some(&i) => (i, false),
                    None => (*edge_lookup.get(&(b, a))?, true),
                };
                Some((a, b, edge_info[i], flip))
            });
            match on_edge {
                Some((a, b, info, flip)) => {
                    let (na, nb) = (&nodes[a], &nodes[b]);
                    // Parameter along a → b from the domain positions (the domain map is
                    // linear along every constraint edge), then the 3D point on the segment.
                    let t = (dist2(na.p2, [p.x, p.y]) / dist2(na.p2, nb.p2)).clamp(0.0, 1.0);
                    let p3 = lerp3(na.p3, nb.p3, t);
                    let [ta, tb] = if flip { [info.t[1], info.t[0]] } else { info.t };
                    origins.push(info.origin(ta + t * (tb - ta)));
                    fixed3.push(Some(p3));
                }
                None => {
                    origins.push(VertexOrigin::Interior);
                    fixed3.push(None);
                }
            }
        } else {
            // A box vertex cannot be in an inside face (the box is outside the loop).
            return Err(WireframeError::Solve("box vertex inside the domain"));
        }
    }

    let node_of = handles
        .iter()
        .map(|&hdl| {
            let tag = cdt.vertex(hdl).data().tag as usize;
            (tag < nodes.len()).then_some(tag)
        })
        .collect();
    Ok(Meshed {
        faces,
        domain,
        origins,
        fixed3,
        node_of,
    })
}

/// For a vertex spade inserted on a constraint edge: the two of our nodes at the ends of
/// the original constraint edge it lies on (walking along constraint edges through other
/// inserted vertices). `None` for an interior vertex.
fn split_of(
    cdt: &ConstrainedDelaunayTriangulation<DomVertex>,
    v: FixedVertexHandle,
) -> Option<(usize, usize)> {
    let constraint_nbrs: Vec<FixedVertexHandle> = cdt
        .vertex(v)
        .out_edges()
        .filter(|e| e.is_constraint_edge())
        .map(|e| e.to().fix())
        .collect();
    if constraint_nbrs.len() != 2 {
        return None;
    }
    let walk = |mut prev: FixedVertexHandle, mut cur: FixedVertexHandle| -> Option<usize> {
        // A chain never revisits a vertex; the bound only guards against a malformed one.
        for _ in 0..cdt.num_vertices() {
            let tag = cdt.vertex(cur).data().tag;
            if tag != NEW_VERTEX {
                return (tag < BOX_VERTEX).then_some(tag as usize);
            }
            let next = cdt
                .vertex(cur)
                .out_edges()
                .filter(|e| e.is_constraint_edge())
                .map(|e| e.to().fix())
                .find(|&w| w != prev)?;
            prev = cur;
            cur = next;
        }
        None
    };
    let a = walk(v, constraint_nbrs[0])?;
    let b = walk(v, constraint_nbrs[1])?;
    Some((a, b))
}
