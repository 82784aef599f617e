//! The run: stages in order, pieces in parallel, everything computed in memory before the
//! output folder is touched (so a failing stage leaves no folder behind), then written with
//! the report last.
//!
//! Stages: input (read, generate or span wire-frames), clean, remesh (optional), pieces, darts
//! and feature curves (per piece), process (per piece), flatten (per piece), outputs. Results do not depend on the thread count: pieces are independent, collected in
//! order, and each stage's algorithm is itself thread-count independent.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use flatcut_flattenable::hole_closure::least_closed;
use flatcut_flattenable::{FlattenableError, HoleRims, Processed};
use flatcut_io::{Format, Units, WriteOptions};
use flatcut_lscm::{Pins, distortion, flatten_with_topology};
use flatcut_mesh::shapes::{self, dress_form};
use flatcut_mesh::{FaceLabels, SeamLedger, Topology, TriMesh, geometry};
use rayon::prelude::*;

use crate::html::{PiecePictures, report_html};
use crate::pieces::{PieceMesh, cut, split};
use crate::progress::Progress;
use crate::render::{Frame, VIEWS, render_2d, render_3d};
use crate::report::{
    FeatureSummary, FileHash, FlattenSummary, InputHash, MeshCounts, OutputFile, PatternSummary,
    PieceReport, ProcessSummary, Report, StageTime, Timings, sha256_hex, to_json,
};
use crate::seams::seam_table;
use crate::spec::{Generator, Pipeline, SCHEMA};
use crate::{PipelineError, output};

/// How to run a pipeline.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder; default the pipeline's `output` (default `out/<name>` beside the TOML).
    pub out: Option<PathBuf>,
    /// Write into a folder that belongs to another pipeline or to nobody.
    pub force: bool,
    /// Worker threads; default rayon's (all cores, or `RAYON_NUM_THREADS`).
    pub threads: Option<usize>,
    /// No progress bars.
    pub quiet: bool,
}

/// A finished run.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// Where it was written.
    pub out_dir: PathBuf,
    /// report.json's content.
    pub report: Report,
    /// timings.json's content.
    pub timings: Timings,
}

/// Everything a run produces, before anything is written.
pub struct Computed {
    /// Files by path inside the output folder (sorted).
    pub files: BTreeMap<String, Vec<u8>>,
    /// The report (its `files` already filled).
    pub report: Report,
    /// Wall times.
    pub timings: Timings,
}

/// The input files of `p` (the TOML itself and the mesh, if any), resolved.
pub fn input_paths(p: &Pipeline) -> Vec<PathBuf> {
    let mut v = vec![p.source.clone()];
    if let Some(Ok(m)) = p
        .spec
        .input
        .get_ref()
        .mesh
        .as_ref()
        .map(|m| p.expand(m, "input.mesh"))
    {
        v.push(m);
    }
    if let Some(ws) = &p.spec.input.get_ref().wireframes {
        v.extend(
            ws.get_ref()
                .iter()
                .filter_map(|w| p.expand(w, "input.wireframes").ok()),
        );
    }
    v
}

/// Runs `p` and writes its output folder.
pub fn run(p: &Pipeline, opts: &RunOptions) -> Result<RunOutcome, PipelineError> {
    let out_dir = opts.out.clone().unwrap_or_else(|| p.default_output());
    let inputs = input_paths(p);
    // Refuse a bad folder before spending the time.
    output::check(&out_dir, p.name(), opts.force, &inputs, &[])
        .map_err(|e| locate_output_error(p, opts, e))?;
    let progress = Progress::new(opts.quiet, p.name());
    let computed = with_threads(opts.threads, || compute(p, &progress))?;
    let names: Vec<String> = computed.files.keys().cloned().collect();
    output::check(&out_dir, p.name(), opts.force, &inputs, &names)?;
    output::write(
        &out_dir,
        p.name(),
        &computed.files,
        &to_json(&computed.timings),
        &to_json(&computed.report),
    )?;
    Ok(RunOutcome {
        out_dir,
        report: computed.report,
        timings: computed.timings,
    })
}

/// Runs `f` on a pool of `threads` workers, or on rayon's global pool.
/// A folder path that is a file came from the TOML's `output` unless `--out` was given: then
/// the error names that line, as every other error in the file does.
fn locate_output_error(p: &Pipeline, opts: &RunOptions, e: PipelineError) -> PipelineError {
    match (&e, &opts.out, &p.spec.output) {
        (PipelineError::OutputIsFile { path }, None, Some(key)) => p.invalid(
            key.span(),
            "output",
            format!(
                "the output folder {} is an existing file; name a folder here or pass --out",
                path.display()
            ),
        ),
        _ => e,
    }
}

