//! glTF 2.0 / GLB reader: every triangle primitive of every mesh instance in the default
//! scene (or in all scenes, or all root nodes), with node transforms applied.
//!
//! The `gltf` crate parses and validates the JSON; the GLB container, the buffers (data URIs,
//! external files, the BIN chunk) and the accessors are read here with bounds checks on every
//! access, because the crate's own readers can panic on out-of-range data.

use std::path::Path;

use flatcut_mesh::{FaceLabels, TriMesh};
use gltf::accessor::DataType;
use gltf::mesh::{Mode, Semantic};

use crate::{IoError, Parsed};

/// Node instances visited at most (a node may be referenced by several parents, which can
/// blow up exponentially in a malicious file).
const MAX_NODE_INSTANCES: usize = 1_000_000;
/// Vertices produced at most (1.2 GB of positions): instancing a mesh through many nodes
/// multiplies it, and a tiny file must not be able to ask for unbounded memory.
const MAX_OUTPUT_VERTICES: usize = 50_000_000;

pub(crate) fn read_glb(
    bytes: &[u8],
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<Parsed, IoError> {
    let (json, bin) = split_glb(bytes, path)?;
    let doc = parse_document(json, path, true)?;
    let buffers = load_buffers(&doc, bin, path, base_dir)?;
    extract(&doc, &buffers, path)
}

pub(crate) fn read_gltf(
    bytes: &[u8],
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<Parsed, IoError> {
    if bytes.starts_with(b"glTF") {
        return read_glb(bytes, path, base_dir);
    }
    let doc = parse_document(bytes, path, false)?;
    let buffers = load_buffers(&doc, None, path, base_dir)?;
    extract(&doc, &buffers, path)
}

fn u32_at(d: &[u8], at: usize) -> Option<u32> {
    let b = d.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB into its JSON and optional BIN chunk.
fn split_glb<'a>(d: &'a [u8], path: &Path) -> Result<(&'a [u8], Option<&'a [u8]>), IoError> {
    let bin_err = |offset: usize, reason: String| IoError::Binary {
        path: path.to_path_buf(),
        offset: offset as u64,
        reason,
    };
    let trunc = |what: &str, offset: usize, needed: usize| IoError::Truncated {
        path: path.to_path_buf(),
        what: what.to_string(),
        offset: offset as u64,
        needed: needed as u64,
        available: d.len().saturating_sub(offset) as u64,
    };
    if d.len() < 12 {
        return Err(trunc("the 12-byte GLB header", 0, 12));
    }
    if &d[0..4] != b"glTF" {
        return Err(bin_err(0, "not a GLB file: magic is not 'glTF'".into()));
    }
    let version = u32_at(d, 4).unwrap_or(0);
    if version != 2 {
        return Err(bin_err(
            4,
            format!("GLB version {version} is not supported (only glTF 2.0)"),
        ));
    }
    let length = u32_at(d, 8).unwrap_or(0) as usize;
    if length > d.len() {
        return Err(trunc("the GLB (length declared at byte 8)", 0, length));
    }
    let d = &d[..length.max(12)];
    let mut pos = 12;
    let mut json = None;
    let mut bin = None;
    while pos < d.len() {
        let (Some(len), Some(ty)) = (u32_at(d, pos), d.get(pos + 4..pos + 8)) else {
            return Err(trunc("a GLB chunk header", pos, 8));
        };
        let start = pos + 8;
        let Some(chunk) = start
            .checked_add(len as usize)
            .and_then(|end| d.get(start..end))
        else {
            return Err(trunc("a GLB chunk", start, len as usize));
        };
        match ty {
            b"JSON" if json.is_none() => json = Some(chunk),
            b"BIN\0" if bin.is_none() && json.is_some() => bin = Some(chunk),
            b"JSON" | b"BIN\0" => {
                return Err(bin_err(pos + 4, "duplicate or misplaced GLB chunk".into()));
            }
            _ => {} // unknown chunks must be ignored (glTF 2.0 §4.4.3)
        }
        pos = start + len as usize;
    }
    let Some(json) = json else {
        return Err(bin_err(12, "the GLB has no JSON chunk".into()));
    };
    Ok((json, bin))
}

fn parse_document(json: &[u8], path: &Path, in_glb: bool) -> Result<gltf::Document, IoError> {
    let root: gltf::json::Root = serde_json::from_slice(json).map_err(|e| {
        let reason = format!("invalid glTF JSON: {e}");
        if in_glb {
            IoError::Gltf {
                path: path.to_path_buf(),
                element: format!("JSON chunk line {}", e.line()),
                reason,
            }
        } else {
            IoError::Parse {
                path: path.to_path_buf(),
                line: e.line(),
                reason,
            }
        }
    })?;
    // Quantised attributes are read (normalised integers); anything else required, e.g.
    // Draco or meshopt compression, changes how buffers must be decoded.
    if let Some(ext) = root
        .extensions_required
        .iter()
        .find(|e| e.as_str() != "KHR_mesh_quantization")
    {
        return Err(IoError::Gltf {
            path: path.to_path_buf(),
            element: "extensionsRequired".into(),
            reason: format!(
                "requires extension '{ext}', which flatcut cannot decode; re-export without it"
            ),
        });
    }
    // gltf-json 1.4's validation indexes `accessors[POSITION]` without a bounds check;
    // check attribute indices first so that a dangling index is an error, not a panic.
    for (mi, m) in root.meshes.iter().enumerate() {
        for (pi, p) in m.primitives.iter().enumerate() {
            for (sem, acc) in &p.attributes {
                if acc.value() >= root.accessors.len() {
                    return Err(IoError::Gltf {
                        path: path.to_path_buf(),
                        element: format!("mesh {mi} primitive {pi}"),
                        reason: format!(
                            "attribute {sem:?} refers to accessor {}, but there are only {}; re-export the file",
                            acc.value(),
                            root.accessors.len()
                        ),
                    });
                }
            }
        }
    }
    gltf::Document::from_json(root).map_err(|e| IoError::Gltf {
        path: path.to_path_buf(),
        element: "document".into(),
        reason: format!("{e}; the file violates the glTF 2.0 schema (re-export it)"),
    })
}

fn load_buffers(
    doc: &gltf::Document,
    bin: Option<&[u8]>,
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<Vec<Vec<u8>>, IoError> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let element = format!("buffer {}", b.index());
        let gerr = |reason: String| IoError::Gltf {
            path: path.to_path_buf(),
            element: element.clone(),
            reason,
        };
        let data = match b.source() {
            gltf::buffer::Source::Bin => match bin {
                Some(d) => d.to_vec(),
                None => {
                    return Err(gerr(
                        "refers to the GLB BIN chunk, but there is none".into(),
                    ));
                }
            },
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let Some((_, b64)) = rest.split_once(";base64,") else {
                        return Err(gerr(
                            "data URI is not base64 ('data:...;base64,...')".into(),
                        ));
                    };
                    crate::base64::decode(b64.as_bytes()).map_err(|i| {
                        gerr(format!(
                            "invalid base64 character at position {i} of the data URI"
                        ))
                    })?
                } else if uri.contains("://") {
                    return Err(gerr(format!(
                        "external URI '{uri}' is not supported; only files next to the .gltf and data URIs"
                    )));
                } else {
                    let Some(dir) = base_dir else {
                        return Err(gerr(format!(
                            "refers to external file '{uri}', which cannot be resolved without a directory"
                        )));
                    };
                    let file = dir.join(percent_decode(uri));
                    std::fs::read(&file).map_err(|e| {
                        gerr(format!("cannot read external buffer '{}': {e}; keep the .bin next to the .gltf", file.display()))
                    })?
                }
            }
        };
        if data.len() < b.length() {
            return Err(gerr(format!(
                "declares {} bytes but only {} are present",
                b.length(),
                data.len()
            )));
        }
        out.push(data);
    }
    Ok(out)
}

fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && let Some(h) = b
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        {
            out.push(h);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// A bounds-checked view of an accessor's elements.
struct View<'a> {
    data: &'a [u8],
    start: usize,
    stride: usize,
    count: usize,
    ty: DataType,
    dims: usize,
    normalized: bool,
}

impl View<'_> {
    /// Component `k` of element `i` as f64 (normalised integers mapped to [0,1] / [-1,1]).
    /// Callers stay within `count` and `dims`, which `accessor_view` checked against the data.
    #[inline]
    fn get(&self, i: usize, k: usize) -> f64 {
        let at = self.start + i * self.stride + k * self.ty.size();
        let b = |n: usize| self.data.get(at..at + n).unwrap_or(&[0; 4][..n]);
        let raw = match self.ty {
            DataType::I8 => f64::from(b(1)[0] as i8),
            DataType::U8 => f64::from(b(1)[0]),
            DataType::I16 => f64::from(i16::from_le_bytes([b(2)[0], b(2)[1]])),
            DataType::U16 => f64::from(u16::from_le_bytes([b(2)[0], b(2)[1]])),
            DataType::U32 => {
                let x = b(4);
                f64::from(u32::from_le_bytes([x[0], x[1], x[2], x[3]]))
            }
            DataType::F32 => {
                let x = b(4);
                f64::from(f32::from_le_bytes([x[0], x[1], x[2], x[3]]))
            }
        };
        if !self.normalized {
            return raw;
        }
        match self.ty {
            DataType::I8 => (raw / 127.0).max(-1.0),
            DataType::U8 => raw / 255.0,
            DataType::I16 => (raw / 32767.0).max(-1.0),
            DataType::U16 => raw / 65535.0,
            _ => raw,
        }
    }
    #[inline]
    fn index(&self, i: usize) -> u64 {
        let at = self.start + i * self.stride;
        match self.ty {
            DataType::U8 => self.data.get(at).map_or(u64::MAX, |b| u64::from(*b)),
            DataType::U16 => self
                .data
                .get(at..at + 2)
                .map_or(u64::MAX, |b| u64::from(u16::from_le_bytes([b[0], b[1]]))),
            _ => self.data.get(at..at + 4).map_or(u64::MAX, |b| {
                u64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            }),
        }
    }
}

