//! Building the pattern pieces: the 2D frame (grain along +y, material shrink), the sew and cut
//! lines, the seams of the ledger with their notches and darts, the grain line and the label.

use std::collections::{BTreeMap, HashMap};

use flatcut_mesh::{SeamKind, SeamLedger, Topology, TriMesh};
use serde::{Deserialize, Serialize};

use crate::PatternError;
use crate::geom::{
    add, bbox, dist, point_at_arc, point_in_polygon, polyline_length, right_normal, scale,
    segment_intersection, signed_area, sub, unit,
};
use crate::grain::grain_direction_2d;
use crate::seam_allowance::{CornerRule, CornerSpec, seam_allowance};

/// Largest material shrink or stretch accepted (as a fraction): beyond ±50 % the "piece" is
/// another piece, and a typo (−5 for −5 %) is caught.
pub const MAX_SHRINK: f64 = 0.5;
/// Most copies of one piece laid out: more is a typo, and every copy is drawn on the sheet.
pub const MAX_QUANTITY: u32 = 1000;
/// A notch is cut at most this fraction of the local allowance deep, so it never reaches the
/// sew line.
pub const NOTCH_MAX_FRACTION: f64 = 0.6;

/// Width of a label character as a fraction of the text height (sans-serif average), used
/// to keep the grain line clear of the label.
const LABEL_CHAR_WIDTH: f64 = 0.6;

/// What the cutting room needs to know about one piece besides its shape.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PieceMeta {
    /// Size label, e.g. `"38"` (default empty).
    pub size: String,
    /// Pieces to cut (default 1; with `mirror`, an even number: half as drawn, half mirrored).
    pub quantity: u32,
    /// Cut as left/right pairs (default false).
    pub mirror: bool,
    /// Fabric or material name (default empty).
    pub fabric: String,
    /// The 3D direction (no unit) that the grain follows; `None` (default) keeps the 2D +y.
    pub grain_3d: Option<[f64; 3]>,
    /// Material shrink along the grain, as a fraction applied before the allowance (default 0;
    /// −0.05 makes the piece 5 % shorter along the grain, as negative ease for neoprene).
    pub shrink_along_grain: f64,
    /// Material shrink across the grain, as a fraction (default 0).
    pub shrink_across_grain: f64,
}

impl Default for PieceMeta {
    fn default() -> Self {
        Self {
            size: String::new(),
            quantity: 1,
            mirror: false,
            fabric: String::new(),
            grain_3d: None,
            shrink_along_grain: 0.0,
            shrink_across_grain: 0.0,
        }
    }
}

/// One flattened piece as it comes to the pattern stage.
#[derive(Clone, Debug, PartialEq)]
pub struct PieceInput {
    /// Piece name (the ledger's name for it).
    pub name: String,
    /// The 3D piece (mm).
    pub mesh: TriMesh,
    /// Its 2D coordinates, one per vertex (mm).
    pub uv: Vec<[f64; 2]>,
    /// Size, quantity, grain, shrink...
    pub meta: PieceMeta,
    /// Internal lines (feature curves) as piece-local vertex chains.
    pub internal_lines: Vec<Vec<u32>>,
    /// Per-face area distortion E_h (empty when unknown).
    pub e_h: Vec<f64>,
    /// Per-face shape distortion E_r (empty when unknown).
    pub e_r: Vec<f64>,
    /// Per-face edge strain (empty when unknown).
    pub edge_strain: Vec<f64>,
}

