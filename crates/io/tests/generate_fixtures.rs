//! Regenerates fixtures/valid and fixtures/broken (tiny files) and fixtures/broken/README.md.
//!
//! Run: `cargo test -p flatcut_io --test generate_fixtures -- --ignored`
//! The files are committed; this generator documents exactly how each one is made.

#![allow(clippy::unwrap_used)]

use std::fmt::Write as _;
use std::path::PathBuf;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// Wraps a JSON document and a BIN chunk into a GLB container.
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while j.len() % 4 != 0 {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while b.len() % 4 != 0 {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + if b.is_empty() { 0 } else { 8 + b.len() };
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    if !b.is_empty() {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&b);
    }
    out
}

/// A binary STL with the given 80-byte header start, facets and declared count.
fn stl_bin(header: &[u8], tris: &[[[f32; 3]; 3]], count: u32) -> Vec<u8> {
    let mut out = vec![b' '; 80];
    out[..header.len()].copy_from_slice(header);
    out.extend_from_slice(&count.to_le_bytes());
    for t in tris {
        out.extend_from_slice(&[0u8; 12]);
        for v in t {
            for c in v {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// The bytes of the quad+triangle test mesh as float positions and u16 indices:
/// 5 vertices, triangles (0,1,2), (0,2,3), (3,2,4).
fn tri_bin() -> (Vec<u8>, usize) {
    let pos: [[f32; 3]; 5] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0.5, 1.5, 0.25],
    ];
    let mut b = Vec::new();
    for p in pos {
        for c in p {
            b.extend_from_slice(&c.to_le_bytes());
        }
    }
    let pos_len = b.len();
    for i in [0u16, 1, 2, 0, 2, 3, 3, 2, 4] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    (b, pos_len)
}

fn tri_gltf_json(
    extra_node: &str,
    buffer_uri: &str,
    pos_count: usize,
    mode: u32,
    idx_type: u32,
) -> String {
    let (b, pos_len) = tri_bin();
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{extra_node}],
"meshes":[{{"name":"quadtri","primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"mode":{mode}}}]}}],
"buffers":[{{{buffer_uri}"byteLength":{}}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{pos_len}}},{{"buffer":0,"byteOffset":{pos_len},"byteLength":18}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":{pos_count},"type":"VEC3","min":[0,0,0],"max":[1,1.5,0.25]}},
{{"bufferView":1,"componentType":{idx_type},"count":9,"type":"SCALAR"}}]}}"#,
        b.len()
    )
}

fn b64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for ch in data.chunks(3) {
        let n = (u32::from(ch[0]) << 16)
            | (u32::from(*ch.get(1).unwrap_or(&0)) << 8)
            | u32::from(*ch.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= ch.len() {
                s.push(A[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

const PLY_SHUFFLED_HEADER: &str = "property float confidence\nproperty double z\nproperty uchar red\nproperty float x\n\
property list uchar short extra_list\nproperty float y\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n\
element face 2\nproperty uchar flags\nproperty list uchar uint vertex_indices\nproperty list uchar float texcoord\n\
element material 1\nproperty uchar ambient\nend_header\n";

/// The valid PLY mesh: 5 vertices (x, y as float, z as double), a quad and a triangle,
/// colours (10,20,30,255)·(i+1) clipped.
fn ply_binary(be: bool) -> Vec<u8> {
    let fmt = if be {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = format!("ply\nformat {fmt} 1.0\ncomment shuffled properties\nelement vertex 5\n{PLY_SHUFFLED_HEADER}").into_bytes();
    let pos: [[f64; 3]; 5] = [
        [0., 0., 0.1],
        [1., 0., 0.2],
        [1., 1., 0.30000000000000004],
        [0., 1., -0.0],
        [0.5, 1.5, 1e-300],
    ];
    macro_rules! put {
        ($v:expr) => {
            if be {
                out.extend_from_slice(&$v.to_be_bytes())
            } else {
                out.extend_from_slice(&$v.to_le_bytes())
            }
        };
    }
    for (i, p) in pos.iter().enumerate() {
        put!(0.5f32);
        put!(p[2]);
        out.push(10 * (i as u8 + 1));
        put!(p[0] as f32);
        out.push(2);
        put!(7i16);
        put!(-8i16);
        put!(p[1] as f32);
        out.push(20 * (i as u8 + 1));
        out.push(30 * (i as u8 + 1));
        out.push(255);
    }
    for f in [&[0u32, 1, 2, 3][..], &[3, 2, 4][..]] {
        out.push(9);
        out.push(f.len() as u8);
        for &i in f {
            put!(i);
        }
        out.push(1);
        put!(0.25f32);
    }
    out.push(42);
    out
}

fn ply_ascii() -> Vec<u8> {
    let mut s = format!(
        "ply\nformat ascii 1.0\ncomment shuffled properties\nelement vertex 5\n{PLY_SHUFFLED_HEADER}"
    );
    let pos = [
        ["0", "0", "0.1"],
        ["1", "0", "0.2"],
        ["1", "1", "0.30000000000000004"],
        ["0", "1", "-0.0"],
        ["0.5", "1.5", "1e-300"],
    ];
    for (i, p) in pos.iter().enumerate() {
        let k = i + 1;
        writeln!(
            s,
            "0.5 {} {} {} 2 7 -8 {} {} {} 255",
            p[2],
            10 * k,
            p[0],
            p[1],
            20 * k,
            30 * k
        )
        .unwrap();
    }
    s.push_str("9 4 0 1 2 3 1 0.25\n9 3 3 2 4 1 0.25\n42\n");
    s.into_bytes()
}

#[test]
#[ignore = "writes the committed fixtures; run explicitly"]
fn generate() {
    let valid = fixtures().join("valid");
    let broken = fixtures().join("broken");
    std::fs::create_dir_all(&valid).unwrap();
    std::fs::create_dir_all(&broken).unwrap();
    let (bin, _) = tri_bin();

    // ---- valid ----
    let v: Vec<(&str, Vec<u8>)> = vec![
        (
            "quad_groups.obj",
            b"# two groups sharing an edge; v/vt/vn forms and a negative index\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
vt 0 0\nvn 0 0 1\nv 0.5 1.5 0.25\nv 9 9 9\ng left side\nusemtl skin\ns 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\no right\nf 4//1 3//1 -2\nl 1 2\n"
                .to_vec(),
        ),
        ("shuffled_ascii.ply", ply_ascii()),
        ("shuffled_le.ply", ply_binary(false)),
        ("shuffled_be.ply", ply_binary(true)),
        (
            "two_facets_ascii.stl",
            b"solid two\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 1 1 0\n    endloop\n  endfacet\n\
  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 1 0\n      vertex 0 1 0\n    endloop\n  endfacet\nendsolid two\n"
                .to_vec(),
        ),
        (
            "solid_header_binary.stl",
            stl_bin(
                b"solid but actually binary",
                &[[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.]], [[0., 0., 0.], [1., 1., 0.], [0., 1., -0.0]]],
                2,
            ),
        ),
        (
            "datauri.gltf",
            tri_gltf_json(r#"{"mesh":0}"#, &format!(r#""uri":"data:application/octet-stream;base64,{}","#, b64(&bin)), 5, 4, 5123)
                .into_bytes(),
        ),
        ("external.gltf", tri_gltf_json(r#"{"mesh":0}"#, r#""uri":"external.bin","#, 5, 4, 5123).into_bytes()),
        ("external.bin", bin.clone()),
        (
            "transform.glb",
            glb(
                &tri_gltf_json(
                    r#"{"children":[1],"translation":[10,20,30]},{"mesh":0,"scale":[2,2,2],"rotation":[0,0,0.7071067811865476,0.7071067811865476]}"#,
                    "",
                    5,
                    4,
                    5123,
                ),
                &bin,
            ),
        ),
    ];
    for (name, bytes) in &v {
        std::fs::write(valid.join(name), bytes).unwrap();
    }

    // ---- broken ----
    let tri = [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.]];
    let ply_le_head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    let ply_le = |faces_decl: &str, body: &[u8]| {
        let mut b = format!("{ply_le_head}{faces_decl}end_header\n").into_bytes();
        for c in [0f32, 0., 0., 1., 0., 0., 1., 1., 0.] {
            b.extend_from_slice(&c.to_le_bytes());
        }
        b.extend_from_slice(body);
        b
    };
    let face_le = |idx: [i32; 3]| {
        let mut b = vec![3u8];
        for i in idx {
            b.extend_from_slice(&i.to_le_bytes());
        }
        b
    };
    let ascii_ply = |body: &str| {
        format!("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n{body}").into_bytes()
    };
    let one_tri_obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\n";
    let good_glb_json =
        |mode: u32, pos_count: usize| tri_gltf_json(r#"{"mesh":0}"#, "", pos_count, mode, 5123);
    let mut bad_idx_bin = bin.clone();
    let n = bad_idx_bin.len();
    bad_idx_bin[n - 2..].copy_from_slice(&77u16.to_le_bytes());

    let b: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty.obj", vec![], "empty OBJ file: no faces"),
        ("obj_bad_number.obj", b"v 0 0 0\nv 1 abc 0\nv 1 1 0\nf 1 2 3\n".to_vec(), "vertex coordinate is not a number (line 2)"),
        ("obj_index_out_of_range.obj", format!("{one_tri_obj}f 1 2 9\n").into_bytes(), "face refers to vertex 9 of 3 (line 4)"),
        ("obj_negative_out_of_range.obj", format!("{one_tri_obj}f -1 -2 -7\n").into_bytes(), "relative index -7 before the first vertex (line 4)"),
        ("obj_index_zero.obj", format!("{one_tri_obj}f 0 1 2\n").into_bytes(), "index 0 (OBJ is 1-based) (line 4)"),
        ("obj_nan.obj", b"v 0 0 0\nv nan 0 0\nv 1 1 0\nf 1 2 3\n".to_vec(), "NaN coordinate (line 2)"),
        ("obj_inf.obj", b"v 0 0 0\nv 1 0 0\nv 1 1e999 0\nf 1 2 3\n".to_vec(), "coordinate overflowing to infinity (line 3)"),
        ("obj_two_vertex_face.obj", format!("{one_tri_obj}f 1 2 3\nf 1 2\n").into_bytes(), "face with 2 corners (line 5)"),
        ("obj_vertex_two_coords.obj", b"v 0 0 0\nv 1 0\nv 1 1 0\nf 1 2 3\n".to_vec(), "vertex with 2 coordinates (line 2)"),
        ("obj_bad_face_token.obj", format!("{one_tri_obj}f 1 x/1 3\n").into_bytes(), "face corner is not an index (line 4)"),
        ("obj_only_vertices.obj", one_tri_obj.as_bytes().to_vec(), "vertices but no faces"),
        ("obj_forward_out_of_range.obj", b"v 0 0 0\nf 1 2 5\nv 1 0 0\nv 1 1 0\n".to_vec(), "forward reference beyond the last vertex (line 2)"),
        ("obj_huge_index.obj", format!("{one_tri_obj}f 1 2 99999999999999999999999\n").into_bytes(), "index too large to be a number (line 4)"),
        ("obj_binary_garbage.obj", vec![0x00, 0xff, 0x13, 0x37, 0x0a, 0xfe, 0x80, 0x0a, 0x01], "binary garbage: no faces"),
        ("empty.ply", vec![], "empty PLY file (line 1)"),
        ("ply_no_magic.ply", b"plx\nformat ascii 1.0\nend_header\n".to_vec(), "first line is not 'ply' (line 1)"),
        ("ply_no_end_header.ply", b"ply\nformat ascii 1.0\nelement vertex 0\n".to_vec(), "header never ends (line 4)"),
        ("ply_bad_format.ply", b"ply\nformat binary_middle_endian 1.0\nend_header\n".to_vec(), "unknown format (line 2)"),
        ("ply_unknown_type.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n0\n".to_vec(), "unknown property type (line 4)"),
        ("ply_no_z.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n".to_vec(), "vertex element without z (line 3)"),
        ("ply_face_no_indices.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty uchar flags\nend_header\n0 0 0\n1 0 0\n1 1 0\n1\n".to_vec(), "face element without vertex_indices (line 7)"),
        ("ply_ascii_missing_values.ply", ascii_ply("0 0 0\n1 0\n"), "ASCII body ends early: values missing (line 12)"),
        ("ply_ascii_bad_number.ply", ascii_ply("0 0 0\n1 zero 0\n1 1 0\n3 0 1 2\n"), "'zero' is not a float (line 11)"),
        ("ply_ascii_index_out_of_range.ply", ascii_ply("0 0 0\n1 0 0\n1 1 0\n3 0 1 3\n"), "face refers to vertex 3 of 3 (line 13)"),
        ("ply_ascii_negative_index.ply", ascii_ply("0 0 0\n1 0 0\n1 1 0\n3 0 -1 2\n"), "negative vertex index (line 13)"),
        ("ply_ascii_nan.ply", ascii_ply("0 0 0\n1 0 0\n1 NaN 0\n3 0 1 2\n"), "NaN coordinate (line 12)"),
        ("ply_ascii_two_vertex_face.ply", ascii_ply("0 0 0\n1 0 0\n1 1 0\n2 0 1\n"), "face with 2 corners (line 13)"),
        ("ply_ascii_count_not_integer.ply", b"ply\nformat ascii 1.0\nelement vertex 3.5\nend_header\n".to_vec(), "element count is not an integer (line 3)"),
        ("ply_binary_truncated.ply", { let mut x = ply_le("element face 1\nproperty list uchar int vertex_indices\n", &face_le([0, 1, 2])); x.truncate(x.len() - 5); x }, "binary PLY cut inside the face list"),
        ("ply_binary_4billion_faces.ply", ply_le("element face 4294967295\nproperty list uchar int vertex_indices\n", &face_le([0, 1, 2])), "header claims 4294967295 faces (no huge allocation)"),
        ("ply_binary_list_count_float.ply", ply_le("element face 1\nproperty list float int vertex_indices\n", &[0, 0, 64, 64]), "list count type float (line 8)"),
        ("ply_binary_index_out_of_range.ply", ply_le("element face 1\nproperty list uchar int vertex_indices\n", &face_le([0, 1, 3])), "face refers to vertex 3 of 3"),
        ("ply_binary_negative_index.ply", ply_le("element face 1\nproperty list uchar int vertex_indices\n", &face_le([0, -1, 2])), "negative vertex index"),
        ("ply_binary_inf.ply", { let mut x = ply_le("element face 1\nproperty list uchar int vertex_indices\n", &face_le([0, 1, 2])); let p = x.len() - 13 - 4; x[p..p + 4].copy_from_slice(&f32::INFINITY.to_le_bytes()); x }, "infinite coordinate in vertex 2"),
        ("ply_binary_list_overflow.ply", ply_le("element face 1\nproperty list uchar int vertex_indices\n", &[255, 0, 0, 0, 0]), "list claims 255 indices, 4 bytes remain"),
        ("ply_no_faces.ply", ply_le("element face 0\nproperty list uchar int vertex_indices\n", &[]), "vertices but zero faces"),
        ("empty.stl", vec![], "empty STL file (line 1)"),
        ("stl_short_binary.stl", vec![7u8; 50], "binary STL shorter than its 84-byte header"),
        ("stl_binary_truncated.stl", stl_bin(b"binary", &[tri, tri], 10), "count says 10 facets, 2 present"),
        ("stl_binary_4billion.stl", stl_bin(b"binary", &[tri], u32::MAX), "count says 4294967295 facets (no huge allocation)"),
        ("stl_binary_nan.stl", stl_bin(b"binary", &[[[0., f32::NAN, 0.], [1., 0., 0.], [1., 1., 0.]]], 1), "NaN coordinate in facet 0"),
        ("stl_binary_zero_facets.stl", stl_bin(b"binary", &[], 0), "binary STL with 0 facets: no faces"),
        ("stl_ascii_bad_number.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 O 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid x\n".to_vec(), "letter O instead of zero (line 5)"),
        ("stl_ascii_two_vertex_facet.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid x\n".to_vec(), "facet with 2 vertices (line 7)"),
        ("stl_ascii_unterminated.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n".to_vec(), "file ends inside a facet (line 6)"),
        ("stl_ascii_nan.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex nan 1 0\nendloop\nendfacet\nendsolid x\n".to_vec(), "NaN coordinate (line 6)"),
        ("stl_ascii_no_facets.stl", b"solid x\nendsolid x\n".to_vec(), "ASCII solid without facets: no faces"),
        ("empty.glb", vec![], "empty GLB: shorter than its header"),
        ("glb_bad_magic.glb", b"gLTF\x02\0\0\0\x0c\0\0\0".to_vec(), "magic is not 'glTF'"),
        ("glb_version1.glb", b"glTF\x01\0\0\0\x0c\0\0\0".to_vec(), "glTF 1.0 container"),
        ("glb_truncated.glb", { let mut x = glb(&good_glb_json(4, 5), &bin); x.truncate(x.len() - 20); x }, "GLB cut short (length header exceeds file)"),
        ("glb_bad_json.glb", glb("{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [", &[]), "JSON chunk is not valid JSON"),
        ("glb_no_mesh.glb", glb(r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"name":"empty"}]}"#, &[]), "valid GLB with a node but no mesh"),
        ("glb_short_buffer.glb", { let j = good_glb_json(4, 5); glb(&j, &bin[..20]) }, "buffer declares 78 bytes, BIN chunk has 20"),
        ("glb_points_mode.glb", glb(&good_glb_json(0, 5), &bin), "only primitive has mode POINTS: no triangles"),
        ("glb_accessor_out_of_bounds.glb", glb(&good_glb_json(4, 50), &bin), "POSITION accessor count 50 exceeds its bufferView"),
        ("glb_index_out_of_range.glb", glb(&good_glb_json(4, 5), &bad_idx_bin), "index 77 with 5 vertices"),
        ("glb_node_cycle.glb", glb(&tri_gltf_json(r#"{"mesh":0,"children":[1]},{"children":[0]}"#, "", 5, 4, 5123), &bin), "node 0 and node 1 are each other's child"),
        ("glb_float_indices.glb", glb(&tri_gltf_json(r#"{"mesh":0}"#, "", 5, 4, 5126), &bin), "indices accessor has float components"),
        ("gltf_bad_json.gltf", b"{\n  \"asset\": {\"version\": \"2.0\"},\n  \"meshes\": [,]\n}\n".to_vec(), "syntax error in JSON (line 3)"),
        ("gltf_missing_bin.gltf", tri_gltf_json(r#"{"mesh":0}"#, r#""uri":"missing.bin","#, 5, 4, 5123).into_bytes(), "external buffer file does not exist"),
        ("gltf_bad_base64.gltf", tri_gltf_json(r#"{"mesh":0}"#, r#""uri":"data:application/octet-stream;base64,AAAA*AAA","#, 5, 4, 5123).into_bytes(), "invalid character in base64 data URI"),
        ("gltf_dangling_index.gltf", tri_gltf_json(r#"{"mesh":3}"#, r#""uri":"data:application/octet-stream;base64,AAAA","#, 5, 4, 5123).into_bytes(), "node refers to mesh 3 which does not exist (schema)"),
        ("glb_draco_required.glb", glb(&good_glb_json(4, 5).replacen('{', r#"{"extensionsRequired":["KHR_draco_mesh_compression"],"extensionsUsed":["KHR_draco_mesh_compression"],"#, 1), &bin), "requires the Draco extension, which cannot be decoded"),
        ("unknown.xyz", b"0 0 0\n1 0 0\n".to_vec(), "unsupported extension .xyz"),
    ];
    let mut readme = String::from(
        "# Broken mesh files\n\nEvery file here must be rejected by `flatcut_io::read_mesh` with an error that names the file \
(and, for text formats, the line). Generated by `cargo test -p flatcut_io --test generate_fixtures -- --ignored`; \
checked by `crates/io/tests/broken.rs`.\n\n| file | what is broken |\n|---|---|\n",
    );
    for (name, bytes, what) in &b {
        std::fs::write(broken.join(name), bytes).unwrap();
        writeln!(readme, "| {name} | {what} |").unwrap();
    }
    std::fs::write(broken.join("README.md"), readme).unwrap();
}
