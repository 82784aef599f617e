//! Darts in the seam ledger: each dart is a seam of its piece with itself, leg A ↔ leg B,
//! both chains from the tip to the boundary, so that the pattern stage marks both legs, puts
//! matching notches and checks that they have equal 2D length.

use std::collections::{HashMap, HashSet};

use flatcut_mesh::{Seam, SeamKind, SeamLedger, SeamSide, Topology, vec3};

use crate::{DartError, Darted};

/// Seam id of a dart: its name, then the stretch index, as cutting-line seams
/// (`"<name>/0"`; a dart is one stretch).
pub fn dart_seam_id(name: &str) -> String {
    format!("{name}/0")
}

/// The seams of the darts of `darted`, a piece named `piece`: kind [`SeamKind::Dart`], side a
/// leg A, side b leg B, from the tip (`start_mm`) to the boundary (`end_mm`), 3D length.
pub fn dart_seams(darted: &Darted, piece: &str) -> Vec<Seam> {
    darted
        .darts
        .iter()
        .map(|d| Seam {
            id: dart_seam_id(&d.name),
            line: d.name.clone(),
            kind: SeamKind::Dart,
            a: SeamSide {
                piece: piece.to_string(),
                vertices: d.leg_a.clone(),
            },
            b: SeamSide {
                piece: piece.to_string(),
                vertices: d.leg_b.clone(),
            },
            length_3d_mm: d.length_mm,
            start_mm: d.tip_mm,
            end_mm: d.start_mm,
        })
        .collect()
}

