//! Repairs for scanned meshes: weld duplicate vertices, drop degenerate and duplicate faces,
//! make the orientation consistent, keep the largest piece, drop unreferenced vertices.
//!
//! [`clean`] returns a new mesh, a [`CleanReport`] counting everything it changed, and a
//! [`CleanMap`] from every new vertex and face back to the source, so that results computed
//! on the clean mesh can be carried back to the scan.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use crate::geometry::is_degenerate_face;
use crate::vec3::{cross, dot, norm2, sub};
use crate::{
    FaceId, FaceLabels, INVALID, MeshError, Topology, TriMesh, VertexAttributes, VertexId,
};

/// Which connected components [`clean`] keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Keep {
    /// Only the component with the most faces (ties: the one whose first face comes first):
    /// drops scanner debris floating around the part.
    Largest,
    /// Every component.
    #[default]
    All,
}

/// Options of [`clean`]; every field has a documented default (`CleanOptions::default()`,
/// also what a missing field means when read from the pipeline TOML).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CleanOptions {
    /// Vertices closer than this (millimetres) are merged. Default 0: only vertices at exactly
    /// the same position (the per-triangle copies of STL and unindexed OBJ). A positive
    /// tolerance also merges distinct vertices of thin features (the two sides of a narrow
    /// fold, the lips of a small cut) and so can change the topology; set it only knowing the
    /// scan's resolution. Merging is transitive (a chain of close vertices becomes one), and the
    /// lowest-index vertex of each group is kept at its own position. `weld_mm` is accepted
    /// for it.
    #[serde(alias = "weld_mm")]
    pub weld_tolerance_mm: f64,
    /// Refuse a weld whose merged vertex would be non-manifold (or on a non-manifold edge)
    /// where the input was not: coincident corners of two scan holes stay apart instead of
    /// pinching the surface. Default true; refused welds are counted in the report.
    pub weld_keeps_manifold: bool,
    /// Which components to keep. Default [`Keep::All`].
    pub keep: Keep,
    /// Drop faces with a repeated vertex or zero area (area ≤ (ε · bounding-box diagonal)²,
    /// ε = [`crate::geometry::DEGENERATE_AREA_RELATIVE`]). Default true.
    pub drop_degenerate: bool,
    /// Drop faces on the same three vertices as an earlier face, in either orientation.
    /// Default true.
    pub drop_duplicate_faces: bool,
    /// Drop vertices no face uses. Default true. (Vertices welded into another are removed
    /// either way; [`CleanMap::vertex_target`] says where they went.)
    pub drop_unreferenced: bool,
    /// Make face orientation consistent within each piece joined by two-face edges, by
    /// breadth-first flipping; closed pieces end up outward (positive signed volume), open
    /// pieces keep the orientation most of their faces had. Pieces that cannot be oriented
    /// (a Möbius strip) are left as they are and counted. Default true.
    pub orient: bool,
}

impl Default for CleanOptions {
    fn default() -> Self {
        Self {
            weld_tolerance_mm: 0.0,
            weld_keeps_manifold: true,
            keep: Keep::All,
            drop_degenerate: true,
            drop_duplicate_faces: true,
            drop_unreferenced: true,
            orient: true,
        }
    }
}

/// What [`clean`] changed, by count.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct CleanReport {
    /// Vertices of the input.
    pub input_vertices: usize,
    /// Faces of the input.
    pub input_faces: usize,
    /// Vertices merged into another vertex by welding.
    pub welded_vertices: usize,
    /// Vertices left unwelded because welding them would have pinched the surface into a
    /// non-manifold vertex or edge (e.g. coincident corners of two scan holes).
    pub refused_welds: usize,
    /// Faces dropped as degenerate (after welding).
    pub degenerate_faces: usize,
    /// Faces dropped as duplicates of an earlier face.
    pub duplicate_faces: usize,
    /// Faces whose orientation was reversed.
    pub flipped_faces: usize,
    /// Orientation pieces that cannot be oriented consistently (left unchanged).
    pub unorientable_components: usize,
    /// Connected components dropped by [`Keep::Largest`].
    pub dropped_components: usize,
    /// Faces in the dropped components.
    pub dropped_component_faces: usize,
    /// All faces removed, for any reason.
    pub dropped_faces: usize,
    /// Vertices removed because no face used them (not counting welded ones).
    pub unreferenced_vertices: usize,
    /// Vertices of the result.
    pub output_vertices: usize,
    /// Faces of the result.
    pub output_faces: usize,
}