fn accessor_view<'a>(
    acc: &gltf::Accessor,
    buffers: &'a [Vec<u8>],
    path: &Path,
    what: &str,
) -> Result<View<'a>, IoError> {
    let gerr = |reason: String| IoError::Gltf {
        path: path.to_path_buf(),
        element: format!("accessor {} ({what})", acc.index()),
        reason,
    };
    if acc.sparse().is_some() {
        return Err(gerr(
            "sparse accessors are not supported; re-export without sparse data".into(),
        ));
    }
    let Some(view) = acc.view() else {
        return Err(gerr(
            "has no bufferView; re-export with explicit data".into(),
        ));
    };
    let data = buffers
        .get(view.buffer().index())
        .map(Vec::as_slice)
        .unwrap_or_default();
    let elem = acc.size();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(gerr(format!(
            "bufferView {} stride {stride} is smaller than the element size {elem}",
            view.index()
        )));
    }
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|e| e > data.len()) {
        return Err(gerr(format!(
            "bufferView {} (offset {}, length {}) lies outside buffer {} ({} bytes)",
            view.index(),
            view.offset(),
            view.length(),
            view.buffer().index(),
            data.len()
        )));
    }
    let Some(start) = view.offset().checked_add(acc.offset()) else {
        return Err(gerr("byte offset overflows".into()));
    };
    let count = acc.count();
    if count > 0 {
        let last = (count - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(start))
            .and_then(|x| x.checked_add(elem));
        if last.is_none_or(|l| Some(l) > view_end) {
            return Err(gerr(format!(
                "{count} elements of {elem} bytes (stride {stride}) from offset {} do not fit in bufferView {} ({} bytes); the accessor is out of bounds",
                acc.offset(),
                view.index(),
                view.length()
            )));
        }
    }
    Ok(View {
        data,
        start,
        stride,
        count,
        ty: acc.data_type(),
        dims: acc.dimensions().multiplicity(),
        normalized: acc.normalized(),
    })
}

type Mat = [[f64; 4]; 4]; // column-major, m[col][row]

const IDENTITY: Mat = [
    [1., 0., 0., 0.],
    [0., 1., 0., 0.],
    [0., 0., 1., 0.],
    [0., 0., 0., 1.],
];

fn mul(a: &Mat, b: &Mat) -> Mat {
    let mut r = [[0.0; 4]; 4];
    for (c, col) in r.iter_mut().enumerate() {
        for (row, v) in col.iter_mut().enumerate() {
            *v = (0..4).map(|k| a[k][row] * b[c][k]).sum();
        }
    }
    r
}

fn local_matrix(node: &gltf::Node) -> Mat {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => matrix.map(|c| c.map(f64::from)),
        gltf::scene::Transform::Decomposed {
            translation: t,
            rotation: q,
            scale: s,
        } => {
            let [x, y, z, w] = q.map(f64::from);
            let [sx, sy, sz] = s.map(f64::from);
            // Rotation matrix of the unit quaternion (x, y, z, w), columns scaled: T·R·S.
            let r = [
                [
                    1. - 2. * (y * y + z * z),
                    2. * (x * y + z * w),
                    2. * (x * z - y * w),
                ],
                [
                    2. * (x * y - z * w),
                    1. - 2. * (x * x + z * z),
                    2. * (y * z + x * w),
                ],
                [
                    2. * (x * z + y * w),
                    2. * (y * z - x * w),
                    1. - 2. * (x * x + y * y),
                ],
            ];
            [
                [r[0][0] * sx, r[0][1] * sx, r[0][2] * sx, 0.],
                [r[1][0] * sy, r[1][1] * sy, r[1][2] * sy, 0.],
                [r[2][0] * sz, r[2][1] * sz, r[2][2] * sz, 0.],
                [f64::from(t[0]), f64::from(t[1]), f64::from(t[2]), 1.],
            ]
        }
    }
}

