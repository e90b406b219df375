//! glTF loading: a small hand-built `.gltf` with an embedded buffer, plus broken and line-less files.

use std::path::{Path, PathBuf};

use glam::Vec3;
use hairlab::scene::gltf_load::{GltfError, load_gltf};
use hairlab::scene::load::load_scene;

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn base64_matches_known_encodings() {
    assert_eq!(base64(b"Man"), "TWFu");
    assert_eq!(base64(b"Ma"), "TWE=");
    assert_eq!(base64(b"M"), "TQ==");
}

/// Collects binary arrays into one buffer and writes the matching bufferViews and accessors.
#[derive(Default)]
struct Builder {
    bytes: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Builder {
    fn add(&mut self, data: Vec<u8>, count: usize, component: u32, ty: &str, extra: &str) -> usize {
        let offset = self.bytes.len();
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#,
            data.len()
        ));
        self.bytes.extend_from_slice(&data);
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":{component},"count":{count},"type":"{ty}"{extra}}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }
    fn vec3(&mut self, v: &[[f32; 3]]) -> usize {
        let data = v.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for p in v {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let extra = format!(r#","min":{lo:?},"max":{hi:?}"#);
        self.add(data, v.len(), 5126, "VEC3", &extra)
    }
    fn vec4(&mut self, v: &[[f32; 4]]) -> usize {
        let data = v.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
        self.add(data, v.len(), 5126, "VEC4", "")
    }
    fn indices(&mut self, v: &[u16]) -> usize {
        let data = v.iter().flat_map(|i| i.to_le_bytes()).collect();
        self.add(data, v.len(), 5123, "SCALAR", "")
    }
    fn json(&self, meshes: &str, nodes: &str, scene_nodes: &str, materials: &str) -> String {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":{scene_nodes}}}],"nodes":{nodes},
            "meshes":{meshes},"materials":{materials},
            "buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
            "bufferViews":[{}],"accessors":[{}]}}"#,
            self.bytes.len(),
            base64(&self.bytes),
            self.views.join(","),
            self.accessors.join(",")
        )
    }
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).abs().max_element() < 1e-6, "{a} != {b}");
}

/// Quad (rotated 90° about X), indexed LINES (2 chained segments + 1 separate), an unindexed LINES pair
/// joined by position, a LINE_STRIP of 4 points with rgba colours, and a POINTS primitive that is skipped.
pub(crate) fn sample(dir: &Path) -> PathBuf {
    let mut b = Builder::default();
    let quad_pos = b.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]]);
    let quad_nrm = b.vec3(&[[0.0, 1.0, 0.0]; 4]);
    let quad_idx = b.indices(&[0, 2, 1, 0, 3, 2]);
    let lines_pos = b.vec3(&[
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 2.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
    ]);
    let lines_col = b.vec3(&[
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.5, 0.5],
        [0.25, 0.25, 0.25],
    ]);
    let lines_idx = b.indices(&[0, 1, 1, 2, 3, 4]);
    let dup_pos = b.vec3(&[[2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [2.0, 1.0, 0.0], [2.0, 3.0, 0.0]]);
    let strip_pos = b.vec3(&[[3.0, 0.0, 0.0], [3.0, 1.0, 0.0], [3.0, 2.0, 0.0], [3.0, 3.0, 0.0]]);
    let strip_col = b.vec4(&[
        [1.0, 1.0, 1.0, 1.0],
        [1.0, 1.0, 1.0, 0.75],
        [1.0, 1.0, 1.0, 0.5],
        [0.0, 0.0, 0.0, 0.25],
    ]);
    let meshes = format!(
        r#"[{{"name":"quad","primitives":[{{"attributes":{{"POSITION":{quad_pos},"NORMAL":{quad_nrm}}},
              "indices":{quad_idx},"material":0}}]}},
           {{"name":"hair","primitives":[
              {{"attributes":{{"POSITION":{lines_pos},"COLOR_0":{lines_col}}},
                "indices":{lines_idx},"mode":1}},
              {{"attributes":{{"POSITION":{dup_pos}}},"mode":1}},
              {{"attributes":{{"POSITION":{strip_pos},"COLOR_0":{strip_col}}},"mode":3}},
              {{"attributes":{{"POSITION":{dup_pos}}},"mode":0}}]}}]"#
    );
    let nodes = r#"[{"name":"root","translation":[10.0,0.0,0.0],"children":[1]},
        {"name":"hair","mesh":1,"translation":[0.0,5.0,0.0]},
        {"name":"quad","mesh":0,"rotation":[0.70710677,0.0,0.0,0.70710677]}]"#;
    let materials = r#"[{"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.4,0.6,1.0]}}]"#;
    write(dir, "sample.gltf", &b.json(&meshes, nodes, "[0,2]", materials))
}

