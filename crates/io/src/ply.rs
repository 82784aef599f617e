//! Stanford PLY: hand-written reader (ASCII, binary little and big endian) and binary writer.
//!
//! Any property order, extra properties and extra elements; every scalar type (also the
//! `int8`-style aliases); list count types must be integers. Faces are the list property
//! `vertex_indices` (or `vertex_index`) of element `face`, fan-triangulated. Vertex colours
//! `red`/`green`/`blue`[/`alpha`] (integer types normalised by their maximum, floats taken
//! as 0..1) are sRGB and converted to linear.

use std::io::{self, Write};
use std::path::Path;

use flatcut_mesh::TriMesh;

use crate::text::{is_space, parse_f64, parse_i64, show};
use crate::{IoError, Parsed, color};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &[u8]) -> Option<Scalar> {
        Some(match s {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn is_int(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
    /// The value 1.0 of a colour component stored in this type.
    fn color_full_scale(self) -> f64 {
        match self {
            Scalar::I8 => 127.0,
            Scalar::U8 => 255.0,
            Scalar::I16 => 32767.0,
            Scalar::U16 => 65535.0,
            Scalar::I32 => 2_147_483_647.0,
            Scalar::U32 => 4_294_967_295.0,
            Scalar::F32 | Scalar::F64 => 1.0,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List(Scalar, Scalar),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Skip,
    Coord(usize),
    Color(usize),
    Indices,
}

#[derive(Debug)]
struct Property {
    name: String,
    kind: Kind,
    role: Role,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    line: usize,
    props: Vec<Property>,
}

impl Element {
    /// Smallest possible binary record (lists empty).
    fn min_record(&self) -> usize {
        self.props
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(s) => s.size(),
                Kind::List(c, _) => c.size(),
            })
            .sum()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Le,
    Be,
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    body_start: usize,
    body_line: usize,
}

fn parse_header(bytes: &[u8], path: &Path) -> Result<Header, IoError> {
    let err = |line: usize, reason: String| IoError::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    };
    if bytes.is_empty() {
        return Err(err(
            1,
            "empty file; expected a PLY header starting with 'ply'".into(),
        ));
    }
    let mut pos = 0usize;
    let mut line_no = 0usize;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        line_no += 1;
        let Some(nl) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(err(
                line_no,
                "the PLY header never ends: 'end_header' is missing".into(),
            ));
        };
        let mut line = &bytes[pos..pos + nl];
        pos += nl + 1;
        if let [head @ .., b'\r'] = line {
            line = head;
        }
        let toks: Vec<&[u8]> = line
            .split(|&b| is_space(b))
            .filter(|t| !t.is_empty())
            .collect();
        if line_no == 1 {
            if toks.as_slice() != [b"ply"] {
                return Err(err(
                    1,
                    format!(
                        "not a PLY file: first line is '{}', expected 'ply'",
                        show(line)
                    ),
                ));
            }
            continue;
        }
        match toks.as_slice() {
            [] => {}
            [b"comment" | b"obj_info", ..] => {}
            [b"format", f, v] => {
                if *v != b"1.0" {
                    return Err(err(
                        line_no,
                        format!("PLY version '{}' is not supported (only 1.0)", show(v)),
                    ));
                }
                encoding = Some(match *f {
                    b"ascii" => Encoding::Ascii,
                    b"binary_little_endian" => Encoding::Le,
                    b"binary_big_endian" => Encoding::Be,
                    _ => {
                        return Err(err(
                            line_no,
                            format!(
                                "unknown PLY format '{}'; expected ascii, binary_little_endian or binary_big_endian",
                                show(f)
                            ),
                        ));
                    }
                });
            }
            [b"element", name, count] => {
                let Some(count) = parse_i64(count).filter(|c| *c >= 0) else {
                    return Err(err(
                        line_no,
                        format!(
                            "element count '{}' is not a non-negative integer",
                            show(count)
                        ),
                    ));
                };
                elements.push(Element {
                    name: String::from_utf8_lossy(name).into_owned(),
                    count: count as u64,
                    line: line_no,
                    props: Vec::new(),
                });
            }
            [b"property", b"list", ct, it, name] => {
                let Some(el) = elements.last_mut() else {
                    return Err(err(line_no, "property before any element".into()));
                };
                let (Some(c), Some(i)) = (Scalar::parse(ct), Scalar::parse(it)) else {
                    return Err(err(line_no, format!("unknown type in '{}'", show(line))));
                };
                if !c.is_int() {
                    return Err(err(
                        line_no,
                        format!(
                            "list count type '{}' of property '{}' must be an integer type",
                            show(ct),
                            show(name)
                        ),
                    ));
                }
                el.props.push(Property {
                    name: String::from_utf8_lossy(name).into_owned(),
                    kind: Kind::List(c, i),
                    role: Role::Skip,
                });
            }
            [b"property", ty, name] => {
                let Some(el) = elements.last_mut() else {
                    return Err(err(line_no, "property before any element".into()));
                };
                let Some(t) = Scalar::parse(ty) else {
                    return Err(err(
                        line_no,
                        format!("unknown property type '{}'", show(ty)),
                    ));
                };
                el.props.push(Property {
                    name: String::from_utf8_lossy(name).into_owned(),
                    kind: Kind::Scalar(t),
                    role: Role::Skip,
                });
            }
            [b"end_header"] => break,
            _ => {
                return Err(err(
                    line_no,
                    format!("cannot understand PLY header line '{}'", show(line)),
                ));
            }
        }
    }
    let Some(encoding) = encoding else {
        return Err(err(line_no, "the PLY header has no 'format' line".into()));
    };
    Ok(Header {
        encoding,
        elements,
        body_start: pos,
        body_line: line_no + 1,
    })
}

/// Assigns roles to the properties of the vertex and face elements.
fn assign_roles(h: &mut Header, path: &Path) -> Result<(), IoError> {
    let err = |line: usize, reason: String| IoError::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    };
    for el in &mut h.elements {
        if el.name == "vertex" {
            for p in &mut el.props {
                let role = match p.name.as_str() {
                    "x" => Role::Coord(0),
                    "y" => Role::Coord(1),
                    "z" => Role::Coord(2),
                    "red" | "r" | "diffuse_red" => Role::Color(0),
                    "green" | "g" | "diffuse_green" => Role::Color(1),
                    "blue" | "b" | "diffuse_blue" => Role::Color(2),
                    "alpha" | "a" | "diffuse_alpha" => Role::Color(3),
                    _ => Role::Skip,
                };
                if role != Role::Skip && matches!(p.kind, Kind::List(..)) {
                    return Err(err(
                        el.line,
                        format!("vertex property '{}' is a list, expected a scalar", p.name),
                    ));
                }
                p.role = role;
            }
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                if !el.props.iter().any(|p| p.role == Role::Coord(k)) {
                    return Err(err(
                        el.line,
                        format!("element vertex has no property '{axis}'"),
                    ));
                }
            }
        } else if el.name == "face" {
            let mut found = false;
            for p in &mut el.props {
                if !found && (p.name == "vertex_indices" || p.name == "vertex_index") {
                    let Kind::List(_, it) = p.kind else {
                        return Err(err(
                            el.line,
                            format!("face property '{}' must be a list", p.name),
                        ));
                    };
                    if !it.is_int() {
                        return Err(err(
                            el.line,
                            format!("face property '{}' has non-integer index type", p.name),
                        ));
                    }
                    p.role = Role::Indices;
                    found = true;
                }
            }
            if !found && el.count > 0 {
                return Err(err(
                    el.line,
                    "element face has no list property 'vertex_indices' (or 'vertex_index')".into(),
                ));
            }
        }
    }
    Ok(())
}