fn det3(m: &Mat) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2])
        - m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2])
        + m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2])
}

fn extract(doc: &gltf::Document, buffers: &[Vec<u8>], path: &Path) -> Result<Parsed, IoError> {
    // Roots: the default scene, else every scene, else every node that is nobody's child.
    let mut roots: Vec<gltf::Node> = Vec::new();
    if let Some(s) = doc.default_scene() {
        roots.extend(s.nodes());
    } else if doc.scenes().len() > 0 {
        for s in doc.scenes() {
            roots.extend(s.nodes());
        }
    } else {
        let mut is_child = vec![false; doc.nodes().len()];
        for n in doc.nodes() {
            for c in n.children() {
                if let Some(f) = is_child.get_mut(c.index()) {
                    *f = true;
                }
            }
        }
        roots.extend(
            doc.nodes()
                .filter(|n| !is_child.get(n.index()).copied().unwrap_or(true)),
        );
    }
    let node_count = doc.nodes().len();
    let mut stack: Vec<(gltf::Node, Mat, bool, usize)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, IDENTITY, true, 0))
        .collect();
    let mut mesh = TriMesh::default();
    let mut colors: Vec<[f32; 4]> = Vec::new();
    let mut any_color = false;
    let mut labels: Vec<u32> = Vec::new();
    let mut names: Vec<String> = Vec::new();
    let mut warnings = Vec::new();
    let mut vertices_read = 0usize;
    let mut visited = 0usize;
    while let Some((node, parent, parent_identity, depth)) = stack.pop() {
        visited += 1;
        if depth > node_count || visited > MAX_NODE_INSTANCES {
            return Err(IoError::Gltf {
                path: path.to_path_buf(),
                element: format!("node {}", node.index()),
                reason: "the node hierarchy has a cycle or too many instances; re-export it".into(),
            });
        }
        let local = local_matrix(&node);
        let identity = parent_identity && local == IDENTITY;
        let world = if identity {
            IDENTITY
        } else {
            mul(&parent, &local)
        };
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, identity, depth + 1));
        }
        let Some(m) = node.mesh() else { continue };
        let flip = det3(&world) < 0.0;
        for prim in m.primitives() {
            let element = format!("mesh {} primitive {}", m.index(), prim.index());
            let gerr = |reason: String| IoError::Gltf {
                path: path.to_path_buf(),
                element: element.clone(),
                reason,
            };
            let mode = prim.mode();
            if matches!(
                mode,
                Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
            ) {
                warnings.push(format!(
                    "{element}: mode {mode:?} has no triangles; skipped"
                ));
                continue;
            }
            let Some(pos_acc) = prim.get(&Semantic::Positions) else {
                return Err(gerr("triangle primitive without POSITION".into()));
            };
            let pv = accessor_view(&pos_acc, buffers, path, "POSITION")?;
            if pv.dims != 3 {
                return Err(gerr("POSITION must be VEC3".into()));
            }
            let n = pv.count;
            let base = mesh.positions.len();
            if base.saturating_add(n) > MAX_OUTPUT_VERTICES {
                return Err(gerr(format!(
                    "the scene would expand to more than {MAX_OUTPUT_VERTICES} vertices (through node instancing); \
                     flatcut refuses to allocate that much"
                )));
            }
            vertices_read += n;
            mesh.positions.reserve(n);
            for i in 0..n {
                let p = [pv.get(i, 0), pv.get(i, 1), pv.get(i, 2)];
                if !p.iter().all(|c| c.is_finite()) {
                    return Err(gerr(format!(
                        "POSITION element {i} is not finite {p:?}; fix the source file"
                    )));
                }
                let p = if identity {
                    p
                } else {
                    let w = &world;
                    [0, 1, 2].map(|r| w[0][r] * p[0] + w[1][r] * p[1] + w[2][r] * p[2] + w[3][r])
                };
                mesh.positions.push(p);
            }
            // Colours: linear RGB(A), float or normalised integers.
            match prim.get(&Semantic::Colors(0)) {
                Some(ca) => {
                    let cv = accessor_view(&ca, buffers, path, "COLOR_0")?;
                    if cv.count != n || !(cv.dims == 3 || cv.dims == 4) {
                        return Err(gerr(format!(
                            "COLOR_0 has {} elements of {} components; needs {n} of 3 or 4",
                            cv.count, cv.dims
                        )));
                    }
                    if !any_color {
                        colors.resize(base, [1.0; 4]);
                        any_color = true;
                    }
                    for i in 0..n {
                        let a = if cv.dims == 4 {
                            cv.get(i, 3) as f32
                        } else {
                            1.0
                        };
                        colors.push([
                            cv.get(i, 0) as f32,
                            cv.get(i, 1) as f32,
                            cv.get(i, 2) as f32,
                            a,
                        ]);
                    }
                }
                None => {
                    if any_color {
                        colors.resize(base + n, [1.0; 4]);
                    }
                }
            }
            // Corner list.
            let corner_count;
            let idx_view = match prim.indices() {
                Some(ia) => {
                    if ia.dimensions().multiplicity() != 1
                        || !matches!(ia.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
                    {
                        return Err(gerr(format!(
                            "indices accessor {} must be SCALAR unsigned byte, short or int, found {:?} {:?}",
                            ia.index(),
                            ia.dimensions(),
                            ia.data_type()
                        )));
                    }
                    let v = accessor_view(&ia, buffers, path, "indices")?;
                    corner_count = v.count;
                    Some(v)
                }
                None => {
                    corner_count = n;
                    None
                }
            };
            if mesh.faces.len().saturating_add(corner_count) > 2 * MAX_OUTPUT_VERTICES {
                return Err(gerr(format!(
                    "the scene would expand to more than {} triangles (through node instancing); flatcut refuses to allocate that much",
                    2 * MAX_OUTPUT_VERTICES
                )));
            }
            let corner = |k: usize| -> Result<u32, IoError> {
                let i = match &idx_view {
                    Some(v) => v.index(k),
                    None => k as u64,
                };
                if i >= n as u64 {
                    return Err(gerr(format!(
                        "index {k} refers to vertex {i}, but POSITION has {n} elements"
                    )));
                }
                Ok((base as u64 + i) as u32)
            };
            let before = mesh.faces.len();
            let push = |t: [u32; 3], faces: &mut Vec<[u32; 3]>| {
                faces.push(if flip { [t[0], t[2], t[1]] } else { t });
            };
            match mode {
                Mode::Triangles => {
                    if corner_count % 3 != 0 {
                        warnings.push(format!("{element}: {corner_count} corners is not a multiple of 3; the last {} ignored", corner_count % 3));
                    }
                    mesh.faces.reserve(corner_count / 3);
                    for t in 0..corner_count / 3 {
                        push(
                            [corner(3 * t)?, corner(3 * t + 1)?, corner(3 * t + 2)?],
                            &mut mesh.faces,
                        );
                    }
                }
                Mode::TriangleStrip => {
                    for k in 2..corner_count.max(2) {
                        let (a, b, c) = (corner(k - 2)?, corner(k - 1)?, corner(k)?);
                        // Every other triangle of a strip is wound the other way.
                        push(
                            if k % 2 == 0 { [a, b, c] } else { [b, a, c] },
                            &mut mesh.faces,
                        );
                    }
                }
                _ => {
                    // TriangleFan
                    for k in 2..corner_count.max(2) {
                        push([corner(0)?, corner(k - 1)?, corner(k)?], &mut mesh.faces);
                    }
                }
            }
            let label = names.len() as u32;
            names.push(match (m.name(), m.primitives().len()) {
                (Some(nm), 1) => nm.to_string(),
                (Some(nm), _) => format!("{nm}/{}", prim.index()),
                (None, _) => element.clone(),
            });
            labels.resize(mesh.faces.len(), label);
            debug_assert!(mesh.faces.len() >= before);
        }
    }
    let faces_read = mesh.faces.len();
    if any_color {
        colors.resize(mesh.positions.len(), [1.0; 4]);
        mesh.attributes.colors = Some(colors);
    }
    if names.len() > 1 {
        mesh.face_labels = Some(FaceLabels { names, labels });
    }
    Ok(Parsed {
        mesh,
        vertices_read,
        faces_read,
        polygons_triangulated: 0,
        warnings,
    })
}