#[test]
fn loads_triangles_and_lines_with_transforms() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = load_gltf(&sample(dir.path())).expect("loads");

    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.triangle_count(), 2);
    let quad = &scene.meshes[0];
    assert_eq!(quad.indices, vec![0, 2, 1, 0, 3, 2]);
    assert_eq!(quad.color, Vec3::new(0.2, 0.4, 0.6));
    // 90° about +X maps (x, y, z) to (x, -z, y).
    assert_close(quad.positions[2], Vec3::new(1.0, -1.0, 0.0));
    for n in &quad.normals {
        assert_close(*n, Vec3::new(0.0, 0.0, 1.0));
    }

    let s = &scene.strands;
    assert_eq!(s.counts, vec![3, 2, 3, 4]);
    let t = Vec3::new(10.0, 5.0, 0.0);
    let expected: Vec<Vec3> = [
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 2.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
        [2.0, 3.0, 0.0],
        [3.0, 0.0, 0.0],
        [3.0, 1.0, 0.0],
        [3.0, 2.0, 0.0],
        [3.0, 3.0, 0.0],
    ]
    .iter()
    .map(|p| Vec3::from_array(*p) + t)
    .collect();
    assert_eq!(s.points, expected);

    // Primitives without colours get white (and opaque) entries once another primitive brings colours.
    let color = s.color.as_ref().expect("colours");
    assert_eq!(
        color[..5],
        [Vec3::X, Vec3::Y, Vec3::Z, Vec3::splat(0.5), Vec3::splat(0.25)]
    );
    assert_eq!(color[5..8], [Vec3::ONE; 3]);
    assert_eq!(color[8..], [Vec3::ONE, Vec3::ONE, Vec3::ONE, Vec3::ZERO]);
    let alpha = s.alpha.as_ref().expect("alpha from the rgba strip");
    assert_eq!(
        alpha,
        &vec![1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.75, 0.5, 0.25]
    );

    let via_dispatch = load_scene(&dir.path().join("sample.gltf")).expect("load_scene handles .gltf");
    assert_eq!(via_dispatch, scene);
}

#[test]
fn broken_json_names_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = write(
        dir.path(),
        "broken_model.gltf",
        r#"{"asset": {"version": "2.0"}, "nodes": [ "#,
    );
    let err = load_gltf(&path).expect_err("broken");
    assert!(matches!(err, GltfError::Gltf { .. }), "{err:?}");
    assert!(err.to_string().contains("broken_model.gltf"), "{err}");
}

#[test]
fn only_points_is_no_geometry() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut b = Builder::default();
    let pos = b.vec3(&[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
    let meshes = format!(r#"[{{"primitives":[{{"attributes":{{"POSITION":{pos}}},"mode":0}}]}}]"#);
    let path = write(
        dir.path(),
        "dots.gltf",
        &b.json(&meshes, r#"[{"mesh":0}]"#, "[0]", "[]"),
    );
    let err = load_gltf(&path).expect_err("no geometry");
    assert!(matches!(err, GltfError::NoGeometry { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("dots.gltf") && msg.contains("contains no triangles or lines"),
        "{msg}"
    );
}

#[test]
fn out_of_range_index_is_an_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut b = Builder::default();
    let pos = b.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let idx = b.indices(&[0, 1, 7]);
    let meshes = format!(r#"[{{"primitives":[{{"attributes":{{"POSITION":{pos}}},"indices":{idx}}}]}}]"#);
    let path = write(
        dir.path(),
        "bad_index.gltf",
        &b.json(&meshes, r#"[{"mesh":0}]"#, "[0]", "[]"),
    );
    let err = load_gltf(&path).expect_err("bad index");
    assert!(
        matches!(
            err,
            GltfError::IndexOutOfRange {
                index: 7,
                vertices: 3,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("bad_index.gltf"), "{err}");
}

#[test]
fn non_finite_position_is_an_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut b = Builder::default();
    let pos = b.add(
        [0.0f32, 0.0, 0.0, 1.0, f32::NAN, 0.0]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect(),
        2,
        5126,
        "VEC3",
        r#","min":[0.0,0.0,0.0],"max":[1.0,0.0,0.0]"#,
    );
    let meshes = format!(r#"[{{"primitives":[{{"attributes":{{"POSITION":{pos}}},"mode":1}}]}}]"#);
    let path = write(
        dir.path(),
        "nan.gltf",
        &b.json(&meshes, r#"[{"mesh":0}]"#, "[0]", "[]"),
    );
    let err = load_gltf(&path).expect_err("NaN");
    assert!(
        matches!(err, GltfError::NonFinitePosition { vertex: 1, .. }),
        "{err:?}"
    );
}

#[test]
fn dangling_accessor_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":99}}]}]}"#;
    let path = write(dir.path(), "dangling.gltf", text);
    let err = load_gltf(&path).expect_err("malformed");
    assert!(matches!(err, GltfError::Malformed { .. }), "{err:?}");
    assert!(
        err.to_string()
            .ends_with("dangling.gltf: malformed glTF: mesh 0 primitive 0: an attribute names accessor 99, and there are 0"),
        "{err}"
    );
}

#[test]
fn missing_buffer_file_names_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":12,"uri":"nowhere.bin"}]}"#;
    let path = write(dir.path(), "lost_buffer.gltf", text);
    let msg = load_gltf(&path).expect_err("missing buffer").to_string();
    assert!(msg.contains("lost_buffer.gltf"), "{msg}");
}

#[test]
fn unknown_extension_is_rejected_by_load_scene() {
    let msg = load_scene(Path::new("model.obj"))
        .expect_err("unsupported")
        .to_string();
    assert!(
        msg.contains("model.obj") && msg.contains(".hair") && msg.contains(".glb"),
        "{msg}"
    );
}

/// A file with one triangle and the given extra JSON for its primitive, accessors and views (positions: accessor 0,
/// 36 bytes at byte 0 of a 36-byte buffer, as a data URI).
fn triangle_with(dir: &Path, name: &str, more: &str, extra_accessor: &str, view: &str) -> PathBuf {
    let mut b = Builder::default();
    let pos = b.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    assert_eq!(pos, 0);
    let (attribute, indices) = split_more(more);
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0{attribute}}}{indices}}}]}}],
        "buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
        "bufferViews":[{}{view}],"accessors":[{}{extra_accessor}]}}"#,
        b.bytes.len(),
        base64(&b.bytes),
        b.views.join(","),
        b.accessors.join(",")
    );
    write(dir, name, &text)
}