fn with_threads<T: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<T, PipelineError> + Send,
) -> Result<T, PipelineError> {
    match threads {
        None => f(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| PipelineError::Threads {
                threads: n,
                reason: e.to_string(),
            })?
            .install(f),
    }
}

/// The loaded surface and what it came from.
struct Loaded {
    mesh: TriMesh,
    inputs: Vec<InputHash>,
    generator: Option<serde_json::Value>,
    units: Units,
    /// Warnings of the input stage (e.g. a wire-frame patch below its angle goal).
    warnings: Vec<String>,
}

fn load_input(p: &Pipeline) -> Result<Loaded, PipelineError> {
    let input = p.spec.input.get_ref();
    if let Some(m) = &input.mesh {
        let path = p.expand(m, "input.mesh")?;
        let units = p
            .spec
            .units
            .unwrap_or_else(|| Format::from_extension(&path).map_or(Units::Mm, Units::default_for));
        let located = |source: flatcut_io::IoError| {
            let (line, column) = crate::spec::line_col(&p.text, m.span().start);
            PipelineError::InputMesh {
                file: p.source.clone(),
                line,
                column,
                source: Box::new(source),
            }
        };
        let loaded = flatcut_io::read_mesh(&path, units).map_err(located)?;
        let bytes = std::fs::read(&path).map_err(|source| {
            located(flatcut_io::IoError::Io {
                path: path.clone(),
                source,
            })
        })?;
        Ok(Loaded {
            mesh: loaded.mesh,
            inputs: vec![InputHash {
                key: "input.mesh".into(),
                path: m.get_ref().display().to_string(),
                sha256: sha256_hex(&bytes),
                bytes: bytes.len() as u64,
            }],
            generator: None,
            units,
            warnings: Vec::new(),
        })
    } else if let Some(g) = &input.generator {
        let bad = |message: String| p.invalid(g.span(), "input.generator", message);
        let (mesh, kind, params) = match g.get_ref() {
            Generator::DressForm(m) => (dress_form(m), "dress-form", serde_json::to_value(m)),
            Generator::SphereCap(c) => {
                if !(c.n >= 3
                    && c.cap_angle_deg > 0.0
                    && c.cap_angle_deg < 360.0
                    && c.radius_mm.is_finite()
                    && c.radius_mm > 0.0)
                {
                    return Err(bad(
                        "sphere-cap needs n ≥ 3, 0 < cap_angle_deg < 360 and radius_mm > 0".into(),
                    ));
                }
                let m = shapes::sphere_cap_grid(c.n, c.cap_angle_deg.to_radians(), c.radius_mm);
                (m, "sphere-cap", serde_json::to_value(c))
            }
            Generator::Saddle(s) => {
                if !(s.n >= 3
                    && s.size_mm.is_finite()
                    && s.size_mm > 0.0
                    && s.curvature_per_mm.is_finite())
                {
                    return Err(bad(
                        "saddle needs n ≥ 3, size_mm > 0 and a finite curvature_per_mm".into(),
                    ));
                }
                let c = s.curvature_per_mm;
                let m = shapes::grid_patch(s.n, s.n, s.size_mm, |x, y| c * (x * x - y * y));
                (m, "saddle", serde_json::to_value(s))
            }
        };
        let mut generator = params.unwrap_or_default();
        if let Some(o) = generator.as_object_mut() {
            o.insert("kind".into(), kind.into());
        }
        Ok(Loaded {
            mesh,
            inputs: Vec::new(),
            generator: Some(generator),
            units: p.spec.units.unwrap_or(Units::Mm),
            warnings: Vec::new(),
        })
    } else if let Some(ws) = &input.wireframes {
        load_wireframes(p, ws.get_ref())
    } else {
        // `Pipeline::parse` guarantees one of the three.
        Err(p.invalid(
            p.spec.input.span(),
            "input",
            "[input] needs `mesh` or `generator`".into(),
        ))
    }
}