/// Provenance of a cleaned mesh.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CleanMap {
    /// For each new vertex, the source vertex whose position it has.
    pub vertex_source: Vec<VertexId>,
    /// For each new face, the source face (its corners may be reordered by a flip and
    /// renumbered by welding).
    pub face_source: Vec<FaceId>,
    /// For each source vertex, the new vertex it became or was welded into
    /// ([`INVALID`] if dropped).
    pub vertex_target: Vec<u32>,
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

/// Joins the sets of `a` and `b`, the smaller root index becoming the representative.
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

/// Representative (lowest index) of each vertex after welding referenced vertices closer
/// than `tol` (exactly equal positions for `tol = 0`).
fn weld(positions: &[[f64; 3]], used: &[bool], tol: f64) -> Vec<u32> {
    let n = positions.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    if tol == 0.0 {
        let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(n);
        for v in 0..n {
            if !used[v] {
                continue;
            }
            // −0 folded onto +0 so that equal coordinates hash equally.
            let key = positions[v].map(|c| (c + 0.0).to_bits());
            let first = *seen.entry(key).or_insert(v as u32);
            union(&mut parent, first, v as u32);
        }
    } else {
        // Spatial hash with cells of the tolerance: close points are in the same or a
        // neighbouring cell. Points are sorted by cell, and each cell is compared with itself
        // and its 13 "forward" neighbours, so every close pair is tested once and there is one
        // hash lookup per cell and neighbour rather than per point. Cell coordinates are
        // clamped so huge coordinates cannot overflow.
        let cell = |p: [f64; 3]| p.map(|c| (c / tol).floor().clamp(-1e15, 1e15) as i64);
        let mut keyed: Vec<([i64; 3], u32)> = (0..n)
            .filter(|&v| used[v])
            .map(|v| (cell(positions[v]), v as u32))
            .collect();
        keyed.sort_unstable();
        let mut ranges: HashMap<[i64; 3], (usize, usize)> = HashMap::new();
        let mut i = 0;
        while i < keyed.len() {
            let mut j = i;
            while j < keyed.len() && keyed[j].0 == keyed[i].0 {
                j += 1;
            }
            ranges.insert(keyed[i].0, (i, j));
            i = j;
        }
        let tol2 = tol * tol;
        let close =
            |a: u32, b: u32| norm2(sub(positions[a as usize], positions[b as usize])) <= tol2;
        let forward: Vec<[i64; 3]> = (-1..=1)
            .flat_map(|dx| (-1..=1).flat_map(move |dy| (-1..=1).map(move |dz| [dx, dy, dz])))
            .filter(|o| *o > [0, 0, 0])
            .collect();
        for (&c, &(s0, e0)) in &ranges {
            for x in s0..e0 {
                for y in x + 1..e0 {
                    if close(keyed[x].1, keyed[y].1) {
                        union(&mut parent, keyed[x].1, keyed[y].1);
                    }
                }
            }
            for o in &forward {
                let Some(&(s1, e1)) = ranges.get(&[c[0] + o[0], c[1] + o[1], c[2] + o[2]]) else {
                    continue;
                };
                for x in s0..e0 {
                    for y in s1..e1 {
                        if close(keyed[x].1, keyed[y].1) {
                            union(&mut parent, keyed[x].1, keyed[y].1);
                        }
                    }
                }
            }
        }
    }
    (0..n as u32).map(|v| find(&mut parent, v)).collect()
}

