//! The pipeline TOML, schema 1: what a run reads, with every table deserialized straight into
//! the options struct of the crate that uses it (one definition of each parameter).
//!
//! Unknown keys and wrong types are errors that name the key, its line and column, and what
//! is allowed ([`PipelineError::Toml`]). Paths are relative to the TOML file's folder.

use std::path::{Path, PathBuf};

use flatcut_flattenable::ProcessOptions;
use flatcut_io::Units;
use flatcut_lscm::FlattenOptions;
use flatcut_mesh::clean::CleanOptions;
use flatcut_mesh::shapes::BodyMeasurements;
use serde::Deserialize;
use toml::Spanned;

use crate::PipelineError;

/// The schema this flatcut reads.
pub const SCHEMA: u32 = 1;

/// A parsed pipeline TOML.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PipelineSpec {
    /// Must be [`SCHEMA`].
    pub schema: Spanned<u32>,
    /// Name of the pipeline: names the default output folder and marks the folders it owns.
    pub name: Spanned<String>,
    /// Units of the input mesh's coordinates and of every coordinate in this file (seeds,
    /// grain lines are directions and need none). Default: the mesh format's convention (m for
    /// glTF/GLB, mm otherwise); mm for a generator.
    #[serde(default)]
    pub units: Option<Units>,
    /// Output folder, relative to this file. Default `out/<name>`.
    #[serde(default)]
    pub output: Option<Spanned<PathBuf>>,
    /// The surface to cut.
    pub input: Spanned<InputSpec>,
    /// Cutting lines (`[[cut]]`, [`flatcut_trim::CutSpec`]): points in `units`, joined by
    /// geodesics on the surface; the surface is cut along them into pieces.
    #[serde(default, rename = "cut")]
    pub cuts: Vec<Spanned<flatcut_trim::CutSpec>>,
    /// Named pieces, each the piece that contains its seed point.
    #[serde(default, rename = "piece")]
    pub pieces: Vec<Spanned<PieceSpec>>,
    /// Cutting options ([`flatcut_trim::TrimOptions`], `[trim]`).
    #[serde(default)]
    pub trim: flatcut_trim::TrimOptions,
    /// Dart options ([`flatcut_dart::DartOptions`], `[dart]`: `boundary_tolerance_mm`,
    /// `tip_tolerance_mm`), for every piece's `darts`.
    #[serde(default)]
    pub dart: flatcut_dart::DartOptions,
    /// Flattenable processing ([`flatcut_flattenable::ProcessOptions`]).
    #[serde(default)]
    pub process: ProcessOptions,
    /// Flattening ([`flatcut_lscm::FlattenOptions`]).
    #[serde(default)]
    pub flatten: FlattenOptions,
    /// Pattern pieces ([`flatcut_pattern::PatternOptions`]: seam allowance, notches, corners).
    #[serde(default)]
    pub pattern: flatcut_pattern::PatternOptions,
    /// The sheet ([`flatcut_pattern::LayoutOptions`]).
    #[serde(default)]
    pub layout: flatcut_pattern::LayoutOptions,
    /// Files to write ([`crate::export::ExportSpec`]).
    #[serde(default)]
    pub export: crate::export::ExportSpec,
}

/// `[input]`: a mesh file, a generated surface or wire-frame surfaces, then cleaning.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputSpec {
    /// Mesh file (OBJ, PLY, STL, glTF, GLB), relative to the TOML file.
    #[serde(default)]
    pub mesh: Option<Spanned<PathBuf>>,
    /// A generated surface instead of a file.
    #[serde(default)]
    pub generator: Option<Spanned<Generator>>,
    /// Wire-frame files (WIRE.toml, as `flatcut surface` reads; each with its own `units`),
    /// relative to the pipeline file: each becomes a surface patch
    /// ([`flatcut_trim::wireframe_surface`]), one connected component of the input.
    #[serde(default)]
    pub wireframes: Option<Spanned<Vec<Spanned<PathBuf>>>>,
    /// Cleaning ([`flatcut_mesh::clean::CleanOptions`]); default: weld exact duplicates, drop
    /// degenerate and duplicate faces, orient, keep every component.
    #[serde(default)]
    pub clean: CleanOptions,
    /// Isotropic remeshing to a working resolution after cleaning
    /// ([`flatcut_remesh::RemeshOptions`], e.g. `{ target_edge_mm = 8.0 }`); default none.
    #[serde(default)]
    pub remesh: Option<flatcut_remesh::RemeshOptions>,
}

