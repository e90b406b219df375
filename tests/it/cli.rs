//! The command line as a user runs it: success paths write whole files; bad input gives one error line naming
//! the file and the problem, a non-zero exit, and no output file.

use crate::common::cli::{assert_fails, error_lines, hairlab, stderr};
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

#[test]
fn render_rejects_bad_presets_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shot.png");
    let o = dir.path().join("shot.png");
    let out_s = out.to_str().unwrap();
    assert_fails(
        &hairlab(&["render", "--preset", "no-such-preset", "--out", out_s]),
        &["no-such-preset"],
    );
    assert_fails(
        &hairlab(&["render", "--set", "render.hair_alpha=5", "--out", out_s]),
        &["hair_alpha"],
    );
    assert_fails(
        &hairlab(&["render", "--set", "method.name=magic", "--out", out_s]),
        &["magic"],
    );
    let preset = dir.path().join("broken.toml");
    std::fs::write(&preset, "[render]\nmap_resolution = \"big\"\n").unwrap();
    assert_fails(
        &hairlab(&["render", "--preset", preset.to_str().unwrap(), "--out", out_s]),
        &["broken.toml"],
    );
    let missing = dir.path().join("scene.toml");
    std::fs::write(&missing, "[scene]\nfile = \"missing.hair\"\n").unwrap();
    assert_fails(
        &hairlab(&["render", "--preset", missing.to_str().unwrap(), "--out", out_s]),
        &["missing.hair"],
    );
    assert!(!Path::new(&o).exists(), "no output on failure");
}

#[test]
fn render_writes_a_png_of_the_requested_size() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shot.png");
    let o = hairlab(&[
        "render",
        "--set",
        "scene.generator.strands=300",
        "--set",
        "scene.generator.segments=8",
        "--width",
        "96",
        "--height",
        "64",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers.len(), 1, "temporary files left behind: {leftovers:?}");
}

