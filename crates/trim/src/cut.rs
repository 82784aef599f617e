//! The whole cut: lines on the surface, embedded exactly, the surface opened along them into
//! named pieces with provenance, the seam ledger, and a report of every face's fate.

use std::collections::HashMap;

use flatcut_mesh::{SeamLedger, Topology, TriMesh, geometry};

use crate::TrimError;
use crate::cuts::Cuts;
use crate::embed::{Embedded, embed_with};
use crate::lines::{CutLine, LineContext, resolve};
use crate::pieces::{Piece, PieceReport, build_piece, cut_edges, name_pieces, report_of, split};
use crate::seams::build_ledger;

/// One line in the report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LineReport {
    /// Name.
    pub name: String,
    /// Closed loop?
    pub closed: bool,
    /// Length on the surface, mm.
    pub length_mm: f64,
    /// Vertices of the embedded line.
    pub vertices: usize,
}

/// What happened to everything.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TrimReport {
    /// Faces of the source.
    pub source_faces: usize,
    /// Area of the source, mm².
    pub source_area_mm2: f64,
    /// Every piece, kept or dropped: named pieces in seed order, then unnamed ones.
    pub pieces: Vec<PieceReport>,
    /// For every source face, the pieces (indices into `pieces`) holding a part of it: one
    /// for a face no line crosses, more where a line cuts through it. Dropped pieces count.
    pub face_fates: Vec<Vec<u32>>,
    /// Every line.
    pub lines: Vec<LineReport>,
    /// Cut edges not in any seam: on the mesh boundary or beside a dropped piece.
    pub unsewn_edges: usize,
}

/// The result of [`trim`].
#[derive(Clone, Debug)]
pub struct Trimmed {
    /// The lines as computed on the source.
    pub lines: Vec<CutLine>,
    /// The source with the lines embedded (before opening).
    pub embedded: Embedded,
    /// The kept pieces, in the order of [`TrimReport::pieces`] (dropped ones left out).
    pub pieces: Vec<Piece>,
    /// The seams between kept pieces.
    pub ledger: SeamLedger,
    /// The report.
    pub report: TrimReport,
}

/// Cuts `mesh` along `cuts` into pieces. Mesh and points in mm (convert with
/// [`Cuts::scale`] and [`TriMesh::scale`] first).
pub fn trim(mesh: &TriMesh, cuts: &Cuts) -> Result<Trimmed, TrimError> {
    mesh.validate()?;
    if mesh.faces.is_empty() {
        return Err(TrimError::EmptyMesh);
    }
    let ctx = LineContext::new(mesh, cuts.options.max_strip_updates)?;
    let lines = resolve(&ctx, cuts)?;
    let embedded = embed_with(&ctx, &lines)?;
    let topo = Topology::build(&embedded.mesh)?;
    let cut = cut_edges(&embedded);
    let sp = split(&embedded, &topo, &cut);
    let named = name_pieces(&embedded, &sp, &lines, &cut, &cuts.pieces, cuts)?;

    // Report order: named pieces in seed order, then unnamed in discovery order.
    let mut faces_of: Vec<Vec<u32>> = vec![Vec::new(); sp.piece_count];
    for (f, &p) in sp.face_piece.iter().enumerate() {
        faces_of[p as usize].push(f as u32);
    }
    let mut order: Vec<usize> = (0..sp.piece_count)
        .filter(|&p| named[p].is_some())
        .collect();
    order.sort_by_key(|&p| named[p]);
    order.extend((0..sp.piece_count).filter(|&p| named[p].is_none()));

    let mut names: Vec<Option<String>> = vec![None; sp.piece_count];
    let mut local: Vec<HashMap<u32, u32>> = vec![HashMap::new(); sp.piece_count];
    let mut report_index = vec![0u32; sp.piece_count];
    let mut pieces = Vec::new();
    let mut reports = Vec::new();
    let mut unnamed = 0;
    for (ri, &p) in order.iter().enumerate() {
        report_index[p] = ri as u32;
        let name = match named[p] {
            Some(s) => cuts.pieces[s].name.clone(),
            None => {
                unnamed += 1;
                format!("unnamed-{unnamed}")
            }
        };
        let kept = named[p].is_some() || cuts.options.keep_unnamed;
        let (piece, loc) = build_piece(&embedded, &sp, &faces_of[p], name.clone());
        reports.push(report_of(&piece, named[p].is_some(), kept)?);
        if kept {
            names[p] = Some(name);
            local[p] = loc;
            pieces.push(piece);
        }
    }
    let mut face_fates: Vec<Vec<u32>> = vec![Vec::new(); mesh.faces.len()];
    for (f, &p) in sp.face_piece.iter().enumerate() {
        let src = embedded.face_source[f] as usize;
        let r = report_index[p as usize];
        if !face_fates[src].contains(&r) {
            face_fates[src].push(r);
        }
    }
    for ff in &mut face_fates {
        ff.sort_unstable();
    }
    let ledger_pieces = pieces.iter().map(|p| p.name.clone()).collect();
    let (ledger, unsewn_edges) =
        build_ledger(&embedded, &sp, &lines, &cut, &names, &local, ledger_pieces);
    let report = TrimReport {
        source_faces: mesh.faces.len(),
        source_area_mm2: geometry::total_area(mesh),
        pieces: reports,
        face_fates,
        lines: lines
            .iter()
            .zip(&embedded.line_vertices)
            .map(|(l, c)| LineReport {
                name: l.name.clone(),
                closed: l.closed,
                length_mm: l.length,
                vertices: c.len(),
            })
            .collect(),
        unsewn_edges,
    };
    Ok(Trimmed {
        lines,
        embedded,
        pieces,
        ledger,
        report,
    })
}