/// Options of [`build_pieces`]; the pipeline's `[pattern]` table.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PatternOptions {
    /// Seam allowance of every edge without an override, mm (default 10).
    pub seam_allowance_mm: f64,
    /// Allowance per seam id, mm (default none), e.g. `{"hem/0" = 30}`.
    pub seam_overrides: BTreeMap<String, f64>,
    /// Rule at corners (default mitre, limit 2).
    pub corner: CornerRule,
    /// Rule where a dart leg meets the outline (default mirrored about the leg).
    pub dart_corner: CornerRule,
    /// Allowance of edges on no seam of the ledger (hems, facings), mm (default `None`: the
    /// seam allowance).
    pub free_edge_allowance_mm: Option<f64>,
    /// Rule where a seam meets a free edge (default `None`: the `corner` rule); `mirrored`
    /// folds about the free edge, as a hem turned up needs.
    pub hem_corner: Option<CornerRule>,
    /// A convex vertex turning by at least this much is a corner (default 0.35 rad ≈ 20°);
    /// gentler vertices are joined round, the exact parallel curve of a smooth outline.
    pub corner_angle_rad: f64,
    /// Largest spacing of notches along a seam, mm (default 100): a seam longer than this gets
    /// notches at evenly spaced matching arc lengths between its end notches.
    pub notch_spacing_mm: f64,
    /// Notch depth, mm (default 6), at most [`NOTCH_MAX_FRACTION`] of the local allowance.
    pub notch_depth_mm: f64,
    /// Height of label text, mm (default 8).
    pub label_height_mm: f64,
}

impl Default for PatternOptions {
    fn default() -> Self {
        Self {
            seam_allowance_mm: 10.0,
            seam_overrides: BTreeMap::new(),
            corner: CornerRule::default(),
            dart_corner: CornerRule::Mirrored,
            free_edge_allowance_mm: None,
            hem_corner: None,
            corner_angle_rad: 0.35,
            notch_spacing_mm: 100.0,
            notch_depth_mm: 6.0,
            label_height_mm: 8.0,
        }
    }
}

/// One side of a seam as it lies on a piece.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PieceSeam {
    /// Seam id from the ledger.
    pub id: String,
    /// Seam or dart.
    pub kind: SeamKind,
    /// `"a"` or `"b"`.
    pub side: &'static str,
    /// The 2D chain from the seam's start to its end (mm).
    pub points: Vec<[f64; 2]>,
    /// Its 2D length (mm).
    pub length_2d_mm: f64,
    /// The mate's 2D length (mm); a difference is ease the sewer must work in.
    pub mate_length_2d_mm: f64,
    /// The seam's allowance (mm).
    pub allowance_mm: f64,
}

/// A notch: a short slit cut in from the cut line towards a point of the sew line.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Notch {
    /// Seam id.
    pub seam: String,
    /// Arc length from the seam's start along this side's 2D chain (mm).
    pub arc_mm: f64,
    /// The point on the sew line (mm).
    pub at: [f64; 2],
    /// Outward unit normal of the seam there.
    pub outward: [f64; 2],
    /// Where the notch meets the cut line (mm).
    pub cut: [f64; 2],
    /// The notch's inner end (mm).
    pub inner: [f64; 2],
}

/// A dart: its two legs (from the tip) and the tip.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Dart {
    /// Seam id.
    pub seam: String,
    /// Tip (mm).
    pub tip: [f64; 2],
    /// Legs from the tip (mm).
    pub legs: [Vec<[f64; 2]>; 2],
}

/// The label: lines of text and where they start.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Label {
    /// Lower-left of the first line (mm).
    pub at: [f64; 2],
    /// Text height (mm).
    pub height_mm: f64,
    /// Lines: name, size, quantity ("cut 2, mirrored"), fabric (empty ones left out).
    pub lines: Vec<String>,
}

/// What material shrink did to the piece.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ShrinkReport {
    /// Fraction along the grain.
    pub along_grain: f64,
    /// Fraction across the grain.
    pub across_grain: f64,
    /// Area inside the sew line before (mm²).
    pub area_before_mm2: f64,
    /// ... and after (mm²).
    pub area_after_mm2: f64,
}

