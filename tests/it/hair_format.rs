//! `.hair` format: round trips, a hand-built file, and each kind of malformed input.

use std::time::{Duration, Instant};

use glam::Vec3;
use hairlab::scene::Strands;
use hairlab::scene::hair::{HairError, HairFile, read_hair, read_hair_file, write_hair, write_hair_file};

/// Two strands (3 and 2 points) with every optional array; alpha values are exact under `1 - (1 - a)`.
pub(crate) fn full_strands() -> Strands {
    Strands {
        points: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.5, 2.0, -0.25),
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(3.0, -1.5, 1.0),
        ],
        counts: vec![3, 2],
        thickness: Some(vec![1.0, 0.5, 0.25, 2.0, 0.0]),
        alpha: Some(vec![1.0, 0.75, 0.5, 0.25, 0.0]),
        color: Some(vec![
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(0.25, 0.125, 1.0),
        ]),
    }
}

fn put_u32(b: &mut Vec<u8>, v: u32) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_f32(b: &mut Vec<u8>, v: f32) {
    b.extend_from_slice(&v.to_le_bytes());
}

/// A header built field by field, independent of `write_hair`.
fn header(strands: u32, points: u32, flags: u32, default_segments: u32, info: &[u8]) -> Vec<u8> {
    let mut b = b"HAIR".to_vec();
    put_u32(&mut b, strands);
    put_u32(&mut b, points);
    put_u32(&mut b, flags);
    put_u32(&mut b, default_segments);
    put_f32(&mut b, 0.5); // default thickness
    put_f32(&mut b, 0.25); // default transparency
    for c in [0.1, 0.2, 0.3] {
        put_f32(&mut b, c);
    }
    let mut info_field = [0u8; 88];
    info_field[..info.len()].copy_from_slice(info);
    b.extend_from_slice(&info_field);
    assert_eq!(b.len(), 128);
    b
}

/// One strand of 2 segments (3 points), flags segments | points | transparency.
fn hand_built() -> Vec<u8> {
    let mut b = header(1, 3, 1 | 2 | 8, 7, b"by hand");
    b.extend_from_slice(&2u16.to_le_bytes());
    for v in [1.0, 2.0, 3.0, -1.0, 0.5, 4.0, 0.0, 0.0, 8.0] {
        put_f32(&mut b, v);
    }
    for t in [0.0, 0.5, 1.0] {
        put_f32(&mut b, t);
    }
    b
}

#[test]
fn hand_built_buffer_decodes_to_known_values() {
    let h = read_hair(&hand_built()).expect("valid file");
    assert_eq!(h.strand_count, 1);
    assert_eq!(h.default_segments, 7);
    assert_eq!(h.default_thickness, 0.5);
    assert_eq!(h.default_transparency, 0.25);
    assert_eq!(h.default_color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(h.info, "by hand");
    assert_eq!(h.segments, Some(vec![2]));
    assert_eq!(h.thickness, None);
    assert_eq!(h.color, None);
    let s = h.to_strands().expect("convertible");
    assert_eq!(s.counts, vec![3]);
    assert_eq!(
        s.points,
        vec![
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-1.0, 0.5, 4.0),
            Vec3::new(0.0, 0.0, 8.0)
        ]
    );
    assert_eq!(s.alpha, Some(vec![1.0, 0.5, 0.0]));
    assert_eq!(s.thickness, None);
    assert_eq!(s.color, None);
}

#[test]
fn default_segments_apply_without_segments_array() {
    // 2 strands × (1 default segment + 1) = 4 points; flags: points only.
    let mut b = header(2, 4, 2, 1, b"");
    for v in [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 5.0, 0.0, 0.0, 5.0, 1.0, 0.0] {
        put_f32(&mut b, v);
    }
    let s = read_hair(&b)
        .expect("valid file")
        .to_strands()
        .expect("convertible");
    assert_eq!(s.counts, vec![2, 2]);
    assert_eq!(s.points[3], Vec3::new(5.0, 1.0, 0.0));
    assert_eq!(s.alpha, None);
}

#[test]
fn round_trip_with_all_arrays() {
    let strands = full_strands();
    let file = HairFile::from_strands(&strands, "all arrays").expect("valid strands");
    let back = read_hair(&write_hair(&file)).expect("reads back");
    assert_eq!(back, file);
    assert_eq!(back.info, "all arrays");
    assert_eq!(back.to_strands().expect("convertible"), strands);
}