/// Orients faces consistently across two-face edges. Returns per-face flip flags and the
/// number of pieces that could not be oriented.
fn orient(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> (Vec<bool>, usize) {
    let nf = faces.len();
    // Halfedges sorted by undirected edge: each two-face edge becomes a pair.
    let mut he: Vec<(u32, u32, u32, bool)> = Vec::with_capacity(3 * nf);
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            he.push((a.min(b), a.max(b), fi as u32, a < b));
        }
    }
    he.sort_unstable();
    // Adjacency: (neighbour, parity) with parity = both faces run the edge the same way.
    let mut adj_offsets = vec![0u32; nf + 1];
    let mut pairs = Vec::new();
    let mut i = 0;
    while i < he.len() {
        let mut j = i;
        while j < he.len() && (he[j].0, he[j].1) == (he[i].0, he[i].1) {
            j += 1;
        }
        if j - i == 2 && he[i].2 != he[i + 1].2 {
            let same = he[i].3 == he[i + 1].3;
            pairs.push((he[i].2, he[i + 1].2, same));
            adj_offsets[he[i].2 as usize + 1] += 1;
            adj_offsets[he[i + 1].2 as usize + 1] += 1;
        }
        i = j;
    }
    for f in 0..nf {
        adj_offsets[f + 1] += adj_offsets[f];
    }
    let mut fill = adj_offsets.clone();
    let mut adj = vec![(0u32, false); adj_offsets[nf] as usize];
    for &(f, g, same) in &pairs {
        adj[fill[f as usize] as usize] = (g, same);
        fill[f as usize] += 1;
        adj[fill[g as usize] as usize] = (f, same);
        fill[g as usize] += 1;
    }

    let mut flip = vec![false; nf];
    let mut seen = vec![false; nf];
    let mut unorientable = 0;
    let mut queue = std::collections::VecDeque::new();
    let mut piece = Vec::new();
    for seed in 0..nf {
        if seen[seed] {
            continue;
        }
        piece.clear();
        let mut ok = true;
        let mut boundary = false;
        seen[seed] = true;
        queue.push_back(seed as u32);
        while let Some(f) = queue.pop_front() {
            piece.push(f);
            let (s, e) = (
                adj_offsets[f as usize] as usize,
                adj_offsets[f as usize + 1] as usize,
            );
            if e - s < 3 {
                // Fewer than three two-face edges: a boundary or non-manifold edge, so the
                // piece is not closed and its signed volume means nothing.
                boundary = true;
            }
            for &(g, same) in &adj[s..e] {
                let want = flip[f as usize] ^ same;
                if !seen[g as usize] {
                    seen[g as usize] = true;
                    flip[g as usize] = want;
                    queue.push_back(g);
                } else if flip[g as usize] != want {
                    ok = false;
                }
            }
        }
        if !ok {
            unorientable += 1;
            for &f in &piece {
                flip[f as usize] = false;
            }
            continue;
        }
        let flipped = piece.iter().filter(|&&f| flip[f as usize]).count();
        let mut reverse = 2 * flipped > piece.len();
        if !boundary {
            // Closed: outward means positive signed volume (about the piece's first vertex,
            // which keeps the products small).
            let o = positions[faces[seed][0] as usize];
            let vol: f64 = piece
                .iter()
                .map(|&f| {
                    let [a, b, c] = faces[f as usize].map(|i| sub(positions[i as usize], o));
                    let v = dot(a, cross(b, c));
                    if flip[f as usize] { -v } else { v }
                })
                .sum();
            reverse = vol < 0.0;
        }
        if reverse {
            for &f in &piece {
                flip[f as usize] = !flip[f as usize];
            }
        }
    }
    (flip, unorientable)
}