/// Accumulates what the elements deliver.
struct Sink {
    positions: Vec<[f64; 3]>,
    colors: Vec<[f32; 4]>,
    has_color: [bool; 4],
    color_scale: [f64; 4],
    faces: Vec<[u32; 3]>,
    faces_read: usize,
    polygons: usize,
    vertex_count: u64,
    corners: Vec<i64>,
}

impl Sink {
    /// Adds one polygon; returns an error reason if it is malformed.
    fn polygon(&mut self) -> Result<(), String> {
        let c = &self.corners;
        if c.len() < 3 {
            return Err(format!("face has {} corners, needs at least 3", c.len()));
        }
        for &i in c {
            if i < 0 || i as u64 >= self.vertex_count || i > i64::from(u32::MAX) {
                return Err(format!(
                    "face refers to vertex {i}, but the file has {} vertices (indices start at 0)",
                    self.vertex_count
                ));
            }
        }
        self.faces_read += 1;
        if c.len() > 3 {
            self.polygons += 1;
        }
        let a = c[0] as u32;
        for w in c[1..].windows(2) {
            self.faces.push([a, w[0] as u32, w[1] as u32]);
        }
        Ok(())
    }
}

pub(crate) fn read(bytes: &[u8], path: &Path) -> Result<Parsed, IoError> {
    let mut h = parse_header(bytes, path)?;
    assign_roles(&mut h, path)?;
    let vertex_count = h
        .elements
        .iter()
        .find(|e| e.name == "vertex")
        .map_or(0, |e| e.count);
    let mut has_color = [false; 4];
    let mut color_scale = [1.0; 4];
    if let Some(v) = h.elements.iter().find(|e| e.name == "vertex") {
        for p in &v.props {
            if let (Role::Color(k), Kind::Scalar(s)) = (p.role, p.kind) {
                has_color[k] = true;
                color_scale[k] = s.color_full_scale();
            }
        }
    }
    let mut sink = Sink {
        positions: Vec::new(),
        colors: Vec::new(),
        has_color,
        color_scale,
        faces: Vec::new(),
        faces_read: 0,
        polygons: 0,
        vertex_count,
        corners: Vec::with_capacity(16),
    };
    let mut warnings = Vec::new();
    for el in &h.elements {
        if el.name != "vertex" && el.name != "face" && el.count > 0 {
            warnings.push(format!(
                "element '{}' ({} records, header line {}) ignored",
                el.name, el.count, el.line
            ));
        }
    }
    match h.encoding {
        Encoding::Ascii => read_ascii(bytes, &h, path, &mut sink)?,
        Encoding::Le => read_binary::<false>(bytes, &h, path, &mut sink)?,
        Encoding::Be => read_binary::<true>(bytes, &h, path, &mut sink)?,
    }
    let Sink {
        positions,
        colors,
        has_color,
        faces,
        faces_read,
        polygons,
        ..
    } = sink;
    let colors = if has_color[0] && has_color[1] && has_color[2] {
        Some(colors)
    } else {
        if has_color.iter().any(|c| *c) {
            warnings.push(
                "vertex colours incomplete (need red, green and blue); colours dropped".into(),
            );
        }
        None
    };
    let vertices_read = positions.len();
    let mut mesh = TriMesh {
        positions,
        faces,
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

fn finish_vertex(sink: &mut Sink, xyz: [f64; 3], rgba: [f64; 4]) -> Result<(), String> {
    if !xyz.iter().all(|c| c.is_finite()) {
        return Err(format!(
            "non-finite coordinate ({} {} {}); fix or remove it in the source file",
            xyz[0], xyz[1], xyz[2]
        ));
    }
    sink.positions.push(xyz);
    if sink.has_color[0] {
        let mut c = [0.0f32; 4];
        for k in 0..3 {
            c[k] = color::srgb_to_linear(((rgba[k] / sink.color_scale[k]).clamp(0.0, 1.0)) as f32);
        }
        c[3] = if sink.has_color[3] {
            ((rgba[3] / sink.color_scale[3]).clamp(0.0, 1.0)) as f32
        } else {
            1.0
        };
        sink.colors.push(c);
    }
    Ok(())
}

/// Reserves for `count` records but never more than the remaining bytes could hold.
fn capped(count: u64, remaining: usize, min_record: usize) -> usize {
    let cap = remaining / min_record.max(1);
    (count.min(cap as u64)) as usize
}

fn read_ascii(bytes: &[u8], h: &Header, path: &Path, sink: &mut Sink) -> Result<(), IoError> {
    let body = bytes.get(h.body_start..).unwrap_or_default();
    let mut toks = AsciiTokens {
        data: body,
        pos: 0,
        line: h.body_line,
    };
    let err = |line: usize, reason: String| IoError::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    };
    for el in &h.elements {
        let is_vertex = el.name == "vertex";
        let is_face = el.name == "face";
        if is_vertex {
            let n = capped(el.count, body.len(), 2 * el.props.len());
            sink.positions.reserve(n);
            if sink.has_color[0] {
                sink.colors.reserve(n);
            }
        } else if is_face {
            sink.faces.reserve(capped(el.count, body.len(), 8));
        }
        if el.props.is_empty() {
            // Records without properties take no bytes; do not loop over a huge count.
            continue;
        }
        for rec in 0..el.count {
            let mut xyz = [0.0; 3];
            let mut rgba = [0.0; 4];
            let mut rec_line = 0;
            for (pi, p) in el.props.iter().enumerate() {
                let mut next = |what: &str| {
                    toks.next().ok_or_else(|| {
                        err(
                            toks.line,
                            format!(
                                "file ends inside {} {rec} ({what} of property '{}'), but the header (line {}) promises {} records; values are missing",
                                el.name, p.name, el.line, el.count
                            ),
                        )
                    })
                };
                match p.kind {
                    Kind::Scalar(s) => {
                        let (line, t) = next("value")?;
                        if pi == 0 {
                            rec_line = line;
                        }
                        let v = parse_ascii_scalar(t, s).ok_or_else(|| {
                            err(
                                line,
                                format!(
                                    "'{}' is not a valid {:?} for property '{}'",
                                    show(t),
                                    s,
                                    p.name
                                ),
                            )
                        })?;
                        match p.role {
                            Role::Coord(k) => xyz[k] = v,
                            Role::Color(k) => rgba[k] = v,
                            _ => {}
                        }
                    }
                    Kind::List(ct, it) => {
                        let (line, t) = next("list count")?;
                        if pi == 0 {
                            rec_line = line;
                        }
                        let n = parse_ascii_scalar(t, ct)
                            .filter(|n| *n >= 0.0)
                            .ok_or_else(|| err(line, format!("list count '{}' of property '{}' is not a non-negative integer", show(t), p.name)))?
                            as usize;
                        if p.role == Role::Indices {
                            sink.corners.clear();
                        }
                        for _ in 0..n {
                            let (line, t) = next("list item")?;
                            let v = parse_ascii_scalar(t, it).ok_or_else(|| {
                                err(
                                    line,
                                    format!(
                                        "'{}' is not a valid {:?} in list '{}'",
                                        show(t),
                                        it,
                                        p.name
                                    ),
                                )
                            })?;
                            if p.role == Role::Indices {
                                sink.corners.push(v as i64);
                            }
                        }
                    }
                }
            }
            if is_vertex {
                finish_vertex(sink, xyz, rgba)
                    .map_err(|r| err(rec_line, format!("vertex {rec}: {r}")))?;
            } else if is_face {
                sink.polygon()
                    .map_err(|r| err(rec_line, format!("face {rec}: {r}")))?;
            }
        }
    }
    Ok(())
}

fn parse_ascii_scalar(t: &[u8], s: Scalar) -> Option<f64> {
    if s.is_int() {
        let v = parse_i64(t)?;
        let ok = match s {
            Scalar::I8 => i8::try_from(v).is_ok(),
            Scalar::U8 => u8::try_from(v).is_ok(),
            Scalar::I16 => i16::try_from(v).is_ok(),
            Scalar::U16 => u16::try_from(v).is_ok(),
            Scalar::I32 => i32::try_from(v).is_ok(),
            _ => u32::try_from(v).is_ok(),
        };
        ok.then_some(v as f64)
    } else {
        parse_f64(t)
    }
}

struct AsciiTokens<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> AsciiTokens<'a> {
    fn next(&mut self) -> Option<(usize, &'a [u8])> {
        let d = self.data;
        let mut i = self.pos;
        while i < d.len() && (is_space(d[i]) || d[i] == b'\n') {
            if d[i] == b'\n' {
                self.line += 1;
            }
            i += 1;
        }
        if i >= d.len() {
            self.pos = i;
            return None;
        }
        let start = i;
        while i < d.len() && !is_space(d[i]) && d[i] != b'\n' {
            i += 1;
        }
        self.pos = i;
        Some((self.line, &d[start..i]))
    }
}

