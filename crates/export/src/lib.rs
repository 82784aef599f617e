//! Writers of flatcut's cut patterns: SVG, PNG, EXR, DXF (AAMA/ASTM D6673), tiled PDF.
//! They produce bytes; the caller writes files (atomically). GLB colour maps of the 3D pieces
//! are written by flatcut_io (GLB with `COLOR_0`), which the CLI calls directly.

pub mod dxf_aama;
mod error;
pub mod exr;
pub mod pdf;
pub mod png;
pub mod svg;
pub mod text;

pub use dxf_aama::{DxfOptions, DxfVersion, dxf_aama};
pub use error::ExportError;
pub use exr::{ExrOptions, piece_exr};
pub use pdf::{Paper, PdfOptions, tiled_pdf};
pub use png::{Field, PngOptions, piece_png, sheet_png};
pub use svg::{LayerColours, SvgOptions, piece_svg, sheet_svg};
