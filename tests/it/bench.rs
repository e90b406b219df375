//! The bench: the Pareto front on hand-made points, the PNG and SVG charts of a hand-made chart (points where the
//! data puts them, one SVG circle per point), a small real bench and scaling run through the CLI binary (files,
//! rows, charts, OSM's error falling with slices), bad input, and the Bench window driven headless (run, click a
//! point, the configuration applied).

use crate::common::cli::{error_lines, hairlab, interrupt_once_written, stderr};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::HairlabApp;
use hairlab::bench::{chart, pareto_front};
use hairlab::gpu::Gpu;
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

/// A chart with three red points on linear axes at (2, 1), (6, 3), (10, 2), and a line.
fn three_point_chart(name: &str) -> chart::Chart {
    let point = |x: f64, y: f64| chart::Point {
        x,
        y,
        label: format!("p{x}"),
        row: None,
    };
    chart::Chart {
        title: "Three points × 2".to_string(),
        notes: vec!["a note with Δ and σ²".to_string()],
        x: chart::Axis {
            label: "x".to_string(),
            scale: chart::Scale::Linear,
        },
        y: chart::Axis {
            label: "y".to_string(),
            scale: chart::Scale::Linear,
        },
        series: vec![
            chart::Series {
                name: name.to_string(),
                color: RED,
                mark: chart::Mark::Points,
                points: vec![point(2.0, 1.0), point(6.0, 3.0), point(10.0, 2.0)],
            },
            chart::Series {
                name: String::new(),
                color: [0, 0, 255],
                mark: chart::Mark::Line,
                points: vec![point(2.0, 0.5), point(10.0, 0.5)],
            },
        ],
        front: None,
    }
}

const RED: [u8; 3] = [214, 39, 40];

/// Centroids of the 4-connected groups of pixels of exactly `color`, left to right.
fn blobs(img: &image::RgbImage, color: [u8; 3]) -> Vec<(f64, f64, usize)> {
    let (w, h) = img.dimensions();
    let mut seen = vec![false; (w * h) as usize];
    let mut out = Vec::new();
    for start in 0..w * h {
        if seen[start as usize] || img.get_pixel(start % w, start / w).0 != color {
            continue;
        }
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0);
        let mut stack = vec![start];
        seen[start as usize] = true;
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            sx += x as f64;
            sy += y as f64;
            n += 1;
            let next = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then(|| i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then(|| i + w),
            ];
            for j in next.into_iter().flatten() {
                if !seen[j as usize] && img.get_pixel(j % w, j / w).0 == color {
                    seen[j as usize] = true;
                    stack.push(j);
                }
            }
        }
        out.push((sx / n as f64, sy / n as f64, n));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

#[test]
fn png_chart_draws_the_points_where_the_data_puts_them() {
    let png = chart::png(&three_point_chart(""), 600, 400).unwrap();
    let img = image::load_from_memory(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (600, 400));
    assert_eq!(img.get_pixel(2, 2).0, [255, 255, 255], "background");
    // Exactly three red discs (the series has no name, so no legend marker).
    let b = blobs(&img, RED);
    assert_eq!(b.len(), 3, "{b:?}");
    assert!(b.iter().all(|&(_, _, n)| n >= 50), "discs of radius 5: {b:?}");
    // x 2, 6, 10: equally spaced; y 1, 3, 2: the second highest, the first lowest, the third halfway.
    let (dx1, dx2) = (b[1].0 - b[0].0, b[2].0 - b[1].0);
    assert!(dx1 > 50.0 && (dx1 - dx2).abs() <= 1.5, "{b:?}");
    let (rise1, rise2) = (b[0].1 - b[1].1, b[0].1 - b[2].1);
    assert!(rise1 > 50.0 && (rise1 - 2.0 * rise2).abs() <= 1.5, "{b:?}");
    // The fit line is drawn in its colour, and there is text and axes in dark ink.
    assert!(img.pixels().filter(|p| p.0 == [0, 0, 255]).count() > 100);
    assert!(img.pixels().filter(|p| p.0.iter().all(|c| *c < 100)).count() > 500);
}