/// Reads one scalar at `pos` as f64 (exact for every PLY type); `None` if out of bytes.
#[inline]
fn read_scalar<const BE: bool>(d: &[u8], pos: usize, s: Scalar) -> Option<f64> {
    macro_rules! rd {
        ($t:ty, $n:expr) => {{
            let b: [u8; $n] = d.get(pos..pos + $n)?.try_into().ok()?;
            (if BE {
                <$t>::from_be_bytes(b)
            } else {
                <$t>::from_le_bytes(b)
            }) as f64
        }};
    }
    Some(match s {
        Scalar::I8 => f64::from(*d.get(pos)? as i8),
        Scalar::U8 => f64::from(*d.get(pos)?),
        Scalar::I16 => rd!(i16, 2),
        Scalar::U16 => rd!(u16, 2),
        Scalar::I32 => rd!(i32, 4),
        Scalar::U32 => rd!(u32, 4),
        Scalar::F32 => rd!(f32, 4),
        Scalar::F64 => rd!(f64, 8),
    })
}

fn read_binary<const BE: bool>(
    bytes: &[u8],
    h: &Header,
    path: &Path,
    sink: &mut Sink,
) -> Result<(), IoError> {
    let d = bytes;
    let mut pos = h.body_start;
    for el in &h.elements {
        let min_rec = el.min_record();
        let remaining = d.len().saturating_sub(pos);
        let needed = el.count.saturating_mul(min_rec as u64);
        if needed > remaining as u64 {
            return Err(IoError::Truncated {
                path: path.to_path_buf(),
                what: format!(
                    "element '{}' ({} records of at least {min_rec} bytes, header line {})",
                    el.name, el.count, el.line
                ),
                offset: pos as u64,
                needed,
                available: remaining as u64,
            });
        }
        let is_vertex = el.name == "vertex";
        let is_face = el.name == "face";
        if is_vertex {
            sink.positions.reserve(el.count as usize);
            if sink.has_color[0] {
                sink.colors.reserve(el.count as usize);
            }
        } else if is_face {
            sink.faces.reserve(el.count as usize);
        }
        let truncated_n = |rec: u64, at: usize, what: &str, needed: u64| IoError::Truncated {
            path: path.to_path_buf(),
            what: format!("{} {rec} ({what})", el.name),
            offset: at as u64,
            needed,
            available: d.len().saturating_sub(at) as u64,
        };
        let truncated = |rec: u64, at: usize, what: &str| truncated_n(rec, at, what, 1);
        if el.props.is_empty() {
            continue;
        }
        for rec in 0..el.count {
            let rec_start = pos;
            let mut xyz = [0.0; 3];
            let mut rgba = [0.0; 4];
            for p in &el.props {
                match p.kind {
                    Kind::Scalar(s) => {
                        if p.role != Role::Skip {
                            let v = read_scalar::<BE>(d, pos, s)
                                .ok_or_else(|| truncated(rec, pos, &p.name))?;
                            match p.role {
                                Role::Coord(k) => xyz[k] = v,
                                Role::Color(k) => rgba[k] = v,
                                _ => {}
                            }
                        }
                        pos += s.size();
                    }
                    Kind::List(ct, it) => {
                        let n = read_scalar::<BE>(d, pos, ct)
                            .ok_or_else(|| truncated(rec, pos, &p.name))?;
                        if n < 0.0 {
                            return Err(IoError::Binary {
                                path: path.to_path_buf(),
                                offset: pos as u64,
                                reason: format!(
                                    "{} {rec}: negative list count {n} for '{}'",
                                    el.name, p.name
                                ),
                            });
                        }
                        let n = n as usize;
                        pos += ct.size();
                        let end = pos.saturating_add(n.saturating_mul(it.size()));
                        if end > d.len() {
                            let what = format!("{n} items of list '{}'", p.name);
                            return Err(truncated_n(
                                rec,
                                pos,
                                &what,
                                (n as u64).saturating_mul(it.size() as u64),
                            ));
                        }
                        if p.role == Role::Indices {
                            sink.corners.clear();
                            for k in 0..n {
                                let v = read_scalar::<BE>(d, pos + k * it.size(), it)
                                    .ok_or_else(|| truncated(rec, pos, &p.name))?;
                                sink.corners.push(v as i64);
                            }
                        }
                        pos = end;
                    }
                }
            }
            if is_vertex {
                finish_vertex(sink, xyz, rgba).map_err(|r| IoError::Binary {
                    path: path.to_path_buf(),
                    offset: rec_start as u64,
                    reason: format!("vertex {rec}: {r}"),
                })?;
            } else if is_face {
                sink.polygon().map_err(|r| IoError::Binary {
                    path: path.to_path_buf(),
                    offset: rec_start as u64,
                    reason: format!("face {rec}: {r}"),
                })?;
            }
        }
    }
    Ok(())
}

