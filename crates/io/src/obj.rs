//! Wavefront OBJ: hand-written reader (global vertex identity, line-numbered errors) and writer.
//!
//! Read: `v x y z [w]` and the common `v x y z r g b` colour extension; `f`/`fo` polygons
//! with `i`, `i/t`, `i//n`, `i/t/n` corners and negative (relative) indices, fan-triangulated;
//! `g`/`o` names become face labels. `vt`, `vn`, `vp`, `l`, `p`, `usemtl`, `mtllib`, `s` and
//! comments are ignored; other keywords are ignored with a warning.

use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;

use flatcut_mesh::{FaceLabels, TriMesh};

use crate::text::{Lines, parse_f64, parse_i64, show, tokens};
use crate::{IoError, Parsed, color};

/// Name given to faces before the first `g`/`o` statement (the OBJ specification's default group).
const DEFAULT_GROUP: &str = "default";

pub(crate) fn read(bytes: &[u8], path: &Path) -> Result<Parsed, IoError> {
    match parse(bytes, path, None) {
        Err(Forward) => {
            // A positive index beyond the vertices seen so far may be a forward reference,
            // which OBJ readers tolerate; only at the end is it known to be out of range.
            // Parse again with the final count to report the first offending line.
            let n = count_vertices(bytes);
            match parse(bytes, path, Some(n)) {
                Err(Located(e)) => Err(e),
                Err(Forward) | Ok(_) => Err(IoError::Parse {
                    path: path.to_path_buf(),
                    line: 0,
                    reason: "a face index is out of range".into(),
                }),
            }
        }
        Err(Located(e)) => Err(e),
        Ok(p) => Ok(p),
    }
}

enum Failure {
    Located(IoError),
    Forward,
}
use Failure::{Forward, Located};

impl From<IoError> for Failure {
    fn from(e: IoError) -> Self {
        Located(e)
    }
}

fn count_vertices(bytes: &[u8]) -> usize {
    Lines::new(bytes, 1)
        .filter(|(_, l)| tokens(l).next() == Some(b"v"))
        .count()
}

