//! Building the seam ledger: every stretch of a cutting line, seen from its two sides.
//!
//! Each cut edge `u → v` (in the line's direction) has a face on its left (halfedge `u → v`)
//! and one on its right (`v → u`); the left side's piece is side `a`, the right side's `b`,
//! and both chains list the piece-local copies of the same line vertices in the line's
//! order, so `a.vertices[k]` and `b.vertices[k]` are one source point. A seam is a maximal
//! run of cut edges with the same pair of pieces that does not pass a junction (a vertex
//! where three or more cut edges meet: a T-junction or crossing). A closed line's run may
//! wrap past its first vertex; a closed line with no junction and one piece pair gives one
//! seam whose chain starts and ends on the same vertex.

use std::collections::HashMap;

use flatcut_mesh::{Seam, SeamKind, SeamLedger, SeamSide, Topology, vec3};

use crate::embed::Embedded;
use crate::lines::CutLine;
use crate::pieces::Split;

/// Piece and local vertex chains of one cut edge's two sides.
#[derive(Clone, Copy, PartialEq)]
struct EdgeSides {
    pa: u32,
    pb: u32,
    a: [u32; 2],
    b: [u32; 2],
}

/// The ledger over the kept pieces (`names[p]` is `Some` for kept piece `p`; `local[p]` maps
/// split vertices to piece-local ones). Returns it and the number of cut edges not in any
/// seam (on the mesh boundary, or beside a dropped piece).
pub(crate) fn build_ledger(
    emb: &Embedded,
    split: &Split,
    lines: &[CutLine],
    cut: &HashMap<(u32, u32), usize>,
    names: &[Option<String>],
    local: &[HashMap<u32, u32>],
    ledger_pieces: Vec<String>,
) -> (SeamLedger, usize) {
    let faces = &emb.mesh.faces;
    let mut half: HashMap<(u32, u32), u32> = HashMap::with_capacity(2 * cut.len());
    for (f, face) in faces.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            if cut.contains_key(&(a.min(b), a.max(b))) {
                half.insert((a, b), (3 * f + k) as u32);
            }
        }
    }
    let mut degree: HashMap<u32, u32> = HashMap::new();
    for &(a, b) in cut.keys() {
        *degree.entry(a).or_default() += 1;
        *degree.entry(b).or_default() += 1;
    }
    let junction = |v: u32| degree.get(&v).copied().unwrap_or(0) > 2;
    let loc = |piece: u32, corner: u32| -> Option<u32> {
        let sv = split.corner_vertex[corner as usize];
        local[piece as usize].get(&sv).copied()
    };

    let mut ledger = SeamLedger::new(ledger_pieces);
    let mut unsewn = 0;
    for (li, chain) in emb.line_vertices.iter().enumerate() {
        let m = chain.len().saturating_sub(1);
        if m == 0 {
            continue;
        }
        let sides: Vec<Option<EdgeSides>> = (0..m)
            .map(|k| {
                let (u, v) = (chain[k], chain[k + 1]);
                let ha = *half.get(&(u, v))?;
                let hb = *half.get(&(v, u))?;
                let pa = split.face_piece[(ha / 3) as usize];
                let pb = split.face_piece[(hb / 3) as usize];
                names[pa as usize].as_ref()?;
                names[pb as usize].as_ref()?;
                Some(EdgeSides {
                    pa,
                    pb,
                    a: [loc(pa, ha)?, loc(pa, Topology::next(ha))?],
                    b: [loc(pb, Topology::next(hb))?, loc(pb, hb)?],
                })
            })
            .collect();
        unsewn += sides.iter().filter(|s| s.is_none()).count();
        let same = |x: Option<EdgeSides>, y: Option<EdgeSides>| match (x, y) {
            (Some(x), Some(y)) => x.pa == y.pa && x.pb == y.pb,
            _ => false,
        };
        let closed = lines[li].closed && chain.first() == chain.last();
        let brk = |k: usize| -> bool {
            if k == 0 {
                !closed || junction(chain[0]) || !same(sides[m - 1], sides[0])
            } else {
                junction(chain[k]) || !same(sides[k - 1], sides[k])
            }
        };
        let start = (0..m).find(|&k| brk(k));
        let order: Vec<usize> = match start {
            Some(s) => (s..m).chain(0..s).collect(),
            None => (0..m).collect(),
        };
        let mut runs: Vec<Vec<usize>> = Vec::new();
        for &k in &order {
            match runs.last_mut() {
                Some(r) if !brk(k) => r.push(k),
                _ => runs.push(vec![k]),
            }
        }
        let mut idx = 0;
        for run in runs {
            let Some(first) = sides[run[0]] else { continue };
            let mut a = vec![first.a[0]];
            let mut b = vec![first.b[0]];
            let mut length = 0.0;
            for &k in &run {
                let Some(s) = sides[k] else { continue };
                a.push(s.a[1]);
                b.push(s.b[1]);
                length += vec3::dist(
                    emb.mesh.positions[chain[k] as usize],
                    emb.mesh.positions[chain[k + 1] as usize],
                );
            }
            let (k0, k1) = (run[0], run[run.len() - 1] + 1);
            let name_of = |p: u32| names[p as usize].clone().unwrap_or_default();
            ledger.seams.push(Seam {
                id: format!("{}/{idx}", lines[li].name),
                line: lines[li].name.clone(),
                kind: SeamKind::Seam,
                a: SeamSide {
                    piece: name_of(first.pa),
                    vertices: a,
                },
                b: SeamSide {
                    piece: name_of(first.pb),
                    vertices: b,
                },
                length_3d_mm: length,
                start_mm: emb.mesh.positions[chain[k0] as usize],
                end_mm: emb.mesh.positions[chain[k1] as usize],
            });
            idx += 1;
        }
    }
    ledger.seams.sort_by(|x, y| x.id.cmp(&y.id));
    (ledger, unsewn)
}