/// Undoes every weld whose merged vertex would be non-manifold (or lie on a non-manifold edge)
/// while none of its source vertices was: welding is meant to zip a triangle soup, not to pinch
/// a surface where two of its vertices happen to coincide. Returns how many vertices were left
/// unwelded. One pass suffices: undoing a weld restores the input's connectivity there.
fn refuse_pinching_welds(mesh: &TriMesh, rep: &mut [u32]) -> usize {
    let n = rep.len();
    let mut cluster_size = vec![0u32; n];
    for &r in rep.iter() {
        cluster_size[r as usize] += 1;
    }
    if cluster_size.iter().all(|&k| k <= 1) {
        return 0;
    }
    let welded = TriMesh {
        positions: mesh.positions.clone(),
        faces: mesh
            .faces
            .iter()
            .map(|f| f.map(|v| rep[v as usize]))
            .filter(|g| g[0] != g[1] && g[1] != g[2] && g[2] != g[0])
            .collect(),
        ..Default::default()
    };
    let (Ok(after), Ok(before)) = (Topology::build(&welded), Topology::build(mesh)) else {
        return 0;
    };
    let was_bad: std::collections::HashSet<u32> = before
        .non_manifold_vertices()
        .iter()
        .map(|v| v.0)
        .chain(before.non_manifold_edges().into_iter().flatten())
        .collect();
    let mut undo = vec![false; n];
    let bad_now = after
        .non_manifold_vertices()
        .into_iter()
        .map(|v| v.0)
        .chain(after.non_manifold_edges().into_iter().flatten());
    for r in bad_now {
        if cluster_size[r as usize] > 1 && !was_bad.contains(&r) {
            undo[r as usize] = true;
        }
    }
    let mut refused = 0;
    for (v, r) in rep.iter_mut().enumerate() {
        if undo[*r as usize] && *r as usize != v {
            *r = v as u32;
            refused += 1;
        }
    }
    refused
}

