//! TressFX `.tfx` and USC-HairSalon `.data`: hand-built files decoded to known values, one groom written as
//! `.hair`, `.tfx` and `.data` loading as the same strands, lying and truncated files refused by name, `hairlab
//! info` on both, and `hairlab convert` round trips.

use glam::{Vec3, Vec4};
use hairlab::scene::Strands;
use hairlab::scene::hair::{HairFile, write_hair_file};
use hairlab::scene::load::load_scene;
use hairlab::scene::tfx::{TfxError, TfxFile, read_tfx, read_tfx_file, write_tfx_file};
use hairlab::scene::usc_data::{DataError, read_data, read_data_file, write_data_file};

use crate::common::cli::{assert_fails, hairlab};

fn put_u32(b: &mut Vec<u8>, v: u32) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_i32(b: &mut Vec<u8>, v: i32) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_f32s(b: &mut Vec<u8>, v: &[f32]) {
    v.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
}

/// A TressFX 4 header built field by field: version, strands, vertices per strand, then the five offsets
/// (positions, strand UVs, vertex UVs, strand thickness, vertex colours) and 32 reserved words.
fn tfx_header(version: f32, strands: u32, per: u32, offsets: [u32; 5]) -> Vec<u8> {
    let mut b = Vec::new();
    put_f32s(&mut b, &[version]);
    put_u32(&mut b, strands);
    put_u32(&mut b, per);
    offsets.iter().for_each(|&o| put_u32(&mut b, o));
    (0..32).for_each(|_| put_u32(&mut b, 0));
    assert_eq!(b.len(), 160);
    b
}

/// 2 strands of 3 vertices with every array: positions at 160 (6 × 16 bytes), strand UVs at 256 (2 × 8), vertex
/// UVs at 272 (6 × 8), strand thickness at 320 (2 × 4), vertex colours at 328 (6 × 16); 424 bytes in all.
pub(crate) fn hand_built_tfx() -> Vec<u8> {
    let mut b = tfx_header(4.0, 2, 3, [160, 256, 272, 320, 328]);
    put_f32s(
        &mut b,
        &[
            0.0, 0.0, 0.0, 0.0, //
            0.0, 1.0, 0.0, 0.0, //
            0.5, 2.0, -0.25, 1.0, //
            3.0, 0.0, 1.0, 0.0, //
            3.0, -1.5, 1.0, 0.0, //
            3.0, -3.0, 2.0, 1.0,
        ],
    );
    assert_eq!(b.len(), 256);
    put_f32s(&mut b, &[0.1, 0.2, 0.3, 0.4]);
    put_f32s(&mut b, &[0.0; 12]);
    assert_eq!(b.len(), 320);
    put_f32s(&mut b, &[0.5, 2.0]);
    put_f32s(
        &mut b,
        &[
            1.0, 0.0, 0.0, 1.0, //
            0.0, 1.0, 0.0, 0.75, //
            0.0, 0.0, 1.0, 0.5, //
            0.5, 0.5, 0.5, 0.25, //
            0.25, 0.125, 1.0, 0.0, //
            1.0, 1.0, 1.0, 1.0,
        ],
    );
    assert_eq!(b.len(), 424);
    b
}

#[test]
fn hand_built_tfx_decodes_to_known_values() {
    let f = read_tfx(&hand_built_tfx()).expect("valid file");
    assert_eq!((f.strand_count, f.vertices_per_strand), (2, 3));
    assert!(f.strand_uvs && f.vertex_uvs);
    assert_eq!(f.positions[2], Vec4::new(0.5, 2.0, -0.25, 1.0));
    let s = f.to_strands();
    assert_eq!(s.counts, [3, 3]);
    assert_eq!(
        s.points,
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.5, 2.0, -0.25),
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(3.0, -1.5, 1.0),
            Vec3::new(3.0, -3.0, 2.0),
        ]
    );
    assert_eq!(s.thickness, Some(vec![0.5, 0.5, 0.5, 2.0, 2.0, 2.0]));
    assert_eq!(s.alpha, Some(vec![1.0, 0.75, 0.5, 0.25, 0.0, 1.0]));
    assert_eq!(s.color.as_ref().map(|c| c[4]), Some(Vec3::new(0.25, 0.125, 1.0)));
}

