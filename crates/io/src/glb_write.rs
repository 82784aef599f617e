//! GLB writer: one node, one mesh, one indexed triangle primitive.
//!
//! glTF stores positions as f32 only; colours go to `COLOR_0` (linear RGBA f32) from
//! `attributes.colors`, or, when only `attributes.scalar` is present, from the scalar through
//! the viridis ramp ([`crate::color::viridis`]) over the caller's range or the scalar's min..max.
//! Face labels are not written (a single primitive keeps vertices shared).

use std::borrow::Cow;
use std::io::{self, Write};

use flatcut_mesh::TriMesh;
use serde_json::json;

use crate::color;

fn pad4(buf: &mut Vec<u8>) {
    while buf.len() % 4 != 0 {
        buf.push(0);
    }
}

pub(crate) fn write(
    w: &mut dyn Write,
    mesh: &TriMesh,
    scalar_range: Option<(f64, f64)>,
) -> io::Result<()> {
    let n = mesh.positions.len();
    let mut bin: Vec<u8> = Vec::with_capacity(n * 28 + mesh.faces.len() * 12 + 16);
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in &mesh.positions {
        for k in 0..3 {
            let x = p[k] as f32;
            if !x.is_finite() {
                return Err(io::Error::other(format!(
                    "coordinate {} does not fit in the f32 that glTF requires",
                    p[k]
                )));
            }
            lo[k] = lo[k].min(x);
            hi[k] = hi[k].max(x);
            bin.extend_from_slice(&x.to_le_bytes());
        }
    }
    if n == 0 {
        lo = [0.0; 3];
        hi = [0.0; 3];
    }
    let pos_len = bin.len();
    let colors: Option<Vec<[f32; 4]>> =
        if let Some(c) = mesh.attributes.colors.as_ref().filter(|c| c.len() == n) {
            Some(
                c.iter()
                    .map(|c| c.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }))
                    .collect(),
            )
        } else if let Some(s) = mesh.attributes.scalar.as_ref().filter(|s| s.len() == n) {
            let (a, b) = scalar_range.unwrap_or_else(|| {
                let finite = s.iter().copied().filter(|v| v.is_finite());
                let a = finite.clone().fold(f64::INFINITY, f64::min);
                let b = finite.fold(f64::NEG_INFINITY, f64::max);
                if a.is_finite() { (a, b) } else { (0.0, 1.0) }
            });
            Some(s.iter().map(|&v| color::viridis(v, a, b)).collect())
        } else {
            None
        };
    let color_offset = bin.len();
    if let Some(c) = &colors {
        for rgba in c {
            for v in rgba {
                bin.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    let color_len = bin.len() - color_offset;
    let idx_offset = bin.len();
    for f in &mesh.faces {
        for i in f {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    let idx_len = bin.len() - idx_offset;
    pad4(&mut bin);

    let mut views =
        vec![json!({"buffer": 0, "byteOffset": 0, "byteLength": pos_len, "target": 34962})];
    let mut accessors = vec![json!({
        "bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
        "min": lo, "max": hi
    })];
    let mut attributes = json!({"POSITION": 0});
    if colors.is_some() {
        views.push(json!({"buffer": 0, "byteOffset": color_offset, "byteLength": color_len, "target": 34962}));
        accessors.push(json!({"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC4"}));
        attributes["COLOR_0"] = json!(1);
    }
    views.push(
        json!({"buffer": 0, "byteOffset": idx_offset, "byteLength": idx_len, "target": 34963}),
    );
    accessors.push(json!({
        "bufferView": views.len() - 1, "componentType": 5125, "count": mesh.faces.len() * 3, "type": "SCALAR"
    }));
    let doc = json!({
        "asset": {"version": "2.0", "generator": "flatcut"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": accessors.len() - 1, "mode": 4}]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    // Going through gltf::json::Root checks the document against the glTF schema types.
    let root: gltf::json::Root = serde_json::from_value(doc).map_err(io::Error::other)?;
    let json_bytes = serde_json::to_vec(&root).map_err(io::Error::other)?;
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0,
        },
        json: Cow::Owned(json_bytes),
        bin: Some(Cow::Owned(bin)),
    };
    glb.to_writer(w).map_err(|e| match e {
        gltf::Error::Io(e) => e,
        other => io::Error::other(other.to_string()),
    })
}