/// Binary little-endian PLY: double x/y/z, uchar RGBA (sRGB) when colours are present,
/// `list uchar int vertex_indices`.
pub(crate) fn write(w: &mut dyn Write, mesh: &TriMesh) -> io::Result<()> {
    let colors = mesh
        .attributes
        .colors
        .as_ref()
        .filter(|c| c.len() == mesh.positions.len());
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by flatcut\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\n",
        mesh.positions.len()
    );
    if colors.is_some() {
        header.push_str(
            "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n",
        );
    }
    // `int` indices as most tools expect; `uint` only when a signed index could not hold them.
    let index_type = if mesh.positions.len() > i32::MAX as usize {
        "uint"
    } else {
        "int"
    };
    header.push_str(&format!(
        "element face {}\nproperty list uchar {index_type} vertex_indices\nend_header\n",
        mesh.faces.len()
    ));
    w.write_all(header.as_bytes())?;
    let mut buf = Vec::with_capacity(1 << 16);
    for (i, p) in mesh.positions.iter().enumerate() {
        for c in p {
            buf.extend_from_slice(&c.to_le_bytes());
        }
        if let Some(cs) = colors {
            let c = cs[i];
            buf.extend_from_slice(&[
                color::linear_to_u8(c[0]),
                color::linear_to_u8(c[1]),
                color::linear_to_u8(c[2]),
                (c[3].clamp(0.0, 1.0) * 255.0).round() as u8,
            ]);
        }
        if buf.len() > 60_000 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    for f in &mesh.faces {
        buf.push(3);
        for &i in f {
            buf.extend_from_slice(&i.to_le_bytes()); // same bytes as i32 below 2³¹
        }
        if buf.len() > 60_000 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}