#[test]
fn tfx_with_positions_only() {
    let mut b = tfx_header(4.0, 1, 2, [160, 0, 0, 0, 0]);
    put_f32s(&mut b, &[1.0, 2.0, 3.0, 0.0, 4.0, 5.0, 6.0, 0.0]);
    let s = read_tfx(&b).expect("valid").to_strands();
    assert_eq!(s.points, [Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0)]);
    assert_eq!((s.thickness, s.alpha, s.color), (None, None, None));
}

/// Strands of 2, 0 and 1 vertices: 4 + (4 + 24) + 4 + (4 + 12) = 52 bytes.
pub(crate) fn hand_built_data() -> Vec<u8> {
    let mut b = Vec::new();
    put_i32(&mut b, 3);
    put_i32(&mut b, 2);
    put_f32s(&mut b, &[1.0, 2.0, 3.0, -1.0, 0.5, 4.0]);
    put_i32(&mut b, 0);
    put_i32(&mut b, 1);
    put_f32s(&mut b, &[7.0, 8.0, 9.0]);
    assert_eq!(b.len(), 52);
    b
}

#[test]
fn hand_built_data_decodes_to_known_values() {
    let f = read_data(&hand_built_data()).expect("valid file");
    assert_eq!(f.empty_strands, 1);
    // The strand of one vertex is a bare root, kept apart from the strands drawn.
    assert_eq!(f.strands.counts, [2]);
    assert_eq!(
        f.strands.points,
        [Vec3::new(1.0, 2.0, 3.0), Vec3::new(-1.0, 0.5, 4.0)]
    );
    assert_eq!(f.bare_roots, [Vec3::new(7.0, 8.0, 9.0)]);
    assert_eq!(
        (&f.strands.thickness, &f.strands.alpha, &f.strands.color),
        (&None, &None, &None)
    );
}

/// 2 strands of 4 points; thickness constant along each strand (a `.tfx` thickness is per strand); alpha values
/// exact under `.hair`'s `1 - (1 - a)`.
pub(crate) fn uniform_groom() -> Strands {
    Strands {
        points: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.1, 0.01),
            Vec3::new(0.02, 0.2, 0.03),
            Vec3::new(0.05, 0.3, 0.04),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(1.0, -0.25, -1.0),
            Vec3::new(1.5, -0.5, -1.25),
            Vec3::new(2.0, -0.75, -1.5),
        ],
        counts: vec![4, 4],
        thickness: Some(vec![0.5, 0.5, 0.5, 0.5, 0.25, 0.25, 0.25, 0.25]),
        alpha: Some(vec![1.0, 0.75, 0.5, 0.25, 0.0, 1.0, 0.5, 0.75]),
        color: Some(vec![
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(0.25, 0.125, 1.0),
            Vec3::new(0.75, 0.5, 0.25),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 1.0),
        ]),
    }
}

#[test]
fn one_groom_as_hair_tfx_and_data_gives_the_same_strands() {
    let dir = tempfile::tempdir().expect("tempdir");
    let groom = uniform_groom();
    let (hair, tfx, data) = (
        dir.path().join("g.hair"),
        dir.path().join("g.tfx"),
        dir.path().join("g.data"),
    );
    write_hair_file(&hair, &HairFile::from_strands(&groom, "groom").unwrap()).unwrap();
    write_tfx_file(&tfx, &TfxFile::from_strands(&groom).unwrap()).unwrap();
    write_data_file(&data, &groom).unwrap();
    // 160-byte header + 8 × 16 positions + 2 × 4 thickness + 8 × 16 colours; 4 + 2 × (4 + 4 × 12).
    assert_eq!(std::fs::metadata(&tfx).unwrap().len(), 160 + 128 + 8 + 128);
    assert_eq!(std::fs::metadata(&data).unwrap().len(), 4 + 2 * (4 + 48));
    let from_hair = load_scene(&hair).unwrap().strands;
    let from_tfx = load_scene(&tfx).unwrap().strands;
    let from_data = load_scene(&data).unwrap().strands;
    assert_eq!(from_hair, groom);
    assert_eq!(
        from_tfx, groom,
        "every array: points, counts, thickness, alpha, colour"
    );
    assert_eq!(from_data.points, groom.points);
    assert_eq!(from_data.counts, groom.counts);
    assert_eq!(
        (from_data.thickness, from_data.alpha, from_data.color),
        (None, None, None),
        ".data holds positions only"
    );
}