#[test]
fn svg_chart_is_xml_with_one_circle_per_point_and_the_names() {
    use quick_xml::events::Event;
    let svg = chart::svg(&three_point_chart("red series"), 600, 400).unwrap();
    let mut reader = quick_xml::Reader::from_str(&svg);
    let (mut root, mut red_circles, mut texts) = (None, 0, Vec::new());
    let mut in_text = false;
    loop {
        match reader.read_event().unwrap() {
            Event::Eof => break,
            Event::Start(e) | Event::Empty(e) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                root.get_or_insert(name.clone());
                let fill = e
                    .attributes()
                    .flatten()
                    .find(|a| a.key.as_ref() == b"fill")
                    .map(|a| a.value.to_vec());
                if name == "circle" && fill.as_deref() == Some(b"#D62728") {
                    red_circles += 1;
                }
                in_text = name == "text";
            }
            Event::Text(t) if in_text => texts.push(t.decode().unwrap().trim().to_string()),
            Event::End(_) => in_text = false,
            _ => {}
        }
    }
    assert_eq!(root.as_deref(), Some("svg"));
    // Three points and the legend's marker.
    assert_eq!(red_circles, 4);
    for t in ["red series", "Three points × 2", "a note with Δ and σ²", "x", "y"] {
        assert!(texts.iter().any(|s| s == t), "no text {t:?} in {texts:?}");
    }
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
        "3",
        "--warmup",
        "1",
        "--points",
        "4",
        "--max-segments",
        "30000",
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, fits) = read_csv(&out.join("scaling.csv"));
    let labels: Vec<&str> = fits.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(
        labels,
        [
            "osm:slices=16",
            "osm:slices=64",
            "occupancy",
            "shared light passes"
        ]
    );
    for r in &fits {
        let slope: f64 = r[column(&header, "ms_per_segment")].parse().unwrap();
        let ns: f64 = r[column(&header, "ns_per_segment")].parse().unwrap();
        assert!(
            slope.is_finite() && (ns - slope * 1e6).abs() <= 1e-9 * ns.abs().max(1.0),
            "{r:?}"
        );
        let r2: f64 = r[column(&header, "r_squared")].parse().unwrap();
        assert!(r2.is_finite() && r2 <= 1.0, "{r:?}");
        let exponent: f64 = r[column(&header, "exponent")].parse().unwrap();
        let verdict = &r[column(&header, "verdict")];
        assert_eq!(verdict == "linear", r2 >= 0.98 && exponent <= 1.2, "{r:?}");
        // Growth names its exponent; a poor fit at a linear exponent, its distance from the line and the frames'
        // spread, both as in the CSV.
        let percent = |c: &str| format!("{:.0} %", 100.0 * r[column(&header, c)].parse::<f64>().unwrap());
        let off_the_line =
            verdict.contains(&percent("max_residual")) && verdict.contains(&percent("max_spread"));
        assert!(
            verdict == "linear"
                || (exponent > 1.2 && verdict.contains("segments^"))
                || (exponent <= 1.2 && off_the_line),
            "{r:?}"
        );
    }
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("ns per segment") && stdout.contains("osm:slices=64"),
        "{stdout}"
    );
    // The points: 4 densities evenly spaced in segments up to 30,000 (200 strands of 24 segments at × 1: × 1.5625
    // apart, 7500 segments, within a strand's rounding), 3 configurations and the shared light passes each, 3
    // timed frames per configuration, the shared passes' pooled over the 3 configurations (9).
    let (header, points) = read_csv(&out.join("scaling_points.csv"));
    assert_eq!(points.len(), 16);
    let segments: Vec<i64> = points
        .iter()
        .filter(|r| r[0] == "occupancy")
        .map(|r| r[column(&header, "segments")].parse().unwrap())
        .collect();
    assert_eq!(segments.len(), 4);
    for (k, s) in segments.iter().enumerate() {
        assert!((s - 7500 * (k as i64 + 1)).abs() <= 24, "{segments:?}");
    }
    for r in &points {
        let frames = if r[0] == "shared light passes" { "9" } else { "3" };
        assert_eq!(r[column(&header, "frames")], frames, "{r:?}");
        let (lo, med, hi): (f64, f64, f64) = (
            r[column(&header, "gpu_ms_min")].parse().unwrap(),
            r[column(&header, "gpu_ms_median")].parse().unwrap(),
            r[column(&header, "gpu_ms_max")].parse().unwrap(),
        );
        assert!(lo <= med && med <= hi, "{r:?}");
    }
    let png = image::open(out.join("scaling.png")).unwrap();
    assert_eq!((png.width(), png.height()), hairlab::bench::CHART_SIZE);
    let svg = std::fs::read_to_string(out.join("scaling.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("osm:slices=64 ("),
        "scaling.svg"
    );
}

/// Every fragment in one texel (a 1² map): AVSM's compressor walks lists of up to about 1400 fragments, over
/// several dispatches on a CPU adapter, so no density is refused and every density is an AVSM point, as it is an
/// occupancy point.
#[test]
fn bench_scaling_walks_long_lists_at_every_density() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path();
    let o = hairlab(&[
        "bench",
        "--scaling",
        "--preset",
        "default",
        "--set",
        "scene.generator.strands=100",
        "--set",
        "render.map_resolution=1",
        "--methods",
        "avsm,occupancy",
        "--frames",
        "3",
        "--warmup",
        "1",
        "--points",
        "3",
        "--max-segments",
        "20000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(!stdout.contains(" refused at "), "{stdout}");
    let (_, fits) = read_csv(&out.join("scaling.csv"));
    let mut labels: Vec<&str> = fits.iter().map(|r| r[0].as_str()).collect();
    labels.sort_unstable();
    assert_eq!(labels, ["avsm", "occupancy", "shared light passes"], "{stdout}");
    let (header, points) = read_csv(&out.join("scaling_points.csv"));
    let segments = |label: &str| -> Vec<usize> {
        points
            .iter()
            .filter(|r| r[0] == label)
            .map(|r| r[column(&header, "segments")].parse().unwrap())
            .collect()
    };
    let occupancy = segments("occupancy");
    assert_eq!(occupancy.len(), 3);
    assert!(*occupancy.last().unwrap() >= 20000 - 24, "{occupancy:?}");
    assert_eq!(segments("avsm"), occupancy);
}

/// `bench scaling --raster both`: every density measured under each rasteriser, a fit per configuration and
/// rasteriser in scaling.csv (its `raster` column), every point in scaling_points.csv, and the compute/hardware
/// light-pass ratio per density printed.
#[test]
fn bench_scaling_measures_each_density_under_both_rasterisers() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path();
    let mut args = vec!["bench", "scaling", "--preset", "default"];
    args.extend_from_slice(TINY);
    args.extend([
        "--methods",
        "occupancy",
        "--raster",
        "both",
        "--frames",
        "3",
        "--warmup",
        "1",
        "--points",
        "2",
        "--max-segments",
        "10000",
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, fits) = read_csv(&out.join("scaling.csv"));
    let rasters: Vec<&str> = fits
        .iter()
        .map(|r| r[column(&header, "raster")].as_str())
        .collect();
    // The configuration's fits, then the shared light passes' (under compute: its count, scan and fill too).
    assert_eq!(rasters, ["hardware", "compute", "hardware", "compute"]);
    for r in &fits {
        let slope: f64 = r[column(&header, "ms_per_segment")].parse().unwrap();
        let intercept: f64 = r[column(&header, "intercept_ms")].parse().unwrap();
        assert!(slope.is_finite() && intercept.is_finite(), "{r:?}");
    }
    let (header, points) = read_csv(&out.join("scaling_points.csv"));
    assert_eq!(points.len(), 8);
    for raster in ["hardware", "compute"] {
        let of: Vec<&Vec<String>> = points
            .iter()
            .filter(|r| r[0] == "occupancy" && r[column(&header, "raster")] == raster)
            .collect();
        assert_eq!(of.len(), 2, "{raster}: {points:?}");
        for r in of {
            let ms: f64 = r[column(&header, "gpu_ms_median")].parse().unwrap();
            assert!(ms.is_finite() && ms > 0.0, "{r:?}");
        }
    }
    // The shared light passes one by one: under compute the rasteriser's passes, at each density.
    let (header, passes) = read_csv(&out.join("scaling_passes.csv"));
    let shared_passes = |raster: &str| -> Vec<String> {
        passes
            .iter()
            .filter(|r| r[0] == "shared light passes" && r[column(&header, "raster")] == raster)
            .map(|r| r[column(&header, "pass")].clone())
            .collect()
    };
    assert!(
        shared_passes("hardware").contains(&"light depth".to_string()),
        "{passes:?}"
    );
    let compute = shared_passes("compute");
    for pass in ["light depth", "compute raster: count", "compute raster: fill"] {
        assert_eq!(
            compute.iter().filter(|p| *p == pass).count(),
            2,
            "{pass}: {passes:?}"
        );
    }
    let stdout = String::from_utf8_lossy(&o.stdout);
    let ratios: Vec<f64> = stdout
        .lines()
        .skip_while(|l| !l.starts_with("compute / hardware raster"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| l.split_whitespace().last().unwrap().parse().unwrap())
        .collect();
    // Two densities, the configuration and the shared light passes at each.
    assert_eq!(ratios.len(), 4, "{stdout}");
    assert!(ratios.iter().all(|r| r.is_finite() && *r > 0.0), "{stdout}");
    let svg = std::fs::read_to_string(out.join("scaling.svg")).unwrap();
    assert!(svg.contains("compute, dashed)"), "scaling.svg");
}

/// Ctrl-C stops `bench scaling` after the density in progress: scaling_points.csv holds every point of the
/// finished densities, whole, and the run exits 130 saying how many configurations it timed.
#[test]
fn sigint_leaves_complete_scaling_rows_of_the_finished_densities() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let args = [
        "bench",
        "scaling",
        "--methods",
        "occupancy",
        "--points",
        "6",
        "--max-segments",
        "30000",
        "--warmup",
        "1",
    ];
    // Six densities, each with the configuration's row and the shared light passes'.
    let (_dir, _out, header, rows) = sigint_after_the_first_file(&args, "scaling_points.csv", 2, 12);
    let mut last = 0;
    for r in rows.iter().filter(|r| r[0] == "occupancy") {
        assert_eq!(r[column(&header, "raster")], "hardware");
        let segments: usize = r[column(&header, "segments")].parse().unwrap();
        assert!(segments > last, "densities in order: {rows:?}");
        last = segments;
        let ms: f64 = r[column(&header, "gpu_ms_median")].parse().unwrap();
        assert!(ms.is_finite() && ms > 0.0, "{r:?}");
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
    let mut harness = crate::common::snapshot_harness(settings, [1200.0, 900.0]);
    crate::common::bench_window_on_osm(&mut harness);
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
    assert!(!result.is_stopped());
    let labels: Vec<String> = result.rows.iter().map(|r| r.config.label()).collect();
    let osm = hairlab::methods::registry::find("osm").unwrap();
    assert_eq!(labels.len(), osm.sweep().len(), "{labels:?}");
    assert!(labels.iter().all(|l| l.starts_with("osm:slices=")), "{labels:?}");
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, e)| !e && m.contains("7 configurations")),
        "{:?}",
        harness.state().message()
    );

    // Export: the files `hairlab bench` writes, into a folder set in place of the dialog.
    let export = tempfile::tempdir().unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    harness.get_by_label("Export results…").click();
    harness.run();
    let (header, rows) = read_csv(&export.path().join("results.csv"));
    let exported: Vec<&String> = rows.iter().map(|r| &r[column(&header, "label")]).collect();
    assert_eq!(exported, labels.iter().collect::<Vec<_>>());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(export.path().join("results.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(labels.len()));
    let png = image::open(export.path().join("speed_vs_accuracy.png")).unwrap();
    assert_eq!((png.width(), png.height()), hairlab::bench::CHART_SIZE);
    let svg = std::fs::read_to_string(export.path().join("speed_vs_accuracy.svg")).unwrap();
    assert!(
        svg.contains("<svg") && svg.trim_end().ends_with("</svg>"),
        "not an SVG document"
    );
    // Copies: the table as the exported CSV's text, the chart as an image of the exported PNG's size.
    let copied = |harness: &mut Harness<'_, HairlabApp>, button: &str| {
        harness.get_by_label(button).click();
        harness.step();
        harness.output().platform_output.commands.clone()
    };
    let text = copied(&mut harness, "Copy table")
        .into_iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyText(t) => Some(t),
            _ => None,
        })
        .expect("the table copied");
    assert_eq!(
        text,
        std::fs::read_to_string(export.path().join("results.csv")).unwrap()
    );
    let image = copied(&mut harness, "Copy chart")
        .into_iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyImage(i) => Some(i),
            _ => None,
        })
        .expect("the chart copied");
    assert_eq!(image.size, [png.width() as usize, png.height() as usize]);
    harness.run();

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