fn parse(bytes: &[u8], path: &Path, final_count: Option<usize>) -> Result<Parsed, Failure> {
    let err = |line: usize, reason: String| IoError::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    };
    // Sized by what the file could hold at most (a vertex line is at least 8 bytes); real
    // files are ~35 bytes per vertex and ~20 per face.
    let guess = bytes.len() / 48;
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(guess);
    let mut colors: Vec<[f32; 4]> = Vec::new();
    let mut colors_max = 0.0f64;
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(guess * 2);
    let mut labels: Option<Vec<u32>> = None;
    let mut names: Vec<String> = vec![DEFAULT_GROUP.to_string()];
    let mut name_ids: HashMap<String, u32> = HashMap::new();
    name_ids.insert(DEFAULT_GROUP.to_string(), 0);
    let mut current_label = 0u32;
    let mut corners: Vec<u32> = Vec::with_capacity(16);
    let mut faces_read = 0usize;
    let mut polygons = 0usize;
    let mut max_index: u64 = 0;
    let mut unknown: Vec<(String, usize, usize)> = Vec::new(); // keyword, first line, count
    let mut warnings = Vec::new();

    for (ln, raw) in Lines::new(bytes, 1) {
        let line = match raw.iter().position(|&b| b == b'#') {
            Some(i) => &raw[..i],
            None => raw,
        };
        let mut toks = tokens(line);
        let Some(key) = toks.next() else { continue };
        match key {
            b"v" => {
                let mut vals = [0.0f64; 7];
                let mut n = 0;
                for t in toks {
                    if n == 7 {
                        return Err(err(ln, "vertex line has more than 7 numbers; expected 'v x y z' (optionally 'w' or 'r g b')".into()).into());
                    }
                    let Some(x) = parse_f64(t) else {
                        return Err(err(
                            ln,
                            format!("vertex coordinate '{}' is not a number", show(t)),
                        )
                        .into());
                    };
                    vals[n] = x;
                    n += 1;
                }
                if n < 3 {
                    return Err(err(
                        ln,
                        format!("vertex has {n} coordinates, needs 3 ('v x y z')"),
                    )
                    .into());
                }
                if !(vals[0].is_finite() && vals[1].is_finite() && vals[2].is_finite()) {
                    return Err(err(
                        ln,
                        format!(
                            "vertex {} has a non-finite coordinate ({} {} {}); fix or remove it in the source file",
                            positions.len() + 1,
                            vals[0],
                            vals[1],
                            vals[2]
                        ),
                    )
                    .into());
                }
                if n >= 6 && colors.len() == positions.len() {
                    for c in &vals[3..6] {
                        colors_max = colors_max.max(*c);
                    }
                    colors.push([vals[3] as f32, vals[4] as f32, vals[5] as f32, 1.0]);
                }
                positions.push([vals[0], vals[1], vals[2]]);
            }
            b"f" | b"fo" => {
                corners.clear();
                let count = positions.len() as i64;
                for t in toks {
                    let idx_tok = match t.iter().position(|&b| b == b'/') {
                        Some(i) => &t[..i],
                        None => t,
                    };
                    let Some(i) = parse_i64(idx_tok) else {
                        return Err(err(
                            ln,
                            format!("face corner '{}' is not a vertex index", show(t)),
                        )
                        .into());
                    };
                    let zero_based = if i > 0 {
                        i - 1
                    } else if i < 0 {
                        let r = count + i;
                        if r < 0 {
                            return Err(err(
                                ln,
                                format!("relative index {i} points before the first vertex (only {count} vertices defined so far)"),
                            )
                            .into());
                        }
                        r
                    } else {
                        return Err(err(
                            ln,
                            "face index 0 is invalid (OBJ indices start at 1)".into(),
                        )
                        .into());
                    };
                    if let Some(n) = final_count
                        && zero_based as u64 >= n as u64
                    {
                        return Err(err(
                            ln,
                            format!(
                                "face refers to vertex {} but the file has only {n} vertices",
                                zero_based + 1
                            ),
                        )
                        .into());
                    }
                    if zero_based > i64::from(u32::MAX - 1) {
                        return Err(err(
                            ln,
                            format!("vertex index {i} exceeds the u32 range flatcut supports"),
                        )
                        .into());
                    }
                    max_index = max_index.max(zero_based as u64);
                    corners.push(zero_based as u32);
                }
                if corners.len() < 3 {
                    return Err(err(
                        ln,
                        format!("face has {} corners, needs at least 3; remove the line or repair the export", corners.len()),
                    )
                    .into());
                }
                faces_read += 1;
                if corners.len() > 3 {
                    polygons += 1;
                }
                let a = corners[0];
                for w in corners[1..].windows(2) {
                    faces.push([a, w[0], w[1]]);
                }
                if let Some(l) = labels.as_mut() {
                    l.resize(faces.len(), current_label);
                }
            }
            b"g" | b"o" => {
                let name = toks
                    .map(|t| String::from_utf8_lossy(t).into_owned())
                    .collect::<Vec<_>>()
                    .join(" ");
                let name = if name.is_empty() {
                    DEFAULT_GROUP.to_string()
                } else {
                    name
                };
                let next = names.len() as u32;
                current_label = *name_ids.entry(name.clone()).or_insert_with(|| {
                    names.push(name);
                    next
                });
                if labels.is_none() {
                    labels = Some(vec![0; faces.len()]);
                }
            }
            b"vt" | b"vn" | b"vp" | b"l" | b"p" | b"usemtl" | b"mtllib" | b"s" | b"usemap"
            | b"maplib" | b"lod" => {}
            other => {
                let k = show(other);
                match unknown.iter_mut().find(|(u, _, _)| *u == k) {
                    Some(e) => e.2 += 1,
                    None => unknown.push((k, ln, 1)),
                }
            }
        }
    }
    if max_index >= positions.len() as u64 && !faces.is_empty() {
        return Err(Forward);
    }
    for (k, first, n) in unknown {
        warnings.push(format!(
            "{n} line(s) with unknown keyword '{k}' ignored (first at line {first})"
        ));
    }
    let colors = if colors.is_empty() {
        None
    } else if colors.len() != positions.len() {
        warnings.push(format!(
            "only {} of {} vertices have colours; colours dropped",
            colors.len(),
            positions.len()
        ));
        None
    } else {
        // Most writers use 0..1; some use 0..255.
        let scale = if colors_max > 1.0 {
            warnings.push("vertex colours exceed 1; read as 0..255".into());
            1.0 / 255.0
        } else {
            1.0
        };
        for c in &mut colors {
            for v in &mut c[..3] {
                *v = color::srgb_to_linear((*v * scale).clamp(0.0, 1.0));
            }
        }
        Some(colors)
    };
    let face_labels = labels.map(|mut labels| {
        labels.resize(faces.len(), current_label);
        // The default group exists only if some face came before the first `g`/`o`.
        if !labels.contains(&0) {
            names.remove(0);
            for l in &mut labels {
                *l -= 1;
            }
        }
        FaceLabels { names, labels }
    });
    let vertices_read = positions.len();
    let mut mesh = TriMesh {
        positions,
        faces,
        face_labels,
        ..Default::default()
    };
    mesh.attributes.colors = colors;
    Ok(Parsed {
        mesh,
        vertices_read,
        faces_read,
        polygons_triangulated: polygons,
        warnings,
    })
}

/// Writes `v` lines (shortest round-trip decimals), `vt` lines when the mesh has texcoords
/// (a flattening, in the same units as `v`), then `f` lines (1-based, `v/vt` when texcoords
/// are present), with a `g` line whenever the face label changes.
pub(crate) fn write(w: &mut dyn Write, mesh: &TriMesh) -> io::Result<()> {
    writeln!(
        w,
        "# written by flatcut: {} vertices, {} triangles",
        mesh.positions.len(),
        mesh.faces.len()
    )?;
    for p in &mesh.positions {
        writeln!(w, "v {:?} {:?} {:?}", p[0], p[1], p[2])?;
    }
    let texcoords = mesh
        .attributes
        .texcoords
        .as_ref()
        .filter(|t| t.len() == mesh.positions.len());
    if let Some(t) = texcoords {
        for uv in t {
            writeln!(w, "vt {:?} {:?}", uv[0], uv[1])?;
        }
    }
    let labels = mesh
        .face_labels
        .as_ref()
        .filter(|l| l.labels.len() == mesh.faces.len());
    let mut last = None;
    for (f, t) in mesh.faces.iter().enumerate() {
        if let Some(l) = labels {
            let id = l.labels[f];
            if last != Some(id) {
                let name = l
                    .names
                    .get(id as usize)
                    .map_or(DEFAULT_GROUP, String::as_str);
                // A newline would end the statement and '#' would start a comment.
                let name: String = name
                    .chars()
                    .map(|c| {
                        if c.is_control() {
                            ' '
                        } else if c == '#' {
                            '_'
                        } else {
                            c
                        }
                    })
                    .collect();
                writeln!(w, "g {}", name.trim())?;
                last = Some(id);
            }
        }
        let [a, b, c] = [t[0] + 1, t[1] + 1, t[2] + 1];
        if texcoords.is_some() {
            writeln!(w, "f {a}/{a} {b}/{b} {c}/{c}")?;
        } else {
            writeln!(w, "f {a} {b} {c}")?;
        }
    }
    Ok(())
}
