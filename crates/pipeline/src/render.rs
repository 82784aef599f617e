//! Pictures for report.html, drawn with tiny-skia into PNG bytes: a 3D piece from fixed views
//! coloured by a per-vertex field (|θ − 2π|), and a flattened piece coloured per face (E_h).
//!
//! Orthographic projection, painter's order (far to near, ties by face index, so the bytes do
//! not depend on anything but the input), Lambert shading by |n · view| so the shape reads.

use flatcut_mesh::TriMesh;
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Transform};

/// Pixel size of one 3D view and of a flattened piece's longer side: enough to see where
/// the curvature or distortion sits, small enough to inline a dozen pieces.
pub const VIEW_PX: u32 = 220;
/// Empty border around a drawing, pixels.
const MARGIN_PX: f64 = 6.0;

/// A fixed view: the direction the camera looks along and the screen axes (right, up).
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Its name, shown under the picture.
    pub name: &'static str,
    right: [f64; 3],
    up: [f64; 3],
    /// Towards the camera.
    toward: [f64; 3],
}

/// Front (from +z), side (from +x) and back (from −z), y up: the body and furniture
/// conventions of flatcut's inputs (y up, +z front).
pub const VIEWS: [View; 3] = [
    View {
        name: "front",
        right: [1.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        toward: [0.0, 0.0, 1.0],
    },
    View {
        name: "side",
        right: [0.0, 0.0, -1.0],
        up: [0.0, 1.0, 0.0],
        toward: [1.0, 0.0, 0.0],
    },
    View {
        name: "back",
        right: [-1.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        toward: [0.0, 0.0, -1.0],
    },
];

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// sRGB bytes of viridis at `t` in [0, 1].
pub fn viridis_u8(t: f64) -> [u8; 3] {
    flatcut_io::color::viridis_srgb(t).map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// The screen frame shared by several pictures of one piece (before and after processing
/// must be framed alike to compare): the extent of `positions` in each view.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    lo: [f64; 2],
    scale: f64,
}

impl Frame {
    /// The frame fitting `positions` seen from `view` into a square picture.
    pub fn fit(positions: &[[f64; 3]], view: &View) -> Frame {
        fit2(
            positions
                .iter()
                .map(|p| [dot(*p, view.right), dot(*p, view.up)]),
        )
    }
}

fn fit2(points: impl Iterator<Item = [f64; 2]>) -> Frame {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in points {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let avail = VIEW_PX as f64 - 2.0 * MARGIN_PX;
    let scale = if span.is_finite() && span > 0.0 {
        avail / span
    } else {
        1.0
    };
    // Centre the drawing in the square.
    let pad = |k: usize| (avail / scale - (hi[k] - lo[k])) / 2.0;
    let lo = if lo[0].is_finite() {
        [lo[0] - pad(0), lo[1] - pad(1)]
    } else {
        [0.0, 0.0]
    };
    Frame { lo, scale }
}

impl Frame {
    fn px(&self, q: [f64; 2]) -> (f32, f32) {
        let x = MARGIN_PX + (q[0] - self.lo[0]) * self.scale;
        // Image rows grow downwards.
        let y = VIEW_PX as f64 - MARGIN_PX - (q[1] - self.lo[1]) * self.scale;
        (x as f32, y as f32)
    }
}

fn triangle(pixmap: &mut Pixmap, pts: [(f32, f32); 3], rgb: [u8; 3]) {
    let mut pb = PathBuilder::new();
    pb.move_to(pts[0].0, pts[0].1);
    pb.line_to(pts[1].0, pts[1].1);
    pb.line_to(pts[2].0, pts[2].1);
    pb.close();
    if let Some(path) = pb.finish() {
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
        // Without anti-aliasing, neighbouring triangles meet without hairline gaps.
        paint.anti_alias = false;
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

fn png(pixmap: &Pixmap) -> Vec<u8> {
    pixmap.encode_png().unwrap_or_default()
}

/// `mesh` seen from `view` in `frame`, each face coloured by the mean of `field` at its
/// corners mapped onto viridis over `0..=max`, shaded by |n · view|.
pub fn render_3d(mesh: &TriMesh, field: &[f64], max: f64, view: &View, frame: &Frame) -> Vec<u8> {
    let Some(mut pixmap) = Pixmap::new(VIEW_PX, VIEW_PX) else {
        return Vec::new();
    };
    pixmap.fill(Color::WHITE);
    let mut order: Vec<(f64, usize)> = mesh
        .faces
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let depth: f64 = f
                .iter()
                .map(|&v| dot(mesh.positions[v as usize], view.toward))
                .sum();
            (depth, i)
        })
        .collect();
    // Far faces first.
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (_, i) in order {
        let f = mesh.faces[i];
        let p = f.map(|v| mesh.positions[v as usize]);
        let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let len = dot(n, n).sqrt();
        let shade = if len > 0.0 {
            0.35 + 0.65 * (dot(n, view.toward) / len).abs()
        } else {
            0.35
        };
        let value = f.iter().map(|&v| field[v as usize]).sum::<f64>() / 3.0;
        let t = if max > 0.0 { value / max } else { 0.0 };
        let rgb = viridis_u8(t).map(|c| (c as f64 * shade).round() as u8);
        let pts = p.map(|q| frame.px([dot(q, view.right), dot(q, view.up)]));
        triangle(&mut pixmap, pts, rgb);
    }
    png(&pixmap)
}

/// The flattened piece (`uv`, mm) with each face coloured by `per_face` on viridis over
/// `0..=max`.
pub fn render_2d(faces: &[[u32; 3]], uv: &[[f64; 2]], per_face: &[f64], max: f64) -> Vec<u8> {
    let Some(mut pixmap) = Pixmap::new(VIEW_PX, VIEW_PX) else {
        return Vec::new();
    };
    pixmap.fill(Color::WHITE);
    let frame = fit2(uv.iter().copied());
    for (f, &value) in faces.iter().zip(per_face) {
        let t = if max > 0.0 { value / max } else { 0.0 };
        let pts = f.map(|v| frame.px(uv[v as usize]));
        triangle(&mut pixmap, pts, viridis_u8(t));
    }
    png(&pixmap)
}

/// Base64 (RFC 4648, with padding) for data URIs.
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (c.get(1).copied().unwrap_or(0) as u32) << 8
            | c.get(2).copied().unwrap_or(0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        // RFC 4648 §10.
        for (i, o) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    #[test]
    fn a_square_fills_its_frame_and_is_coloured_by_the_field() {
        // Two triangles covering the unit square, field 0 on one, max on the other.
        let uv = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let faces = [[0, 1, 2], [0, 2, 3]];
        let bytes = render_2d(&faces, &uv, &[0.0, 1.0], 1.0);
        let pm = Pixmap::decode_png(&bytes).unwrap();
        let at = |x: u32, y: u32| {
            let c = pm.pixel(x, y).unwrap();
            [c.red(), c.green(), c.blue()]
        };
        // Below the diagonal (face 0, value 0): viridis(0); above (face 1): viridis(1);
        // the margin stays white.
        let m = MARGIN_PX as u32;
        assert_eq!(at(VIEW_PX - m - 10, VIEW_PX - m - 40), viridis_u8(0.0));
        assert_eq!(at(m + 10, m + 40), viridis_u8(1.0));
        assert_eq!(at(1, 1), [255, 255, 255]);
    }
}
