//! The bench: the Pareto front on hand-made points, the chart's bitmap font, a small real bench and scaling run
//! through the CLI binary (files, rows, chart, OSM's error falling with slices), bad input, and the Bench window
//! driven headless (run, click a point, the configuration applied).

mod common;

use common::cli::{error_lines, hairlab, stderr};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::bench::{chart, pareto_front};
use hairlab::gpu::{AdapterPreference, Gpu};
use hairlab::settings::Settings;
use std::path::Path;

/// The tiny scene of the CLI runs: 200 strands, a 64² light map.
const TINY: &[&str] = &[
    "--set",
    "scene.generator.strands=200",
    "--set",
    "render.map_resolution=64",
];

/// Splits one CSV line into fields (quoted fields may hold commas and doubled quotes).
fn csv_fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            _ => out.last_mut().unwrap().push(c),
        }
    }
    out
}

/// The CSV as (header, rows).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = csv_fields(lines.next().expect("a header"));
    let rows: Vec<Vec<String>> = lines.map(csv_fields).collect();
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
    }
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

#[test]
fn pareto_front_keeps_the_points_nothing_beats() {
    let points = [
        [1.0, 5.0],      // 0: fastest of those with error 5
        [2.0, 3.0],      // 1
        [3.0, 4.0],      // 2: beaten by 1 on both
        [4.0, 1.0],      // 3
        [0.0, 9.0],      // 4: 0 ms, the worst error: still nothing is faster
        [5.0, 1.0],      // 5: as accurate as 3 but slower
        [2.0, 3.5],      // 6: as fast as 1 but less accurate
        [f64::NAN, 0.0], // 7: not measured
        [6.0, 0.0],      // 8: the most accurate
    ];
    assert_eq!(pareto_front(&points), [4, 0, 1, 3, 8]);
    // Exact duplicates do not beat each other.
    assert_eq!(pareto_front(&[[1.0, 1.0], [1.0, 1.0], [2.0, 2.0]]), [0, 1]);
    assert!(pareto_front(&[]).is_empty());
}

#[test]
fn font_renders_known_glyph_pixels() {
    // 'H': both outer columns full height, the bar on row 3, nothing else.
    for row in 0..7 {
        assert!(chart::glyph_pixel('H', 0, row) && chart::glyph_pixel('H', 4, row));
        for col in 1..4 {
            assert_eq!(chart::glyph_pixel('H', col, row), row == 3, "H ({col}, {row})");
        }
    }
    // 'p' descends into the eighth row, 'a' does not; outside ASCII draws '?'.
    assert!(chart::glyph_pixel('p', 0, 7) && !chart::glyph_pixel('a', 0, 7));
    assert_eq!(chart::glyph('é'), chart::glyph('?'));
    // 'T' drawn at scale 2 from (3, 4): the top bar is rows 4..6 over x 3..13, the stem x 7..9.
    let mut img = image::RgbaImage::from_pixel(20, 24, image::Rgba([255, 255, 255, 255]));
    chart::draw_text(&mut img, 3, 4, "T", 2, [0, 0, 0]);
    let black = |x, y| img.get_pixel(x, y).0[..3] == [0, 0, 0];
    let inked: Vec<(u32, u32)> = (0..24)
        .flat_map(|y| (0..20).map(move |x| (x, y)))
        .filter(|&(x, y)| black(x, y))
        .collect();
    let expected: Vec<(u32, u32)> = (0..24)
        .flat_map(|y| (0..20).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            (4..6).contains(&y) && (3..13).contains(&x) || (4..18).contains(&y) && (7..9).contains(&x)
        })
        .collect();
    assert_eq!(inked, expected);
    assert_eq!(chart::text_width("T", 2), 10);
    assert_eq!(chart::text_width("ab", 1), 11);
}

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
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("9/9"), "no progress: {}", stderr(&o));

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
            "occupancy:variant=0",
            "occupancy:variant=1",
        ]
    );
    for name in [
        "gpu_ms_median",
        "gpu_ms_min",
        "gpu_ms_max",
        "memory_bytes",
        "map_error",
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
}

