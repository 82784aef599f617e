//! EXR rasters (float32) of E_h and E_r over a piece, with the pixel size in mm recorded.
//!
//! Channels: `A` (1 inside the piece, 0 outside), `E_h`, `E_r` (0 outside). Row 0 is the top of
//! the piece (largest y). The layer attribute `pixelSizeMm` (f32, mm per pixel, square pixels)
//! gives the scale; the data window's position (column c, row r) places the top-left pixel's
//! corner at pattern coordinates (c · pixelSizeMm, −r · pixelSizeMm) mm. The bytes depend only on
//! the piece and the options (one custom attribute, sequential compression).

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
    /// Pattern coordinates (mm) of the top-left corner of pixel (0, 0): a whole number of
    /// pixels from the pattern origin (x = column · pixel, y = −row · pixel).
    pub origin_mm: [f64; 2],
    /// The global pixel (column, row) of pixel (0, 0): `origin_mm / pixel_mm` with y negated.
    pub origin_px: [i32; 2],
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
    // The raster sits on the global grid of pixel_mm squares (column i covers x ∈ [i·px,
    // (i+1)·px], row j covers y ∈ [−(j+1)·px, −j·px]): its origin is a whole pixel, written as
    // the EXR data-window position, so no further custom attribute is needed (custom ones sit
    // in a HashMap inside the exr crate and would come out in a different order every run).
    let (col0, row0) = ((b[0][0] / px).floor(), (-b[1][1] / px).floor());
    let (w, h) = (
        ((b[1][0] / px).ceil() - col0).max(1.0),
        ((-b[0][1] / px).ceil() - row0).max(1.0),
    );
    if col0.abs() > i32::MAX as f64 / 2.0 || row0.abs() > i32::MAX as f64 / 2.0 {
        return Err(ExportError::TooLarge {
            width: w as u64,
            height: h as u64,
            limit: MAX_SIDE_PX,
        });
    }
    if w > MAX_SIDE_PX as f64 || h > MAX_SIDE_PX as f64 {
        return Err(ExportError::TooLarge {
            width: w as u64,
            height: h as u64,
            limit: MAX_SIDE_PX,
        });
    }
    let (w, h) = (w as usize, h as usize);
    let origin = [col0 * px, -row0 * px];
    let mut r = Raster {
        width: w,
        height: h,
        origin_mm: origin,
        origin_px: [col0 as i32, row0 as i32],
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
    // One custom attribute only (see `raster`): the origin is the data-window position.
    attrs.other = HashMap::from([(
        Text::from("pixelSizeMm"),
        AttributeValue::F32(opts.pixel_mm as f32),
    )]);
    attrs.layer_position = exr::math::Vec2(r.origin_px[0], r.origin_px[1]);
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
        // Sequential: parallel compression may emit chunks in any order.
        .non_parallel()
        .to_buffered(&mut out)
        .map_err(|e| ExportError::Exr(e.to_string()))?;
    Ok(out.into_inner())
}