#[test]
fn round_trip_without_optional_arrays_keeps_header_defaults() {
    let strands = Strands {
        thickness: None,
        alpha: None,
        color: None,
        ..full_strands()
    };
    let mut file = HairFile::from_strands(&strands, "").expect("valid strands");
    file.default_thickness = 0.125;
    file.default_transparency = 0.75;
    file.default_color = Vec3::new(0.5, 0.25, 1.0);
    let bytes = write_hair(&file);
    // Header + 2 u16 segment counts + 5 points × 12 bytes, nothing else.
    assert_eq!(bytes.len(), 128 + 2 * 2 + 5 * 12);
    let back = read_hair(&bytes).expect("reads back");
    assert_eq!(back.default_thickness, 0.125);
    assert_eq!(back.default_transparency, 0.75);
    assert_eq!(back.default_color, Vec3::new(0.5, 0.25, 1.0));
    assert_eq!(
        (
            back.thickness.as_ref(),
            back.transparency.as_ref(),
            back.color.as_ref()
        ),
        (None, None, None)
    );
    assert_eq!(back.to_strands().expect("convertible"), strands);
}

#[test]
fn empty_file_has_zero_strands() {
    let h = read_hair(&header(0, 0, 1 | 2, 0, b"")).expect("zero strands are allowed");
    let s = h.to_strands().expect("convertible");
    assert_eq!((s.strand_count(), s.point_count()), (0, 0));
}

#[test]
fn long_info_is_cut_to_87_bytes() {
    let info = "é".repeat(60); // 120 bytes of two-byte characters
    let file = HairFile::from_strands(&full_strands(), &info).expect("valid strands");
    let back = read_hair(&write_hair(&file)).expect("reads back");
    // 87 bytes would split a character: 43 whole characters (86 bytes) remain.
    assert_eq!(back.info, "é".repeat(43));
}

#[test]
fn write_hair_file_replaces_atomically_and_reads_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("out.hair");
    std::fs::write(&path, b"old contents").expect("write");
    let file = HairFile::from_strands(&full_strands(), "disk").expect("valid strands");
    write_hair_file(&path, &file).expect("writes");
    assert_eq!(read_hair_file(&path).expect("reads"), file);
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("list")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(
        names,
        vec![std::ffi::OsString::from("out.hair")],
        "no temporary file is left behind"
    );
}

#[test]
fn write_hair_file_refuses_invalid_contents_and_leaves_old_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("keep.hair");
    std::fs::write(&path, b"old contents").expect("write");
    let mut file = HairFile::from_strands(&full_strands(), "").expect("valid strands");
    file.segments = Some(vec![2, 2]); // 6 points promised, 5 present
    let err = write_hair_file(&path, &file).expect_err("invalid");
    let HairError::InFile { cause, .. } = &err else {
        panic!("expected an error naming the file: {err:?}")
    };
    assert!(matches!(**cause, HairError::SegmentMismatch { .. }), "{cause:?}");
    assert_eq!(std::fs::read(&path).expect("read"), b"old contents");
}

#[test]
fn truncated_header() {
    let b = &hand_built()[..100];
    assert!(matches!(
        read_hair(b),
        Err(HairError::TruncatedHeader { len: 100 })
    ));
    assert!(matches!(
        read_hair(b"HA"),
        Err(HairError::TruncatedHeader { len: 2 })
    ));
}