/// A finished pattern piece. All coordinates are mm in the piece's frame: grain along +y.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PatternPiece {
    /// Name.
    pub name: String,
    /// Size, quantity, fabric...
    pub meta: PieceMeta,
    /// The 3D piece (mm).
    #[serde(skip)]
    pub mesh: TriMesh,
    /// 2D coordinates of the mesh vertices after grain rotation and shrink (mm).
    #[serde(skip)]
    pub uv: Vec<[f64; 2]>,
    /// Rotation applied to the given 2D coordinates to bring the grain to +y (rad).
    pub rotation_rad: f64,
    /// The sew line, counter-clockwise (the outer boundary loop).
    pub sew_line: Vec<[f64; 2]>,
    /// Mesh vertex of each sew-line point.
    pub sew_vertices: Vec<u32>,
    /// Allowance of each sew-line edge `i → i+1` (mm).
    pub edge_allowance_mm: Vec<f64>,
    /// For each sew-line edge `i → i+1`, the index in [`PatternPiece::seams`] of the seam it
    /// belongs to (`None`: a free edge, e.g. a hem or neckline).
    pub edge_seam: Vec<Option<usize>>,
    /// The cut line, counter-clockwise.
    pub cut_line: Vec<[f64; 2]>,
    /// Inner boundary loops (holes), drawn as internal lines without allowance.
    pub holes: Vec<Vec<[f64; 2]>>,
    /// Seams of the ledger on this piece.
    pub seams: Vec<PieceSeam>,
    /// Notches.
    pub notches: Vec<Notch>,
    /// Darts.
    pub darts: Vec<Dart>,
    /// Grain line, from tail to arrow head (+y).
    pub grain_line: [[f64; 2]; 2],
    /// Label.
    pub label: Label,
    /// Internal lines.
    pub internal_lines: Vec<Vec<[f64; 2]>>,
    /// Material shrink applied.
    pub shrink: ShrinkReport,
    /// Per-face E_h (empty when unknown).
    #[serde(skip)]
    pub e_h: Vec<f64>,
    /// Per-face E_r (empty when unknown).
    #[serde(skip)]
    pub e_r: Vec<f64>,
    /// Per-face edge strain (empty when unknown).
    #[serde(skip)]
    pub edge_strain: Vec<f64>,
}

struct Prepared {
    uv: Vec<[f64; 2]>,
    rotation: f64,
    sew: Vec<[f64; 2]>,
    sew_vertices: Vec<u32>,
    pos: HashMap<u32, usize>,
    holes: Vec<Vec<[f64; 2]>>,
    shrink: ShrinkReport,
}

/// A seam side mapped onto its piece's sew line.
struct SideOnPiece {
    seam: usize,
    side: &'static str,
    /// Sew-line indices of the chain.
    idx: Vec<usize>,
    /// Edge `idx[k] → idx[k+1]` runs along the loop (true) or against it.
    forward: bool,
    points: Vec<[f64; 2]>,
}

fn check_width(what: String, value: f64) -> Result<(), PatternError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(PatternError::BadOption {
            what,
            value,
            hint: "use a finite width ≥ 0 mm",
        })
    }
}

fn check_options(opts: &PatternOptions) -> Result<(), PatternError> {
    check_width("seam_allowance_mm".into(), opts.seam_allowance_mm)?;
    if let Some(w) = opts.free_edge_allowance_mm {
        check_width("free_edge_allowance_mm".into(), w)?;
    }
    for (id, w) in &opts.seam_overrides {
        check_width(format!("seam_overrides[{id:?}]"), *w)?;
    }
    let hem = opts.hem_corner.unwrap_or_default();
    for (name, rule) in [
        ("corner", opts.corner),
        ("dart_corner", opts.dart_corner),
        ("hem_corner", hem),
    ] {
        if let CornerRule::Miter { limit } = rule {
            if !(limit.is_finite() && limit >= 1.0) {
                return Err(PatternError::BadOption {
                    what: format!("{name}.miter.limit"),
                    value: limit,
                    hint: "use a mitre limit ≥ 1 (allowance widths)",
                });
            }
        }
    }
    let positive = [
        ("corner_angle_rad", opts.corner_angle_rad),
        ("notch_spacing_mm", opts.notch_spacing_mm),
        ("notch_depth_mm", opts.notch_depth_mm),
        ("label_height_mm", opts.label_height_mm),
    ];
    for (what, value) in positive {
        if !(value.is_finite() && value > 0.0) {
            return Err(PatternError::BadOption {
                what: what.into(),
                value,
                hint: "use a finite number > 0",
            });
        }
    }
    Ok(())
}

