//! `hairlab gen` and `hairlab info`: every generator kind and style written and read back, bad parameters and
//! failed writes refused, broken `.hair` files named.

use crate::common::cli::{assert_fails, hairlab, stderr};
use clap::ValueEnum;
use hairlab::scene::generate::{GenKind, GenParams, HairStyle, generate};
use hairlab::scene::hair::read_hair_file;
use std::path::Path;

/// A generator kind's name on the command line (a match, so a new kind must be named here).
fn kind_name(kind: GenKind) -> &'static str {
    match kind {
        GenKind::Head => "head",
        GenKind::Patch => "patch",
        GenKind::StrayStrand => "stray-strand",
        GenKind::MixedSizes => "mixed-sizes",
        GenKind::ManyClumps => "many-clumps",
        GenKind::FurCylinder => "fur-cylinder",
        GenKind::FurHat => "fur-hat",
    }
}

fn style_name(style: HairStyle) -> &'static str {
    match style {
        HairStyle::Straight => "straight",
        HairStyle::Wavy => "wavy",
        HairStyle::Curly => "curly",
    }
}

/// Runs `hairlab gen KIND --style STYLE` on a small scene and returns the file's bytes.
fn gen_file(dir: &Path, kind: &str, style: &str) -> Vec<u8> {
    let f = dir.join(format!("{kind}-{style}.hair"));
    let o = hairlab(&[
        "gen",
        kind,
        "--style",
        style,
        "--strands",
        "40",
        "--segments",
        "4",
        "--clumps",
        "3",
        "--seed",
        "5",
        "--out",
        f.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "gen {kind} --style {style}: {}", stderr(&o));
    std::fs::read(&f).unwrap()
}

#[test]
fn gen_then_info_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("patch.hair");
    let f = f.to_str().unwrap();
    let o = hairlab(&[
        "gen",
        "patch",
        "--strands",
        "50",
        "--segments",
        "4",
        "--seed",
        "9",
        "--out",
        f,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = hairlab(&["info", f]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("strands:   50"), "{out}");
    assert!(out.contains("points:    250"), "{out}");
    assert!(out.contains("segments:  200"), "{out}");
    assert!(out.contains("arrays:    segments, points"), "{out}");
}

#[test]
fn gen_writes_every_generator_kind_and_style() {
    let dir = tempfile::tempdir().unwrap();
    let head = gen_file(dir.path(), "head", "wavy");
    for &kind in GenKind::value_variants() {
        for &style in HairStyle::value_variants() {
            let (k, s) = (kind_name(kind), style_name(style));
            let bytes = gen_file(dir.path(), k, s);
            if (kind, style) != (GenKind::Head, HairStyle::Wavy) {
                assert_ne!(bytes, head, "gen {k} --style {s} wrote the default head");
            }
            let path = dir.path().join(format!("{k}-{s}.hair"));
            let written = read_hair_file(&path).unwrap().to_strands().unwrap();
            let expected = generate(&GenParams {
                kind,
                style,
                strands: 40,
                segments: 4,
                clumps: 3,
                seed: 5,
                ..GenParams::default()
            })
            .unwrap()
            .strands;
            assert_eq!(
                written.strand_count(),
                expected.strand_count(),
                "gen {k} --style {s}"
            );
            assert_eq!(written, expected, "gen {k} --style {s}");
        }
    }
}

#[test]
fn gen_help_lists_every_kind_and_style_and_unknown_ones_are_refused() {
    let o = hairlab(&["gen", "--help"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let help = String::from_utf8_lossy(&o.stdout);
    for &kind in GenKind::value_variants() {
        assert!(help.contains(&format!("- {}:", kind_name(kind))), "{help}");
    }
    for &style in HairStyle::value_variants() {
        assert!(help.contains(style_name(style)), "{help}");
    }
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("x.hair");
    for args in [
        ["gen", "blob", "--out", f.to_str().unwrap()].as_slice(),
        &["gen", "head", "--style", "frizzy", "--out", f.to_str().unwrap()],
    ] {
        let o = hairlab(args);
        assert!(!o.status.success(), "{args:?} succeeded");
        let err = stderr(&o);
        assert!(
            err.contains("invalid value") && err.contains("possible values"),
            "{err}"
        );
        assert!(!f.exists());
    }
}

#[test]
fn gen_rejects_invalid_parameters_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("bad.hair");
    let o = hairlab(&["gen", "head", "--segments", "0", "--out", f.to_str().unwrap()]);
    assert_fails(&o, &["segments"]);
    assert!(!f.exists());
    let o = hairlab(&[
        "gen",
        "head",
        "--set",
        "clump_strength=3",
        "--out",
        f.to_str().unwrap(),
    ]);
    assert_fails(&o, &["clump_strength"]);
    assert!(!f.exists());
}

#[test]
fn gen_write_failures_name_the_path_and_leave_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let listing = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    // The output is a non-empty folder: the hair is written to a temporary file that cannot replace it.
    let taken = dir.path().join("taken.hair");
    std::fs::create_dir(&taken).unwrap();
    std::fs::write(taken.join("inside"), b"x").unwrap();
    let missing = dir.path().join("no-such-folder").join("out.hair");
    for out in [&taken, &missing] {
        let o = hairlab(&["gen", "patch", "--strands", "10", "--out", out.to_str().unwrap()]);
        assert_fails(&o, &[out.to_str().unwrap()]);
        assert_eq!(listing(dir.path()), ["taken.hair"]);
        assert_eq!(listing(&taken), ["inside"]);
    }
}

#[test]
fn info_reports_broken_files_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let truncated = dir.path().join("truncated.hair");
    std::fs::write(&truncated, b"HAIR\x01\x00\x00\x00").unwrap();
    assert_fails(
        &hairlab(&["info", truncated.to_str().unwrap()]),
        &["truncated.hair"],
    );
    let magic = dir.path().join("magic.hair");
    std::fs::write(&magic, [b'X'; 128]).unwrap();
    assert_fails(&hairlab(&["info", magic.to_str().unwrap()]), &["magic.hair"]);
    let gltf = dir.path().join("broken.gltf");
    std::fs::write(&gltf, b"{ not json").unwrap();
    assert_fails(&hairlab(&["info", gltf.to_str().unwrap()]), &["broken.gltf"]);
    let other = dir.path().join("strands.obj");
    std::fs::write(&other, b"v 0 0 0").unwrap();
    assert_fails(&hairlab(&["info", other.to_str().unwrap()]), &["strands.obj"]);
    assert_fails(
        &hairlab(&["info", "/nonexistent/x.hair"]),
        &["/nonexistent/x.hair"],
    );
}

/// A `.hair` warning (bytes after the last array) is printed once and names the file.
#[test]
fn hair_warnings_print_once_and_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("padded.hair");
    let o = hairlab(&["gen", "patch", "--strands", "3", "--out", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut bytes = std::fs::read(&path).unwrap();
    bytes.extend_from_slice(b"pad!");
    std::fs::write(&path, bytes).unwrap();
    let o = hairlab(&["info", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let warnings: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("after the last array"))
        .collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(
        warnings[0].contains("padded.hair: 4 bytes after the last array"),
        "{err}"
    );
}