#[test]
fn bench_scaling_fits_cost_per_segment() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path();
    let mut args = vec!["bench", "--scaling", "--preset", "default"];
    args.extend_from_slice(TINY);
    args.extend([
        "--methods",
        "osm,occupancy",
        "--frames",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, fits) = read_csv(&out.join("scaling.csv"));
    let labels: Vec<&str> = fits.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(labels, ["osm:slices=16", "osm:slices=64", "occupancy"]);
    for r in &fits {
        let slope: f64 = r[column(&header, "ms_per_segment")].parse().unwrap();
        let ns: f64 = r[column(&header, "ns_per_segment")].parse().unwrap();
        assert!(
            slope.is_finite() && (ns - slope * 1e6).abs() <= 1e-9 * ns.abs().max(1.0),
            "{r:?}"
        );
    }
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("ns per segment") && stdout.contains("osm:slices=64"),
        "{stdout}"
    );
    // The points: 5 densities × 3 configurations; 24 segments per strand, 200 strands × 0.25..4.
    let (header, points) = read_csv(&out.join("scaling_points.csv"));
    assert_eq!(points.len(), 15);
    let segments: Vec<&str> = points
        .iter()
        .filter(|r| r[0] == "occupancy")
        .map(|r| r[column(&header, "segments")].as_str())
        .collect();
    assert_eq!(segments, ["1200", "2400", "4800", "9600", "19200"]);
    let png = image::open(out.join("scaling.png")).unwrap();
    assert_eq!((png.width(), png.height()), hairlab::bench::CHART_SIZE);
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
}

#[test]
fn bench_window_runs_and_a_clicked_point_becomes_the_method() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = Settings::load_preset(
        "default",
        &[
            "scene.generator.strands=200".into(),
            "render.map_resolution=64".into(),
            "render.width=160".into(),
            "render.height=120".into(),
            "method.name=opaque-shadow-map".into(),
        ],
    )
    .unwrap();
    let mut harness = Harness::builder()
        .with_size([1200.0, 900.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| {
            let mut app = HairlabApp::new(cc, Some(settings));
            app.set_snapshot_mode(true);
            app
        });
    harness.run();
    harness.get_by_label("Bench").click();
    harness.run();
    // Sweep only OSM: uncheck the others.
    for m in ["opaque-shadow-map", "dom", "bom", "dc", "occupancy", "reference"] {
        harness.get_by_label(m).click();
    }
    harness.run();
    harness.get_by_label("Run bench").click();
    harness.step();
    assert!(harness.state().bench_running());
    let start = std::time::Instant::now();
    while harness.state().bench_running() {
        assert!(start.elapsed().as_secs() < 300, "the bench did not finish");
        std::thread::sleep(std::time::Duration::from_millis(50));
        harness.step();
    }
    harness.run();
    let result = harness.state().bench_result().expect("a result").clone();
    assert!(!result.cancelled);
    let labels: Vec<String> = result.rows.iter().map(|r| r.config.label()).collect();
    assert_eq!(labels.len(), 7);
    assert!(labels.iter().all(|l| l.starts_with("osm:slices=")), "{labels:?}");
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, e)| !e && m.contains("7 configurations")),
        "{:?}",
        harness.state().message()
    );

    // Click the 64-slice point: the app now uses OSM with 64 slices.
    let pos = harness.state().bench_point_position(4).expect("point drawn");
    harness.hover_at(pos);
    harness.step();
    harness.drag_at(pos);
    harness.step();
    harness.drop_at(pos);
    harness.run();
    let method = &harness.state().settings().method;
    assert_eq!(method.name, "osm");
    assert_eq!(method.params.get("slices"), Some(&64.0));
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, _)| m.contains("applied osm:slices=64")),
        "{:?}",
        harness.state().message()
    );
}
