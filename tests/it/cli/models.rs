//! `hairlab curve` and `hairlab composite`: the CPU models printed against hand-computed values, and bad fragment
//! and pixel rows refused by file, line and value.

use crate::common::cli::{assert_fails, hairlab, stderr};
use std::path::Path;

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
