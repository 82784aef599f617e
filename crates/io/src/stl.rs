//! STL: hand-written reader (binary and ASCII, welded by exact position) and binary writer.
//!
//! Binary vs ASCII: a file whose size is exactly `84 + 50·n` (n = the facet count at byte
//! 80) is binary, even if it starts with "solid" (many exporters write that into the binary
//! header). Otherwise a file starting with "solid" whose first lines contain "facet" or
//! "endsolid" is ASCII; anything else is treated as (broken) binary and reported.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::io::{self, Write};
use std::path::Path;

use flatcut_mesh::TriMesh;

use crate::text::{Lines, parse_f64, show, tokens};
use crate::{IoError, Parsed};

const HEADER: usize = 80;
const FACET: usize = 50;

/// A fast multiplicative hasher for bit patterns of coordinates (the std SipHash would
/// dominate the read time of large binary STL files; keys here are not attacker-chosen in a
/// way that matters: a pathological file only makes welding slower).
#[derive(Default)]
struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_u32(&mut self, v: u32) {
        self.write_u64(u64::from(v));
    }
    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }
}

type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<BitsHasher>>;

/// Welds corners by exact position (−0.0 and +0.0 are the same position).
struct Welder<K> {
    map: FastMap<K, u32>,
    positions: Vec<[f64; 3]>,
}

impl<K: std::hash::Hash + Eq> Welder<K> {
    fn with_capacity(n: usize) -> Self {
        let mut map = FastMap::default();
        map.reserve(n);
        Welder {
            map,
            positions: Vec::with_capacity(n),
        }
    }
    #[inline]
    fn add(&mut self, key: K, p: [f64; 3]) -> u32 {
        let next = self.positions.len() as u32;
        let positions = &mut self.positions;
        *self.map.entry(key).or_insert_with(|| {
            positions.push(p);
            next
        })
    }
}

