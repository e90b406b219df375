//! The bench's files: `results.csv` and `results.json` (one row per configuration, the same rows), the scaling
//! mode's `scaling.csv` and `scaling_points.csv`, and the charts as PNG and SVG, each written atomically into
//! the output folder. CSV rows are serde structs written by the `csv` crate (a header from the first row's
//! field names); JSON rows are serde structs too.

use super::chart::{self, CHART_SIZE, Chart};
use super::{BenchResult, ScalingResult, Spread};
use crate::io::csv_text;
use crate::methods::ParamValues;
use crate::progress::Outcome;
use anyhow::{Context, Result};
use serde::Serialize;
use serde::ser::SerializeStruct;
use std::path::{Path, PathBuf};

/// A row's error metrics as named fields: one CSV column or JSON key each, in [`super::error_metrics`] order.
/// JSON has no infinity or NaN: those (the infinite PSNR of an exact image) are written as `null`.
struct Metrics<'a>(&'a [(&'static str, f64)]);

impl Serialize for Metrics<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("Metrics", self.0.len())?;
        for (name, v) in self.0 {
            st.serialize_field(name, v)?;
        }
        st.end()
    }
}

/// The columns of `results.csv` before the metrics.
#[derive(Serialize)]
struct CsvHead<'a> {
    method: &'a str,
    params: String,
    label: String,
    note: &'a str,
    gpu_ms_median: f64,
    gpu_ms_min: f64,
    gpu_ms_max: f64,
    memory_bytes: u64,
    build_memory_bytes: u64,
    geometry_passes: u32,
}

/// The columns of `results.csv` after the metrics.
#[derive(Serialize)]
struct CsvTail<'a> {
    pareto: bool,
    /// `name: median [min, max]` per pass, `; `-separated.
    passes: String,
    device: &'a str,
}

/// `results.csv`: a header, then one row per configuration.
pub fn to_csv(result: &BenchResult) -> Result<String> {
    let front = result.front();
    csv_text(
        "results.csv",
        result.rows.iter().enumerate().map(|(i, r)| {
            let head = CsvHead {
                method: &r.config.name,
                // As the label spells them (choices as words), `;`-separated.
                params: r.config.param_words().join(";"),
                label: r.config.label(),
                note: &r.note,
                gpu_ms_median: r.total_ms.median,
                gpu_ms_min: r.total_ms.min,
                gpu_ms_max: r.total_ms.max,
                memory_bytes: r.memory_bytes,
                build_memory_bytes: r.build_memory_bytes,
                geometry_passes: r.geometry_passes,
            };
            let tail = CsvTail {
                pareto: front.contains(&i),
                passes: r
                    .passes
                    .iter()
                    .map(|(n, s)| format!("{n}: {} [{}, {}]", s.median, s.min, s.max))
                    .collect::<Vec<_>>()
                    .join("; "),
                device: &r.device,
            };
            (head, Metrics(&r.metrics), tail)
        }),
    )
}

#[derive(Serialize)]
struct JsonResults<'a> {
    preset: &'a str,
    device: &'a str,
    frames: u32,
    /// Whether the run was stopped before every configuration was measured (the name kept for readers of
    /// earlier files; filled from the run's [`Outcome`]).
    cancelled: bool,
    /// What the GPU times cover.
    gpu_ms: &'static str,
    scene: JsonScene,
    rows: Vec<JsonRow<'a>>,
}

#[derive(Serialize)]
struct JsonScene {
    strands: usize,
    segments: usize,
    map_resolution: u32,
    fragments: usize,
    occupied_texels: usize,
    max_depth_complexity: usize,
    mean_depth_complexity: f64,
}

#[derive(Serialize)]
struct JsonRow<'a> {
    method: &'a str,
    params: &'a ParamValues,
    label: String,
    note: &'a str,
    gpu_ms: Spread,
    passes: Vec<JsonPass<'a>>,
    memory_bytes: u64,
    build_memory_bytes: u64,
    geometry_passes: u32,
    #[serde(flatten)]
    metrics: Metrics<'a>,
    pareto: bool,
    device: &'a str,
}

