//! Small real bench runs through the CLI binary: the files, rows and charts (OSM's error falling with slices), the
//! transparency and fur benches, `measure --out`, and bad input refused in one line.

use super::{TINY, column, csv_fields, read_csv};
use crate::common::cli::{error_lines, hairlab, stderr};
use hairlab::gpu::Gpu;

#[test]
fn bench_cli_writes_results_chart_and_osm_error_falls() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("nested/bench");
    let mut args = vec!["bench", "--preset", "default"];
    args.extend_from_slice(TINY);
    args.extend([
        "--methods",
        "osm,occupancy",
        "--frames",
        "1",
        "--metric",
        "texel_error_p95",
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    // A progress line per configuration, and the last at 100 %.
    let err = stderr(&o);
    for label in ["osm:slices=4", "osm:slices=256", "occupancy"] {
        assert!(
            err.lines().any(|l| l.contains(label)),
            "no progress line for {label}: {err}"
        );
    }
    assert!(
        err.contains("100 % measured 9 of 9 configurations"),
        "no progress: {err}"
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout
            .lines()
            .nth(1)
            .is_some_and(|h| h.contains("texel_error_p95")),
        "--metric names the table's accuracy column: {stdout}"
    );

    // CSV: a header and one row per configuration, in sweep order.
    let (header, rows) = read_csv(&out.join("results.csv"));
    let labels: Vec<&str> = rows
        .iter()
        .map(|r| r[column(&header, "label")].as_str())
        .collect();
    assert_eq!(
        labels,
        [
            "osm:slices=4",
            "osm:slices=8",
            "osm:slices=16",
            "osm:slices=32",
            "osm:slices=64",
            "osm:slices=128",
            "osm:slices=256",
            "occupancy:variant=slab-map",
            "occupancy:variant=occupancy-only",
        ]
    );
    for name in [
        "gpu_ms_median",
        "gpu_ms_min",
        "gpu_ms_max",
        "memory_bytes",
        "map_error",
        "flip",
        "device",
    ] {
        column(&header, name);
    }
    let num = |r: &Vec<String>, c: &str| -> f64 { r[column(&header, c)].parse().unwrap() };
    for r in &rows {
        let (med, min, max) = (
            num(r, "gpu_ms_median"),
            num(r, "gpu_ms_min"),
            num(r, "gpu_ms_max"),
        );
        assert!(med > 0.0 && min == med && max == med, "one frame: {r:?}");
        assert!(!r[column(&header, "device")].is_empty());
        assert!((0.0..=1.0).contains(&num(r, "flip")), "FLIP is in [0, 1]: {r:?}");
    }
    // OSM's memory doubles with the slices, and its map error falls from 4 to 256 slices.
    let osm: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "osm").collect();
    let memory: Vec<f64> = osm.iter().map(|r| num(r, "memory_bytes")).collect();
    assert!(memory.windows(2).all(|m| m[1] == 2.0 * m[0]), "{memory:?}");
    let errors: Vec<f64> = osm.iter().map(|r| num(r, "map_error")).collect();
    assert!(
        errors.windows(2).all(|e| e[1] < e[0]),
        "OSM map error by slices 4..256: {errors:?}"
    );
    // The texel-error distribution: ordered percentiles up to the worst texel, nested shares; OSM-4's band of
    // bad texels is real (some texel above 0.05) and the map error lies between the median and the worst.
    for r in &rows {
        let p = [
            "texel_error_p50",
            "texel_error_p95",
            "texel_error_p99",
            "worst_texel_error",
        ]
        .map(|c| num(r, c));
        assert!(p.windows(2).all(|w| w[0] <= w[1]), "{r:?}");
        let (s5, s10) = (num(r, "share_texels_over_0.05"), num(r, "share_texels_over_0.1"));
        assert!((0.0..=1.0).contains(&s5) && s10 <= s5, "{r:?}");
        assert!(num(r, "map_error") <= p[3], "{r:?}");
    }
    assert!(num(osm[0], "share_texels_over_0.05") > 0.0, "{:?}", osm[0]);

    // JSON: the same rows.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let jrows = json["rows"].as_array().unwrap();
    assert_eq!(jrows.len(), rows.len());
    for (j, r) in jrows.iter().zip(&rows) {
        assert_eq!(j["label"].as_str(), Some(r[column(&header, "label")].as_str()));
        assert_eq!(j["map_error"].as_f64(), Some(num(r, "map_error")));
        assert_eq!(j["gpu_ms"]["median"].as_f64(), Some(num(r, "gpu_ms_median")));
        assert_eq!(
            j["pareto"].as_bool(),
            Some(r[column(&header, "pareto")] == "true")
        );
    }
    assert_eq!(json["scene"]["strands"].as_u64(), Some(200));
    assert!(jrows.iter().any(|j| j["pareto"].as_bool() == Some(true)));

    // The chart: the expected size, white background, and both methods' colours drawn.
    let png = image::open(out.join("speed_vs_accuracy.png")).unwrap().to_rgba8();
    assert_eq!(png.dimensions(), hairlab::bench::CHART_SIZE);
    let count = |c: [u8; 3]| png.pixels().filter(|p| p.0[..3] == c).count();
    assert!(count([255, 255, 255]) > png.pixels().len() / 2);
    for m in ["osm", "occupancy"] {
        // A disc of radius 5 has about 70 fully covered pixels.
        assert!(count(hairlab::bench::method_color(m)) > 40, "{m} points missing");
    }
    assert!(count([30, 30, 30]) > 2000, "axes and text missing");
    // The same chart as SVG: both methods named in the legend.
    let svg = std::fs::read_to_string(out.join("speed_vs_accuracy.svg")).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(200)]);
    for m in ["osm", "occupancy", "Pareto front"] {
        assert!(svg.contains(&format!("\n{m}\n</text>")), "no legend entry {m}");
    }
}