/// Appends the darts of `darted` (cut into the ledger's piece `piece`) to `ledger`, and
/// renumbers the existing seams of that piece onto the darted piece. Its vertices keep their
/// indices except where a dart's start split a boundary vertex in two: a seam running
/// through a dart's start is split there into two seams (`<id>.1`, `<id>.2`; the mate's
/// chain split at the same index, 3D lengths and ends recomputed), since the dart's mouth
/// now opens between them. A dart whose start lies inside a boundary edge of an existing
/// seam is refused ([`DartError::StartSplitsSeam`]): the seam's mate on the other piece
/// would need the same new vertex — start the dart at a vertex of the seam.
pub fn append_dart_seams(
    ledger: &mut SeamLedger,
    piece: &str,
    darted: &Darted,
) -> Result<(), DartError> {
    if !ledger.pieces.iter().any(|p| p == piece) {
        return Err(DartError::UnknownPiece {
            piece: piece.to_string(),
        });
    }
    let topo = Topology::build(&darted.mesh)?;
    let mut boundary: HashSet<(u32, u32)> = HashSet::new();
    for h in 0..3 * darted.mesh.faces.len() as u32 {
        if topo.twin(h).is_none() {
            let (a, b) = (topo.from_vertex(h).0, topo.to_vertex(h).0);
            boundary.insert((a.min(b), a.max(b)));
        }
    }
    let is_edge = |a: u32, b: u32| boundary.contains(&(a.min(b), a.max(b)));
    let mut copies: HashMap<u32, Vec<u32>> = HashMap::new();
    for (v, &s) in darted.split_from.iter().enumerate() {
        copies.entry(s).or_default().push(v as u32);
    }
    let copies_of = |v: u32| copies.get(&v).cloned().unwrap_or_else(|| vec![v]);

    let mut renumbered = Vec::new();
    for seam in &ledger.seams {
        // Per side on this piece: the vertex for each chain index when a stretch ends there
        // (`before`) and when one starts there (`after`); they differ where the dart's mouth
        // opened the seam.
        let mut sides: Vec<(Vec<u32>, Vec<u32>)> = Vec::new();
        let mut breaks: Vec<usize> = Vec::new();
        for side in [&seam.a, &seam.b] {
            let chain = &side.vertices;
            if side.piece != piece || chain.len() < 2 {
                sides.push((chain.clone(), chain.clone()));
                continue;
            }
            let err = |k: usize| DartError::StartSplitsSeam {
                name: dart_on_edge(darted, chain[k - 1], chain[k]),
                seam: seam.id.clone(),
            };
            let next = copies_of(chain[1]);
            let first = copies_of(chain[0])
                .into_iter()
                .find(|&c| next.iter().any(|&n| is_edge(c, n)))
                .ok_or_else(|| err(1))?;
            let mut before = vec![first];
            let mut after = vec![first];
            for k in 1..chain.len() {
                let prev = after[k - 1];
                let cands = copies_of(chain[k]);
                if let Some(c) = cands.iter().copied().find(|&c| is_edge(prev, c)) {
                    before.push(c);
                    after.push(c);
                    continue;
                }
                // The previous point is a dart's start: the seam goes on from its other copy.
                let other = copies_of(chain[k - 1]).into_iter().find_map(|p| {
                    (p != before[k - 1])
                        .then(|| {
                            cands
                                .iter()
                                .copied()
                                .find(|&c| is_edge(p, c))
                                .map(|c| (p, c))
                        })
                        .flatten()
                });
                let Some((p, c)) = other else {
                    return Err(err(k));
                };
                after[k - 1] = p;
                before.push(c);
                after.push(c);
                breaks.push(k - 1);
            }
            sides.push((before, after));
        }
        breaks.sort_unstable();
        breaks.dedup();
        let n = seam.a.vertices.len();
        if n < 2 || seam.b.vertices.len() != n {
            // Malformed (SeamLedger::check refuses it); kept as it is rather than guessed at.
            renumbered.push(seam.clone());
            continue;
        }
        let mut cuts = vec![0];
        cuts.extend(breaks.iter().copied().filter(|&b| b > 0 && b + 1 < n));
        cuts.push(n - 1);
        let parts = cuts.len() - 1;
        for j in 0..parts {
            let (s, e) = (cuts[j], cuts[j + 1]);
            let pick = |(before, after): &(Vec<u32>, Vec<u32>)| -> Vec<u32> {
                (s..=e)
                    .map(|k| if k == s { after[k] } else { before[k] })
                    .collect()
            };
            let mut part = seam.clone();
            part.a.vertices = pick(&sides[0]);
            part.b.vertices = pick(&sides[1]);
            if parts > 1 {
                part.id = format!("{}.{}", seam.id, j + 1);
                let on = if seam.a.piece == piece {
                    &part.a
                } else {
                    &part.b
                };
                let p = |v: u32| darted.mesh.positions[v as usize];
                part.length_3d_mm = on
                    .vertices
                    .windows(2)
                    .map(|w| vec3::dist(p(w[0]), p(w[1])))
                    .sum();
                part.start_mm = p(on.vertices[0]);
                part.end_mm = p(on.vertices[on.vertices.len() - 1]);
            }
            renumbered.push(part);
        }
    }
    let new = dart_seams(darted, piece);
    for s in &new {
        if renumbered.iter().any(|r| r.id == s.id) {
            return Err(DartError::DuplicateSeam { seam: s.id.clone() });
        }
    }
    renumbered.extend(new);
    renumbered.sort_by(|x, y| x.id.cmp(&y.id));
    ledger.seams = renumbered;
    Ok(())
}

/// The dart whose start lies on the segment between input vertices `u` and `v` (the one
/// nearest to it).
fn dart_on_edge(darted: &Darted, u: u32, v: u32) -> String {
    let p = &darted.mesh.positions;
    let (a, b) = (p[u as usize], p[v as usize]);
    let dist = |x: [f64; 3]| {
        let ab = vec3::sub(b, a);
        let l2 = vec3::norm2(ab);
        let s = if l2 > 0.0 {
            (vec3::dot(vec3::sub(x, a), ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        vec3::dist(x, vec3::add(a, vec3::scale(ab, s)))
    };
    darted
        .darts
        .iter()
        .min_by(|x, y| dist(x.start_mm).total_cmp(&dist(y.start_mm)))
        .map_or_else(String::new, |d| d.name.clone())
}