#[derive(Serialize)]
struct JsonPass<'a> {
    name: &'a str,
    #[serde(flatten)]
    ms: Spread,
}

/// `results.json`: the scene, whether the run was stopped, then `rows` with the same configurations as the CSV.
pub fn to_json(result: &Outcome<BenchResult>) -> Result<String> {
    let front = result.front();
    let s = &result.stats;
    let doc = JsonResults {
        preset: &result.preset,
        device: &s.device,
        frames: result.frames,
        cancelled: result.is_stopped(),
        gpu_ms: "the method's own light passes per frame (the shared light-depth pass left out)",
        scene: JsonScene {
            strands: s.strands,
            segments: s.segments,
            map_resolution: s.map_resolution,
            fragments: s.fragments,
            occupied_texels: s.occupied_texels,
            max_depth_complexity: s.max_depth_complexity,
            mean_depth_complexity: s.mean_depth_complexity,
        },
        rows: result
            .rows
            .iter()
            .enumerate()
            .map(|(i, r)| JsonRow {
                method: &r.config.name,
                params: &r.config.params,
                label: r.config.label(),
                note: &r.note,
                gpu_ms: r.total_ms,
                passes: r
                    .passes
                    .iter()
                    .map(|(name, ms)| JsonPass { name, ms: *ms })
                    .collect(),
                memory_bytes: r.memory_bytes,
                build_memory_bytes: r.build_memory_bytes,
                geometry_passes: r.geometry_passes,
                metrics: Metrics(&r.metrics),
                pareto: front.contains(&i),
                device: &r.device,
            })
            .collect(),
    };
    serde_json::to_string_pretty(&doc).context("cannot encode results.json")
}

/// One line of `scaling.csv`.
#[derive(Serialize)]
struct FitRow<'a> {
    method: &'a str,
    raster: &'static str,
    ms_per_segment: f64,
    ns_per_segment: f64,
    intercept_ms: f64,
    r_squared: f64,
    exponent: f64,
    max_residual: f64,
    max_spread: f64,
    verdict: String,
    device: &'a str,
}

/// `scaling.csv`: the fit per configuration and rasteriser.
pub fn scaling_csv(r: &ScalingResult) -> Result<String> {
    csv_text(
        "scaling.csv",
        r.fits.iter().map(|f| FitRow {
            method: &f.label,
            raster: f.raster.word(),
            ms_per_segment: f.ms_per_segment,
            ns_per_segment: f.ms_per_segment * 1e6,
            intercept_ms: f.intercept_ms,
            r_squared: f.r_squared,
            exponent: f.exponent,
            max_residual: f.max_residual,
            max_spread: f.max_spread,
            verdict: f.verdict(),
            device: &r.device,
        }),
    )
}

/// One line of `scaling_points.csv`.
#[derive(Serialize)]
struct PointRow<'a> {
    method: &'a str,
    raster: &'static str,
    density: f32,
    strands: usize,
    segments: usize,
    frames: usize,
    gpu_ms_median: f64,
    gpu_ms_min: f64,
    gpu_ms_max: f64,
    /// (max − min) / median over the timed frames.
    spread: f64,
    ns_per_segment: f64,
}

/// `scaling_points.csv`: every measurement behind the fits.
pub fn scaling_points_csv(r: &ScalingResult) -> Result<String> {
    csv_text(
        "scaling_points.csv",
        r.points.iter().map(|p| PointRow {
            method: &p.label,
            raster: p.raster.word(),
            density: p.density,
            strands: p.strands,
            segments: p.segments,
            frames: p.frames,
            gpu_ms_median: p.ms.median,
            gpu_ms_min: p.ms.min,
            gpu_ms_max: p.ms.max,
            spread: (p.ms.max - p.ms.min) / p.ms.median,
            ns_per_segment: p.ms.median * 1e6 / p.segments.max(1) as f64,
        }),
    )
}

