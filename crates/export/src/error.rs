//! The one error type of the export crate.

/// What went wrong writing a pattern; each variant names the piece or option.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// An option is out of range.
    #[error("{what} = {value} is not allowed: {hint}")]
    BadOption {
        /// Which option.
        what: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range.
        hint: &'static str,
    },
    /// A piece has nothing to draw for the requested output.
    #[error("piece {piece:?}: {what}")]
    Piece {
        /// Piece name.
        piece: String,
        /// What is missing and what to do.
        what: String,
    },
    /// The raster would be too large.
    #[error(
        "a {width} × {height} pixel raster is too large (limit {limit} pixels a side); lower the resolution"
    )]
    TooLarge {
        /// Width in pixels.
        width: u64,
        /// Height in pixels.
        height: u64,
        /// Largest side allowed.
        limit: u64,
    },
    /// The EXR encoder failed.
    #[error("EXR encoding failed: {0}")]
    Exr(String),
    /// The PNG encoder failed.
    #[error("PNG encoding failed: {0}")]
    Png(String),
    /// The DXF (R13) writer failed.
    #[error("DXF writing failed: {0}")]
    Dxf(String),
}