/// A generated input surface, chosen by `kind`.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Generator {
    /// [`flatcut_mesh::shapes::dress_form`] from body measurements (mm).
    DressForm(BodyMeasurements),
    /// [`flatcut_mesh::shapes::sphere_cap_grid`]: a doubly curved disk (positive curvature).
    SphereCap(SphereCap),
    /// A saddle height field z = c (x² − y²) over a square (negative curvature), made with
    /// [`flatcut_mesh::shapes::grid_patch`].
    Saddle(Saddle),
}

/// Parameters of `kind = "sphere-cap"`.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SphereCap {
    /// Vertices along each side of the grid laid on the cap (default 25, at least 3).
    pub n: usize,
    /// Full opening angle of the cap seen from the sphere centre, degrees (default 60).
    pub cap_angle_deg: f64,
    /// Sphere radius, mm (default 200).
    pub radius_mm: f64,
}

impl Default for SphereCap {
    fn default() -> Self {
        Self {
            n: 25,
            cap_angle_deg: 60.0,
            radius_mm: 200.0,
        }
    }
}

/// Parameters of `kind = "saddle"`.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct Saddle {
    /// Vertices along each side (default 25, at least 3).
    pub n: usize,
    /// Side of the square, mm (default 300).
    pub size_mm: f64,
    /// c in z = c (x² − y²), 1/mm (default 0.001: 22.5 mm rise at the side midpoints of the
    /// default square).
    pub curvature_per_mm: f64,
}

impl Default for Saddle {
    fn default() -> Self {
        Self {
            n: 25,
            size_mm: 300.0,
            curvature_per_mm: 0.001,
        }
    }
}

/// `[[piece]]`: one named piece of the pattern.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PieceSpec {
    /// Piece name: file names under `pieces/` and the label. Letters, digits, `-`, `_`, `.`.
    pub name: Spanned<String>,
    /// A point on (or within [`crate::SEED_TOLERANCE_MM`] of) the piece, in `units`.
    pub seed: Spanned<[f64; 3]>,
    /// How many to cut. Default 1.
    #[serde(default = "one")]
    pub quantity: u32,
    /// Cut the copies as a mirrored left/right pair. Default false.
    #[serde(default)]
    pub mirror: bool,
    /// The 3D direction that becomes the grain line (+y in the pattern); any length, not zero.
    /// Default `[flatten.placement].grain`, else the piece's principal axis.
    #[serde(default)]
    pub grain: Option<Spanned<[f64; 3]>>,
    /// Material shrink (`{ along_grain, across_grain }`, fractions; −0.05 makes the pattern
    /// 5 % smaller, the negative ease of neoprene). Default none (0, 0).
    #[serde(default)]
    pub shrink: Option<Spanned<Shrink>>,
    /// Darts (`[{ from = [x, y, z], tip = [x, y, z] }]`, optionally `name`, or `direction`
    /// and `length_mm` instead of `tip`; [`flatcut_dart::DartSpec`], points in `units`): cut
    /// into the piece before processing. Default none.
    #[serde(default)]
    pub darts: Vec<Spanned<flatcut_dart::DartSpec>>,
    /// Feature curves (`[[[x, y, z], …], …]`, landmarks in `units` on the piece): each joined
    /// by the shortest edge path between its landmarks, weighted by `[process].feature_weight`
    /// in processing (moved less) and drawn as internal lines. Default none.
    #[serde(default)]
    pub features: Vec<Spanned<Vec<[f64; 3]>>>,
    /// Size label, e.g. "38" (default empty).
    #[serde(default)]
    pub size: String,
    /// Fabric or material name, e.g. "leather" (default empty).
    #[serde(default)]
    pub fabric: String,
}

/// `shrink = { along_grain, across_grain }` of a `[[piece]]`: fractions, each with
/// |value| < [`flatcut_pattern::MAX_SHRINK`] (0.5).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Shrink {
    /// Along the grain (default 0).
    pub along_grain: Option<Spanned<f64>>,
    /// Across the grain (default 0).
    pub across_grain: Option<Spanned<f64>>,
}

impl Shrink {
    /// (along, across) as fractions.
    pub fn values(&self) -> (f64, f64) {
        let v = |x: &Option<Spanned<f64>>| x.as_ref().map_or(0.0, |s| *s.get_ref());
        (v(&self.along_grain), v(&self.across_grain))
    }
}

fn one() -> u32 {
    1
}

/// A parsed pipeline and where it came from.
#[derive(Clone, Debug)]
pub struct Pipeline {
    /// The parsed file.
    pub spec: PipelineSpec,
    /// The TOML text (for error locations and its hash).
    pub text: String,
    /// The file it was read from, or a display name for an embedded pipeline.
    pub source: PathBuf,
    /// Folder relative paths are resolved against.
    pub base_dir: PathBuf,
}