/// One line of `scaling_passes.csv`.
#[derive(Serialize)]
struct PassRow<'a> {
    method: &'a str,
    raster: &'static str,
    pass: &'a str,
    density: f32,
    segments: usize,
    gpu_ms_median: f64,
    ns_per_segment: f64,
}

/// `scaling_passes.csv`: each configuration's passes, and the shared light passes', at every point (median GPU ms
/// over the timed frames), where a cost that is not linear grows.
pub fn scaling_passes_csv(r: &ScalingResult) -> Result<String> {
    csv_text(
        "scaling_passes.csv",
        r.points.iter().flat_map(|p| {
            p.passes.iter().map(|(pass, ms)| PassRow {
                method: &p.label,
                raster: p.raster.word(),
                pass,
                density: p.density,
                segments: p.segments,
                gpu_ms_median: *ms,
                ns_per_segment: ms * 1e6 / p.segments.max(1) as f64,
            })
        }),
    )
}

/// Creates the output folder (and its parents); fails with one line when it cannot.
pub fn prepare_out_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    Ok(())
}

/// `chart` as `<stem>.png` and `<stem>.svg`.
pub(crate) fn chart_files(stem: &str, chart: &Chart) -> Result<[(String, Vec<u8>); 2]> {
    let (w, h) = CHART_SIZE;
    Ok([
        (format!("{stem}.png"), chart::png(chart, w, h)?),
        (format!("{stem}.svg"), chart::svg(chart, w, h)?.into_bytes()),
    ])
}

/// Writes `files` into `dir` (created), each atomically; returns their paths.
pub(crate) fn write_files(dir: &Path, files: Vec<(String, Vec<u8>)>) -> Result<Vec<PathBuf>> {
    prepare_out_dir(dir)?;
    let mut out = Vec::new();
    for (name, bytes) in files {
        let path = dir.join(name);
        crate::io::write_atomic(&path, &bytes)?;
        out.push(path);
    }
    Ok(out)
}

/// Writes `results.csv` and `results.json` into `dir` (created), each atomically: what a run writes after each
/// configuration, so that a stopped run leaves every finished one.
pub fn write_tables(dir: &Path, result: &Outcome<BenchResult>) -> Result<Vec<PathBuf>> {
    write_files(
        dir,
        vec![
            ("results.csv".to_string(), to_csv(result)?.into_bytes()),
            ("results.json".to_string(), to_json(result)?.into_bytes()),
        ],
    )
}

/// Writes `results.csv`, `results.json`, `speed_vs_accuracy.png` and `speed_vs_accuracy.svg` into `dir`
/// (created), each atomically; returns their paths.
pub fn write_results(dir: &Path, result: &Outcome<BenchResult>) -> Result<Vec<PathBuf>> {
    let mut files = vec![
        ("results.csv".to_string(), to_csv(result)?.into_bytes()),
        ("results.json".to_string(), to_json(result)?.into_bytes()),
    ];
    files.extend(chart_files(
        "speed_vs_accuracy",
        &chart::speed_accuracy_chart(result),
    )?);
    write_files(dir, files)
}

fn scaling_tables(r: &ScalingResult) -> Result<Vec<(String, Vec<u8>)>> {
    Ok(vec![
        ("scaling.csv".to_string(), scaling_csv(r)?.into_bytes()),
        (
            "scaling_points.csv".to_string(),
            scaling_points_csv(r)?.into_bytes(),
        ),
        (
            "scaling_passes.csv".to_string(),
            scaling_passes_csv(r)?.into_bytes(),
        ),
    ])
}

/// Writes `scaling.csv`, `scaling_points.csv` and `scaling_passes.csv` into `dir` (created), each atomically:
/// what a scaling run writes after each density, so that an interrupted run leaves every finished one.
pub fn write_scaling_tables(dir: &Path, r: &ScalingResult) -> Result<Vec<PathBuf>> {
    write_files(dir, scaling_tables(r)?)
}