#[test]
fn truncated_arrays() {
    let full = hand_built();
    // Arrays need 2 + 36 + 12 = 50 bytes; drop the last 5.
    let err = read_hair(&full[..full.len() - 5]).expect_err("truncated");
    assert!(
        matches!(
            err,
            HairError::Truncated {
                needed: 50,
                available: 45,
                ..
            }
        ),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(msg.contains("needs 5 more bytes"), "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
}

#[test]
fn bad_magic() {
    let mut b = hand_built();
    b[..4].copy_from_slice(b"glTF");
    assert!(matches!(read_hair(&b), Err(HairError::BadMagic { found }) if &found == b"glTF"));
}

#[test]
fn lying_point_count_fails_fast_without_allocating() {
    let mut b = header(1, 4_000_000_000, 1 | 2 | 4 | 8 | 16, 0, b"");
    b.extend_from_slice(&[0u8; 64]);
    let start = Instant::now();
    let err = read_hair(&b).expect_err("cannot fit");
    assert!(
        start.elapsed() < Duration::from_millis(200),
        "took {:?}",
        start.elapsed()
    );
    // 2 + 4e9 × (12 + 4 + 4 + 12) bytes.
    assert!(
        matches!(
            err,
            HairError::Truncated {
                needed: 128_000_000_002,
                available: 64,
                points: 4_000_000_000,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn segment_sum_mismatch() {
    let mut b = hand_built();
    b[128..130].copy_from_slice(&3u16.to_le_bytes()); // 4 points promised, 3 present
    assert!(matches!(
        read_hair(&b),
        Err(HairError::SegmentMismatch {
            expected: 4,
            points: 3,
            default_segments: None,
            ..
        })
    ));
}

#[test]
fn segment_sum_mismatch_with_default_segments() {
    // 1 strand × (3 default segments + 1) = 4 points promised, but the header has 3.
    let mut b = header(1, 3, 2, 3, b"");
    b.extend_from_slice(&[0u8; 36]);
    let err = read_hair(&b).expect_err("mismatch");
    assert!(
        matches!(
            err,
            HairError::SegmentMismatch {
                expected: 4,
                points: 3,
                default_segments: Some(3),
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn missing_points_array() {
    let mut b = header(1, 3, 1, 0, b"");
    b.extend_from_slice(&2u16.to_le_bytes());
    assert!(matches!(read_hair(&b), Err(HairError::NoPoints)));
}

#[test]
fn nan_point_names_its_index() {
    let mut b = hand_built();
    let second_point_y = 128 + 2 + 12 + 4;
    b[second_point_y..second_point_y + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let err = read_hair(&b).expect_err("NaN");
    assert!(
        matches!(err, HairError::NonFinitePoint { index: 1, .. }),
        "{err:?}"
    );
    assert!(err.to_string().contains("point 1"), "{err}");
}

#[test]
fn out_of_range_transparency() {
    let mut b = hand_built();
    let third_transparency = 128 + 2 + 36 + 8;
    b[third_transparency..third_transparency + 4].copy_from_slice(&1.5f32.to_le_bytes());
    assert!(matches!(
        read_hair(&b),
        Err(HairError::BadTransparency { index: 2, value: 1.5 })
    ));
}

#[test]
fn negative_or_nan_thickness() {
    let mut b = header(1, 2, 2 | 4, 1, b"");
    b.extend_from_slice(&[0u8; 24]);
    put_f32(&mut b, 1.0);
    put_f32(&mut b, -0.5);
    assert!(matches!(
        read_hair(&b),
        Err(HairError::BadThickness {
            index: 1,
            value: -0.5
        })
    ));
    let n = b.len();
    b[n - 8..n - 4].copy_from_slice(&f32::NAN.to_le_bytes());
    assert!(matches!(
        read_hair(&b),
        Err(HairError::BadThickness { index: 0, .. })
    ));
}

#[test]
fn trailing_bytes_are_ignored() {
    let mut b = hand_built();
    b.extend_from_slice(b"padding");
    assert_eq!(
        read_hair(&b).expect("valid"),
        read_hair(&hand_built()).expect("valid")
    );
}

#[test]
fn file_errors_name_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("broken_strands.hair");
    std::fs::write(&path, b"HAIR but far too short").expect("write");
    let msg = read_hair_file(&path).expect_err("truncated").to_string();
    assert!(
        msg.contains("broken_strands.hair") && msg.contains("truncated header"),
        "{msg}"
    );
    let missing = dir.path().join("missing.hair");
    let msg = read_hair_file(&missing).expect_err("missing").to_string();
    assert!(msg.contains("missing.hair"), "{msg}");
}

#[test]
fn from_strands_rejects_unrepresentable_strands() {
    let empty_strand = Strands {
        points: vec![Vec3::ZERO],
        counts: vec![1, 0],
        ..Strands::default()
    };
    assert!(matches!(
        HairFile::from_strands(&empty_strand, ""),
        Err(HairError::StrandPoints { strand: 1, points: 0 })
    ));
    let too_long = Strands {
        points: vec![Vec3::ZERO; 65537],
        counts: vec![65537],
        ..Strands::default()
    };
    assert!(matches!(
        HairFile::from_strands(&too_long, ""),
        Err(HairError::StrandPoints { strand: 0, .. })
    ));
}
