//! `bench --scaling`: the cost per segment fitted, long lists walked at every density, each density under both
//! rasterisers.

use super::{TINY, column, read_csv};
use crate::common::cli::{hairlab, stderr};
use hairlab::gpu::Gpu;

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
