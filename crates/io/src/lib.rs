//! Mesh files for flatcut: OBJ, PLY, STL, glTF/GLB read and write, with units.
//!
//! Entry points: [`read_mesh`] / [`read_mesh_from_bytes`] give a [`LoadedMesh`] (the
//! [`TriMesh`] in millimetres plus [`SourceInfo`] about the file); [`write_mesh`] writes OBJ,
//! binary PLY, binary STL or GLB atomically.
//!
//! The OBJ, PLY and STL readers are hand-written: they keep global vertex identity (a vertex
//! shared by two OBJ groups stays one vertex), report errors with line numbers or byte
//! offsets, never allocate more than the file could hold and never panic on any input.
//! Readers do not weld or clean, except that STL (which has no shared vertices) is welded by
//! exact position, as every tool does. Unreferenced vertices are kept.

mod atomic;
mod base64;
pub mod color;
mod error;
mod glb_write;
mod gltf_read;
mod obj;
mod ply;
mod stl;
mod text;
mod units;

use std::path::{Path, PathBuf};

use flatcut_mesh::TriMesh;

pub use error::IoError;
pub use units::{ParseUnitsError, Units};

/// The extensions [`read_mesh`] understands, for messages.
pub const READ_EXTENSIONS: &str = ".obj, .ply, .stl, .gltf, .glb";
/// The extensions [`write_mesh`] understands, for messages.
pub const WRITE_EXTENSIONS: &str = ".obj, .ply (binary), .stl (binary), .glb";

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// Wavefront OBJ (text).
    Obj,
    /// Stanford PLY (ASCII or binary).
    Ply,
    /// STL (ASCII or binary).
    Stl,
    /// glTF 2.0 JSON with data-URI or external buffers.
    Gltf,
    /// Binary glTF 2.0.
    Glb,
}

impl Format {
    /// The format named by a path's extension (case-insensitive), or `None`.
    pub fn from_extension(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Format::Obj),
            "ply" => Some(Format::Ply),
            "stl" => Some(Format::Stl),
            "gltf" => Some(Format::Gltf),
            "glb" => Some(Format::Glb),
            _ => None,
        }
    }

    /// The format named by a path's extension, or [`IoError::UnsupportedFormat`].
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        Format::from_extension(path).ok_or_else(|| IoError::UnsupportedFormat {
            path: path.to_path_buf(),
            extension: extension_of(path),
            action: "reads",
            supported: READ_EXTENSIONS,
        })
    }

    /// Lower-case name ("obj", "ply", ...).
    pub fn name(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Ply => "ply",
            Format::Stl => "stl",
            Format::Gltf => "gltf",
            Format::Glb => "glb",
        }
    }
}

fn extension_of(path: &Path) -> String {
    path.extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default()
}

/// What the reader saw in the file, before flatcut changed anything.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceInfo {
    /// The file (or the name given to [`read_mesh_from_bytes`]).
    pub path: PathBuf,
    /// The format it was read as.
    pub format: Format,
    /// Size of the file in bytes.
    pub file_size: u64,
    /// The unit the coordinates were read in (positions were multiplied by its factor).
    pub units: Units,
    /// Vertex records in the file (STL: 3 × facets, before welding; glTF: accessor
    /// elements of all primitive instances).
    pub vertices_read: usize,
    /// Faces as in the file, before triangulation (OBJ/PLY polygons, STL facets, glTF
    /// triangles after strip/fan conversion).
    pub faces_read: usize,
    /// How many of `faces_read` had more than 3 corners and were fan-triangulated.
    pub polygons_triangulated: usize,
    /// Benign oddities the reader skipped or fixed, one sentence each with its location.
    pub warnings: Vec<String>,
}

/// A mesh read from a file, in millimetres, with what was seen in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedMesh {
    /// The mesh in millimetres; validated (indices in range, finite positions).
    pub mesh: TriMesh,
    /// Facts about the source file.
    pub source: SourceInfo,
}

/// What a format reader hands back before units and validation.
pub(crate) struct Parsed {
    pub mesh: TriMesh,
    pub vertices_read: usize,
    pub faces_read: usize,
    pub polygons_triangulated: usize,
    pub warnings: Vec<String>,
}