#[test]
fn curve_prints_the_cpu_model_against_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("texel.csv");
    std::fs::write(&csv, "depth,alpha\n0.2,0.5\n0.5,0.5\n0.8,0.5\n").unwrap();
    let o = hairlab(&[
        "curve",
        "--fragments",
        csv.to_str().unwrap(),
        "--method",
        "osm",
        "--param",
        "slices=4",
        "--samples",
        "11",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let rows: Vec<Vec<f32>> = out
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(out.lines().next(), Some("depth,reference,osm"));
    assert_eq!(rows.len(), 11);
    // b = ln 2 per fragment. Reference: 1 up to 0.2, then 1/2, 1/4 past 0.5, 1/8 past 0.8.
    let reference = [1.0, 1.0, 1.0, 0.5, 0.5, 0.5, 0.25, 0.25, 0.25, 0.125, 0.125];
    // OSM-4 planes (optical depth at 0.25, 0.5, 0.75, 1): ln2, ln2, 2 ln2, 3 ln2. At z = 0.1 (x = 0.4 in slice 0)
    // V = 2^-0.4; at 0.3 (x = 1.2) between ln2 and ln2: 1/2; at 0.6 (x = 2.4): ln2 + 0.4 ln2 -> 2^-1.4.
    let osm = [(1, 2f32.powf(-0.4)), (3, 0.5), (6, 2f32.powf(-1.4)), (10, 0.125)];
    for (i, r) in rows.iter().enumerate() {
        assert!((r[0] - i as f32 / 10.0).abs() < 1e-6);
        assert!(
            (r[1] - reference[i]).abs() < 1e-6,
            "reference at row {i}: {}",
            r[1]
        );
    }
    for (i, v) in osm {
        assert!(
            (rows[i][2] - v).abs() < 1e-5,
            "osm at row {i}: {} vs {v}",
            rows[i][2]
        );
    }
    std::fs::write(&csv, "0.2,0.5\n0.4,lots\n").unwrap();
    let o = hairlab(&["curve", "--fragments", csv.to_str().unwrap(), "--method", "osm"]);
    assert_fails(&o, &["texel.csv:2"]);
    let o = hairlab(&[
        "curve",
        "--fragments",
        csv.to_str().unwrap(),
        "--method",
        "osm",
        "--param",
        "slices=999",
    ]);
    assert_fails(&o, &["slices"]);
}

/// Runs `hairlab curve --method reference` on a fragment CSV holding `text`.
fn curve_on(dir: &Path, text: &str) -> std::process::Output {
    let csv = dir.join("texel.csv");
    std::fs::write(&csv, text).unwrap();
    hairlab(&[
        "curve",
        "--fragments",
        csv.to_str().unwrap(),
        "--method",
        "reference",
        "--samples",
        "5",
    ])
}

#[test]
fn curve_skips_comments_anywhere_and_takes_an_optional_header() {
    let dir = tempfile::tempdir().unwrap();
    let plain = curve_on(dir.path(), "0.2,0.5\n0.6,0.75\n");
    assert!(plain.status.success(), "{}", stderr(&plain));
    // Two fragments of alpha 1/2 and 3/4: V is 1, then 1/2 past 0.2, then 1/8 past 0.6.
    assert_eq!(
        String::from_utf8_lossy(&plain.stdout),
        "depth,reference,reference\n0.0,1.0,1.0\n0.25,0.5,0.5\n0.5,0.5,0.5\n0.75,0.125,0.125\n1.0,0.125,0.125\n"
    );
    for text in [
        "depth,alpha\n0.2,0.5\n0.6,0.75\n",
        "# fragments of one texel\ndepth,alpha\n0.2,0.5\n0.6,0.75\n",
        "\n  # indented comment\n\nDepth, Alpha\n# between rows\n0.2 , 0.5\n\n# again\n0.6,0.75\n# last\n",
        "alpha,depth\n0.5,0.2\n0.75,0.6\n",
        "depth,alpha\r\n\"0.2\",0.5\r\n0.6,0.75\r\n",
    ] {
        let o = curve_on(dir.path(), text);
        assert!(o.status.success(), "{text:?}: {}", stderr(&o));
        assert_eq!(o.stdout, plain.stdout, "{text:?}");
    }
}

#[test]
fn curve_rejects_bad_fragment_rows_by_file_line_and_value() {
    let dir = tempfile::tempdir().unwrap();
    for (text, needles) in [
        // An unparsable first row is not taken for a header.
        ("z,a\n0.2,0.5\n", ["texel.csv:1", "`z,a`"]),
        ("0.2,0.5\n# c\n\n0.4,lots\n", ["texel.csv:4", "`0.4,lots`"]),
        ("0.2,0.5\ndepth,alpha\n", ["texel.csv:2", "`depth,alpha`"]),
        ("0.2,0.5,0.1\n", ["texel.csv:1", "`0.2,0.5,0.1`"]),
        ("0.2\n", ["texel.csv:1", "`0.2`"]),
        ("# c\n0.2,NaN\n", ["texel.csv:2", "alpha NaN"]),
        ("0.2,0.5\ninf,0.5\n", ["texel.csv:2", "depth inf"]),
        ("-0.25,0.5\n", ["texel.csv:1", "depth -0.25"]),
        ("1.5,0.5\n", ["texel.csv:1", "depth 1.5"]),
        ("0.5,1\n", ["texel.csv:1", "alpha 1 "]),
        ("0.5,-0.5\n", ["texel.csv:1", "alpha -0.5"]),
        ("", ["texel.csv", "no fragments"]),
        ("depth,alpha\n", ["texel.csv", "no fragments"]),
        ("# only a comment\n\n", ["texel.csv", "no fragments"]),
    ] {
        let o = curve_on(dir.path(), text);
        assert_fails(&o, &needles);
        assert!(o.stdout.is_empty(), "{text:?}: printed {:?}", o.stdout);
    }
    // A global hair alpha that means nothing (NaN would mean no shadow at all).
    let csv = dir.path().join("texel.csv");
    std::fs::write(&csv, "0.2,0.5\n").unwrap();
    for bad in ["nan", "0", "1.5", "-0.2"] {
        let o = hairlab(&[
            "curve",
            "--fragments",
            csv.to_str().unwrap(),
            "--method",
            "occupancy",
            &format!("--hair-alpha={bad}"),
        ]);
        assert_fails(&o, &["--hair-alpha must be in (0, 1]"]);
        assert!(o.stdout.is_empty(), "--hair-alpha {bad}: printed output");
    }
}

/// Runs `hairlab composite --method wboit` on a pixel CSV holding `text`, with `extra` arguments.
fn composite_on(dir: &Path, text: &str, extra: &[&str]) -> std::process::Output {
    let csv = dir.join("pixel.csv");
    std::fs::write(&csv, text).unwrap();
    let mut args = vec![
        "composite",
        "--fragments",
        csv.to_str().unwrap(),
        "--method",
        "wboit",
    ];
    args.extend_from_slice(extra);
    hairlab(&args)
}

/// The printed `r,g,b`.
fn rgb(o: &std::process::Output) -> Vec<f32> {
    String::from_utf8_lossy(&o.stdout)
        .trim()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect()
}

#[test]
fn composite_prints_a_hand_computed_pixel() {
    // Through WBOIT's model (f16 targets): red at depth 0 (weight α · 2^8 = 128), green and blue at depth 1
    // (weight α = 0.5), α 0.5 each. accum = (64, 0.25, 0.25; 64.5), revealage 0.125 — all exact in f16 — so
    // C = accum.rgb / 64.5 · 0.875 + 0.125 · B, with B = (0.2, 0.4, 0.8).
    let dir = tempfile::tempdir().unwrap();
    let text = "# one pixel\ndepth,r,g,b,alpha\n1,0,1,0,0.5\n0,1,0,0,0.5\n\n1,0,0,1,0.5\n";
    let o = composite_on(dir.path(), text, &["--background", "0.2,0.4,0.8"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let expected = [
        64.0 / 64.5 * 0.875 + 0.025,
        0.25 / 64.5 * 0.875 + 0.05,
        0.25 / 64.5 * 0.875 + 0.1,
    ];
    let c = rgb(&o);
    assert_eq!(c.len(), 3);
    for (c, e) in c.iter().zip(expected) {
        assert!((c - e).abs() < 1e-6, "{c} vs {e}");
    }
    // Without a header, columns in order; the default background is black.
    let o = composite_on(dir.path(), "1,0,1,0,0.5\n0,1,0,0,0.5\n1,0,0,1,0.5\n", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    for (c, e) in rgb(&o)
        .iter()
        .zip([64.0 / 64.5 * 0.875, 0.25 / 64.5 * 0.875, 0.25 / 64.5 * 0.875])
    {
        assert!((c - e).abs() < 1e-6, "{c} vs {e}");
    }
}

#[test]
fn composite_through_the_exact_technique_matches_the_papers_three_fragment_expansion() {
    // S&A §3.4: f = α2c2 + (1 − α2)(α1c1 + (1 − α1)(α0c0 + (1 − α0)b)) back to front. Front to back here: red at
    // depth 0.1 (α 0.5), green at 0.2 (α 0.5), blue at 0.3 (α 0.25), background (0.2, 0.4, 0.8):
    // r = 0.5, g = 0.5 · 0.5 = 0.25, b = 0.25 · 0.25 = 0.0625, then the background through 0.5 · 0.5 · 0.75.
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("pixel.csv");
    std::fs::write(&csv, "0.3,0,0,1,0.25\n0.1,1,0,0,0.5\n0.2,0,1,0,0.5\n").unwrap();
    let o = hairlab(&[
        "composite",
        "--fragments",
        csv.to_str().unwrap(),
        "--method",
        "sorted",
        "--background",
        "0.2,0.4,0.8",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = 0.5 * 0.5 * 0.75;
    for (c, e) in rgb(&o)
        .iter()
        .zip([0.5 + t * 0.2, 0.25 + t * 0.4, 0.0625 + t * 0.8])
    {
        assert!((c - e).abs() < 1e-6, "{c} vs {e}");
    }
}

#[test]
fn composite_help_lists_the_techniques_and_bad_input_names_file_and_line() {
    let o = hairlab(&["composite", "--help"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("Techniques and their parameters"), "{help}");
    for t in hairlab::render::transparency::registry::all() {
        assert!(help.contains(t.name()), "{} missing from {help}", t.name());
    }
    let dir = tempfile::tempdir().unwrap();
    for (text, needles) in [
        ("1,0,1,0,0.5\n0.5,1,1\n", ["pixel.csv:2", "`0.5,1,1`"]),
        ("# c\n1,0,1,0,lots\n", ["pixel.csv:2", "`1,0,1,0,lots`"]),
        (
            "1,0,1,0,0.5\ndepth,r,g,b,alpha\n",
            ["pixel.csv:2", "five numbers"],
        ),
        ("1,NaN,1,0,0.5\n", ["pixel.csv:1", "r NaN"]),
        ("inf,0,1,0,0.5\n", ["pixel.csv:1", "depth inf"]),
        ("-1,0,1,0,0.5\n", ["pixel.csv:1", "depth -1"]),
        ("1,0,-0.5,0,0.5\n", ["pixel.csv:1", "g -0.5"]),
        ("1,0,1,0,1.5\n", ["pixel.csv:1", "alpha 1.5"]),
        ("\n# nothing\n", ["pixel.csv", "no fragments"]),
    ] {
        let o = composite_on(dir.path(), text, &[]);
        assert_fails(&o, &needles);
        assert!(o.stdout.is_empty(), "{text:?}: printed {:?}", o.stdout);
    }
    for (extra, needle) in [
        (["--background", "1,2"], "--background '1,2'"),
        (["--background", "0,0,-1"], "--background '0,0,-1'"),
        (["--hair-alpha", "nan"], "--hair-alpha must be in [0, 1]"),
        (["--param", "k=4"], "has no parameter 'k'"),
    ] {
        let o = composite_on(dir.path(), "1,0,1,0,0.5\n", &extra);
        assert_fails(&o, &[needle]);
    }
}

/// The output path is checked before any work, and the image size flags are named as the user typed them.
#[test]
fn outputs_are_checked_first_and_size_flags_name_themselves() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nowhere/shot.png");
    let o = hairlab(&["render", "--out", missing.to_str().unwrap()]);
    assert_fails(&o, &["nowhere/shot.png: the folder", "does not exist"]);
    let txt = dir.path().join("a.txt");
    let o = hairlab(&["gen", "head", "--out", txt.to_str().unwrap()]);
    assert_fails(&o, &["a.txt: the output must be a .hair file"]);
    assert!(!txt.exists());
    let png = dir.path().join("shot.png");
    let o = hairlab(&["render", "--width", "0", "--out", png.to_str().unwrap()]);
    assert_fails(
        &o,
        &["--width/--height", "render.width/height must be in 1..=8192"],
    );
    let o = hairlab(&[
        "render",
        "--width",
        "64",
        "--set",
        "render=1",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        !stderr(&o).contains("render.width=64"),
        "blames an override the user never typed: {}",
        stderr(&o)
    );
    assert!(!png.exists());
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

/// A headless GPU run with no session (no `XDG_RUNTIME_DIR`) prints no driver noise about it.
#[test]
fn headless_runs_print_nothing_about_a_missing_session() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("small.png");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args([
            "render",
            "--set",
            "scene.generator.strands=50",
            "--width",
            "32",
            "--height",
            "24",
        ])
        .args(["--out", out.to_str().unwrap()])
        .env("RUST_LOG", "warn")
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .expect("run hairlab");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("XDG_RUNTIME_DIR"), "{}", stderr(&o));
}

/// `hairlab soak`, short: four cycles of every method on a tiny scene, one memory sample per cycle, and the growth
/// from the first cycle's end to the last's within the 5 % it allows.
#[test]
fn soak_samples_memory_per_cycle_and_reports_its_growth() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let methods = hairlab::methods::registry::all().len();
    let frames = (4 * 2 * methods).to_string();
    let mut args = vec!["soak", "--frames", &frames, "--switch-every", "2"];
    for s in [
        "scene.generator.strands=50",
        "render.map_resolution=64",
        "render.width=32",
        "render.height=24",
    ] {
        args.extend(["--set", s]);
    }
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let samples: Vec<u64> = out
        .lines()
        .skip(1)
        .filter_map(|l| l.split_whitespace().next()?.parse().ok())
        .collect();
    let cycle = 2 * methods as u64;
    assert_eq!(samples, [cycle, 2 * cycle, 3 * cycle, 4 * cycle], "{out}");
    assert!(
        out.contains("growth from the first cycle's end to the last's: resident"),
        "{out}"
    );
    let o = hairlab(&["soak", "--frames", "10", "--switch-every", "2"]);
    assert_fails(&o, &["--frames 10 holds fewer than two cycles"]);
}

/// `render --preset fur-cylinder` renders the fur in each mode and prints the paper's Table 1 rows; a bad fur
/// value is refused by its key before anything is written, and so is a technique that cannot show fur.
#[test]
fn render_draws_fur_and_prints_table_1() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fur.png");
    let out_s = out.to_str().unwrap();
    for mode in ["implicit", "explicit", "hybrid"] {
        let o = hairlab(&[
            "render",
            "--preset",
            "fur-cylinder",
            "--set",
            &format!("fur.mode={mode}"),
            "--set",
            "fur.max_steps=48",
            "--set",
            "fur.layers=4",
            "--set",
            "fur.max_level=2",
            "--set",
            "scene.generator.strands=200",
            "--width",
            "96",
            "--height",
            "72",
            "--out",
            out_s,
        ]);
        assert!(o.status.success(), "{mode}: {}", stderr(&o));
        let err = stderr(&o);
        for row in hairlab::fur::table::TIME_ROWS
            .iter()
            .chain(&hairlab::fur::table::MEMORY_ROWS)
        {
            assert!(err.contains(row), "{mode}: no '{row}' in\n{err}");
        }
        assert!(
            err.contains(&format!("fur ({mode}, virtual blending): 3584 triangles")),
            "{err}"
        );
        assert_eq!(image::open(&out).unwrap().width(), 96);
    }
    std::fs::remove_file(&out).unwrap();
    assert_fails(
        &hairlab(&[
            "render",
            "--preset",
            "fur-cylinder",
            "--set",
            "fur.layers=0",
            "--out",
            out_s,
        ]),
        &["invalid fur.layers = 0: must be in 1..=256"],
    );
    assert!(!out.exists(), "no output on failure");
    // Fur is shown by its own technique, never swapped in: another one is refused, naming the fur's.
    let strands_only = hairlab::render::transparency::registry::default_technique().name();
    let fur_technique = hairlab::render::transparency::registry::fur().name();
    assert_fails(
        &hairlab(&[
            "render",
            "--preset",
            "fur-cylinder",
            "--set",
            &format!("transparency.name={strands_only}"),
            "--set",
            "fur.layers=4",
            "--set",
            "fur.max_level=2",
            "--width",
            "96",
            "--height",
            "72",
            "--out",
            out_s,
        ]),
        &[
            "the scene has fur",
            format!("'{strands_only}' cannot show it; choose '{fur_technique}'").as_str(),
        ],
    );
    assert!(!out.exists(), "no output on failure");
}

/// `compare`'s printed value of `name`.
fn printed(o: &std::process::Output, name: &str) -> f64 {
    let stdout = String::from_utf8_lossy(&o.stdout);
    stdout
        .lines()
        .find_map(|l| {
            let mut words = l.split_whitespace();
            (words.next() == Some(name)).then(|| words.next().unwrap().parse().unwrap())
        })
        .unwrap_or_else(|| panic!("no {name} in {stdout}"))
}

fn flip_fixture(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/flip")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

#[test]
fn compare_prints_every_image_metric_and_writes_the_flip_map() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("flip.png");
    let (a, b, mask) = (
        flip_fixture("strands_a.png"),
        flip_fixture("strands_b.png"),
        flip_fixture("strands_mask.png"),
    );
    let o = hairlab(&[
        "compare",
        &a,
        &b,
        "--mask",
        &mask,
        "--flip-map",
        map.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // NVIDIA's and scikit-image's values for this pair and mask (`tests/fixtures/flip/reference.py`).
    assert!((printed(&o, "flip") - 0.187_431_14).abs() < 1e-3);
    assert!((printed(&o, "flip_hair") - 0.203_148_66).abs() < 1e-3);
    assert!((printed(&o, "flip_p99_hair") - 0.597_611_90).abs() < 1e-3);
    assert!((printed(&o, "ssim") + 0.221_951_82).abs() < 1e-5);
    for name in [
        "rmse",
        "psnr",
        "rmse_hair",
        "ssim_hair",
        "p99",
        "contrast_retention",
        "flip_p95_hair",
    ] {
        assert!(printed(&o, name).is_finite(), "{name}");
    }
    let heat = image::open(&map).unwrap();
    assert_eq!((heat.width(), heat.height()), (32, 24));
    // Without a mask every pixel is hair; an image against itself has no error.
    let o = hairlab(&["compare", &a, &a]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        (printed(&o, "flip"), printed(&o, "rmse"), printed(&o, "ssim")),
        (0.0, 0.0, 1.0)
    );
}

#[test]
fn compare_names_missing_unreadable_and_mismatched_files() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("flip.png");
    let map_arg = map.to_str().unwrap();
    let a = flip_fixture("strands_a.png");
    let missing = dir.path().join("missing.png");
    let o = hairlab(&["compare", &a, missing.to_str().unwrap(), "--flip-map", map_arg]);
    assert_fails(&o, &["missing.png", "cannot read"]);
    let garbage = dir.path().join("garbage.png");
    std::fs::write(&garbage, b"not a png").unwrap();
    let o = hairlab(&["compare", garbage.to_str().unwrap(), &a, "--flip-map", map_arg]);
    assert_fails(&o, &["garbage.png", "not a readable image"]);
    let small = dir.path().join("small.png");
    image::RgbaImage::new(8, 8).save(&small).unwrap();
    let o = hairlab(&["compare", &a, small.to_str().unwrap(), "--flip-map", map_arg]);
    assert_fails(&o, &["small.png", "8x8", "strands_a.png", "32x24", "same size"]);
    let o = hairlab(&["compare", &a, &a, "--mask", small.to_str().unwrap()]);
    assert_fails(&o, &["small.png", "8x8", "same size"]);
    assert!(!map.exists(), "no heat map after a failure");
}

/// `hairlab ARGS` with `COLUMNS=80`: what a terminal 80 columns wide shows.
fn hairlab_80(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args(args)
        .env("COLUMNS", "80")
        .env("RUST_LOG", "warn")
        .output()
        .expect("run hairlab")
}

/// Every help page: `hairlab`'s and each subcommand's and mode's, as argument lists.
fn help_pages() -> Vec<Vec<String>> {
    use clap::CommandFactory;
    fn walk(cmd: &clap::Command, path: &[String], out: &mut Vec<Vec<String>>) {
        let mut page = path.to_vec();
        page.push("--help".to_string());
        out.push(page);
        for sub in cmd.get_subcommands().filter(|c| c.get_name() != "help") {
            let mut next = path.to_vec();
            next.push(sub.get_name().to_string());
            walk(sub, &next, out);
        }
    }
    let mut out = Vec::new();
    walk(&hairlab::cli::Cli::command(), &[], &mut out);
    out
}

/// The subcommands `hairlab --help` lists.
fn subcommands() -> Vec<String> {
    use clap::CommandFactory;
    hairlab::cli::Cli::command()
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .filter(|n| n != "help")
        .collect()
}

#[test]
fn every_help_page_fits_80_columns_and_names_the_environment() {
    let pages = help_pages();
    for mode in [
        ["measure", "shadows"],
        ["bench", "transparency"],
        ["bench", "scaling"],
    ] {
        assert!(pages.iter().any(|p| p.len() > 2 && p[..2] == mode), "{pages:?}");
    }
    for page in &pages {
        let args: Vec<&str> = page.iter().map(String::as_str).collect();
        let o = hairlab_80(&args);
        assert!(o.status.success(), "{page:?}: {}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        for line in text.lines() {
            assert!(
                line.chars().count() < 80,
                "{page:?}: {} columns: {line:?}",
                line.chars().count()
            );
        }
    }
    let top = String::from_utf8_lossy(&hairlab_80(&["--help"]).stdout).into_owned();
    for var in [
        "HAIRLAB_ADAPTER",
        "WGPU_BACKEND",
        "HAIRLAB_SKIP_GPU_TESTS",
        "HAIRLAB_UPDATE_SNAPSHOTS",
        "HAIRLAB_FUZZ_CASES",
        "RUST_LOG",
        "--adapter",
        "HAIRLAB_SHADERS",
        "--shaders",
    ] {
        assert!(top.contains(var), "--help does not name {var}: {top}");
    }
}

#[test]
fn completions_and_man_pages_cover_every_subcommand() {
    let o = hairlab(&["completions", "bash"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bash = String::from_utf8_lossy(&o.stdout).into_owned();
    let o = hairlab(&["man"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(page.contains(".TH hairlab"), "{page}");
    let dir = tempfile::tempdir().unwrap();
    let o = hairlab(&["man", "--out", dir.path().to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("hairlab.1").is_file());
    for sub in subcommands() {
        assert!(
            bash.contains(&format!("hairlab__subcmd__{sub}")),
            "bash completion lacks {sub}"
        );
        let file = dir.path().join(format!("hairlab-{sub}.1"));
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        assert!(
            text.contains(".TH hairlab") && text.contains(&sub),
            "{}",
            file.display()
        );
    }
    let o = hairlab(&["completions", "tcsh"]);
    assert!(
        !o.status.success() && stderr(&o).contains("tcsh"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn adapter_flag_chooses_by_name_and_names_an_unknown_one() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let o = hairlab(&["adapters"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let list = String::from_utf8_lossy(&o.stdout).into_owned();
    let chosen: Vec<&str> = list.lines().filter(|l| l.starts_with("* ")).collect();
    assert_eq!(chosen.len(), 1, "{list}");
    // Every adapter can be chosen by its own name (its first word, which `describe` starts with).
    let adapters: Vec<&str> = list
        .lines()
        .filter(|l| l.starts_with("  ") || l.starts_with("* "))
        .collect();
    let unusable = |l: &str| l.contains("unusable");
    for line in adapters.iter().filter(|l| !unusable(l)) {
        let name = line[2..].split_whitespace().next().unwrap();
        let o = hairlab(&["--adapter", name, "adapters"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let again = String::from_utf8_lossy(&o.stdout).into_owned();
        let marked = again.lines().find(|l| l.starts_with("* ")).unwrap_or_default();
        assert!(
            marked.to_lowercase().contains(&name.to_lowercase()),
            "--adapter {name}: {again}"
        );
    }
    let o = hairlab(&["--adapter", "no-such-gpu-xyz", "measure", "--frames", "1"]);
    assert_fails(&o, &["no-such-gpu-xyz", "hairlab adapters"]);
}

#[test]
fn mode_help_pages_list_only_their_own_options() {
    let page = |args: &[&str]| String::from_utf8_lossy(&hairlab_80(args).stdout).into_owned();
    let shadows = page(&["measure", "shadows", "--help"]);
    assert!(
        shadows.contains("--config") && shadows.contains("--out"),
        "{shadows}"
    );
    for other in ["--technique", "--fur-config", "--transparency", "--fur "] {
        assert!(
            !shadows.contains(other),
            "measure shadows lists {other}: {shadows}"
        );
    }
    let eye = page(&["bench", "transparency", "--help"]);
    assert!(eye.contains("--out") && eye.contains("--frames"), "{eye}");
    for other in ["--metric", "--methods", "--max-segments", "--scaling"] {
        assert!(!eye.contains(other), "bench transparency lists {other}: {eye}");
    }
    let measure = page(&["measure", "--help"]);
    for mode in ["shadows", "transparency", "fur"] {
        assert!(measure.contains(mode), "{measure}");
    }
}

#[test]
fn conflicting_and_ignored_flags_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let out = out.to_str().unwrap();
    // A mode's page has no other mode's options.
    assert_fails(
        &hairlab(&["measure", "fur", "--technique", "wboit"]),
        &["--technique"],
    );
    assert_fails(
        &hairlab(&["bench", "transparency", "--metric", "flip", "--out", out]),
        &["--metric"],
    );
    // Today's flags: what the chosen mode would ignore is refused, naming both flags.
    assert_fails(
        &hairlab(&["bench", "--scaling", "--metric", "flip", "--out", out]),
        &["--metric", "--scaling"],
    );
    assert_fails(
        &hairlab(&["bench", "--transparency", "--methods", "osm", "--out", out]),
        &["--methods", "--transparency"],
    );
    assert_fails(
        &hairlab(&["bench", "--max-segments", "1000", "--out", out]),
        &["--max-segments", "--scaling"],
    );
    assert_fails(
        &hairlab(&["measure", "--fur", "--config", "osm:slices=16"]),
        &["--config", "--fur"],
    );
    assert_fails(
        &hairlab(&["measure", "--technique", "wboit"]),
        &["--technique", "--transparency"],
    );
    assert!(!Path::new(out).exists(), "nothing written");
}

#[test]
fn old_mode_flags_still_run_and_name_the_new_spelling() {
    // `default` has no fur: both spellings fail the same way, the old one after naming the new.
    let old = hairlab(&["measure", "--fur"]);
    let new = hairlab(&["measure", "fur"]);
    assert_eq!(error_lines(&old), error_lines(&new));
    assert_fails(&new, &["fur.mode is off"]);
    assert!(
        stderr(&old).contains("note: `hairlab measure --fur` is now `hairlab measure fur`"),
        "{}",
        stderr(&old)
    );
    assert!(!stderr(&new).contains("note:"), "{}", stderr(&new));
}