/// Cleans `mesh` as `opts` says, in this order: weld, drop degenerate faces, drop duplicate
/// faces, orient, keep components, drop unreferenced vertices. Vertex attributes and face
/// labels are carried along.
///
/// Errors: a non-finite position ([`MeshError::NonFinitePosition`]) or face index out of
/// range (the mesh must pass [`TriMesh::validate`]), a negative or non-finite
/// `weld_tolerance_mm` ([`MeshError::InvalidParameter`]).
pub fn clean(
    mesh: &TriMesh,
    opts: &CleanOptions,
) -> Result<(TriMesh, CleanReport, CleanMap), MeshError> {
    mesh.validate()?;
    let tol = opts.weld_tolerance_mm;
    if !(tol.is_finite() && tol >= 0.0) {
        return Err(MeshError::InvalidParameter {
            name: "weld_tolerance_mm",
            value: tol,
            reason: "must be a finite distance ≥ 0 (0 welds exact duplicates only)",
        });
    }
    let n = mesh.positions.len();
    let mut report = CleanReport {
        input_vertices: n,
        input_faces: mesh.faces.len(),
        ..Default::default()
    };
    let used = mesh.referenced_vertices();
    let mut rep = weld(&mesh.positions, &used, tol);
    if opts.weld_keeps_manifold {
        report.refused_welds = refuse_pinching_welds(mesh, &mut rep);
    }
    report.welded_vertices = (0..n).filter(|&v| used[v] && rep[v] != v as u32).count();

    // Faces that survive, with their source index.
    let diagonal = mesh.diagonal();
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(mesh.faces.len());
    let mut face_source: Vec<u32> = Vec::with_capacity(mesh.faces.len());
    let mut seen_faces: HashMap<[u32; 3], u32> = HashMap::new();
    for (fi, f) in mesh.faces.iter().enumerate() {
        let g = f.map(|v| rep[v as usize]);
        if opts.drop_degenerate
            && is_degenerate_face(g, g.map(|v| mesh.positions[v as usize]), diagonal)
        {
            report.degenerate_faces += 1;
            continue;
        }
        if opts.drop_duplicate_faces {
            let mut key = g;
            key.sort_unstable();
            if seen_faces.insert(key, fi as u32).is_some() {
                report.duplicate_faces += 1;
                continue;
            }
        }
        faces.push(g);
        face_source.push(fi as u32);
    }

    if opts.orient {
        let (flip, unorientable) = orient(&mesh.positions, &faces);
        report.unorientable_components = unorientable;
        for (f, fl) in faces.iter_mut().zip(&flip) {
            if *fl {
                f.swap(1, 2);
                report.flipped_faces += 1;
            }
        }
    }

    if opts.keep == Keep::Largest && !faces.is_empty() {
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for f in &faces {
            union(&mut parent, f[0], f[1]);
            union(&mut parent, f[0], f[2]);
        }
        // Components in order of their first face; count faces.
        let mut label: HashMap<u32, usize> = HashMap::new();
        let mut counts: Vec<usize> = Vec::new();
        let comp: Vec<usize> = faces
            .iter()
            .map(|f| {
                let r = find(&mut parent, f[0]);
                let next = label.len();
                let c = *label.entry(r).or_insert(next);
                if c == counts.len() {
                    counts.push(0);
                }
                counts[c] += 1;
                c
            })
            .collect();
        // Most faces, first on ties.
        let mut best = 0;
        for (c, &k) in counts.iter().enumerate() {
            if k > counts[best] {
                best = c;
            }
        }
        report.dropped_components = counts.len() - 1;
        report.dropped_component_faces = faces.len() - counts[best];
        let mut k = 0;
        for i in 0..faces.len() {
            if comp[i] == best {
                faces[k] = faces[i];
                face_source[k] = face_source[i];
                k += 1;
            }
        }
        faces.truncate(k);
        face_source.truncate(k);
    }

    // Vertices: representatives in use (or all, keeping unreferenced ones).
    let mut referenced = vec![false; n];
    for f in &faces {
        for &v in f {
            referenced[v as usize] = true;
        }
    }
    let mut new_index = vec![INVALID; n];
    let mut vertex_source = Vec::new();
    for v in 0..n {
        let keep = referenced[v] || (!opts.drop_unreferenced && rep[v] == v as u32);
        if keep {
            new_index[v] = vertex_source.len() as u32;
            vertex_source.push(VertexId(v as u32));
        } else if rep[v] == v as u32 {
            report.unreferenced_vertices += 1;
        }
    }
    let vertex_target: Vec<u32> = (0..n).map(|v| new_index[rep[v] as usize]).collect();
    for f in &mut faces {
        for v in f.iter_mut() {
            *v = new_index[*v as usize];
        }
    }

    let pick = |src: &[VertexId]| -> Vec<usize> { src.iter().map(|v| v.idx()).collect() };
    let src = pick(&vertex_source);
    let attributes = VertexAttributes {
        colors: mesh
            .attributes
            .colors
            .as_ref()
            .map(|c| src.iter().map(|&i| c[i]).collect()),
        scalar: mesh
            .attributes
            .scalar
            .as_ref()
            .map(|c| src.iter().map(|&i| c[i]).collect()),
        texcoords: mesh
            .attributes
            .texcoords
            .as_ref()
            .map(|c| src.iter().map(|&i| c[i]).collect()),
    };
    let face_labels = mesh.face_labels.as_ref().map(|l| FaceLabels {
        names: l.names.clone(),
        labels: face_source.iter().map(|&f| l.labels[f as usize]).collect(),
    });
    let out = TriMesh {
        positions: src.iter().map(|&i| mesh.positions[i]).collect(),
        faces,
        attributes,
        face_labels,
    };
    report.output_vertices = out.positions.len();
    report.output_faces = out.faces.len();
    report.dropped_faces = report.input_faces - report.output_faces;
    let map = CleanMap {
        vertex_source,
        face_source: face_source.into_iter().map(FaceId).collect(),
        vertex_target,
    };
    Ok((out, report, map))
}
