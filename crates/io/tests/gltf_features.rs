//! glTF reading features on small generated GLBs: strips, fans, non-indexed, index widths,
//! COLOR_0 forms, mirror transforms, scene selection and instancing.

#![allow(clippy::unwrap_used)] // helpers outside #[test] fns unwrap too

use flatcut_io::{Format, Units, read_mesh_from_bytes};
use flatcut_mesh::TriMesh;

fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while j.len() % 4 != 0 {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while b.len() % 4 != 0 {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = b"glTF".to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(b.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b);
    out
}

const QUAD: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];

/// A GLB with the quad's positions (accessor 0), an optional index accessor (1) of the
/// given component type and an optional extra accessor (2) of raw bytes for COLOR_0.
struct Doc {
    positions: Vec<[f32; 3]>,
    indices: Option<(u32, Vec<u32>)>,
    color: Option<(u32, &'static str, bool, Vec<u8>)>,
    mode: u32,
    nodes: &'static str,
    scenes: &'static str,
}

impl Doc {
    fn quad(mode: u32, idx: &[u32]) -> Doc {
        Doc {
            positions: QUAD.to_vec(),
            indices: Some((5123, idx.to_vec())),
            color: None,
            mode,
            nodes: r#"[{"mesh":0}]"#,
            scenes: r#""scene":0,"scenes":[{"nodes":[0]}],"#,
        }
    }

    fn bytes(&self) -> Vec<u8> {
        let mut bin = Vec::new();
        for p in &self.positions {
            for c in p {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        let mut views = vec![format!(
            r#"{{"buffer":0,"byteOffset":0,"byteLength":{}}}"#,
            bin.len()
        )];
        let mut accessors = vec![format!(
            r#"{{"bufferView":0,"componentType":5126,"count":{},"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}"#,
            self.positions.len()
        )];
        let mut attrs = r#""POSITION":0"#.to_string();
        let mut prim_extra = String::new();
        if let Some((ty, idx)) = &self.indices {
            let start = bin.len();
            for &i in idx {
                match ty {
                    5121 => bin.push(i as u8),
                    5123 => bin.extend_from_slice(&(i as u16).to_le_bytes()),
                    _ => bin.extend_from_slice(&i.to_le_bytes()),
                }
            }
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{start},"byteLength":{}}}"#,
                bin.len() - start
            ));
            accessors.push(format!(
                r#"{{"bufferView":{},"componentType":{ty},"count":{},"type":"SCALAR"}}"#,
                views.len() - 1,
                idx.len()
            ));
            prim_extra = format!(r#","indices":{}"#, accessors.len() - 1);
            while bin.len() % 4 != 0 {
                bin.push(0);
            }
        }
        if let Some((ty, kind, normalized, data)) = &self.color {
            let start = bin.len();
            bin.extend_from_slice(data);
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{start},"byteLength":{}}}"#,
                data.len()
            ));
            accessors.push(format!(
                r#"{{"bufferView":{},"componentType":{ty},"normalized":{normalized},"count":{},"type":"{kind}"}}"#,
                views.len() - 1,
                self.positions.len()
            ));
            attrs.push_str(&format!(r#","COLOR_0":{}"#, accessors.len() - 1));
        }
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},{}"nodes":{},"meshes":[{{"name":"quad","primitives":[{{"attributes":{{{attrs}}}{prim_extra},"mode":{}}}]}}],"buffers":[{{"byteLength":{}}}],"bufferViews":[{}],"accessors":[{}]}}"#,
            self.scenes,
            self.nodes,
            self.mode,
            bin.len(),
            views.join(","),
            accessors.join(",")
        );
        glb(&json, &bin)
    }

    fn read(&self) -> TriMesh {
        read_mesh_from_bytes(&self.bytes(), Format::Glb, "test.glb", Units::Mm)
            .unwrap()
            .mesh
    }
}

/// Twice the signed area of each triangle projected on the xy plane.
fn signed_areas(m: &TriMesh) -> Vec<f64> {
    m.faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| m.positions[i as usize]);
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        })
        .collect()
}