/// 1-based line and column of a byte offset in `text` (columns count characters).
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

impl Pipeline {
    /// Parses `text` (the contents of `source`), resolving relative paths against `base_dir`.
    pub fn parse(text: &str, source: &Path, base_dir: &Path) -> Result<Self, PipelineError> {
        let spec: PipelineSpec = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map_or((0, 0), |s| line_col(text, s.start));
            PipelineError::Toml {
                file: source.to_path_buf(),
                line,
                column,
                message: e.message().trim().to_string(),
            }
        })?;
        let p = Pipeline {
            spec,
            text: text.to_string(),
            source: source.to_path_buf(),
            base_dir: base_dir.to_path_buf(),
        };
        p.check()?;
        Ok(p)
    }

    /// Reads and parses a pipeline file.
    pub fn read(path: &Path) -> Result<Self, PipelineError> {
        let text = std::fs::read_to_string(path).map_err(|source| PipelineError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let base = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        Self::parse(&text, path, base)
    }

    /// A [`PipelineError::Invalid`] at `span` of this file.
    pub fn invalid(
        &self,
        span: std::ops::Range<usize>,
        key: &str,
        message: String,
    ) -> PipelineError {
        let (line, column) = line_col(&self.text, span.start);
        PipelineError::Invalid {
            file: self.source.clone(),
            line,
            column,
            key: key.to_string(),
            message,
        }
    }

    /// Checks what serde cannot: the schema number, names, one input source, seeds.
    fn check(&self) -> Result<(), PipelineError> {
        let s = &self.spec;
        if *s.schema.get_ref() != SCHEMA {
            return Err(self.invalid(
                s.schema.span(),
                "schema",
                format!(
                    "schema {} is not supported: this flatcut reads schema {SCHEMA}",
                    s.schema.get_ref()
                ),
            ));
        }
        check_name(self, &s.name, "name")?;
        let input = s.input.get_ref();
        let sources: Vec<(&str, std::ops::Range<usize>)> = [
            input.mesh.as_ref().map(|m| ("mesh", m.span())),
            input.generator.as_ref().map(|g| ("generator", g.span())),
            input.wireframes.as_ref().map(|w| ("wireframes", w.span())),
        ]
        .into_iter()
        .flatten()
        .collect();
        match sources.as_slice() {
            [] => {
                return Err(self.invalid(
                    s.input.span(),
                    "input",
                    "[input] needs `mesh = \"file.obj\"` (OBJ, PLY, STL, glTF, GLB), `generator = { kind = \"dress-form\", … }` or `wireframes = [\"seat.toml\", …]`".into(),
                ));
            }
            [_] => {}
            [(first, _), (second, span), ..] => {
                return Err(self.invalid(
                    span.clone(),
                    &format!("input.{second}"),
                    format!("give one of `mesh`, `generator` or `wireframes` in [input], not both `{first}` and `{second}`"),
                ));
            }
        }
        if let Some(w) = &input.wireframes
            && w.get_ref().is_empty()
        {
            return Err(self.invalid(
                w.span(),
                "input.wireframes",
                "give at least one wire-frame file".into(),
            ));
        }
        let mut names = std::collections::BTreeMap::new();
        for p in &s.pieces {
            let p = p.get_ref();
            check_name(self, &p.name, "piece.name")?;
            if let Some(prev) = names.insert(p.name.get_ref().clone(), p.name.span()) {
                let (line, _) = line_col(&self.text, prev.start);
                return Err(self.invalid(
                    p.name.span(),
                    "piece.name",
                    format!(
                        "piece name {:?} is already used on line {line}; piece names must be unique",
                        p.name.get_ref()
                    ),
                ));
            }
            if p.seed.get_ref().iter().any(|c| !c.is_finite()) {
                return Err(self.invalid(
                    p.seed.span(),
                    "piece.seed",
                    "the seed must be three finite numbers [x, y, z]".into(),
                ));
            }
            if p.quantity == 0 {
                return Err(self.invalid(
                    p.name.span(),
                    "piece.quantity",
                    "quantity must be at least 1".into(),
                ));
            }
            if p.mirror && p.quantity % 2 != 0 {
                return Err(self.invalid(
                    p.name.span(),
                    "piece.quantity",
                    format!(
                        "piece {:?} has mirror = true and quantity = {}: mirrored pieces are cut in left/right pairs, give an even quantity (2 for one pair)",
                        p.name.get_ref(),
                        p.quantity
                    ),
                ));
            }
            if let Some(g) = &p.grain {
                let v = g.get_ref();
                if !(v.iter().all(|c| c.is_finite()) && v.iter().any(|c| *c != 0.0)) {
                    return Err(self.invalid(
                        g.span(),
                        "piece.grain",
                        "the grain must be a 3D direction [x, y, z], finite and not zero".into(),
                    ));
                }
            }
            self.check_piece_extras(p)?;
        }
        Ok(())
    }

    /// Shrink ranges, dart and feature numbers of one `[[piece]]`.
    fn check_piece_extras(&self, p: &PieceSpec) -> Result<(), PipelineError> {
        let piece = p.name.get_ref();
        if let Some(sh) = &p.shrink {
            let sh = sh.get_ref();
            for (key, v) in [
                ("along_grain", &sh.along_grain),
                ("across_grain", &sh.across_grain),
            ] {
                let Some(v) = v else { continue };
                let x = *v.get_ref();
                if !(x.is_finite() && x.abs() < flatcut_pattern::MAX_SHRINK) {
                    return Err(self.invalid(
                        v.span(),
                        &format!("piece.shrink.{key}"),
                        format!(
                            "piece {piece:?}: shrink {key} = {x} is out of range: give a fraction between -{m} and {m} (exclusive), e.g. -0.05 for 5 % shrink",
                            m = flatcut_pattern::MAX_SHRINK
                        ),
                    ));
                }
            }
        }
        for d in &p.darts {
            let spec = d.get_ref();
            let finite = spec.from.iter().all(|c| c.is_finite())
                && spec.tip.is_none_or(|t| t.iter().all(|c| c.is_finite()));
            if !finite {
                return Err(self.invalid(
                    d.span(),
                    "piece.darts",
                    format!("piece {piece:?}: a dart's `from` and `tip` must be finite [x, y, z]"),
                ));
            }
        }
        for (k, f) in p.features.iter().enumerate() {
            let pts = f.get_ref();
            if pts.len() < 2 || pts.iter().flatten().any(|c| !c.is_finite()) {
                return Err(self.invalid(
                    f.span(),
                    "piece.features",
                    format!(
                        "piece {piece:?}: feature curve {k} needs at least two finite landmarks [[x, y, z], [x, y, z], …]"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The pipeline's name.
    pub fn name(&self) -> &str {
        self.spec.name.get_ref()
    }

    /// `path` resolved against the TOML file's folder (absolute paths unchanged).
    pub fn resolve(&self, path: &Path) -> PathBuf {
        if path.is_absolute() {
            path.to_path_buf()
        } else {
            self.base_dir.join(path)
        }
    }

    /// A path from the file with `${NAME}` replaced by the environment variable NAME (so a
    /// pipeline can name shared data, `${FLATCUT_DATA}/mh_body.obj`), then resolved. An unset
    /// variable is an error naming the key and line.
    pub fn expand(&self, path: &Spanned<PathBuf>, key: &str) -> Result<PathBuf, PipelineError> {
        let raw = path.get_ref().to_string_lossy().into_owned();
        let mut out = String::with_capacity(raw.len());
        let mut rest = raw.as_str();
        while let Some(i) = rest.find("${") {
            out.push_str(&rest[..i]);
            let after = &rest[i + 2..];
            let Some(j) = after.find('}') else {
                return Err(self.invalid(
                    path.span(),
                    key,
                    "unclosed `${` in the path: write ${NAME} for an environment variable".into(),
                ));
            };
            let name = &after[..j];
            match std::env::var(name) {
                Ok(v) if !v.is_empty() => out.push_str(&v),
                _ => {
                    return Err(self.invalid(
                        path.span(),
                        key,
                        format!("the path uses ${{{name}}}, but the environment variable {name} is not set; set it (e.g. FLATCUT_DATA=/path/to/meshes)"),
                    ));
                }
            }
            rest = &after[j + 1..];
        }
        out.push_str(rest);
        Ok(self.resolve(Path::new(&out)))
    }

    /// The output folder the file asks for (`output`, default `out/<name>`), resolved.
    pub fn default_output(&self) -> PathBuf {
        match &self.spec.output {
            Some(p) => self.resolve(p.get_ref()),
            None => self.resolve(&Path::new("out").join(self.name())),
        }
    }
}

/// Names become file names: keep them portable and unambiguous.
fn check_name(p: &Pipeline, name: &Spanned<String>, key: &str) -> Result<(), PipelineError> {
    let n = name.get_ref();
    let ok = !n.is_empty()
        && n.len() <= 64
        && !n.starts_with('.')
        && n.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if ok {
        Ok(())
    } else {
        Err(p.invalid(
            name.span(),
            key,
            format!(
                "{n:?} is not a usable name: use 1 to 64 ASCII letters, digits, '-', '_' or '.', not starting with '.'"
            ),
        ))
    }
}
