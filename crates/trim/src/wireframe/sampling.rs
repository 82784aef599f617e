//! Samples of the boundary loop and of the guides at the target edge length: the nodes and
//! constraint edges of the domain triangulation, each edge remembering the input segment
//! it lies on.

use flatcut_mesh::vec3::dist;

use super::domain::Frame;
use super::geom::{lerp3, point_in_polygon};
use super::join::{LoopSeg, on_curve};
use super::{DomainKind, VertexOrigin, WireCurve, WireframeError};

/// A vertex of the domain triangulation that we placed (boundary or guide sample).
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    pub(super) p3: [f64; 3],
    pub(super) p2: [f64; 2],
    pub(super) origin: VertexOrigin,
}

/// The input segment a constraint edge lies on, and its ends' parameters there.
#[derive(Clone, Copy, Debug)]
pub(super) struct EdgeOnInput {
    /// true: boundary curve, false: guide.
    pub(super) curve: bool,
    /// Curve or guide index.
    pub(super) index: usize,
    /// The segment (from its point `segment` to `segment + 1`).
    pub(super) segment: usize,
    /// Parameters of the edge's two end nodes on that segment (in the order of `edges`).
    pub(super) t: [f64; 2],
}

impl EdgeOnInput {
    pub(super) fn origin(&self, t: f64) -> VertexOrigin {
        if self.curve {
            VertexOrigin::OnCurve {
                curve: self.index,
                segment: self.segment,
                t,
            }
        } else {
            VertexOrigin::OnGuide {
                guide: self.index,
                segment: self.segment,
                t,
            }
        }
    }
}

/// The boundary samples in loop order: every input point, plus points on each segment at
/// ≤ `h` spacing (and at the `breaks`, segment parameters where a guide ends), placed in the
/// domain (`frame` projection, or around a circle of the loop's length by arc length). Also
/// the input segment under each constraint edge from a sample to the next.
pub(super) fn sample_boundary(
    segs: &[LoopSeg],
    breaks: &[Vec<f64>],
    kind: DomainKind,
    frame: &Frame,
    h: f64,
    loop_length_mm: f64,
) -> (Vec<Node>, Vec<EdgeOnInput>) {
    let mut nodes: Vec<Node> = Vec::new();
    let mut edge_info: Vec<EdgeOnInput> = Vec::new();
    let mut s_acc = 0.0;
    let radius = loop_length_mm / std::f64::consts::TAU;
    for (si, s) in segs.iter().enumerate() {
        let len = dist(s.p0, s.p1);
        let mut cuts = vec![0.0];
        cuts.extend(breaks[si].iter().copied());
        cuts.push(1.0);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        // Parameters of the samples on this segment: every piece at ≤ h spacing.
        let mut ts = Vec::new();
        for w in cuts.windows(2) {
            let k = (((w[1] - w[0]) * len / h).ceil() as usize).max(1);
            ts.extend((0..k).map(|j| w[0] + (w[1] - w[0]) * j as f64 / k as f64));
        }
        ts.push(1.0);
        for j in 0..ts.len() - 1 {
            let t = ts[j];
            let p3 = if j == 0 { s.p0 } else { lerp3(s.p0, s.p1, t) };
            let origin = if j == 0 {
                VertexOrigin::CurvePoint {
                    curve: s.curve,
                    point: s.i0,
                }
            } else {
                on_curve(s, t)
            };
            let p2 = match kind {
                DomainKind::Plane => frame.project(p3),
                DomainKind::Circle => {
                    let a = (s_acc + t * len) / radius;
                    [radius * a.cos(), radius * a.sin()]
                }
            };
            nodes.push(Node { p3, p2, origin });
            // The constraint edge from this sample to the next lies on this segment.
            let local = |t: f64| if s.i1 > s.i0 { t } else { 1.0 - t };
            edge_info.push(EdgeOnInput {
                curve: true,
                index: s.curve,
                segment: s.i0.min(s.i1),
                t: [local(t), local(ts[j + 1])],
            });
        }
        s_acc += len;
    }
    (nodes, edge_info)
}

/// Adds a guide's samples and constraint edges (plane domain).
#[allow(clippy::too_many_arguments)]
pub(super) fn add_guide(
    gi: usize,
    g: &WireCurve,
    frame: &Frame,
    h: f64,
    tol: f64,
    boundary: &[[f64; 2]],
    nodes: &mut Vec<Node>,
    edges: &mut Vec<[usize; 2]>,
    edge_info: &mut Vec<EdgeOnInput>,
) -> Result<(), WireframeError> {
    let n_boundary = boundary.len();
    let pts = &g.points;
    let last = pts.len() - 1;
    // An end within the join tolerance of a boundary sample is that sample.
    let snap = |p: [f64; 3], nodes: &[Node]| -> Option<usize> {
        (0..n_boundary)
            .map(|i| (dist(nodes[i].p3, p), i))
            .filter(|&(d, _)| d <= tol)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, i)| i)
    };
    let mut prev: Option<usize> = None;
    for (i, &p) in pts.iter().enumerate() {
        let snapped = if i == 0 || i == last {
            snap(p, nodes)
        } else {
            None
        };
        let this = match snapped {
            Some(b) => b,
            None => {
                let p2 = frame.project(p);
                if !point_in_polygon(p2, boundary) {
                    return Err(WireframeError::GuideOutside {
                        guide: g.name.clone(),
                        point: i,
                    });
                }
                nodes.push(Node {
                    p3: p,
                    p2,
                    origin: VertexOrigin::GuidePoint {
                        guide: gi,
                        point: i,
                    },
                });
                nodes.len() - 1
            }
        };
        if let Some(a) = prev {
            // Samples on the guide segment (a → this) at ≤ h spacing.
            let (pa, pb) = (nodes[a].p3, nodes[this].p3);
            let k = ((dist(pa, pb) / h).ceil() as usize).max(1);
            let mut from = a;
            let info = |t0: f64, t1: f64| EdgeOnInput {
                curve: false,
                index: gi,
                segment: i - 1,
                t: [t0, t1],
            };
            for j in 1..k {
                let t = j as f64 / k as f64;
                let p3 = lerp3(pa, pb, t);
                nodes.push(Node {
                    p3,
                    p2: frame.project(p3),
                    origin: VertexOrigin::OnGuide {
                        guide: gi,
                        segment: i - 1,
                        t,
                    },
                });
                let id = nodes.len() - 1;
                edges.push([from, id]);
                edge_info.push(info((j - 1) as f64 / k as f64, t));
                from = id;
            }
            edges.push([from, this]);
            edge_info.push(info((k - 1) as f64 / k as f64, 1.0));
        }
        prev = Some(this);
    }
    Ok(())
}