/// Writes `scaling.csv`, `scaling_points.csv`, `scaling_passes.csv`, `scaling.png` and `scaling.svg` into `dir`
/// (created), each atomically; returns their paths.
pub fn write_scaling(dir: &Path, r: &ScalingResult) -> Result<Vec<PathBuf>> {
    let mut files = scaling_tables(r)?;
    files.extend(chart_files("scaling", &chart::scaling_chart(r))?);
    write_files(dir, files)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::bench::{BenchRow, ScalingFit, ScalingPoint};
    use crate::measure::{MethodConfig, SceneStats};
    use crate::render::caster::Raster;

    fn row(name: &str, params: &[(&str, f32)], ms: f64, error: f64) -> BenchRow {
        let spread = Spread {
            median: ms,
            min: ms * 0.5,
            max: ms * 2.0,
        };
        BenchRow {
            config: MethodConfig::new(
                name.to_string(),
                params.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            ),
            note: String::new(),
            total_ms: spread,
            passes: vec![("light".to_string(), spread)],
            memory_bytes: 1024,
            build_memory_bytes: 0,
            geometry_passes: 1,
            metrics: vec![("map_error", error), ("image_psnr", f64::INFINITY)],
            device: "test device, \"quoted\"".to_string(),
        }
    }

    pub(crate) fn result() -> BenchResult {
        BenchResult {
            preset: "tiny".to_string(),
            stats: SceneStats {
                device: "test device".to_string(),
                strands: 10,
                segments: 240,
                map_resolution: 64,
                fragments: 1000,
                occupied_texels: 100,
                max_depth_complexity: 30,
                mean_depth_complexity: 10.0,
            },
            frames: 3,
            rows: vec![
                row("method-a", &[("layers", 3.0), ("spacing", 1.0)], 0.25, 0.5),
                row("method-b", &[("layers", 4.0), ("split_ratio", 0.3)], 0.5, 0.75),
            ],
            metric: crate::bench::DEFAULT_ACCURACY_METRIC,
        }
    }

    #[test]
    fn results_csv_has_the_columns_and_quotes_commas() {
        let text = to_csv(&result()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "method,params,label,note,gpu_ms_median,gpu_ms_min,gpu_ms_max,memory_bytes,build_memory_bytes,\
             geometry_passes,map_error,image_psnr,pareto,passes,device"
        );
        assert_eq!(
            lines[1],
            "method-a,layers=3;spacing=1,\"method-a:layers=3,spacing=1\",,0.25,0.125,0.5,1024,0,1,0.5,inf,true,\
             \"light: 0.25 [0.125, 0.5]\",\"test device, \"\"quoted\"\"\""
        );
        // Slower and less accurate than the DOM row: off the front.
        assert!(
            lines[2].starts_with("method-b,layers=4;split_ratio=0.3,\"method-b:layers=4,split_ratio=0.3\",")
        );
        assert!(lines[2].contains(",0.75,inf,false,"), "{}", lines[2]);
        assert_eq!(lines.len(), 3);
    }

    /// The params column spells a choice as the label and `--config` do (`spacing=uniform`, not its number).
    #[test]
    fn results_csv_params_read_as_the_label_spells_them() {
        let mut r = result();
        r.rows.truncate(1);
        r.rows[0].config = MethodConfig::parse("dom:layers=3,spacing=uniform").unwrap();
        let text = to_csv(&r).unwrap();
        let line = text.lines().nth(1).unwrap();
        assert!(
            line.starts_with("dom,layers=3;spacing=uniform,\"dom:layers=3,spacing=uniform\","),
            "{line}"
        );
    }

    #[test]
    fn results_json_rows_match_with_null_for_infinity() {
        let json: serde_json::Value =
            serde_json::from_str(&to_json(&Outcome::Complete(result())).unwrap()).unwrap();
        assert_eq!(json["preset"], "tiny");
        assert_eq!(json["cancelled"], false);
        assert_eq!(json["scene"]["segments"], 240);
        let rows = json["rows"].as_array().unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0]["label"], "method-a:layers=3,spacing=1");
        assert_eq!(rows[0]["params"]["layers"], 3.0);
        assert_eq!(rows[1]["params"]["split_ratio"], 0.3);
        assert_eq!(rows[0]["gpu_ms"]["min"], 0.125);
        assert_eq!(rows[0]["passes"][0]["name"], "light");
        assert_eq!(rows[0]["passes"][0]["max"], 0.5);
        assert_eq!(rows[0]["map_error"], 0.5);
        assert!(rows[0]["image_psnr"].is_null());
        assert_eq!(rows[0]["pareto"], true);
        assert_eq!(rows[1]["pareto"], false);
        let stopped: serde_json::Value =
            serde_json::from_str(&to_json(&Outcome::Stopped(result())).unwrap()).unwrap();
        assert_eq!(stopped["cancelled"], true);
    }

    fn scaling_point(label: &str, raster: Raster, density: f32, segments: usize, ms: f64) -> ScalingPoint {
        ScalingPoint {
            label: label.to_string(),
            raster,
            density,
            strands: segments / 10,
            segments,
            ms: Spread {
                median: ms,
                min: ms * 0.5,
                max: ms * 2.0,
            },
            frames: 3,
            passes: vec![
                ("fill".to_string(), ms * 0.25),
                ("resolve".to_string(), ms * 0.75),
            ],
        }
    }

    /// A hand-made run of one configuration under both rasterisers at two densities.
    fn scaling_result() -> ScalingResult {
        let fit = |raster, ms_per_segment| ScalingFit {
            label: "method-a:layers=4".to_string(),
            raster,
            ms_per_segment,
            intercept_ms: 0.5,
            r_squared: 1.0,
            exponent: 0.5,
            max_residual: 0.0,
            max_spread: 0.1,
        };
        ScalingResult {
            preset: "tiny".to_string(),
            device: "dev".to_string(),
            map_resolution: 64,
            densities: vec![0.25, 0.5],
            rasters: Raster::ALL.to_vec(),
            frames: 3,
            warmup: 2,
            points: vec![
                scaling_point("method-a:layers=4", Raster::Hardware, 0.25, 1000, 2.0),
                scaling_point("method-a:layers=4", Raster::Compute, 0.25, 1000, 3.0),
                scaling_point("method-a:layers=4", Raster::Hardware, 0.5, 2000, 4.0),
                scaling_point("method-a:layers=4", Raster::Compute, 0.5, 2000, 5.0),
            ],
            refused: Vec::new(),
            fits: vec![
                fit(Raster::Hardware, 2f64.powi(-20)),
                fit(Raster::Compute, 2f64.powi(-19)),
            ],
        }
    }

    #[test]
    fn scaling_csv_has_one_line_per_fit_and_rasteriser() {
        let text = scaling_csv(&scaling_result()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines,
            [
                "method,raster,ms_per_segment,ns_per_segment,intercept_ms,r_squared,exponent,max_residual,max_spread,\
                 verdict,device",
                "method-a:layers=4,hardware,9.5367431640625e-7,0.95367431640625,0.5,1.0,0.5,0.0,0.1,linear,dev",
                "method-a:layers=4,compute,1.9073486328125e-6,1.9073486328125,0.5,1.0,0.5,0.0,0.1,linear,dev"
            ]
        );
    }

    #[test]
    fn scaling_points_csv_has_a_raster_column() {
        let text = scaling_points_csv(&scaling_result()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "method,raster,density,strands,segments,frames,gpu_ms_median,gpu_ms_min,gpu_ms_max,spread,\
             ns_per_segment"
        );
        // 3 ms over 1000 segments: 3000 ns each; (6 − 1.5) / 3 = 1.5.
        assert_eq!(
            lines[2],
            "method-a:layers=4,compute,0.25,100,1000,3,3.0,1.5,6.0,1.5,3000.0"
        );
        assert_eq!(lines.len(), 5);
    }

    #[test]
    fn scaling_passes_csv_has_a_line_per_pass_and_point() {
        let text = scaling_passes_csv(&scaling_result()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "method,raster,pass,density,segments,gpu_ms_median,ns_per_segment"
        );
        // The compute point at 1000 segments: 3 ms, a quarter of it filling (0.75 ms, 750 ns a segment).
        assert_eq!(lines[3], "method-a:layers=4,compute,fill,0.25,1000,0.75,750.0");
        assert_eq!(lines.len(), 1 + 4 * 2);
    }

    #[test]
    fn pass_growth_reads_each_pass_over_the_densities() {
        let mut r = scaling_result();
        // The hardware points at 1000 and 2000 segments: a fill growing linearly (1, 2 ms) and a sort growing as
        // segments² (1, 4 ms).
        for (p, sort) in r
            .points
            .iter_mut()
            .filter(|p| p.raster == Raster::Hardware)
            .zip([1.0, 4.0])
        {
            p.passes = vec![
                ("fill".to_string(), p.segments as f64 / 1000.0),
                ("sort".to_string(), sort),
            ];
        }
        let growth = r.pass_growth("method-a:layers=4", Raster::Hardware);
        let names: Vec<&str> = growth.iter().map(|g| g.pass.as_str()).collect();
        assert_eq!(names, ["fill", "sort"]);
        assert!((growth[0].exponent - 1.0).abs() < 1e-12, "{growth:?}");
        assert!((growth[1].exponent - 2.0).abs() < 1e-12, "{growth:?}");
        // At 2000 segments: 2 of 6 ms filling, 4 sorting.
        assert!((growth[0].share - 1.0 / 3.0).abs() < 1e-12 && (growth[1].share - 2.0 / 3.0).abs() < 1e-12);
        assert!(r.pass_growth("method-b", Raster::Hardware).is_empty());
    }

    #[test]
    fn raster_ratios_pair_the_rasterisers_per_density() {
        let r = scaling_result();
        assert_eq!(
            r.raster_ratios(),
            [
                (0.25, "method-a:layers=4".to_string(), 1.5),
                (0.5, "method-a:layers=4".to_string(), 1.25)
            ]
        );
        // Under one rasteriser there is no pair.
        let hardware_only = ScalingResult {
            points: r
                .points
                .iter()
                .filter(|p| p.raster == Raster::Hardware)
                .cloned()
                .collect(),
            ..r
        };
        assert!(hardware_only.raster_ratios().is_empty());
    }

    #[test]
    fn scaling_chart_dashes_the_compute_fits() {
        use crate::bench::chart::{Mark, Scale};
        let result = scaling_result();
        let chart = chart::scaling_chart(&result);
        let names: Vec<&str> = chart
            .series
            .iter()
            .filter(|s| s.mark == Mark::Points)
            .map(|s| s.name.as_str())
            .collect();
        assert_eq!(names.len(), 2);
        assert!(names[0].ends_with(", hardware)"), "{}", names[0]);
        assert!(names[1].ends_with(", compute, dashed)"), "{}", names[1]);
        // One solid curve (hardware) from 1000 to 2000 segments in 25 pieces, and the compute fit in 13 dashes,
        // each a 25th of the range in log x (a factor 2^(1/25)), on the fitted line.
        assert_eq!((chart.x.scale, chart.y.scale), (Scale::Log, Scale::Log));
        let lines: Vec<&chart::Series> = chart.series.iter().filter(|s| s.mark == Mark::Line).collect();
        assert_eq!(lines.len(), 1 + 13);
        let solid = &lines[0].points;
        assert_eq!(solid.len(), 26);
        assert_eq!((solid[0].x, solid[25].x), (1000.0, 2000.0));
        let fit = &result.fits[0];
        for p in solid {
            assert!(
                (p.y - (fit.ms_per_segment * p.x + fit.intercept_ms)).abs() < 1e-9,
                "{p:?}"
            );
        }
        let step = 2f64.powf(1.0 / 25.0);
        for s in &lines[1..] {
            assert_eq!(s.points.len(), 2);
            assert!(
                (s.points[1].x / s.points[0].x - step).abs() < 1e-9,
                "{:?}",
                s.points
            );
        }
        // Both formats render.
        let files = chart_files("scaling", &chart).unwrap();
        assert!(files.iter().all(|(_, bytes)| bytes.len() > 1000));
    }
}