/// Builds every piece; with a ledger, the seams, notches (matching on both mates) and darts.
/// Every piece the ledger names must be among `inputs` (by name).
pub fn build_pieces(
    inputs: &[PieceInput],
    ledger: Option<&SeamLedger>,
    opts: &PatternOptions,
) -> Result<Vec<PatternPiece>, PatternError> {
    check_options(opts)?;
    let prepared: Vec<Prepared> = inputs.iter().map(prepare).collect::<Result<_, _>>()?;
    let by_name: HashMap<&str, usize> = inputs
        .iter()
        .enumerate()
        .map(|(i, p)| (p.name.as_str(), i))
        .collect();
    let mut sides: Vec<Vec<SideOnPiece>> = (0..inputs.len()).map(|_| Vec::new()).collect();
    let mut side_len: HashMap<(usize, &'static str), f64> = HashMap::new();
    if let Some(ledger) = ledger {
        ledger.check()?;
        for (s, seam) in ledger.seams.iter().enumerate() {
            for (side, chain) in [("a", &seam.a), ("b", &seam.b)] {
                let Some(&p) = by_name.get(chain.piece.as_str()) else {
                    return Err(PatternError::MissingPiece {
                        seam: seam.id.clone(),
                        piece: chain.piece.clone(),
                    });
                };
                let on = map_side(
                    &prepared[p],
                    s,
                    side,
                    &chain.vertices,
                    &seam.id,
                    &chain.piece,
                )?;
                side_len.insert((s, side), polyline_length(&on.points));
                sides[p].push(on);
            }
        }
    }
    let mut out = Vec::with_capacity(inputs.len());
    for (p, (input, prep)) in inputs.iter().zip(prepared).enumerate() {
        out.push(finish(input, prep, &sides[p], &side_len, ledger, opts)?);
    }
    Ok(out)
}

fn prepare(input: &PieceInput) -> Result<Prepared, PatternError> {
    let name = &input.name;
    let bad = |what: String| PatternError::BadPiece {
        piece: name.clone(),
        what,
    };
    let mesh = &input.mesh;
    if mesh.faces.is_empty() {
        return Err(bad("it has no faces; give a flattened piece".into()));
    }
    if input.uv.len() != mesh.positions.len() {
        return Err(bad(format!(
            "{} 2D coordinates for {} vertices; give one per vertex",
            input.uv.len(),
            mesh.positions.len()
        )));
    }
    for (v, (p, q)) in mesh.positions.iter().zip(&input.uv).enumerate() {
        if !(p.iter().all(|c| c.is_finite()) && q.iter().all(|c| c.is_finite())) {
            return Err(PatternError::NotFinite {
                piece: name.clone(),
                vertex: v as u32,
            });
        }
    }
    for (what, vals) in [
        ("E_h", &input.e_h),
        ("E_r", &input.e_r),
        ("edge strain", &input.edge_strain),
    ] {
        if !vals.is_empty() && vals.len() != mesh.faces.len() {
            return Err(bad(format!(
                "{} {what} values for {} faces; give one per face or none",
                vals.len(),
                mesh.faces.len()
            )));
        }
        if let Some(f) = vals.iter().position(|x| !x.is_finite()) {
            return Err(bad(format!("{what} of face {f} is not finite")));
        }
    }
    let meta = &input.meta;
    for (what, value) in [
        ("shrink_along_grain", meta.shrink_along_grain),
        ("shrink_across_grain", meta.shrink_across_grain),
    ] {
        if !(value.is_finite() && value.abs() < MAX_SHRINK) {
            return Err(PatternError::BadOption {
                what: format!("piece {name:?} {what}"),
                value,
                hint: "use a fraction between −0.5 and 0.5 (−0.05 for −5 %)",
            });
        }
    }
    if meta.quantity == 0 || meta.quantity > MAX_QUANTITY || (meta.mirror && meta.quantity % 2 != 0)
    {
        return Err(bad(format!(
            "quantity {} with mirror = {}: use 1 to {MAX_QUANTITY}, and an even number for mirrored pairs",
            meta.quantity, meta.mirror
        )));
    }
    // Grain to +y.
    let mut rotation = 0.0;
    if let Some(g) = meta.grain_3d {
        if !(g.iter().all(|c| c.is_finite()) && g.iter().any(|c| *c != 0.0)) {
            return Err(bad(
                "grain_3d must be three finite numbers, not all zero".into()
            ));
        }
        let d = grain_direction_2d(mesh, &input.uv, g).ok_or_else(|| {
            PatternError::GrainNormalToPiece {
                piece: name.clone(),
            }
        })?;
        rotation = std::f64::consts::FRAC_PI_2 - d[1].atan2(d[0]);
    }
    let (s, c) = rotation.sin_cos();
    let rotated: Vec<[f64; 2]> = input
        .uv
        .iter()
        .map(|q| [c * q[0] - s * q[1], s * q[0] + c * q[1]])
        .collect();
    let (fx, fy) = (
        1.0 + meta.shrink_across_grain,
        1.0 + meta.shrink_along_grain,
    );
    let b = bbox(&rotated);
    let uv: Vec<[f64; 2]> = rotated
        .iter()
        .map(|q| [(q[0] - b[0][0]) * fx, (q[1] - b[0][1]) * fy])
        .collect();
    let topo = Topology::build(mesh).map_err(|e| bad(format!("{e}")))?;
    let loops: Vec<Vec<u32>> = topo
        .boundary_loops()
        .iter()
        .map(|l| l.iter().map(|v| v.0).collect())
        .collect();
    if loops.is_empty() {
        return Err(bad(
            "it has no boundary (a closed surface); cut it open before making a pattern".into(),
        ));
    }
    if topo.component_count() > 1 {
        return Err(bad(format!(
            "it has {} separate parts; give each part as its own piece (one file each)",
            topo.component_count()
        )));
    }
    if !topo.open_boundary_chains().is_empty() {
        return Err(bad(
            "its boundary does not close into loops (non-manifold or inconsistently oriented edges); run flatcut clean".into(),
        ));
    }
    let pts = |l: &Vec<u32>| l.iter().map(|&v| uv[v as usize]).collect::<Vec<_>>();
    let outer = (0..loops.len())
        .max_by(|&a, &b| {
            signed_area(&pts(&loops[a]))
                .abs()
                .total_cmp(&signed_area(&pts(&loops[b])).abs())
        })
        .unwrap_or(0);
    let mut sew_vertices = loops[outer].clone();
    let area_after = signed_area(&pts(&sew_vertices));
    if area_after < 0.0 {
        sew_vertices.reverse();
    }
    let sew = pts(&sew_vertices);
    let holes: Vec<Vec<[f64; 2]>> = loops
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != outer)
        .map(|(_, l)| pts(l))
        .collect();
    let mut all_loops = vec![sew.clone()];
    all_loops.extend(holes.iter().cloned());
    check_self_intersection(name, &all_loops)?;
    let pos = sew_vertices
        .iter()
        .enumerate()
        .map(|(i, &v)| (v, i))
        .collect();
    let area_after = area_after.abs();
    Ok(Prepared {
        uv,
        rotation,
        sew,
        sew_vertices,
        pos,
        holes,
        shrink: ShrinkReport {
            along_grain: meta.shrink_along_grain,
            across_grain: meta.shrink_across_grain,
            area_before_mm2: area_after / (fx * fy),
            area_after_mm2: area_after,
        },
    })
}