pub(crate) fn read(bytes: &[u8], path: &Path) -> Result<Parsed, IoError> {
    if bytes.is_empty() {
        return Err(IoError::Parse {
            path: path.to_path_buf(),
            line: 1,
            reason: "empty file; expected an STL solid".into(),
        });
    }
    let declared = bytes
        .get(HEADER..HEADER + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    let binary_size_matches = declared
        .is_some_and(|n| (HEADER + 4) as u64 + FACET as u64 * u64::from(n) == bytes.len() as u64);
    if !binary_size_matches && looks_ascii(bytes) {
        return read_ascii(bytes, path);
    }
    read_binary(bytes, path)
}

fn looks_ascii(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    if !bytes[start..].starts_with(b"solid") {
        return false;
    }
    let head = &bytes[..bytes.len().min(1024)];
    Lines::new(head, 1).skip(1).take(8).any(|(_, l)| {
        let mut t = tokens(l);
        matches!(t.next(), Some(b"facet" | b"endsolid"))
    })
}

fn read_binary(d: &[u8], path: &Path) -> Result<Parsed, IoError> {
    let Some(count) = d
        .get(HEADER..HEADER + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    else {
        return Err(IoError::Truncated {
            path: path.to_path_buf(),
            what: "the binary STL header (80 bytes + facet count)".into(),
            offset: 0,
            needed: 84,
            available: d.len() as u64,
        });
    };
    let n = count as u64;
    let needed = n * FACET as u64;
    let available = (d.len() - (HEADER + 4)) as u64;
    if needed > available {
        return Err(IoError::Truncated {
            path: path.to_path_buf(),
            what: format!("{count} facets of 50 bytes (count at byte 80)"),
            offset: 84,
            needed,
            available,
        });
    }
    let mut warnings = Vec::new();
    if needed < available {
        warnings.push(format!(
            "{} bytes after the last of {count} facets ignored",
            available - needed
        ));
    }
    let n = count as usize;
    // A closed mesh has about half as many vertices as triangles.
    let mut weld: Welder<[u32; 3]> = Welder::with_capacity(n / 2 + 3);
    let mut faces = Vec::with_capacity(n);
    for (i, rec) in d[HEADER + 4..].chunks_exact(FACET).take(n).enumerate() {
        let mut tri = [0u32; 3];
        for (k, t) in tri.iter_mut().enumerate() {
            let o = 12 + 12 * k;
            let mut p = [0.0f64; 3];
            let mut key = [0u32; 3];
            for a in 0..3 {
                let b = &rec[o + 4 * a..o + 4 * a + 4];
                let v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                if !v.is_finite() {
                    return Err(IoError::Binary {
                        path: path.to_path_buf(),
                        offset: (HEADER + 4 + i * FACET + o + 4 * a) as u64,
                        reason: format!(
                            "facet {i} corner {k} has a non-finite coordinate {v}; fix or remove it in the source file"
                        ),
                    });
                }
                let v = v + 0.0; // −0.0 → +0.0 so equal positions weld
                key[a] = v.to_bits();
                p[a] = f64::from(v);
            }
            *t = weld.add(key, p);
        }
        faces.push(tri);
    }
    let mesh = TriMesh {
        positions: weld.positions,
        faces,
        ..Default::default()
    };
    Ok(Parsed {
        mesh,
        vertices_read: 3 * n,
        faces_read: n,
        polygons_triangulated: 0,
        warnings,
    })
}

fn read_ascii(bytes: &[u8], path: &Path) -> Result<Parsed, IoError> {
    let err = |line: usize, reason: String| IoError::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let mut weld: Welder<[u64; 3]> = Welder::with_capacity(bytes.len() / 600);
    let mut faces = Vec::with_capacity(bytes.len() / 250);
    let mut corners: Vec<u32> = Vec::with_capacity(3);
    let mut in_facet = 0usize; // line of the open `facet`, 0 if none
    let mut facets = 0usize;
    let mut last_line = 0;
    for (ln, line) in Lines::new(bytes, 1) {
        last_line = ln;
        let mut t = tokens(line);
        let Some(key) = t.next() else { continue };
        match key {
            b"solid" | b"endsolid" | b"outer" | b"endloop" => {}
            b"facet" => {
                if in_facet != 0 {
                    return Err(err(
                        ln,
                        format!(
                            "'facet' inside the facet opened at line {in_facet}; 'endfacet' is missing"
                        ),
                    ));
                }
                in_facet = ln;
                corners.clear();
            }
            b"vertex" => {
                if in_facet == 0 {
                    return Err(err(ln, "'vertex' outside a facet".into()));
                }
                let mut p = [0.0f64; 3];
                for c in &mut p {
                    let Some(tok) = t.next() else {
                        return Err(err(ln, "vertex needs 3 coordinates".into()));
                    };
                    let Some(v) = parse_f64(tok) else {
                        return Err(err(
                            ln,
                            format!("vertex coordinate '{}' is not a number", show(tok)),
                        ));
                    };
                    if !v.is_finite() {
                        return Err(err(
                            ln,
                            format!(
                                "non-finite coordinate {v}; fix or remove it in the source file"
                            ),
                        ));
                    }
                    *c = v + 0.0;
                }
                if corners.len() == 3 {
                    return Err(err(
                        ln,
                        format!("facet opened at line {in_facet} has more than 3 vertices"),
                    ));
                }
                corners.push(weld.add(p.map(f64::to_bits), p));
            }
            b"endfacet" => {
                if corners.len() != 3 {
                    return Err(err(
                        ln,
                        format!(
                            "facet opened at line {in_facet} has {} vertices, needs 3",
                            corners.len()
                        ),
                    ));
                }
                faces.push([corners[0], corners[1], corners[2]]);
                facets += 1;
                in_facet = 0;
            }
            other => {
                return Err(err(
                    ln,
                    format!("unexpected '{}' in ASCII STL", show(other)),
                ));
            }
        }
    }
    if in_facet != 0 {
        return Err(err(
            last_line,
            format!("file ends inside the facet opened at line {in_facet}"),
        ));
    }
    let mesh = TriMesh {
        positions: weld.positions,
        faces,
        ..Default::default()
    };
    Ok(Parsed {
        mesh,
        vertices_read: 3 * facets,
        faces_read: facets,
        polygons_triangulated: 0,
        warnings: Vec::new(),
    })
}

/// Binary STL (f32 corners, face normals computed in f64). Labels, colours and shared
/// vertices cannot be stored.
pub(crate) fn write(w: &mut dyn Write, mesh: &TriMesh) -> io::Result<()> {
    let mut header = [b' '; HEADER];
    let tag = b"binary STL written by flatcut";
    header[..tag.len()].copy_from_slice(tag);
    w.write_all(&header)?;
    let n =
        u32::try_from(mesh.faces.len()).map_err(|_| io::Error::other("too many faces for STL"))?;
    w.write_all(&n.to_le_bytes())?;
    let mut buf = Vec::with_capacity(FACET * 1024);
    for f in &mesh.faces {
        let [a, b, c] = [f[0], f[1], f[2]].map(|i| mesh.positions[i as usize]);
        let nrm = flatcut_mesh::vec3::normalize(flatcut_mesh::vec3::cross(
            flatcut_mesh::vec3::sub(b, a),
            flatcut_mesh::vec3::sub(c, a),
        ));
        for v in [nrm, a, b, c] {
            for x in v {
                buf.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        buf.extend_from_slice(&[0, 0]);
        if buf.len() >= FACET * 1024 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}