/// Ctrl-C (SIGINT to the `hairlab` process) stops `bench shadows` and `measure shadows` after the configuration
/// in progress: results.csv and results.json hold every finished configuration, whole and in order, and the run
/// exits 130 saying how many.
#[test]
fn sigint_leaves_a_complete_csv_of_the_finished_configurations() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let sweep = [4, 8, 16, 32, 64, 128, 256].map(|n| format!("osm:slices={n}"));
    sigint_after_the_first_row(&["bench", "shadows", "--methods", "osm"], &sweep);
    let mut measure = vec!["measure", "shadows"];
    for c in &sweep {
        measure.extend(["--config", c.as_str()]);
    }
    sigint_after_the_first_row(&measure, &sweep);
}

/// Ctrl-C stops `measure transparency` after the configuration in progress: transparency.csv and
/// transparency.json hold every finished technique, whole and in order, and the run exits 130 saying how many.
#[test]
fn sigint_leaves_a_complete_csv_of_the_finished_transparency_techniques() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let labels: Vec<String> = hairlab::render::transparency::registry::all()
        .iter()
        .map(|t| t.name().to_string())
        .collect();
    let mut args = vec!["measure", "transparency"];
    for t in &labels {
        args.extend(["--technique", t.as_str()]);
    }
    let (_dir, out, header, rows) = sigint_after_the_first_file(&args, "transparency.csv", 1, labels.len());
    for (r, expected) in rows.iter().zip(&labels) {
        assert_eq!(&r[column(&header, "configuration")], expected);
        let error: f64 = r[column(&header, "rmse_hair")].parse().unwrap();
        assert!(error.is_finite() && error >= 0.0, "{r:?}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("transparency.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(rows.len()), "{json}");
}