/// Refuses an outline whose edges cross (sweep over x-sorted edges; edges sharing a vertex
/// are not compared).
fn check_self_intersection(piece: &str, loops: &[Vec<[f64; 2]>]) -> Result<(), PatternError> {
    struct Seg {
        a: [f64; 2],
        b: [f64; 2],
        lo: f64,
        hi: f64,
        lp: usize,
        i: usize,
        n: usize,
    }
    let mut segs: Vec<Seg> = Vec::new();
    for (lp, l) in loops.iter().enumerate() {
        let n = l.len();
        for i in 0..n {
            let (a, b) = (l[i], l[(i + 1) % n]);
            segs.push(Seg {
                a,
                b,
                lo: a[0].min(b[0]),
                hi: a[0].max(b[0]),
                lp,
                i,
                n,
            });
        }
    }
    segs.sort_by(|s, t| s.lo.total_cmp(&t.lo));
    for x in 0..segs.len() {
        let s = &segs[x];
        for t in &segs[x + 1..] {
            if t.lo > s.hi {
                break;
            }
            if s.lp == t.lp {
                let d = s.i.abs_diff(t.i);
                if d <= 1 || d == s.n - 1 {
                    continue;
                }
            }
            if let Some(u) = segment_intersection(s.a, s.b, t.a, t.b) {
                let p = add(s.a, scale(sub(s.b, s.a), u));
                let (edge_a, edge_b) = (s.i.min(t.i), s.i.max(t.i));
                return Err(PatternError::SelfIntersecting {
                    piece: piece.into(),
                    x: p[0],
                    y: p[1],
                    edge_a,
                    edge_b,
                });
            }
        }
    }
    Ok(())
}