#[test]
fn bench_rejects_bad_input_with_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = hairlab(&["bench", "--methods", "osm,bogus", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    let lines = error_lines(&o);
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(
        lines[0].contains("'bogus'") && lines[0].contains("osm, dom"),
        "{}",
        lines[0]
    );
    assert!(!out.exists());
    // An output folder under a regular file cannot be created.
    let file = dir.path().join("file");
    std::fs::write(&file, b"x").unwrap();
    let bad = file.join("sub");
    let o = hairlab(&["bench", "--methods", "occupancy", "--out", bad.to_str().unwrap()]);
    assert!(!o.status.success());
    let lines = error_lines(&o);
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(
        lines[0].contains("cannot create the output folder") && lines[0].contains("sub"),
        "{}",
        lines[0]
    );
    let o = hairlab(&["bench", "--frames", "0", "--out", out.to_str().unwrap()]);
    assert_eq!(error_lines(&o).len(), 1);
    assert!(error_lines(&o)[0].contains("--frames"));
    let o = hairlab(&["bench", "--metric", "speed", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    let lines = error_lines(&o);
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(
        lines[0].contains("'speed'") && stderr(&o).contains("texel_error_p99"),
        "{}",
        stderr(&o)
    );
}

/// `bench --transparency`: one CSV row per configuration of every technique's sweep, the chart, the JSON with
/// the depth peel / occupancy ratio, and the exact reference measured against itself at zero error.
#[test]
fn bench_transparency_writes_every_techniques_sweep_and_the_peel_ratio() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("eye");
    let mut args = vec!["bench", "--transparency", "--preset", "default"];
    args.extend_from_slice(TINY);
    args.extend(["--frames", "1", "--out", out.to_str().unwrap()]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("t(depth peel) / t(occupancy order) = "),
        "{stdout}"
    );
    assert!(
        stderr(&o).contains("note: `hairlab bench --transparency` is now `hairlab bench transparency`"),
        "{}",
        stderr(&o)
    );
    let csv = std::fs::read_to_string(out.join("transparency.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines.len() - 1,
        hairlab::bench::transparency::sweep_configs().len()
    );
    let head = csv_fields(lines[0]);
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let reference = lines
        .iter()
        .map(|l| csv_fields(l))
        .find(|f| f[col("configuration")] == "sorted")
        .expect("the reference row");
    assert_eq!(reference[col("rmse_hair")].parse::<f64>().unwrap(), 0.0);
    // FLIP of the reference against itself: no difference anywhere.
    for name in ["flip", "flip_hair", "flip_p95_hair", "flip_p99_hair"] {
        assert_eq!(reference[col(name)].parse::<f64>().unwrap(), 0.0, "{name}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("transparency.json")).unwrap()).unwrap();
    assert!(
        json["peel_over_occupancy"].as_f64().is_some_and(|r| r > 0.0),
        "{json}"
    );
    for f in [
        "transparency_speed_vs_accuracy.png",
        "transparency_speed_vs_accuracy.svg",
    ] {
        assert!(std::fs::metadata(out.join(f)).unwrap().len() > 1000, "{f}");
    }
}

/// `bench --fur` writes one CSV row per blending after the reference's, with the paper's Table 1 rows, and the
/// same in JSON with the view and the device; the reference's own error is zero and every blending's is finite.
#[test]
fn fur_bench_writes_every_blending_with_table_1() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let s = hairlab::settings::Settings::load_preset(
        "fur-cylinder",
        &[
            "render.width=96".into(),
            "render.height=72".into(),
            "scene.generator.strands=200".into(),
            "fur.layers=4".into(),
            "fur.max_level=2".into(),
            "fur.max_steps=48".into(),
        ],
    )
    .unwrap();
    let b = hairlab::bench::fur::FurBench::run(&s, "fur-cylinder", 1).unwrap();
    let csv = b.to_csv().unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(
        lines[0].starts_with("configuration,blending,group_steps,rmse,max_error,"),
        "{}",
        lines[0]
    );
    assert_eq!(
        lines.len(),
        1 + 1 + hairlab::measure::fur::usual_configs().len(),
        "{csv}"
    );
    assert!(
        lines[1].starts_with(&format!(
            "{},virtual,1,0.0,0.0,",
            hairlab::measure::fur::REFERENCE_LABEL
        )),
        "{}",
        lines[1]
    );
    for r in &b.rows {
        assert!(
            r.rmse.is_finite() && r.rmse > 0.0,
            "{}: {}",
            r.config.label(),
            r.rmse
        );
        let f = r.flip;
        assert!(
            (0.0..=1.0).contains(&f.mean) && f.p95_hair <= f.p99_hair && f.p99_hair <= 1.0,
            "{}: {f:?}",
            r.config.label()
        );
    }
    assert!(
        b.rows.iter().any(|r| r.flip.mean_hair > 0.0),
        "some blending differs from the reference on the fur pixels"
    );
    let json: serde_json::Value = serde_json::from_str(&b.to_json().unwrap()).unwrap();
    assert_eq!(json["view"], serde_json::json!([96, 72]));
    assert_eq!(json["triangles"], 3584);
    assert_eq!(json["time_rows"].as_array().unwrap().len(), 7);
}

/// `measure --out DIR` writes what `bench` writes, one row per configuration.
#[test]
fn measure_out_writes_results_like_bench() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m");
    let mut args = vec![
        "measure",
        "shadows",
        "--config",
        "osm:slices=16",
        "--config",
        "osm:slices=64",
    ];
    args.extend_from_slice(TINY);
    args.extend(["--frames", "1", "--out", out.to_str().unwrap()]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, rows) = read_csv(&out.join("results.csv"));
    let labels: Vec<&str> = rows
        .iter()
        .map(|r| r[column(&header, "label")].as_str())
        .collect();
    assert_eq!(labels, ["osm:slices=16", "osm:slices=64"]);
    for f in ["results.json", "speed_vs_accuracy.png", "speed_vs_accuracy.svg"] {
        assert!(out.join(f).is_file(), "{f}");
    }
}