/// Runs `hairlab ARGS` (the tiny scene, 40 timed frames, `--out`) until results.csv appears, sends SIGINT, and
/// checks what it left: fewer rows than `labels`, each whole, in that order.
fn sigint_after_the_first_row(args: &[&str], labels: &[String]) {
    let (_dir, out, header, rows) = sigint_after_the_first_file(args, "results.csv", 1, labels.len());
    for (r, expected) in rows.iter().zip(labels) {
        assert_eq!(&r[column(&header, "label")], expected);
        let error: f64 = r[column(&header, "map_error")].parse().unwrap();
        assert!(error.is_finite() && error > 0.0, "{r:?}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(rows.len()), "{json}");
    assert!(out.join("speed_vs_accuracy.png").is_file());
}

/// Runs `hairlab ARGS` (the tiny scene, 40 timed frames, `--out`) until `csv` appears in the output folder, sends
/// SIGINT, and checks that the run exits 130 with one error naming how many configurations it finished, and that
/// `csv` holds `rows_per_config` whole rows for each, fewer than `rows` in all. Returns the temporary folder, the
/// output folder in it, the header and the rows.
fn sigint_after_the_first_file(
    args: &[&str],
    csv: &str,
    rows_per_config: usize,
    all_rows: usize,
) -> (
    tempfile::TempDir,
    std::path::PathBuf,
    Vec<String>,
    Vec<Vec<String>>,
) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut args = args.to_vec();
    args.extend_from_slice(TINY);
    args.extend(["--frames", "40", "--out", out.to_str().unwrap()]);
    // The first configuration's rows are written; then Ctrl-C.
    let csv = out.join(csv);
    let o = interrupt_once_written(&args, &csv);
    assert_eq!(o.status.code(), Some(130), "{args:?}: {}", stderr(&o));
    let (header, rows) = read_csv(&csv);
    assert!(
        !rows.is_empty() && rows.len() < all_rows && rows.len() % rows_per_config == 0,
        "stopped after the configuration in progress: {rows:?}"
    );
    for r in &rows {
        assert_eq!(r.len(), header.len(), "a whole row: {r:?}");
    }
    let errors = error_lines(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("interrupted")
            && errors[0].contains(&format!("after {} configurations", rows.len() / rows_per_config)),
        "{errors:?}"
    );
    (dir, out, header, rows)
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