fn map_side(
    prep: &Prepared,
    seam: usize,
    side: &'static str,
    chain: &[u32],
    id: &str,
    piece: &str,
) -> Result<SideOnPiece, PatternError> {
    let err = |what: String| PatternError::Seam {
        seam: id.into(),
        piece: piece.into(),
        what,
    };
    let n = prep.sew.len();
    let mut idx = Vec::with_capacity(chain.len());
    for &v in chain {
        let i = *prep.pos.get(&v).ok_or_else(|| {
            err(format!(
                "vertex {v} is not on the piece's outer boundary; the ledger does not match this piece"
            ))
        })?;
        idx.push(i);
    }
    let forward = idx.len() >= 2 && idx[1] == (idx[0] + 1) % n;
    for (k, w) in idx.windows(2).enumerate() {
        let ok = if forward {
            w[1] == (w[0] + 1) % n
        } else {
            w[0] == (w[1] + 1) % n
        };
        if !ok {
            return Err(err(format!(
                "vertices {} and {} (chain positions {k} and {}) are not joined by a boundary edge in the chain's direction",
                chain[k],
                chain[k + 1],
                k + 1
            )));
        }
    }
    let points: Vec<[f64; 2]> = idx.iter().map(|&i| prep.sew[i]).collect();
    Ok(SideOnPiece {
        seam,
        side,
        idx,
        forward,
        points,
    })
}