/// `[input] wireframes`: each file a surface patch (in mm, from the file's own `units`), all
/// in one mesh whose connected components are the patches, in file order.
fn load_wireframes(
    p: &Pipeline,
    files: &[toml::Spanned<PathBuf>],
) -> Result<Loaded, PipelineError> {
    use flatcut_trim::wireframe::{WireFrame, wireframe_surface};
    let mut mesh = TriMesh::default();
    let mut inputs = Vec::with_capacity(files.len());
    let mut warnings = Vec::new();
    for w in files {
        let bad = |message: String| p.invalid(w.span(), "input.wireframes", message);
        let path = p.expand(w, "input.wireframes")?;
        let bytes = std::fs::read(&path).map_err(|e| {
            bad(format!(
                "cannot read the wire-frame {}: {e}",
                path.display()
            ))
        })?;
        let text = String::from_utf8(bytes.clone()).map_err(|_| {
            bad(format!(
                "the wire-frame {} is not UTF-8 text (a WIRE.toml file)",
                path.display()
            ))
        })?;
        let wire: WireFrame = toml::from_str(&text).map_err(|e| {
            let (line, column) = e
                .span()
                .map_or((0, 0), |s| crate::spec::line_col(&text, s.start));
            bad(format!(
                "{}:{line}:{column}: {}",
                path.display(),
                e.message().trim()
            ))
        })?;
        let units: Units = wire.units.parse().map_err(|_| {
            bad(format!(
                "{}: units = {:?} is not one of mm, cm, dm, m, in",
                path.display(),
                wire.units
            ))
        })?;
        let patch = wireframe_surface(&wire.scaled(units.factor_to_mm()), &wire.options)
            .map_err(|e| bad(format!("{}: {e}", path.display())))?;
        let base = mesh.positions.len() as u32;
        mesh.positions.extend_from_slice(&patch.mesh.positions);
        mesh.faces
            .extend(patch.mesh.faces.iter().map(|f| f.map(|v| v + base)));
        warnings.extend(
            patch
                .report
                .warnings
                .iter()
                .map(|x| format!("wire-frame {}: {x}", w.get_ref().display())),
        );
        inputs.push(InputHash {
            key: "input.wireframes".into(),
            path: w.get_ref().display().to_string(),
            sha256: sha256_hex(&bytes),
            bytes: bytes.len() as u64,
        });
    }
    Ok(Loaded {
        mesh,
        inputs,
        generator: None,
        units: p.spec.units.unwrap_or(Units::Mm),
        warnings,
    })
}

/// Options that address vertices of one mesh cannot follow a mesh that the pipeline cuts
/// into pieces; refuse them rather than apply them to the wrong vertices.
fn check_stage_options(p: &Pipeline) -> Result<(), PipelineError> {
    let bad = |key: &str, what: &str| {
        let span = p.spec.input.span();
        let (line, column) =
            crate::spec::line_col(&p.text, find_key(&p.text, key).unwrap_or(span.start));
        PipelineError::Invalid {
            file: p.source.clone(),
            line,
            column,
            key: key.to_string(),
            message: format!(
                "{what} name vertices of one mesh; a pipeline makes its own pieces, so this option cannot be used here"
            ),
        }
    };
    if p.spec.process.weights.is_some() {
        return Err(bad("process.weights", "per-vertex weights"));
    }
    if !p.spec.process.feature_curves.is_empty() {
        return Err(bad(
            "process.feature_curves",
            "feature curves given as vertex indices",
        ));
    }
    if matches!(p.spec.flatten.lscm.pins, Pins::Given(_)) {
        return Err(bad("flatten.lscm.pins", "given pins"));
    }
    Ok(())
}

/// Byte offset of the first line that sets the last component of a dotted `key`, for
/// locating values serde gives no span for.
fn find_key(text: &str, key: &str) -> Option<usize> {
    let last = key.rsplit('.').next()?;
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let t = line.trim_start();
        if let Some(rest) = t.strip_prefix(last)
            && rest.trim_start().starts_with('=')
        {
            return Some(offset + (line.len() - t.len()));
        }
        offset += line.len();
    }
    None
}

/// Per piece: the processing result and whether it converged.
struct ProcessedPiece {
    processed: Processed,
    converged: bool,
    seconds: f64,
}