#[test]
fn strip_and_fan_are_converted_with_consistent_winding() {
    let strip = Doc::quad(5, &[0, 1, 3, 2]).read();
    assert_eq!(strip.faces, vec![[0, 1, 3], [3, 1, 2]]);
    let fan = Doc::quad(6, &[0, 1, 2, 3]).read();
    assert_eq!(fan.faces, vec![[0, 1, 2], [0, 2, 3]]);
    for m in [&strip, &fan] {
        // Both cover the unit quad counter-clockwise: areas positive and summing to 1 (×2).
        let a = signed_areas(m);
        assert!(a.iter().all(|x| *x > 0.0), "{a:?}");
        assert_eq!(a.iter().sum::<f64>(), 2.0);
    }
}

#[test]
fn index_widths_and_non_indexed_agree() {
    let idx = [0, 1, 2, 0, 2, 3];
    let mut results = Vec::new();
    for ty in [5121, 5123, 5125] {
        let mut d = Doc::quad(4, &idx);
        d.indices = Some((ty, idx.to_vec()));
        results.push(d.read());
    }
    assert_eq!(results[0].faces, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(results[0], results[1]);
    assert_eq!(results[1], results[2]);
    let mut d = Doc::quad(4, &[]);
    d.positions = idx.iter().map(|&i| QUAD[i as usize]).collect();
    d.indices = None;
    let flat = d.read();
    assert_eq!(flat.faces, vec![[0, 1, 2], [3, 4, 5]]);
    assert_eq!(flat.positions[4], [1., 1., 0.]);
}

#[test]
fn color_0_normalized_u8_and_float() {
    let mut d = Doc::quad(4, &[0, 1, 2, 0, 2, 3]);
    d.color = Some((
        5121,
        "VEC3",
        true,
        vec![255, 0, 0, 0, 51, 0, 0, 0, 255, 255, 255, 255],
    ));
    let c = d.read().attributes.colors.unwrap();
    assert_eq!(c[0], [1.0, 0.0, 0.0, 1.0]);
    assert_eq!(c[1], [0.0, (51.0f64 / 255.0) as f32, 0.0, 1.0]);
    let vals: Vec<f32> = (0..16).map(|i| i as f32 / 16.0).collect();
    d.color = Some((
        5126,
        "VEC4",
        false,
        vals.iter().flat_map(|v| v.to_le_bytes()).collect(),
    ));
    let c = d.read().attributes.colors.unwrap();
    assert_eq!(c[3], [12.0 / 16.0, 13.0 / 16.0, 14.0 / 16.0, 15.0 / 16.0]);
}

#[test]
fn mirror_matrix_flips_winding_back_to_ccw() {
    let mut d = Doc::quad(4, &[0, 1, 2, 0, 2, 3]);
    d.nodes = r#"[{"mesh":0,"matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 5,0,0,1]}]"#;
    let m = d.read();
    assert_eq!(
        m.positions,
        vec![[5., 0., 0.], [4., 0., 0.], [4., 1., 0.], [5., 1., 0.]]
    );
    let a = signed_areas(&m);
    assert!(
        a.iter().all(|x| *x > 0.0),
        "mirrored triangles re-oriented: {a:?}"
    );
}

#[test]
fn scenes_roots_and_instancing() {
    // No default scene: every scene's nodes.
    let mut d = Doc::quad(4, &[0, 1, 2, 0, 2, 3]);
    d.nodes = r#"[{"mesh":0},{"mesh":0,"translation":[0,0,1]}]"#;
    d.scenes = r#""scenes":[{"nodes":[0]},{"nodes":[1]}],"#;
    let m = d.read();
    assert_eq!(m.faces.len(), 4);
    assert_eq!(m.positions.len(), 8);
    assert_eq!(
        m.positions[4..],
        [[0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]]
    );
    assert_eq!(m.face_labels.unwrap().labels, vec![0, 0, 1, 1]);
    // Default scene 1 only.
    d.scenes = r#""scene":1,"scenes":[{"nodes":[0]},{"nodes":[1]}],"#;
    assert_eq!(d.read().positions[0], [0., 0., 1.]);
    // No scenes: root nodes (node 0; its child 1 comes along, translated by both).
    d.scenes = "";
    d.nodes =
        r#"[{"mesh":0,"children":[1],"translation":[1,0,0]},{"mesh":0,"translation":[0,0,1]}]"#;
    let m = d.read();
    assert_eq!(m.faces.len(), 4);
    assert_eq!(m.positions[4], [1., 0., 1.]);
}