/// Reads a mesh file, choosing the format by extension.
///
/// Positions are multiplied by `units.factor_to_mm()` (bit-exact for [`Units::Mm`]).
/// A `.gltf` file's external buffers are looked up next to it.
///
/// # Errors
/// [`IoError::UnsupportedFormat`] for unknown extensions, [`IoError::Io`] if the file
/// cannot be read, and a located parse error for anything wrong inside it (including no
/// triangles at all, indices out of range and NaN/infinite coordinates).
pub fn read_mesh(path: &Path, units: Units) -> Result<LoadedMesh, IoError> {
    let format = Format::from_path(path)?;
    let bytes = std::fs::read(path).map_err(|source| IoError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_impl(&bytes, format, path, path.parent(), units)
}

/// Reads a mesh from bytes in memory; `name` is used in messages and [`SourceInfo::path`].
///
/// A `.gltf` document read this way must carry its buffers as data URIs (there is no
/// directory to find external files in).
pub fn read_mesh_from_bytes(
    bytes: &[u8],
    format: Format,
    name: &str,
    units: Units,
) -> Result<LoadedMesh, IoError> {
    read_impl(bytes, format, Path::new(name), None, units)
}

fn read_impl(
    bytes: &[u8],
    format: Format,
    path: &Path,
    base_dir: Option<&Path>,
    units: Units,
) -> Result<LoadedMesh, IoError> {
    let parsed = match format {
        Format::Obj => obj::read(bytes, path)?,
        Format::Ply => ply::read(bytes, path)?,
        Format::Stl => stl::read(bytes, path)?,
        Format::Gltf => gltf_read::read_gltf(bytes, path, base_dir)?,
        Format::Glb => gltf_read::read_glb(bytes, path, base_dir)?,
    };
    let Parsed {
        mut mesh,
        vertices_read,
        faces_read,
        polygons_triangulated,
        warnings,
    } = parsed;
    if mesh.faces.is_empty() {
        return Err(IoError::NoFaces {
            path: path.to_path_buf(),
            reason: if warnings.is_empty() {
                format!("no faces found ({} vertices)", mesh.positions.len())
            } else {
                format!(
                    "no faces found ({} vertices; {})",
                    mesh.positions.len(),
                    warnings.join("; ")
                )
            },
        });
    }
    if units != Units::Mm {
        mesh.scale(units.factor_to_mm());
    }
    // Readers reject bad indices and non-finite numbers with their line; this catches what
    // only the unit scaling can cause (overflow to infinity) and anything a reader missed.
    mesh.validate().map_err(|source| IoError::Mesh {
        path: path.to_path_buf(),
        line: None,
        source,
    })?;
    Ok(LoadedMesh {
        mesh,
        source: SourceInfo {
            path: path.to_path_buf(),
            format,
            file_size: bytes.len() as u64,
            units,
            vertices_read,
            faces_read,
            polygons_triangulated,
            warnings,
        },
    })
}

/// How [`write_mesh`] writes.
#[derive(Clone, Debug, Default, PartialEq, serde::Deserialize)]
#[serde(default)]
pub struct WriteOptions {
    /// The format; `None` (default) chooses by the path's extension.
    pub format: Option<Format>,
    /// The unit to write coordinates in; positions (mm) are divided by its factor.
    /// Default `None` = the format's convention, [`Units::default_for`]: metres for GLB (the
    /// glTF specification fixes metres, so viewers show the true size), millimetres (bit-exact)
    /// for the others.
    pub units: Option<Units>,
    /// GLB only: the scalar value range mapped onto the colour ramp when the mesh has
    /// `attributes.scalar` but no colours. Default `None` = min..max of the scalar.
    pub scalar_range: Option<(f64, f64)>,
}

/// Writes a mesh atomically: to a temporary file in the same directory, then renamed over
/// `path`, so a failed write never leaves a partial file.
///
/// OBJ: `v` and `f` lines, `g` lines when the mesh has face labels, shortest round-trip
/// decimal numbers. PLY: binary little-endian, double x/y/z, uchar RGBA when colours are
/// present, `int` vertex index lists. STL: binary (f32, welded vertices lost by design).
/// GLB: f32 positions, `COLOR_0` from colours or from the scalar through [`color::viridis`].
///
/// # Errors
/// [`IoError::UnsupportedFormat`] for other extensions (including `.gltf`: write `.glb`),
/// [`IoError::Mesh`] if the mesh is invalid (NaN never reaches a file), [`IoError::Io`].
pub fn write_mesh(path: &Path, mesh: &TriMesh, opts: &WriteOptions) -> Result<(), IoError> {
    let format = writable(opts.format.or_else(|| Format::from_extension(path)), path)?;
    let mesh = prepare(mesh, opts.units.unwrap_or(Units::default_for(format)), path)?;
    atomic::write_atomically(path, |w| encode(w, &mesh, format, opts))
}

/// Encodes a mesh in memory in one of the writable formats (`format` wins over
/// `opts.format`; `opts.units` applies), with the same checks as [`write_mesh`].
pub fn write_mesh_to_vec(
    mesh: &TriMesh,
    format: Format,
    opts: &WriteOptions,
) -> Result<Vec<u8>, IoError> {
    let name = PathBuf::from(format!("<memory>.{}", format.name()));
    let format = writable(Some(format), &name)?;
    let mesh = prepare(
        mesh,
        opts.units.unwrap_or(Units::default_for(format)),
        &name,
    )?;
    let mut out = Vec::new();
    encode(&mut out, &mesh, format, opts).map_err(|source| IoError::Io { path: name, source })?;
    Ok(out)
}

fn writable(format: Option<Format>, path: &Path) -> Result<Format, IoError> {
    match format {
        Some(f @ (Format::Obj | Format::Ply | Format::Stl | Format::Glb)) => Ok(f),
        _ => Err(IoError::UnsupportedFormat {
            path: path.to_path_buf(),
            extension: extension_of(path),
            action: "writes",
            supported: WRITE_EXTENSIONS,
        }),
    }
}

/// Validates (NaN never reaches a file) and converts millimetres to the output unit.
fn prepare<'m>(
    mesh: &'m TriMesh,
    units: Units,
    path: &Path,
) -> Result<std::borrow::Cow<'m, TriMesh>, IoError> {
    let invalid = |source| IoError::Mesh {
        path: path.to_path_buf(),
        line: None,
        source,
    };
    mesh.validate().map_err(invalid)?;
    if units == Units::Mm {
        return Ok(std::borrow::Cow::Borrowed(mesh));
    }
    let mut m = mesh.clone();
    m.scale(1.0 / units.factor_to_mm());
    m.validate().map_err(invalid)?;
    Ok(std::borrow::Cow::Owned(m))
}

fn encode(
    w: &mut dyn std::io::Write,
    mesh: &TriMesh,
    format: Format,
    opts: &WriteOptions,
) -> std::io::Result<()> {
    match format {
        Format::Obj => obj::write(w, mesh),
        Format::Ply => ply::write(w, mesh),
        Format::Stl => stl::write(w, mesh),
        _ => glb_write::write(w, mesh, opts.scalar_range),
    }
}