fn finish(
    input: &PieceInput,
    prep: Prepared,
    sides: &[SideOnPiece],
    side_len: &HashMap<(usize, &'static str), f64>,
    ledger: Option<&SeamLedger>,
    opts: &PatternOptions,
) -> Result<PatternPiece, PatternError> {
    let n = prep.sew.len();
    let mut widths = vec![
        opts.free_edge_allowance_mm
            .unwrap_or(opts.seam_allowance_mm);
        n
    ];
    let mut on_seam = vec![false; n];
    let default_corner = CornerSpec {
        rule: opts.corner,
        fold_next: true,
    };
    let mut corners = vec![default_corner; n];
    let seams_of = |s: usize| ledger.map(|l| &l.seams[s]);
    for side in sides {
        let Some(seam) = seams_of(side.seam) else {
            continue;
        };
        let w = *opts
            .seam_overrides
            .get(&seam.id)
            .unwrap_or(&opts.seam_allowance_mm);
        for k in 0..side.idx.len() - 1 {
            let e = if side.forward {
                side.idx[k]
            } else {
                side.idx[k + 1]
            };
            widths[e] = w;
            on_seam[e] = true;
        }
        if seam.kind == SeamKind::Dart {
            // The mouth vertex is the chain's last; its leg edge is the chain's last edge.
            let m = side.idx.len() - 1;
            let mouth = side.idx[m];
            // Leg edge enters the mouth along the loop when the chain runs forward.
            corners[mouth] = CornerSpec {
                rule: opts.dart_corner,
                fold_next: !side.forward,
            };
        }
    }
    if let Some(rule) = opts.hem_corner {
        // Where a seam meets a free edge (a hem), fold about the free edge.
        for i in 0..n {
            let (inc, out) = (on_seam[(i + n - 1) % n], on_seam[i]);
            if inc != out && corners[i] == default_corner {
                corners[i] = CornerSpec {
                    rule,
                    fold_next: !out,
                };
            }
        }
    }
    let b = bbox(&prep.sew);
    let half = 0.5 * (b[1][0] - b[0][0]).min(b[1][1] - b[0][1]);
    if let Some(&w) = widths.iter().find(|&&w| w > half) {
        return Err(PatternError::AllowanceTooLarge {
            piece: input.name.clone(),
            allowance_mm: w,
            half_mm: half,
        });
    }
    let cut =
        seam_allowance(&prep.sew, &widths, &corners, opts.corner_angle_rad).ok_or_else(|| {
            PatternError::OffsetFailed {
                piece: input.name.clone(),
            }
        })?;

    let mut seams = Vec::new();
    let mut edge_seam = vec![None; n];
    let mut notches = Vec::new();
    let mut darts = Vec::new();
    for side in sides {
        let Some(seam) = seams_of(side.seam) else {
            continue;
        };
        let own = side_len[&(side.seam, side.side)];
        let mate_side = if side.side == "a" { "b" } else { "a" };
        let mate = side_len[&(side.seam, mate_side)];
        let w = *opts
            .seam_overrides
            .get(&seam.id)
            .unwrap_or(&opts.seam_allowance_mm);
        for k in 0..side.idx.len() - 1 {
            let e = if side.forward {
                side.idx[k]
            } else {
                side.idx[k + 1]
            };
            edge_seam[e] = Some(seams.len());
        }
        seams.push(PieceSeam {
            id: seam.id.clone(),
            kind: seam.kind,
            side: side.side,
            points: side.points.clone(),
            length_2d_mm: own,
            mate_length_2d_mm: mate,
            allowance_mm: w,
        });
        // The same arc lengths on both mates: the ends, and even steps over the shorter one.
        let common = own.min(mate);
        let steps = (common / opts.notch_spacing_mm).ceil().max(1.0) as usize;
        let mut arcs: Vec<f64> = (0..steps)
            .map(|k| common * k as f64 / steps as f64)
            .collect();
        arcs.push(own);
        if seam.kind == SeamKind::Dart {
            // Darts are marked by their legs; the notches go at the mouth only.
            arcs = vec![own];
        }
        let depth = opts.notch_depth_mm.min(NOTCH_MAX_FRACTION * w);
        for arc in arcs {
            if let Some(nt) = notch_at(&seam.id, side, arc, &cut, depth) {
                notches.push(nt);
            }
        }
        if seam.kind == SeamKind::Dart && side.side == "a" {
            let other = sides
                .iter()
                .find(|o| o.seam == side.seam && o.side == "b")
                .map(|o| o.points.clone())
                .unwrap_or_default();
            darts.push(Dart {
                seam: seam.id.clone(),
                tip: side.points[0],
                legs: [side.points.clone(), other],
            });
        }
    }

    // Label and grain line around an inside point.
    let inside = inside_point(&prep.uv, &input.mesh.faces, &prep.sew);
    let meta = &input.meta;
    let mut lines = vec![input.name.clone()];
    if !meta.size.is_empty() {
        lines.push(format!("size {}", meta.size));
    }
    lines.push(if meta.mirror {
        format!("cut {}, mirrored", meta.quantity)
    } else {
        format!("cut {}", meta.quantity)
    });
    if !meta.fabric.is_empty() {
        lines.push(meta.fabric.clone());
    }
    // The label block is centred on the inside point; the grain line runs one text height to
    // its left when that is still inside the piece, else through the label.
    let h = opts.label_height_mm;
    let chars = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let text_w = LABEL_CHAR_WIDTH * h * chars as f64;
    let label = Label {
        at: [inside[0] - 0.5 * text_w, inside[1]],
        height_mm: h,
        lines,
    };
    let beside = [inside[0] - 0.5 * text_w - h, inside[1]];
    let grain_at = if point_in_polygon(beside, &prep.sew) {
        beside
    } else {
        inside
    };
    let grain_line = grain_line(&prep.sew, grain_at);
    let mut internal_lines = Vec::new();
    for (k, l) in input.internal_lines.iter().enumerate() {
        let mut pts = Vec::with_capacity(l.len());
        for &v in l {
            let q = prep
                .uv
                .get(v as usize)
                .ok_or_else(|| PatternError::BadPiece {
                    piece: input.name.clone(),
                    what: format!(
                        "internal line {k} names vertex {v}, but the piece has {} vertices",
                        prep.uv.len()
                    ),
                })?;
            pts.push(*q);
        }
        internal_lines.push(pts);
    }
    Ok(PatternPiece {
        name: input.name.clone(),
        meta: meta.clone(),
        mesh: input.mesh.clone(),
        uv: prep.uv,
        rotation_rad: prep.rotation,
        sew_line: prep.sew,
        sew_vertices: prep.sew_vertices,
        edge_allowance_mm: widths,
        edge_seam,
        cut_line: cut,
        holes: prep.holes,
        seams,
        notches,
        darts,
        grain_line,
        label,
        internal_lines,
        shrink: prep.shrink,
        e_h: input.e_h.clone(),
        e_r: input.e_r.clone(),
        edge_strain: input.edge_strain.clone(),
    })
}

/// The notch at arc length `arc` along a seam side: perpendicular to the seam there, from the
/// cut line in by `depth`.
fn notch_at(id: &str, side: &SideOnPiece, arc: f64, cut: &[[f64; 2]], depth: f64) -> Option<Notch> {
    let (at, seg) = point_at_arc(&side.points, arc);
    let t = unit(sub(side.points[seg + 1], side.points[seg]));
    let out = if side.forward {
        right_normal(t)
    } else {
        scale(right_normal(t), -1.0)
    };
    // First crossing of the outward ray with the cut line.
    let far = add(at, scale(out, 1e6));
    let mut best: Option<f64> = None;
    for i in 0..cut.len() {
        if let Some(u) = segment_intersection(at, far, cut[i], cut[(i + 1) % cut.len()]) {
            best = Some(best.map_or(u, |b: f64| b.min(u)));
        }
    }
    let c = add(at, scale(out, best? * 1e6));
    let reach = dist(c, at);
    let inner = add(at, scale(out, (reach - depth).max(0.0)));
    Some(Notch {
        seam: id.into(),
        arc_mm: arc,
        at,
        outward: out,
        cut: c,
        inner,
    })
}

/// A point well inside the piece: the area centroid when inside, else the centroid of the
/// largest triangle.
fn inside_point(uv: &[[f64; 2]], faces: &[[u32; 3]], sew: &[[f64; 2]]) -> [f64; 2] {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    let mut best = (0.0, [0.0, 0.0]);
    for f in faces {
        let [p, q, r] = f.map(|v| uv[v as usize]);
        let ar = 0.5 * crate::geom::cross(sub(q, p), sub(r, p)).abs();
        let c = [(p[0] + q[0] + r[0]) / 3.0, (p[1] + q[1] + r[1]) / 3.0];
        a += ar;
        cx += ar * c[0];
        cy += ar * c[1];
        if ar > best.0 {
            best = (ar, c);
        }
    }
    let c = if a > 0.0 { [cx / a, cy / a] } else { best.1 };
    if point_in_polygon(c, sew) { c } else { best.1 }
}

/// A vertical grain line through `p`: the middle 70 % of the piece's vertical chord there.
fn grain_line(sew: &[[f64; 2]], p: [f64; 2]) -> [[f64; 2]; 2] {
    let n = sew.len();
    let mut ys: Vec<f64> = Vec::new();
    for i in 0..n {
        let (a, b) = (sew[i], sew[(i + 1) % n]);
        if (a[0] > p[0]) != (b[0] > p[0]) {
            ys.push(a[1] + (p[0] - a[0]) / (b[0] - a[0]) * (b[1] - a[1]));
        }
    }
    ys.sort_by(f64::total_cmp);
    let lo = ys
        .iter()
        .rev()
        .find(|&&y| y <= p[1])
        .copied()
        .unwrap_or(p[1]);
    let hi = ys.iter().find(|&&y| y >= p[1]).copied().unwrap_or(p[1]);
    let len = hi - lo;
    [[p[0], lo + 0.15 * len], [p[0], hi - 0.15 * len]]
}