#[test]
fn tfx_writer_refuses_what_the_format_cannot_hold() {
    let mut uneven = uniform_groom();
    uneven.counts = vec![3, 5];
    let e = TfxFile::from_strands(&uneven).unwrap_err().to_string();
    assert!(e.contains("strand 1 has 5 points and strand 0 has 3"), "{e}");
    let mut tapered = uniform_groom();
    tapered.thickness.as_mut().unwrap()[6] = 0.125;
    let e = TfxFile::from_strands(&tapered).unwrap_err().to_string();
    assert!(e.contains("thickness of strand 1 varies"), "{e}");
    let mut no_alpha = uniform_groom();
    no_alpha.alpha = None;
    let e = TfxFile::from_strands(&no_alpha).unwrap_err().to_string();
    assert!(e.contains("RGBA"), "{e}");
}

fn tfx_err(bytes: &[u8]) -> String {
    read_tfx(bytes).expect_err("refused").to_string()
}

#[test]
fn lying_and_truncated_tfx_files_are_refused() {
    let good = hand_built_tfx();
    assert!(tfx_err(&good[..159]).contains("truncated header: the file holds 159 bytes"));
    // Cut inside the colours: the last array runs past the end.
    let e = tfx_err(&good[..423]);
    assert_eq!(
        e,
        "vertex colours at byte 328 (6 entries, 96 bytes) runs past the end of the file, in a file of 423 bytes"
    );
    // A lying strand count: 2³² − 1 strands × 3 vertices × 16 bytes, refused before anything is allocated.
    let mut lying = good.clone();
    lying[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    let start = std::time::Instant::now();
    let e = tfx_err(&lying);
    assert!(start.elapsed() < std::time::Duration::from_millis(100));
    assert_eq!(
        e,
        format!(
            "vertex positions at byte 160 ({} entries, {} bytes) runs past the end of the file, in a file of 424 bytes",
            u64::from(u32::MAX) * 3,
            u64::from(u32::MAX) * 48
        )
    );
    // An offset past the end, and one inside the header.
    let mut far = good.clone();
    far[28..32].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(tfx_err(&far).starts_with("vertex colours at byte 4294967295"));
    let mut inside = good.clone();
    inside[12..16].copy_from_slice(&8u32.to_le_bytes());
    assert!(tfx_err(&inside).contains("starts inside the 160-byte header"));
    // TressFX 3 and garbage versions; no positions; zero vertices per strand.
    let mut v3 = good.clone();
    v3[0..4].copy_from_slice(&3.0f32.to_le_bytes());
    assert_eq!(
        tfx_err(&v3),
        "TressFX version 3: only version 4 files are read (TressFX 3 has a different header)"
    );
    let mut no_positions = good.clone();
    no_positions[12..16].copy_from_slice(&0u32.to_le_bytes());
    assert_eq!(
        tfx_err(&no_positions),
        "the header has no vertex positions (offset 0)"
    );
    let mut zero = good.clone();
    zero[8..12].copy_from_slice(&0u32.to_le_bytes());
    assert!(tfx_err(&zero).contains("2 strands of 0 vertices"));
    // Bad values, named by index.
    let mut nan = good.clone();
    nan[160 + 16 + 4..160 + 16 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    assert!(tfx_err(&nan).starts_with("position of vertex 1 is not finite"));
    let mut thick = good.clone();
    thick[324..328].copy_from_slice(&(-1.0f32).to_le_bytes());
    assert_eq!(
        tfx_err(&thick),
        "thickness of strand 1 is -1; it must be finite and not negative"
    );
    let mut alpha = good.clone();
    alpha[328 + 12..328 + 16].copy_from_slice(&1.5f32.to_le_bytes());
    assert_eq!(tfx_err(&alpha), "alpha of vertex 0 is 1.5; it must lie in [0, 1]");
    let mut uv = good;
    uv[272 + 8 * 5..272 + 8 * 5 + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_eq!(tfx_err(&uv), "vertex UV of vertex 5 is not finite: [inf, 0]");
}

fn data_err(bytes: &[u8]) -> String {
    read_data(bytes).expect_err("refused").to_string()
}

#[test]
fn lying_and_truncated_data_files_are_refused() {
    let good = hand_built_data();
    assert_eq!(
        data_err(&good[..3]),
        "truncated: the file holds 3 bytes, the strand count alone needs 4"
    );
    // Cut inside the last strand's point: 12 bytes needed at byte 40, 11 left.
    assert_eq!(
        data_err(&good[..51]),
        "truncated: strand 2 says 1 vertices (12 bytes) at byte 40, but only 11 bytes are left"
    );
    // Cut right after the second strand: the third has no vertex count.
    assert_eq!(
        data_err(&good[..36]),
        "truncated: strand 2 of 3 has no vertex count (the file ends at byte 36)"
    );
    // A lying strand count, refused before `counts` is allocated: i32::MAX × 4 bytes > 48.
    let mut lying = good.clone();
    lying[0..4].copy_from_slice(&i32::MAX.to_le_bytes());
    assert_eq!(
        data_err(&lying),
        format!(
            "the header says {} strands, whose vertex counts alone need {} bytes, but only 48 follow it",
            i32::MAX,
            i64::from(i32::MAX) * 4
        )
    );
    // A lying vertex count.
    let mut lying = good.clone();
    lying[4..8].copy_from_slice(&i32::MAX.to_le_bytes());
    assert_eq!(
        data_err(&lying),
        format!(
            "truncated: strand 0 says {} vertices ({} bytes) at byte 8, but only 44 bytes are left",
            i32::MAX,
            i64::from(i32::MAX) * 12
        )
    );
    let mut negative = good.clone();
    negative[0..4].copy_from_slice(&(-1i32).to_le_bytes());
    assert_eq!(
        data_err(&negative),
        "the strand count is -1; it must not be negative"
    );
    let mut negative = good.clone();
    negative[32..36].copy_from_slice(&(-5i32).to_le_bytes());
    assert_eq!(
        data_err(&negative),
        "strand 1 has -5 vertices; a count must not be negative"
    );
    let mut nan = good;
    nan[40..44].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(data_err(&nan), "point 2 (strand 2) is not finite: [NaN, 8, 9]");
}

#[test]
fn file_errors_name_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tfx = dir.path().join("short_groom.tfx");
    std::fs::write(&tfx, &hand_built_tfx()[..300]).unwrap();
    let e = read_tfx_file(&tfx).unwrap_err();
    assert!(matches!(e, TfxError::InFile { .. }));
    assert!(
        e.to_string()
            .starts_with(&format!("{}: vertex UVs at byte 272", tfx.display())),
        "{e}"
    );
    let data = dir.path().join("short_groom.data");
    std::fs::write(&data, &hand_built_data()[..20]).unwrap();
    let e = read_data_file(&data).unwrap_err();
    assert!(matches!(e, DataError::InFile { .. }));
    assert!(
        e.to_string()
            .starts_with(&format!("{}: truncated: strand 0", data.display())),
        "{e}"
    );
    for missing in ["missing.tfx", "missing.data"] {
        let e = format!("{:#}", load_scene(&dir.path().join(missing)).unwrap_err());
        assert!(e.contains(missing), "{e}");
    }
}

#[test]
fn info_prints_arrays_and_what_is_dropped() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tfx = dir.path().join("groom.tfx");
    std::fs::write(&tfx, hand_built_tfx()).unwrap();
    let o = hairlab(&["info", tfx.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    for line in [
        "arrays:    positions, strand UVs, vertex UVs, strand thickness, vertex colours",
        "dropped:   position w (TressFX's simulation flag)",
        "dropped:   strand UVs (hairlab has no texture coordinates)",
        "dropped:   vertex UVs (hairlab has no texture coordinates)",
        "strands:   2",
        "points:    6",
        "segments:  4",
        "bounds:    min (0.0000, -3.0000, -0.2500) max (3.0000, 2.0000, 2.0000)",
    ] {
        assert!(out.lines().any(|l| l == line), "{line:?} missing from:\n{out}");
    }
    let data = dir.path().join("groom.data");
    std::fs::write(&data, hand_built_data()).unwrap();
    let o = hairlab(&["info", data.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    for line in [
        "arrays:    positions",
        "dropped:   1 strands of 0 vertices",
        "roots:     1 bare roots (strands of one vertex: scalp with no hair), counted apart from the strands drawn",
        "strands:   1",
        "points:    2",
        "segments:  1",
        "bounds:    min (-1.0000, 0.5000, 3.0000) max (1.0000, 2.0000, 4.0000)",
    ] {
        assert!(out.lines().any(|l| l == line), "{line:?} missing from:\n{out}");
    }
    let broken = dir.path().join("broken.data");
    std::fs::write(&broken, &hand_built_data()[..10]).unwrap();
    assert_fails(
        &hairlab(&["info", broken.to_str().unwrap()]),
        &[
            "broken.data",
            "3 strands, whose vertex counts alone need 12 bytes, but only 6 follow it",
        ],
    );
}

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The names in `dir`, sorted.
fn names(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn convert_tfx_to_hair_and_back_keeps_every_point() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = |n: &str| dir.path().join(n).to_str().unwrap().to_owned();
    std::fs::write(p("in.tfx"), hand_built_tfx()).unwrap();
    let o = hairlab(&["convert", &p("in.tfx"), &p("out.hair")]);
    assert!(o.status.success(), "{}", crate::common::cli::stderr(&o));
    assert_eq!(
        stdout(&o),
        format!("wrote {}: 2 strands, 6 points, 4 segments\n", p("out.hair"))
    );
    let original = read_tfx(&hand_built_tfx()).unwrap().to_strands();
    let hair = load_scene(std::path::Path::new(&p("out.hair"))).unwrap().strands;
    // Every array: the alphas (1, 0.75, 0.5, 0.25, 0, 1) survive `.hair`'s 1 - (1 - a) exactly.
    assert_eq!(hair, original);
    // And back: the UVs and w were dropped on the way in; the strands are the same.
    let o = hairlab(&["convert", &p("out.hair"), &p("back.tfx")]);
    assert!(o.status.success(), "{}", crate::common::cli::stderr(&o));
    assert_eq!(
        read_tfx_file(std::path::Path::new(&p("back.tfx")))
            .unwrap()
            .to_strands(),
        original
    );
    assert_eq!(names(dir.path()), ["back.tfx", "in.tfx", "out.hair"]);
}

#[test]
fn convert_to_data_says_what_it_drops() {
    let dir = tempfile::tempdir().expect("tempdir");
    let gltf = crate::gltf_load::sample(dir.path());
    let out = dir.path().join("s.data");
    let o = hairlab(&["convert", gltf.to_str().unwrap(), out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", crate::common::cli::stderr(&o));
    // The sample: 1 quad mesh, strands of 3, 2, 3 and 4 points with colour and (on the strip) alpha.
    assert_eq!(
        stdout(&o),
        format!(
            "wrote {}: 4 strands, 12 points, 8 segments\ndropped:   1 meshes (the output holds strands only)\n\
             dropped:   alpha (a .data file holds positions only)\ndropped:   colour (a .data file holds positions \
             only)\n",
            out.display()
        )
    );
    let from_gltf = load_scene(&gltf).unwrap().strands;
    let data = read_data_file(&out).unwrap();
    assert_eq!(
        (data.strands.points, data.strands.counts),
        (from_gltf.points, from_gltf.counts)
    );
}

#[test]
fn convert_keeps_bare_roots_where_the_format_holds_them_and_says_which() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = |n: &str| dir.path().join(n).to_str().unwrap().to_owned();
    std::fs::write(p("in.data"), hand_built_data()).unwrap();
    let o = hairlab(&["convert", &p("in.data"), &p("out.data")]);
    assert!(o.status.success(), "{}", crate::common::cli::stderr(&o));
    assert_eq!(
        stdout(&o),
        format!(
            "wrote {}: 2 strands, 3 points, 1 segments\nkept:      1 bare roots (strands of one vertex, after the \
             strands drawn)\n",
            p("out.data")
        )
    );
    let back = read_data_file(std::path::Path::new(&p("out.data"))).unwrap();
    assert_eq!(back.strands.counts, [2]);
    assert_eq!(back.bare_roots, [Vec3::new(7.0, 8.0, 9.0)]);
    let o = hairlab(&["convert", &p("in.data"), &p("out.hair")]);
    assert!(o.status.success(), "{}", crate::common::cli::stderr(&o));
    let hair = load_scene(std::path::Path::new(&p("out.hair"))).unwrap().strands;
    assert_eq!(hair.counts, [2, 1]);
    let o = hairlab(&["convert", &p("in.data"), &p("out.usda")]);
    assert!(o.status.success(), "{}", crate::common::cli::stderr(&o));
    assert_eq!(
        stdout(&o),
        format!(
            "wrote {}: 1 strands, 2 points, 1 segments\ndropped:   1 bare roots (strands of one vertex: a .usda \
             curve needs two points)\n",
            p("out.usda")
        )
    );
    assert_eq!(
        load_scene(std::path::Path::new(&p("out.usda")))
            .unwrap()
            .strands
            .counts,
        [2]
    );
}

#[test]
fn convert_never_leaves_a_half_written_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = |n: &str| dir.path().join(n).to_str().unwrap().to_owned();
    // Strands of 4 and 3 points: no .tfx holds them; the old output stays as it was, and nothing else appears.
    let mut uneven = uniform_groom();
    uneven.points.pop();
    uneven.counts = vec![4, 3];
    for a in [&mut uneven.thickness, &mut uneven.alpha] {
        a.as_mut().unwrap().pop();
    }
    uneven.color.as_mut().unwrap().pop();
    write_hair_file(
        std::path::Path::new(&p("uneven.hair")),
        &HairFile::from_strands(&uneven, "").unwrap(),
    )
    .unwrap();
    std::fs::write(p("old.tfx"), b"old").unwrap();
    assert_fails(
        &hairlab(&["convert", &p("uneven.hair"), &p("old.tfx")]),
        &["old.tfx", "strand 1 has 3 points and strand 0 has 4"],
    );
    assert_eq!(std::fs::read(p("old.tfx")).unwrap(), b"old");
    // An unreadable input: named, and no output created.
    std::fs::write(p("bad.data"), [1, 0, 0, 0, 9]).unwrap();
    assert_fails(
        &hairlab(&["convert", &p("bad.data"), &p("new.hair")]),
        &[
            "bad.data",
            "1 strands, whose vertex counts alone need 4 bytes, but only 1 follow it",
        ],
    );
    // An output type it does not write: refused before reading anything.
    assert_fails(
        &hairlab(&["convert", &p("uneven.hair"), &p("out.obj")]),
        &["out.obj", "the output must be one of .hair, .tfx, .data"],
    );
    assert_eq!(names(dir.path()), ["bad.data", "old.tfx", "uneven.hair"]);
}

#[test]
fn a_preset_can_name_a_tfx_or_data_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("g.tfx"), hand_built_tfx()).unwrap();
    std::fs::write(dir.path().join("g.data"), hand_built_data()).unwrap();
    for (name, expected) in [
        ("g.tfx", read_tfx(&hand_built_tfx()).unwrap().to_strands()),
        ("g.data", read_data(&hand_built_data()).unwrap().strands),
    ] {
        // A relative scene file is found beside the preset.
        let preset = dir.path().join(format!("{name}.toml"));
        std::fs::write(&preset, format!("[scene]\nfile = \"{name}\"\n")).unwrap();
        let settings = hairlab::settings::Settings::load_preset(preset.to_str().unwrap(), &[]).unwrap();
        assert_eq!(settings.scene.build().unwrap().strands, expected, "{name}");
    }
}
