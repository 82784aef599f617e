//! EXR rasters (float32) of E_h and E_r over a piece, with the pixel size in mm recorded.
//!
//! Channels: `A` (1 inside the piece, 0 outside), `E_h`, `E_r` (0 outside). Row 0 is the top of
//! the piece (largest y). Layer attributes: `pixelSizeMm` (f32, mm per pixel, square pixels)
//! and `originXMm`, `originYMm` (f32: the pattern coordinates of the top-left pixel's corner).

use std::collections::HashMap;

use flatcut_pattern::PatternPiece;
use flatcut_pattern::geom::bbox;
use serde::{Deserialize, Serialize};

use crate::ExportError;
use crate::png::MAX_SIDE_PX;

/// Options of [`piece_exr`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExrOptions {
    /// Pixel size, mm (default 1).
    pub pixel_mm: f64,
}

impl Default for ExrOptions {
    fn default() -> Self {
        Self { pixel_mm: 1.0 }
    }
}

/// The raster before encoding: size and channels, row-major from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Raster {
    /// Width (pixels).
    pub width: usize,
    /// Height (pixels).
    pub height: usize,
    /// Pattern coordinates (mm) of the top-left corner of pixel (0, 0).
    pub origin_mm: [f64; 2],
    /// Coverage.
    pub alpha: Vec<f32>,
    /// E_h per pixel.
    pub e_h: Vec<f32>,
    /// E_r per pixel.
    pub e_r: Vec<f32>,
}

/// Samples the per-face values at pixel centres (each pixel takes the face containing its
/// centre).
pub fn raster(piece: &PatternPiece, opts: &ExrOptions) -> Result<Raster, ExportError> {
    let px = opts.pixel_mm;
    if !(px.is_finite() && px > 0.0) {
        return Err(ExportError::BadOption {
            what: "pixel_mm",
            value: px,
            hint: "use a pixel size > 0 mm",
        });
    }
    let nf = piece.mesh.faces.len();
    if piece.e_h.len() != nf || piece.e_r.len() != nf {
        return Err(ExportError::Piece {
            piece: piece.name.clone(),
            what: "no E_h/E_r values to rasterise; compute the distortion first".into(),
        });
    }
    let b = bbox(&piece.sew_line);
    let (w, h) = (
        ((b[1][0] - b[0][0]) / px).ceil().max(1.0),
        ((b[1][1] - b[0][1]) / px).ceil().max(1.0),
    );
    if w > MAX_SIDE_PX as f64 || h > MAX_SIDE_PX as f64 {
        return Err(ExportError::TooLarge {
            width: w as u64,
            height: h as u64,
            limit: MAX_SIDE_PX,
        });
    }
    let (w, h) = (w as usize, h as usize);
    let origin = [b[0][0], b[1][1]];
    let mut r = Raster {
        width: w,
        height: h,
        origin_mm: origin,
        alpha: vec![0.0; w * h],
        e_h: vec![0.0; w * h],
        e_r: vec![0.0; w * h],
    };
    for (fi, f) in piece.mesh.faces.iter().enumerate() {
        // Pixel coordinates (column, row) of the corners.
        let [a, bq, c] = f.map(|v| {
            let q = piece.uv[v as usize];
            [(q[0] - origin[0]) / px, (origin[1] - q[1]) / px]
        });
        let cr = |o: [f64; 2], u: [f64; 2], v: [f64; 2]| {
            (u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0])
        };
        let den = cr(a, bq, c);
        if den == 0.0 {
            continue;
        }
        let lo = |k: usize| a[k].min(bq[k]).min(c[k]).floor().max(0.0) as usize;
        let hi = |k: usize, n: usize| (a[k].max(bq[k]).max(c[k]).ceil() as usize).min(n);
        for row in lo(1)..hi(1, h) {
            for col in lo(0)..hi(0, w) {
                let p = [col as f64 + 0.5, row as f64 + 0.5];
                // Barycentric coordinates (the sign of `den` cancels).
                let l1 = cr(p, bq, c) / den;
                let l2 = cr(p, c, a) / den;
                let l3 = 1.0 - l1 - l2;
                if l1 >= 0.0 && l2 >= 0.0 && l3 >= 0.0 {
                    let i = row * w + col;
                    r.alpha[i] = 1.0;
                    r.e_h[i] = piece.e_h[fi] as f32;
                    r.e_r[i] = piece.e_r[fi] as f32;
                }
            }
        }
    }
    Ok(r)
}

/// The piece's E_h and E_r as a float32 EXR.
pub fn piece_exr(piece: &PatternPiece, opts: &ExrOptions) -> Result<Vec<u8>, ExportError> {
    use exr::image::{AnyChannel, AnyChannels, Encoding, FlatSamples, Layer};
    use exr::meta::attribute::{AttributeValue, Text};
    use exr::meta::header::LayerAttributes;
    use exr::prelude::WritableImage;
    let r = raster(piece, opts)?;
    let ch = |name: &str, v: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(v));
    let channels =
        AnyChannels::sort(vec![ch("A", r.alpha), ch("E_h", r.e_h), ch("E_r", r.e_r)].into());
    let mut attrs = LayerAttributes::named(crate::text::ascii7(&piece.name).as_str());
    let mut other = HashMap::new();
    other.insert(
        Text::from("pixelSizeMm"),
        AttributeValue::F32(opts.pixel_mm as f32),
    );
    other.insert(
        Text::from("originXMm"),
        AttributeValue::F32(r.origin_mm[0] as f32),
    );
    other.insert(
        Text::from("originYMm"),
        AttributeValue::F32(r.origin_mm[1] as f32),
    );
    attrs.other = other;
    let layer = Layer::new(
        (r.width, r.height),
        attrs,
        Encoding::SMALL_LOSSLESS,
        channels,
    );
    let image = exr::image::Image::from_layer(layer);
    let mut out = std::io::Cursor::new(Vec::new());
    image
        .write()
        .to_buffered(&mut out)
        .map_err(|e| ExportError::Exr(e.to_string()))?;
    Ok(out.into_inner())
}