/// `more` is either `,"indices":N` (after the attributes) or `,"NAME":N` (a further attribute).
fn split_more(more: &str) -> (&str, &str) {
    if more.contains("indices") {
        ("", more)
    } else {
        (more, "")
    }
}

/// The mutation run's reproducers (issue 11): each is one error naming the file and what is wrong, never a
/// panic, never an allocation the header made up.
#[test]
fn malformed_files_are_refused_before_the_gltf_crate_sees_them() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    // A glb whose header length lies (near 2³², and below 12).
    for (length, name) in [(4_294_967_284u32, "huge.glb"), (8, "tiny.glb")] {
        let json = br#"{"asset":{"version":"2.0"}}  "#;
        let mut glb = b"glTF".to_vec();
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&length.to_le_bytes());
        glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
        glb.extend_from_slice(b"JSON");
        glb.extend_from_slice(json);
        let path = d.join(name);
        std::fs::write(&path, &glb).unwrap();
        let msg = load_gltf(&path).expect_err("lying header").to_string();
        assert!(
            msg.contains(name)
                && msg.contains(&format!("declares {length} bytes, the file holds {}", glb.len())),
            "{msg}"
        );
    }
    // Indices pointing at a float accessor; a byteStride smaller than the element; an accessor beyond its view.
    let cases = [
        (
            triangle_with(d, "float_indices.gltf", r#","indices":0"#, "", ""),
            "indices (accessor 0): Vec3 F32 is not a type this attribute can have",
        ),
        (
            triangle_with(
                d,
                "stride.gltf",
                r#","NORMAL":1"#,
                r#",{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}"#,
                r#",{"buffer":0,"byteOffset":0,"byteLength":36,"byteStride":4}"#,
            ),
            "Normals (accessor 1): byteStride 4 is smaller than its 12-byte element",
        ),
        (
            triangle_with(
                d,
                "beyond.gltf",
                r#","indices":1"#,
                r#",{"bufferView":0,"componentType":5125,"count":10,"type":"SCALAR","byteOffset":8}"#,
                "",
            ),
            "10 elements of 4 bytes every 4 from byte 8 do not fit its buffer view of 36 bytes",
        ),
        // Found by the mutation run (tests/it/fuzz.rs): a count of 0 made the crate's reader panic.
        (
            triangle_with(
                d,
                "empty_colors.gltf",
                r#","COLOR_0":1"#,
                r#",{"bufferView":0,"componentType":5126,"count":0,"type":"VEC3"}"#,
                "",
            ),
            "Colors(0) (accessor 1): has count 0 (glTF requires at least 1)",
        ),
    ];
    for (path, needle) in cases {
        let msg = load_gltf(&path).expect_err("malformed").to_string();
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(msg.contains(name) && msg.contains(needle), "{msg}");
    }
    // Buffer URIs: absolute, leaving the folder, a special file.
    for (uri, needle) in [
        ("/etc/hostname", "only relative buffer paths are read"),
        ("../outside.bin", "leaves the file's folder"),
        ("sub/../../x.bin", "leaves the file's folder"),
    ] {
        let text = format!(r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":4,"uri":"{uri}"}}]}}"#);
        let path = write(d, "uri.gltf", &text);
        let msg = load_gltf(&path).expect_err("bad uri").to_string();
        assert!(msg.contains("uri.gltf") && msg.contains(needle), "{uri}: {msg}");
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", d.join("zero.bin")).unwrap();
        let text = r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"zero.bin"}]}"#;
        let path = write(d, "device.gltf", text);
        let msg = load_gltf(&path).expect_err("device").to_string();
        assert!(msg.contains("buffer 0 ('zero.bin'): not a regular file"), "{msg}");
        let link = d.join("zero.glb");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let msg = load_gltf(&link).expect_err("device").to_string();
        assert!(
            msg.contains("zero.glb") && msg.contains("not a regular file"),
            "{msg}"
        );
    }
}