fn process_piece(p: &Pipeline, piece: &PieceMesh) -> Result<ProcessedPiece, PipelineError> {
    let start = Instant::now();
    let features_opts;
    let opts = if piece.features.is_empty() {
        &p.spec.process
    } else {
        let mut o = p.spec.process.clone();
        o.feature_curves = piece.features.clone();
        features_opts = o;
        &features_opts
    };
    let (processed, converged) = match flatcut_flattenable::process(&piece.mesh, opts) {
        Ok(r) => (r, true),
        // The best unfolded state is still the most flattenable surface we have: carry on
        // with it, mark the piece and warn.
        Err(FlattenableError::NotConverged { partial, .. }) => (*partial, false),
        Err(source) => {
            return Err(PipelineError::Process {
                piece: piece.name.clone(),
                source: Box::new(source),
            });
        }
    };
    Ok(ProcessedPiece {
        processed,
        converged,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Per piece: the placed pattern and its distortion.
struct FlatPiece {
    uv: Vec<[f64; 2]>,
    /// E_h per face, for the distortion map.
    e_h: Vec<f64>,
    /// E_r per face.
    e_r: Vec<f64>,
    /// Edge strain per face.
    edge_strain: Vec<f64>,
    summary: FlattenSummary,
    seconds: f64,
}

fn flatten_piece(
    p: &Pipeline,
    piece: &PieceMesh,
    mesh: &TriMesh,
    topo: &Topology,
) -> Result<FlatPiece, PipelineError> {
    let start = Instant::now();
    let mut opts = p.spec.flatten.clone();
    if let Some(g) = piece
        .spec
        .and_then(|i| p.spec.pieces[i].get_ref().grain.as_ref())
    {
        opts.placement.grain = Some(*g.get_ref());
    }
    let err = |source: flatcut_lscm::LscmError| PipelineError::Flatten {
        piece: piece.name.clone(),
        source: Box::new(source),
    };
    let out = flatten_with_topology(mesh, topo, &opts).map_err(err)?;
    let uv = out.flattening.uv;
    if let Some(v) = uv
        .iter()
        .position(|q| !(q[0].is_finite() && q[1].is_finite()))
    {
        return Err(err(flatcut_lscm::LscmError::Mesh(
            flatcut_mesh::MeshError::NonFinitePosition {
                vertex: flatcut_mesh::VertexId(v as u32),
                position: [uv[v][0], uv[v][1], 0.0],
            },
        )));
    }
    let d = distortion(mesh, topo, &uv);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in &uv {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    let summary = FlattenSummary {
        method: match opts.method {
            flatcut_lscm::Method::Lscm => "lscm".into(),
            flatcut_lscm::Method::LscmArap => "lscm+arap".into(),
        },
        e_h: d.e_h,
        e_r: d.e_r,
        edge_strain: d.edge_strain,
        max_edge_strain: d.max_edge_strain,
        area_3d_mm2: d.area_3d_mm2,
        area_2d_mm2: d.area_2d_mm2,
        flipped_faces: d.flipped_faces,
        boundary_3d_mm: d.boundary_loops.iter().map(|l| l.length_3d_mm).sum(),
        boundary_2d_mm: d.boundary_loops.iter().map(|l| l.length_2d_mm).sum(),
        size_mm: [hi[0] - lo[0], hi[1] - lo[1]],
    };
    Ok(FlatPiece {
        e_h: d.per_face.iter().map(|f| f.e_h).collect(),
        e_r: d.per_face.iter().map(|f| f.e_r).collect(),
        edge_strain: d.per_face.iter().map(|f| f.edge_strain).collect(),
        uv,
        summary,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Runs every stage in memory.
pub fn compute(p: &Pipeline, progress: &Progress) -> Result<Computed, PipelineError> {
    let t0 = Instant::now();
    let mut timings = Timings {
        pipeline: p.name().to_string(),
        threads: rayon::current_num_threads(),
        ..Default::default()
    };
    let stage_done = |timings: &mut Timings, name: &str, since: Instant| {
        timings.stages.push(StageTime {
            stage: name.into(),
            seconds: since.elapsed().as_secs_f64(),
        });
    };
    check_stage_options(p)?;

    let t = Instant::now();
    let bar = progress.stage("input", 0);
    let loaded = load_input(p)?;
    bar.finish();
    stage_done(&mut timings, "input", t);

    let t = Instant::now();
    let bar = progress.stage("clean", 0);
    let (mesh, clean_report, _map) =
        flatcut_mesh::clean::clean(&loaded.mesh, &p.spec.input.get_ref().clean).map_err(
            |source| PipelineError::Clean {
                file: p.source.clone(),
                source: Box::new(source),
            },
        )?;
    bar.finish();
    stage_done(&mut timings, "clean", t);

    let mesh = match &p.spec.input.get_ref().remesh {
        Some(opts) => {
            let t = Instant::now();
            let bar = progress.stage("remesh", 0);
            let r =
                flatcut_remesh::remesh(&mesh, opts).map_err(|source| PipelineError::Remesh {
                    file: p.source.clone(),
                    source: Box::new(source),
                })?;
            bar.finish();
            stage_done(&mut timings, "remesh", t);
            r.mesh
        }
        None => mesh,
    };

    let t = Instant::now();
    let bar = progress.stage("pieces", 0);
    let (mut pieces, dropped, mut seams) = if p.spec.cuts.is_empty() {
        let topo = Topology::build(&mesh).map_err(|source| PipelineError::Clean {
            file: p.source.clone(),
            source: Box::new(source),
        })?;
        let (pieces, dropped) = split(p, &mesh, &topo, loaded.units.factor_to_mm())?;
        let seams = SeamLedger::new(pieces.iter().map(|p| p.name.clone()).collect());
        (pieces, dropped, seams)
    } else {
        let (pieces, seams, dropped) = cut(p, &mesh, loaded.units.factor_to_mm())?;
        (pieces, dropped, seams)
    };
    bar.finish();
    stage_done(&mut timings, "pieces", t);

    // Darts and feature curves, per piece in parallel; dart seams join the ledger in piece
    // order.
    let t = Instant::now();
    let bar = progress.stage("darts", pieces.len() as u64);
    let units_to_mm = loaded.units.factor_to_mm();
    // Per piece, the vertices of its seams (a dart starting on a seam starts at one of them).
    let mut seam_vertices: BTreeMap<&str, std::collections::BTreeSet<u32>> = BTreeMap::new();
    for s in &seams.seams {
        for side in [&s.a, &s.b] {
            seam_vertices
                .entry(side.piece.as_str())
                .or_default()
                .extend(side.vertices.iter().copied());
        }
    }
    let no_seams = std::collections::BTreeSet::new();
    let darted: Vec<Option<flatcut_dart::Darted>> = pieces
        .par_iter_mut()
        .map(|piece| {
            let sv = seam_vertices.get(piece.name.as_str()).unwrap_or(&no_seams);
            let r = crate::pieces::darts_and_features(p, piece, units_to_mm, sv);
            bar.inc(1);
            r
        })
        .collect::<Result<_, _>>()?;
    drop(seam_vertices);
    for (piece, d) in pieces.iter().zip(&darted) {
        if let (Some(d), Some(i)) = (d, piece.spec) {
            flatcut_dart::append_dart_seams(&mut seams, &piece.name, d)
                .map_err(|e| crate::pieces::dart_error(p, p.spec.pieces[i].get_ref(), e))?;
        }
    }
    drop(darted);
    bar.finish();
    stage_done(&mut timings, "darts", t);

    let t = Instant::now();
    let bar = progress.stage("process", pieces.len() as u64);
    let processed: Vec<ProcessedPiece> = pieces
        .par_iter()
        .map(|piece| {
            let r = process_piece(p, piece);
            bar.inc(1);
            r
        })
        .collect::<Result<_, _>>()?;
    bar.finish();
    stage_done(&mut timings, "process", t);

    let t = Instant::now();
    let bar = progress.stage("flatten", pieces.len() as u64);
    let flat: Vec<(Topology, FlatPiece)> = pieces
        .par_iter()
        .zip(&processed)
        .map(|(piece, pr)| {
            let m = &pr.processed.mesh;
            let topo = Topology::build(m).map_err(|source| PipelineError::Flatten {
                piece: piece.name.clone(),
                source: Box::new(source.into()),
            })?;
            let f = flatten_piece(p, piece, m, &topo)?;
            bar.inc(1);
            Ok((topo, f))
        })
        .collect::<Result<_, PipelineError>>()?;
    bar.finish();
    stage_done(&mut timings, "flatten", t);

    let t = Instant::now();
    let bar = progress.stage("outputs", 0);
    let mut files = BTreeMap::new();
    let mut warnings = loaded.warnings.clone();
    if p.spec.export.wants(crate::export::ExportFormat::Glb) {
        files.insert(
            "processed.glb".to_string(),
            processed_glb(&pieces, &processed, &flat)?,
        );
    }
    for (piece, (_, f)) in pieces.iter().zip(&flat) {
        let name = format!("pieces/{}.obj", piece.name);
        let pattern = TriMesh {
            positions: f.uv.iter().map(|q| [q[0], q[1], 0.0]).collect(),
            faces: piece.mesh.faces.clone(),
            attributes: flatcut_mesh::VertexAttributes {
                texcoords: Some(f.uv.clone()),
                ..Default::default()
            },
            face_labels: None,
        };
        let bytes = flatcut_io::write_mesh_to_vec(
            &pattern,
            Format::Obj,
            &WriteOptions {
                units: Some(Units::Mm),
                ..Default::default()
            },
        )
        .map_err(|source| PipelineError::Encode {
            name: name.clone(),
            source: Box::new(source),
        })?;
        files.insert(name, bytes);
    }
    let mut seams_json = serde_json::to_string_pretty(&seams).unwrap_or_default();
    seams_json.push('\n');
    files.insert("seams.json".into(), seams_json.into_bytes());
    let inputs: Vec<flatcut_pattern::PieceInput> = pieces
        .iter()
        .zip(&processed)
        .zip(&flat)
        .map(|((piece, pr), (_, f))| {
            let spec = piece.spec.map(|i| p.spec.pieces[i].get_ref());
            flatcut_pattern::PieceInput {
                name: piece.name.clone(),
                mesh: pr.processed.mesh.clone(),
                uv: f.uv.clone(),
                meta: piece_meta(spec),
                internal_lines: piece.features.clone(),
                e_h: f.e_h.clone(),
                e_r: f.e_r.clone(),
                edge_strain: f.edge_strain.clone(),
            }
        })
        .collect();
    let exported = crate::export::export(
        &inputs,
        &seams,
        &p.spec.pattern,
        &p.spec.layout,
        &p.spec.export,
    )?;
    files.extend(exported.files);
    let pattern_pieces = exported.pieces;
    let uv_by_name: BTreeMap<String, &[[f64; 2]]> = pieces
        .iter()
        .zip(&flat)
        .map(|(piece, (_, f))| (piece.name.clone(), f.uv.as_slice()))
        .collect();
    let (seam_table, skipped) = seam_table(&seams, &uv_by_name);
    for id in skipped {
        warnings.push(format!(
            "seam {id:?}: its pieces were not both flattened or its vertex chains do not fit them; left out of the seam table"
        ));
    }

    let mut piece_reports = Vec::with_capacity(pieces.len());
    for (((piece, pr), (ftopo, f)), pat) in pieces
        .iter()
        .zip(&processed)
        .zip(&flat)
        .zip(&pattern_pieces)
    {
        let r = pr.processed.report.pieces.first();
        let spec = piece.spec.map(|i| p.spec.pieces[i].get_ref());
        if !pr.converged {
            let at = r
                .and_then(|r| r.worst_vertex_position_mm)
                .map_or(String::new(), |[x, y, z]| {
                    format!(", least flat at ({x:.1}, {y:.1}, {z:.1}) mm")
                });
            warnings.push(format!(
                "piece {:?}: processing did not reach θ_err ≤ {:.1e} rad (best {:.3e} rad{at}); the best unfolded state was flattened",
                piece.name,
                p.spec.process.tolerance_rad,
                pr.processed.report.final_theta_err
            ));
        }
        // θ = 2π does not close a hole on a curved piece: say so where the pattern will
        // stretch around one (docs/algorithms/flattenable.md, "Holes").
        let tolerance = p.spec.process.tolerance_rad;
        if let Some(r) = r.filter(|r| r.converged) {
            let open: Vec<_> = r.holes.iter().filter(|h| !h.closes(tolerance)).collect();
            if let Some(worst) = least_closed(open.iter().copied()) {
                let remedy = match p.spec.process.hole_rims {
                    HoleRims::Fixed => {
                        "`hole_rims = \"free\"` in [process] lets their rims move so that they close, or a `[[cut]]` line from each hole's rim to the outline makes the piece a disk (its two sides a seam of the piece with itself)"
                    }
                    HoleRims::Free => {
                        "with its holes filled it did not converge, so its rims stayed fixed; a `[[cut]]` line from each hole's rim to the outline makes the piece a disk (its two sides a seam of the piece with itself)"
                    }
                };
                warnings.push(format!(
                    "piece {:?}: {} of its {} holes do not close in the plane though θ = 2π (the worst turns {:+.2e} rad from once around and leaves a {:.2} mm gap), so its pattern stretches around them; {remedy}",
                    piece.name,
                    open.len(),
                    r.holes.len(),
                    worst.turning_residual_rad,
                    worst.gap_mm
                ));
            }
        }
        if f.summary.flipped_faces > 0 {
            warnings.push(format!(
                "piece {:?}: {} faces are flipped in the pattern (it folds over itself); a piece that is not a disk has no fold-free flattening: cut it into disks",
                piece.name, f.summary.flipped_faces
            ));
        }
        piece_reports.push(PieceReport {
            name: piece.name.clone(),
            faces: piece.mesh.face_count(),
            vertices: piece.mesh.vertex_count(),
            boundary_loops: ftopo.boundary_loops().len(),
            euler_characteristic: ftopo.euler_characteristic(),
            quantity: spec.map_or(1, |s| s.quantity),
            mirror: spec.is_some_and(|s| s.mirror),
            size: spec.map(|s| s.size.clone()).unwrap_or_default(),
            fabric: spec.map(|s| s.fabric.clone()).unwrap_or_default(),
            darts: piece.darts.clone(),
            features: piece
                .features
                .iter()
                .map(|c| feature_summary(c, &piece.mesh, &pr.processed.mesh))
                .collect(),
            process: ProcessSummary {
                converged: pr.converged,
                iterations: r.map_or(0, |r| r.iterations),
                theta_err_before: r.and_then(|r| r.theta_err.first().copied()).unwrap_or(0.0),
                theta_err_after: pr.processed.report.final_theta_err,
                theta_rms_before: pr.processed.report.input_theta_rms,
                theta_rms_after: pr.processed.report.final_theta_rms,
                rms_displacement_mm: pr.processed.report.rms_displacement_mm,
                max_displacement_mm: pr.processed.report.max_displacement_mm,
                area_change_percent: pr.processed.report.area_change_percent,
                max_normal_turn_deg: pr.processed.report.max_normal_turn_deg,
                max_crease_deg: pr.processed.report.max_crease_deg,
                creased_edges: pr.processed.report.creased_edges,
                creased_defect_rad: r.map_or(0.0, |r| r.creased_defect_rad),
                sharpest_crease_position_mm: r.and_then(|r| r.sharpest_crease_position_mm),
                least_flat_position_mm: r.and_then(|r| r.worst_vertex_position_mm),
                stop_reason: r.map(|r| r.stop_reason.clone()).unwrap_or_default(),
                theta_err_history: r.map(|r| r.theta_err.clone()).unwrap_or_default(),
            },
            flatten: f.summary.clone(),
            pattern: PatternSummary {
                shrink_along_grain: pat.shrink.along_grain,
                shrink_across_grain: pat.shrink.across_grain,
                size_mm: extent(&pat.sew_line),
            },
        });
        let mut per = BTreeMap::new();
        per.insert("process".to_string(), pr.seconds);
        per.insert("flatten".to_string(), f.seconds);
        timings.pieces.insert(piece.name.clone(), per);
    }
    for d in &dropped {
        warnings.push(format!(
            "component {} ({} faces) contains no [[piece]] seed and was left out",
            d.component, d.faces
        ));
    }
    let mut report = Report {
        flatcut_version: env!("CARGO_PKG_VERSION").into(),
        schema: SCHEMA,
        pipeline: p.name().into(),
        toml: FileHash {
            // The file name only: the report must not depend on where the run started.
            path: p.source.file_name().map_or_else(
                || p.source.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            ),
            sha256: sha256_hex(p.text.as_bytes()),
        },
        inputs: loaded.inputs,
        generator: loaded.generator,
        units: loaded.units.name().into(),
        input_mesh: MeshCounts {
            vertices: loaded.mesh.vertex_count(),
            faces: loaded.mesh.face_count(),
        },
        clean: clean_report,
        dropped_components: dropped,
        pieces: piece_reports,
        seam_table,
        files: Vec::new(),
        warnings,
    };
    let pictures: Vec<PiecePictures> = pieces
        .par_iter()
        .zip(&processed)
        .zip(&flat)
        .map(|((piece, pr), (topo, f))| pictures(piece, &pr.processed.mesh, topo, f))
        .collect();
    let html = report_html(
        &report,
        &pictures,
        files.get("sheet.svg").map(Vec::as_slice),
        p.spec.process.tolerance_rad,
    );
    files.insert("report.html".into(), html.into_bytes());
    report.files = files
        .iter()
        .map(|(name, bytes)| OutputFile {
            name: name.clone(),
            bytes: bytes.len(),
            sha256: sha256_hex(bytes),
        })
        .collect();
    bar.finish();
    stage_done(&mut timings, "outputs", t);
    timings.total_seconds = t0.elapsed().as_secs_f64();
    Ok(Computed {
        files,
        report,
        timings,
    })
}

/// The pattern stage's description of a piece from its `[[piece]]` entry.
fn piece_meta(spec: Option<&crate::spec::PieceSpec>) -> flatcut_pattern::PieceMeta {
    let Some(s) = spec else {
        return flatcut_pattern::PieceMeta::default();
    };
    let (along, across) = s
        .shrink
        .as_ref()
        .map_or((0.0, 0.0), |sh| sh.get_ref().values());
    flatcut_pattern::PieceMeta {
        size: s.size.clone(),
        quantity: s.quantity,
        mirror: s.mirror,
        fabric: s.fabric.clone(),
        // The flattening already placed the grain along +y (`flatten.placement.grain`).
        grain_3d: None,
        shrink_along_grain: along,
        shrink_across_grain: across,
    }
}

/// Width and height of the bounding box of `pts`.
fn extent(pts: &[[f64; 2]]) -> [f64; 2] {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in pts {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    if pts.is_empty() {
        [0.0; 2]
    } else {
        [hi[0] - lo[0], hi[1] - lo[1]]
    }
}

/// A feature curve's length and how far processing moved its vertices.
fn feature_summary(chain: &[u32], before: &TriMesh, after: &TriMesh) -> FeatureSummary {
    let p = |m: &TriMesh, v: u32| m.positions[v as usize];
    let d: Vec<f64> = chain
        .iter()
        .map(|&v| flatcut_mesh::vec3::dist(p(before, v), p(after, v)))
        .collect();
    FeatureSummary {
        vertices: chain.to_vec(),
        length_3d_mm: chain
            .windows(2)
            .map(|w| flatcut_mesh::vec3::dist(p(before, w[0]), p(before, w[1])))
            .sum(),
        max_displacement_mm: d.iter().copied().fold(0.0, f64::max),
        rms_displacement_mm: (d.iter().map(|x| x * x).sum::<f64>() / d.len().max(1) as f64).sqrt(),
    }
}

/// |θ − 2π| per vertex (0 on the boundary).
fn defect_field(mesh: &TriMesh, topo: &Topology) -> Vec<f64> {
    geometry::angle_defects(&mesh.positions, &mesh.faces, topo)
        .iter()
        .map(|d| d.map_or(0.0, f64::abs))
        .collect()
}

/// The report's pictures of one piece: before/after processing from the fixed views (framed
/// alike, one colour scale) and the pattern coloured by E_h.
fn pictures(piece: &PieceMesh, after: &TriMesh, topo: &Topology, f: &FlatPiece) -> PiecePictures {
    let before_field = defect_field(&piece.mesh, topo);
    let after_field = defect_field(after, topo);
    let defect_max = before_field.iter().copied().fold(0.0, f64::max);
    let mut before = Vec::new();
    let mut after_png = Vec::new();
    for v in &VIEWS {
        let frame = Frame::fit(&piece.mesh.positions, v);
        before.push(render_3d(&piece.mesh, &before_field, defect_max, v, &frame));
        after_png.push(render_3d(after, &after_field, defect_max, v, &frame));
    }
    let e_h_max = f.e_h.iter().copied().fold(0.0, f64::max);
    PiecePictures {
        before,
        after: after_png,
        defect_max,
        distortion: render_2d(&after.faces, &f.uv, &f.e_h, e_h_max),
        e_h_max,
        outline: topo
            .boundary_loops()
            .iter()
            .map(|lp| lp.iter().map(|v| f.uv[v.idx()]).collect())
            .collect(),
    }
}

/// All processed pieces in one GLB (metres, as glTF fixes), one group per piece, vertices
/// coloured by |θ − 2π| (0 on the boundary).
fn processed_glb(
    pieces: &[PieceMesh],
    processed: &[ProcessedPiece],
    flat: &[(Topology, FlatPiece)],
) -> Result<Vec<u8>, PipelineError> {
    let mut all = TriMesh::default();
    let mut scalar = Vec::new();
    let mut labels = FaceLabels::default();
    for (i, ((piece, pr), (topo, _))) in pieces.iter().zip(processed).zip(flat).enumerate() {
        let m = &pr.processed.mesh;
        let base = all.positions.len() as u32;
        all.positions.extend_from_slice(&m.positions);
        all.faces
            .extend(m.faces.iter().map(|f| f.map(|v| v + base)));
        scalar.extend(defect_field(m, topo));
        labels.names.push(piece.name.clone());
        labels
            .labels
            .extend(std::iter::repeat_n(i as u32, m.face_count()));
    }
    all.attributes.scalar = Some(scalar);
    all.face_labels = Some(labels);
    flatcut_io::write_mesh_to_vec(&all, Format::Glb, &WriteOptions::default()).map_err(|source| {
        PipelineError::Encode {
            name: "processed.glb".into(),
            source: Box::new(source),
        }
    })
}
