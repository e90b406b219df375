//! The bench: speed charted against accuracy. It sweeps each method's parameters on one scene — Opacity Shadow
//! Maps 4..256 slices, Deep Opacity Maps 1..15 layers × layer spacing, Bounding Opacity Maps 1..15 layers ×
//! split ratio (0, 0.5, 1 and the automatic ratio found on the reference's fragment lists), Density Clustering
//! 2/4/8 clusters, both occupancy variants, the reference and the opaque shadow map — measures every
//! configuration with [`crate::measure::measure`], and writes `results.csv`, `results.json` and the chart
//! `speed_vs_accuracy.png` (GPU time against map error, the Pareto front marked).
//!
//! The scaling mode measures a few configurations over the generator's strand density × 0.25..4 and fits GPU
//! time against segment count by least squares: the cost per segment and the fixed cost.
//!
//! GPU time is that of the method's own light passes per frame (the shared light-depth pass every method uses
//! is left out, so the opaque shadow map, which reads only that pass, costs 0 ms).

pub mod chart;

use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::{self, Measurement, MethodConfig, SceneStats};
use crate::methods::{ParamValues, registry};
use crate::render::Renderer;
use crate::settings::Settings;
use crate::visibility::SplitCriterion;
use anyhow::{Context, Result, bail};
use chart::{Chart, FrontPoint, Series, Style};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Methods the bench sweeps, in chart and table order.
pub const SWEEP_METHODS: &[&str] = &[
    "opaque-shadow-map",
    "osm",
    "dom",
    "bom",
    "dc",
    "occupancy",
    "reference",
];
pub const OSM_SLICES: &[u32] = &[4, 8, 16, 32, 64, 128, 256];
pub const DOM_LAYERS: &[u32] = &[1, 2, 3, 4, 5, 7, 10, 15];
/// Deep Opacity Maps' `spacing` values: 0 linearly increasing layer sizes, 1 uniform.
pub const DOM_SPACINGS: &[u32] = &[0, 1];
pub const BOM_LAYERS: &[u32] = &[1, 2, 3, 4, 6, 8, 12, 15];
/// Fixed split ratios; the automatic ratio is swept beside them.
pub const BOM_RATIOS: &[f32] = &[0.0, 0.5, 1.0];
pub const DC_CLUSTERS: &[u32] = &[2, 4, 8];
/// Strand density factors of the scaling mode.
pub const SCALING_DENSITIES: &[f32] = &[0.25, 0.5, 1.0, 2.0, 4.0];
/// Configurations of the scaling mode.
pub const SCALING_CONFIGS: &[&str] = &["osm:slices=16", "osm:slices=64", "dom:layers=3", "occupancy"];
/// The note of a configuration whose split ratio is the automatic one.
pub const AUTO_NOTE: &str = "automatic split ratio";
/// Size of the PNG charts.
pub const CHART_SIZE: (u32, u32) = (1200, 800);

/// Checks a `--methods` list against [`SWEEP_METHODS`]; empty means all of them.
pub fn parse_methods(names: &[String]) -> Result<Vec<&'static str>> {
    if names.is_empty() {
        return Ok(SWEEP_METHODS.to_vec());
    }
    let mut out = Vec::new();
    for n in names.iter().map(|n| n.trim()) {
        let Some(m) = SWEEP_METHODS.iter().find(|m| **m == n) else {
            let why = match registry::find(n) {
                Ok(_) => format!("method '{n}' has no bench sweep"),
                Err(e) => e,
            };
            bail!("--methods: {why}; the bench sweeps {}", SWEEP_METHODS.join(", "));
        };
        if !out.contains(m) {
            out.push(*m);
        }
    }
    Ok(out)
}

/// A configuration to measure, with a note for the tables (e.g. [`AUTO_NOTE`]).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchConfig {
    pub config: MethodConfig,
    pub note: String,
}

fn config(name: &str, params: &[(&str, f32)]) -> BenchConfig {
    BenchConfig {
        config: MethodConfig {
            name: name.to_string(),
            params: params.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
        },
        note: String::new(),
    }
}

/// The sweep of `methods`, in [`SWEEP_METHODS`] order. `auto_ratios` holds Bounding Opacity Maps' automatic
/// split ratio per layer count; a ratio equal to a fixed one is measured once, with the note.
pub fn sweep_configs(methods: &[&str], auto_ratios: &[(u32, f32)]) -> Vec<BenchConfig> {
    let mut out = Vec::new();
    for &m in SWEEP_METHODS.iter().filter(|m| methods.contains(m)) {
        match m {
            "osm" => out.extend(OSM_SLICES.iter().map(|&n| config(m, &[("slices", n as f32)]))),
            "dom" => {
                for &k in DOM_LAYERS {
                    for &s in DOM_SPACINGS {
                        out.push(config(m, &[("layers", k as f32), ("spacing", s as f32)]));
                    }
                }
            }
            "bom" => {
                for &k in BOM_LAYERS {
                    let start = out.len();
                    for &r in BOM_RATIOS {
                        out.push(config(m, &[("layers", k as f32), ("split_ratio", r)]));
                    }
                    if let Some(&(_, auto)) = auto_ratios.iter().find(|(l, _)| *l == k) {
                        let same = out[start..]
                            .iter_mut()
                            .find(|c| c.config.params.get("split_ratio") == Some(&auto));
                        match same {
                            Some(c) => c.note = AUTO_NOTE.to_string(),
                            None => {
                                let mut c = config(m, &[("layers", k as f32), ("split_ratio", auto)]);
                                c.note = AUTO_NOTE.to_string();
                                out.push(c);
                            }
                        }
                    }
                }
            }
            "dc" => out.extend(DC_CLUSTERS.iter().map(|&n| config(m, &[("clusters", n as f32)]))),
            "occupancy" => out.extend([0.0, 1.0].map(|v| config(m, &[("variant", v)]))),
            _ => out.push(config(m, &[])),
        }
    }
    out
}

/// Where a run is: `done` of `total` steps, what runs now, and the time since the start.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    pub done: usize,
    pub total: usize,
    pub label: String,
    pub elapsed: Duration,
}

/// Bounding Opacity Maps' automatic split ratio (`methods::bom::automatic_split_ratio`, least correlated
/// successive layers) for each layer count, on the reference's fragment lists of `settings`' scene. `None` when
/// cancelled.
pub fn automatic_split_ratios(
    settings: &Settings,
    layers: &[u32],
    cancel: &AtomicBool,
    progress: &mut dyn FnMut(Progress),
) -> Result<Option<Vec<(u32, f32)>>> {
    let start = Instant::now();
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    progress(Progress {
        done: 0,
        total: layers.len(),
        label: "reference fragment lists".to_string(),
        elapsed: start.elapsed(),
    });
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution)?;
    let lists = r.reference_lists(&s.camera, &s.light, &s.render)?;
    let mut out = Vec::with_capacity(layers.len());
    for (i, &k) in layers.iter().enumerate() {
        if cancel.load(Ordering::Relaxed) {
            return Ok(None);
        }
        progress(Progress {
            done: i,
            total: layers.len(),
            label: format!("automatic split ratio, {k} layers"),
            elapsed: start.elapsed(),
        });
        let best =
            crate::methods::bom::automatic_split_ratio(&lists, k).best(SplitCriterion::CrossCorrelation);
        // The search steps by 0.1: keep the ratio on that grid so it prints and compares exactly.
        out.push((k, (best * 10.0).round() / 10.0));
    }
    Ok(Some(out))
}

/// GPU milliseconds over the timed frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    /// Median (upper median for an even count, as `measure` takes it), minimum and maximum, rounded to whole
    /// nanoseconds (timestamps resolve no finer); all 0 when empty.
    pub fn of(values: &[f64]) -> Spread {
        let mut v: Vec<f64> = values.iter().map(|ms| (ms * 1e6).round() / 1e6).collect();
        v.sort_by(f64::total_cmp);
        match (v.first(), v.last()) {
            (Some(&min), Some(&max)) => Spread {
                median: v[v.len() / 2],
                min,
                max,
            },
            _ => Spread {
                median: 0.0,
                min: 0.0,
                max: 0.0,
            },
        }
    }
}

/// Every error metric of a measurement, by column name: adding a metric to [`Measurement`] is one line here,
/// and the CSV, the JSON and the tables follow.
pub fn error_metrics(m: &Measurement) -> Vec<(&'static str, f64)> {
    vec![
        ("map_error", m.map_error),
        ("worst_texel_error", m.worst_texel_error),
        ("shading_error", m.shading_error),
        ("image_rmse", m.image_rmse),
        ("image_psnr", m.image_psnr),
        ("flicker", m.flicker),
    ]
}

/// The metric the chart and the Pareto front use as accuracy.
pub const ACCURACY_METRIC: &str = "map_error";

/// One measured configuration, as the bench reports it.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    pub config: MethodConfig,
    pub note: String,
    /// The method's light passes per frame, summed.
    pub total_ms: Spread,
    /// Each of the method's light passes.
    pub passes: Vec<(String, Spread)>,
    pub memory_bytes: u64,
    pub geometry_passes: u32,
    /// [`error_metrics`].
    pub metrics: Vec<(&'static str, f64)>,
    pub device: String,
}

impl BenchRow {
    pub fn from_measurement(m: &Measurement, note: &str, device: &str) -> BenchRow {
        let frames = m.pass_frames_ms.iter().map(|(_, v)| v.len()).max().unwrap_or(0);
        let totals: Vec<f64> = (0..frames)
            .map(|f| m.pass_frames_ms.iter().filter_map(|(_, v)| v.get(f)).sum())
            .collect();
        BenchRow {
            config: m.config.clone(),
            note: note.to_string(),
            total_ms: Spread::of(&totals),
            passes: m
                .pass_frames_ms
                .iter()
                .map(|(n, v)| (n.clone(), Spread::of(v)))
                .collect(),
            memory_bytes: m.memory_bytes,
            geometry_passes: m.geometry_passes,
            metrics: error_metrics(m),
            device: device.to_string(),
        }
    }

    pub fn metric(&self, name: &str) -> Option<f64> {
        self.metrics.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }

    /// The accuracy the chart shows ([`ACCURACY_METRIC`]).
    pub fn error(&self) -> f64 {
        self.metric(ACCURACY_METRIC).unwrap_or(f64::NAN)
    }

    /// `osm 64`, `dom 3 s1`, `bom 4 r0.5 auto`: short enough for a chart label.
    pub fn short_label(&self) -> String {
        let mut out = self.config.name.clone();
        for (k, v) in &self.config.params {
            let key = match k.as_str() {
                "slices" | "layers" | "clusters" => "",
                "spacing" => "s",
                "split_ratio" => "r",
                "variant" => "v",
                other => other,
            };
            let _ = write!(out, " {key}{v}");
        }
        if self.note == AUTO_NOTE {
            out.push_str(" auto");
        }
        out
    }
}

/// Indices of the points no other point beats on both coordinates (smaller is better on both: at most equal
/// on each and smaller on one), sorted by x. Points with a non-finite coordinate are left out.
pub fn pareto_front(points: &[[f64; 2]]) -> Vec<usize> {
    let finite = |p: &[f64; 2]| p[0].is_finite() && p[1].is_finite();
    let mut front: Vec<usize> = (0..points.len())
        .filter(|&i| finite(&points[i]))
        .filter(|&i| {
            let p = points[i];
            !points
                .iter()
                .any(|q| finite(q) && q[0] <= p[0] && q[1] <= p[1] && (q[0] < p[0] || q[1] < p[1]))
        })
        .collect();
    front.sort_by(|&a, &b| {
        points[a][0]
            .total_cmp(&points[b][0])
            .then(points[a][1].total_cmp(&points[b][1]))
    });
    front
}

/// A finished (or cancelled) bench.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchResult {
    /// The preset's name or path, for titles.
    pub preset: String,
    pub stats: SceneStats,
    pub frames: u32,
    pub rows: Vec<BenchRow>,
    /// Stopped before every configuration was measured.
    pub cancelled: bool,
}

impl BenchResult {
    /// (median GPU ms, accuracy) of every row.
    pub fn points(&self) -> Vec<[f64; 2]> {
        self.rows.iter().map(|r| [r.total_ms.median, r.error()]).collect()
    }

    /// Row indices of the Pareto front, fastest first.
    pub fn front(&self) -> Vec<usize> {
        pareto_front(&self.points())
    }
}

/// Measures `configs` on `settings`' scene, `chunk` configurations per `measure` call (each call renders the
/// reference again; cancelling takes effect between calls). `None` when cancelled before any row.
pub fn measure_configs(
    settings: &Settings,
    preset: &str,
    configs: &[BenchConfig],
    frames: u32,
    chunk: usize,
    cancel: &AtomicBool,
    progress: &mut dyn FnMut(Progress),
) -> Result<Option<BenchResult>> {
    let start = Instant::now();
    let total = configs.len();
    let mut stats = None;
    let mut rows = Vec::with_capacity(total);
    for group in configs.chunks(chunk.max(1)) {
        if cancel.load(Ordering::Relaxed) {
            break;
        }
        let methods: Vec<MethodConfig> = group.iter().map(|c| c.config.clone()).collect();
        let first = rows.len();
        let mut next = 0;
        let (s, measured) = measure::measure(settings, &methods, frames, |label| {
            // `measure` names the configuration it starts, or a phase of its own (the reference).
            if group.get(next).is_some_and(|c| c.config.label() == label) {
                next += 1;
            }
            progress(Progress {
                done: first + next.saturating_sub(1),
                total,
                label: label.to_string(),
                elapsed: start.elapsed(),
            });
        })?;
        rows.extend(
            measured
                .iter()
                .zip(group)
                .map(|(m, c)| BenchRow::from_measurement(m, &c.note, &s.device)),
        );
        stats.get_or_insert(s);
    }
    progress(Progress {
        done: rows.len(),
        total,
        label: "done".to_string(),
        elapsed: start.elapsed(),
    });
    Ok(stats.map(|stats| BenchResult {
        preset: preset.to_string(),
        stats,
        frames,
        cancelled: rows.len() < total,
        rows,
    }))
}

/// The whole bench of `methods` on `settings`: the automatic split ratios when Bounding Opacity Maps are swept,
/// then every configuration. `None` when cancelled before any row.
pub fn run(
    settings: &Settings,
    preset: &str,
    methods: &[&str],
    frames: u32,
    chunk: usize,
    cancel: &AtomicBool,
    progress: &mut dyn FnMut(Progress),
) -> Result<Option<BenchResult>> {
    let auto = if methods.contains(&"bom") {
        match automatic_split_ratios(settings, BOM_LAYERS, cancel, progress)? {
            Some(a) => a,
            None => return Ok(None),
        }
    } else {
        Vec::new()
    };
    let configs = sweep_configs(methods, &auto);
    measure_configs(settings, preset, &configs, frames, chunk, cancel, progress)
}

/// One CSV field, quoted when it holds a comma, a quote or a line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn csv_line(fields: &[String]) -> String {
    let mut line = fields.iter().map(|f| csv_field(f)).collect::<Vec<_>>().join(",");
    line.push('\n');
    line
}

fn params_text(p: &ParamValues) -> String {
    p.iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(";")
}

/// Metric names of the result's rows (every row has the same).
fn metric_names(result: &BenchResult) -> Vec<&'static str> {
    result
        .rows
        .first()
        .map(|r| r.metrics.iter().map(|(n, _)| *n).collect())
        .unwrap_or_default()
}

/// `results.csv`: a header, then one row per configuration.
pub fn to_csv(result: &BenchResult) -> String {
    let metrics = metric_names(result);
    let mut header: Vec<String> = [
        "method",
        "params",
        "label",
        "note",
        "gpu_ms_median",
        "gpu_ms_min",
        "gpu_ms_max",
        "memory_bytes",
        "geometry_passes",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    header.extend(metrics.iter().map(|s| s.to_string()));
    header.extend(["pareto", "passes", "device"].map(String::from));
    let mut out = csv_line(&header);
    let front = result.front();
    for (i, r) in result.rows.iter().enumerate() {
        let mut f = vec![
            r.config.name.clone(),
            params_text(&r.config.params),
            r.config.label(),
            r.note.clone(),
            r.total_ms.median.to_string(),
            r.total_ms.min.to_string(),
            r.total_ms.max.to_string(),
            r.memory_bytes.to_string(),
            r.geometry_passes.to_string(),
        ];
        f.extend(
            metrics
                .iter()
                .map(|m| r.metric(m).map_or(String::new(), |v| v.to_string())),
        );
        f.push(front.contains(&i).to_string());
        f.push(
            r.passes
                .iter()
                .map(|(n, s)| format!("{n}: {} [{}, {}]", s.median, s.min, s.max))
                .collect::<Vec<_>>()
                .join("; "),
        );
        f.push(r.device.clone());
        out.push_str(&csv_line(&f));
    }
    out
}

/// A JSON number, or null where JSON has none (infinite PSNR of an exact image, NaN).
fn json_number(v: f64) -> serde_json::Value {
    serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, serde_json::Value::Number)
}

fn spread_json(s: &Spread) -> serde_json::Value {
    serde_json::json!({ "median": s.median, "min": s.min, "max": s.max })
}

/// `results.json`: the scene, then `rows` with the same configurations as the CSV.
pub fn to_json(result: &BenchResult) -> serde_json::Value {
    let front = result.front();
    let rows: Vec<serde_json::Value> = result
        .rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut o = serde_json::Map::new();
            o.insert("method".into(), r.config.name.clone().into());
            let params: serde_json::Map<String, serde_json::Value> = r
                .config
                .params
                .iter()
                .map(|(k, v)| (k.clone(), json_number(*v as f64)))
                .collect();
            o.insert("params".into(), params.into());
            o.insert("label".into(), r.config.label().into());
            o.insert("note".into(), r.note.clone().into());
            o.insert("gpu_ms".into(), spread_json(&r.total_ms));
            let passes: Vec<serde_json::Value> = r
                .passes
                .iter()
                .map(|(n, s)| {
                    let mut p = spread_json(s);
                    p["name"] = n.clone().into();
                    p
                })
                .collect();
            o.insert("passes".into(), passes.into());
            o.insert("memory_bytes".into(), r.memory_bytes.into());
            o.insert("geometry_passes".into(), r.geometry_passes.into());
            for (name, v) in &r.metrics {
                o.insert(name.to_string(), json_number(*v));
            }
            o.insert("pareto".into(), front.contains(&i).into());
            o.insert("device".into(), r.device.clone().into());
            o.into()
        })
        .collect();
    let s = &result.stats;
    serde_json::json!({
        "preset": result.preset,
        "device": s.device,
        "frames": result.frames,
        "cancelled": result.cancelled,
        "gpu_ms": "the method's own light passes per frame (the shared light-depth pass left out)",
        "scene": {
            "strands": s.strands,
            "segments": s.segments,
            "map_resolution": s.map_resolution,
            "fragments": s.fragments,
            "occupied_texels": s.occupied_texels,
            "max_depth_complexity": s.max_depth_complexity,
            "mean_depth_complexity": json_number(s.mean_depth_complexity),
        },
        "rows": rows,
    })
}

/// Chart colour of a method.
pub fn method_color(name: &str) -> chart::Color {
    match name {
        "osm" => [31, 119, 180],
        "dom" => [255, 127, 14],
        "bom" => [44, 160, 44],
        "dc" => [214, 39, 40],
        "occupancy" => [148, 103, 189],
        "reference" => [140, 86, 75],
        "opaque-shadow-map" => [127, 127, 127],
        _ => [23, 190, 207],
    }
}

/// `text` cut to `max_px` pixels at `scale`, with `...` when cut.
fn fit_text(text: &str, max_px: u32, scale: u32) -> String {
    if chart::text_width(text, scale) <= max_px {
        return text.to_string();
    }
    let mut t: String = text.to_string();
    while !t.is_empty() && chart::text_width(&format!("{t}..."), scale) > max_px {
        t.pop();
    }
    format!("{t}...")
}

/// The lines under a chart's title: the scene, then the device.
fn scene_lines(preset: &str, s: &SceneStats, extra: &str) -> String {
    let scene = format!(
        "preset {preset}: {} strands, {} segments, {res}x{res} light map{extra}",
        s.strands,
        s.segments,
        res = s.map_resolution
    );
    let width = CHART_SIZE.0 - 40;
    format!(
        "{}\n{}",
        fit_text(&scene, width, 2),
        fit_text(&s.device, width, 2)
    )
}

/// The speed-against-accuracy chart of a result: one colour per method, the Pareto front connected.
pub fn speed_accuracy_chart(result: &BenchResult) -> Chart {
    let mut series: Vec<Series> = Vec::new();
    for r in &result.rows {
        let p = [r.total_ms.median, r.error()];
        match series.iter_mut().find(|s| s.name == r.config.name) {
            Some(s) => s.points.push(p),
            None => series.push(Series {
                name: r.config.name.clone(),
                color: method_color(&r.config.name),
                style: Style::Points,
                points: vec![p],
            }),
        }
    }
    let front = result
        .front()
        .into_iter()
        .map(|i| {
            let r = &result.rows[i];
            FrontPoint {
                x: r.total_ms.median,
                y: r.error(),
                label: r.short_label(),
            }
        })
        .collect();
    let partial = if result.cancelled { " (cancelled)" } else { "" };
    Chart {
        title: format!("Speed vs accuracy{partial}"),
        subtitle: scene_lines(&result.preset, &result.stats, ""),
        x_label: format!(
            "GPU ms per frame, method's own light passes (log scale, {})",
            if result.frames == 1 {
                "1 frame".to_string()
            } else {
                format!("median of {} frames", result.frames)
            }
        ),
        y_label: "map error: mean |V - V_ref| per occupied texel".to_string(),
        x_log: true,
        series,
        front,
        front_name: "Pareto front".to_string(),
    }
}

/// Encodes an image as PNG.
pub fn png_bytes(img: &image::RgbaImage) -> Result<Vec<u8>> {
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .context("cannot encode the chart as PNG")?;
    Ok(png)
}

/// Creates the output folder (and its parents); fails with one line when it cannot.
pub fn prepare_out_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    Ok(())
}

/// Writes `results.csv`, `results.json` and `speed_vs_accuracy.png` into `dir` (created), each atomically;
/// returns their paths.
pub fn write_results(dir: &Path, result: &BenchResult) -> Result<Vec<PathBuf>> {
    prepare_out_dir(dir)?;
    let json = serde_json::to_string_pretty(&to_json(result)).context("cannot encode results.json")?;
    let img = chart::render(&speed_accuracy_chart(result), CHART_SIZE.0, CHART_SIZE.1);
    let files = [
        ("results.csv", to_csv(result).into_bytes()),
        ("results.json", json.into_bytes()),
        ("speed_vs_accuracy.png", png_bytes(&img)?),
    ];
    let mut out = Vec::new();
    for (name, bytes) in files {
        let path = dir.join(name);
        crate::io::write_atomic(&path, &bytes)?;
        out.push(path);
    }
    Ok(out)
}

/// Least-squares line `y = slope·x + intercept` through `points`, with R²; `None` with fewer than two distinct
/// x values.
pub fn fit_line(points: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if points.len() < 2 || sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ss_tot: f64 = points.iter().map(|p| (p.1 - my).powi(2)).sum();
    let ss_res: f64 = points
        .iter()
        .map(|p| (p.1 - slope * p.0 - intercept).powi(2))
        .sum();
    let r2 = if ss_tot > 0.0 { 1.0 - ss_res / ss_tot } else { 1.0 };
    Some((slope, intercept, r2))
}

/// One configuration measured at one strand density.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingPoint {
    pub label: String,
    pub density: f32,
    pub strands: usize,
    pub segments: usize,
    pub ms: Spread,
}

/// GPU ms ≈ `ms_per_segment` · segments + `intercept_ms`, fitted over the densities.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingFit {
    pub label: String,
    pub ms_per_segment: f64,
    pub intercept_ms: f64,
    pub r_squared: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ScalingResult {
    pub preset: String,
    pub device: String,
    /// Stats of the scene at density factor 1.
    pub stats: Option<SceneStats>,
    pub points: Vec<ScalingPoint>,
    pub fits: Vec<ScalingFit>,
}

/// The scaling configurations of `methods` (those [`SCALING_CONFIGS`] names).
pub fn scaling_configs(methods: &[&str]) -> Vec<MethodConfig> {
    SCALING_CONFIGS
        .iter()
        .filter_map(|c| MethodConfig::parse(c).ok())
        .filter(|c| methods.contains(&c.name.as_str()))
        .collect()
}

/// Measures `configs` at the generator's strand density × [`SCALING_DENSITIES`] and fits GPU ms against
/// segment count. `None` when cancelled.
pub fn run_scaling(
    settings: &Settings,
    preset: &str,
    configs: &[MethodConfig],
    frames: u32,
    cancel: &AtomicBool,
    progress: &mut dyn FnMut(Progress),
) -> Result<Option<ScalingResult>> {
    if let Some(f) = &settings.scene.file {
        bail!(
            "--scaling varies the generator's strand density, and this preset loads {}",
            f.display()
        );
    }
    if configs.is_empty() {
        bail!(
            "--scaling measures {}: --methods names none of them",
            SCALING_CONFIGS.join(", ")
        );
    }
    let start = Instant::now();
    let total = SCALING_DENSITIES.len() * configs.len();
    let mut points = Vec::new();
    let mut device = String::new();
    let mut stats = None;
    for (d, &factor) in SCALING_DENSITIES.iter().enumerate() {
        if cancel.load(Ordering::Relaxed) {
            return Ok(None);
        }
        let mut s = settings.clone();
        s.scene.generator.density *= factor;
        let mut n = 0;
        let (st, rows) = measure::measure(&s, configs, frames, |label| {
            if configs.get(n).is_some_and(|c| c.label() == label) {
                n += 1;
            }
            progress(Progress {
                done: d * configs.len() + n.saturating_sub(1),
                total,
                label: format!("density x{factor}: {label}"),
                elapsed: start.elapsed(),
            });
        })?;
        for m in &rows {
            let row = BenchRow::from_measurement(m, "", &st.device);
            points.push(ScalingPoint {
                label: m.config.label(),
                density: s.scene.generator.density,
                strands: st.strands,
                segments: st.segments,
                ms: row.total_ms,
            });
        }
        device = st.device.clone();
        if factor == 1.0 {
            stats = Some(st);
        }
    }
    let fits = configs
        .iter()
        .filter_map(|c| {
            let label = c.label();
            let xy: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.label == label)
                .map(|p| (p.segments as f64, p.ms.median))
                .collect();
            fit_line(&xy).map(|(slope, intercept, r2)| ScalingFit {
                label,
                ms_per_segment: slope,
                intercept_ms: intercept,
                r_squared: r2,
            })
        })
        .collect();
    Ok(Some(ScalingResult {
        preset: preset.to_string(),
        device,
        stats,
        points,
        fits,
    }))
}

/// `scaling.csv`: the fit per configuration.
pub fn scaling_csv(r: &ScalingResult) -> String {
    let mut out = csv_line(
        &[
            "method",
            "ms_per_segment",
            "ns_per_segment",
            "intercept_ms",
            "r_squared",
            "device",
        ]
        .map(String::from),
    );
    for f in &r.fits {
        out.push_str(&csv_line(&[
            f.label.clone(),
            f.ms_per_segment.to_string(),
            (f.ms_per_segment * 1e6).to_string(),
            f.intercept_ms.to_string(),
            f.r_squared.to_string(),
            r.device.clone(),
        ]));
    }
    out
}

/// `scaling_points.csv`: every measurement behind the fits.
pub fn scaling_points_csv(r: &ScalingResult) -> String {
    let mut out = csv_line(
        &[
            "method",
            "density",
            "strands",
            "segments",
            "gpu_ms_median",
            "gpu_ms_min",
            "gpu_ms_max",
        ]
        .map(String::from),
    );
    for p in &r.points {
        out.push_str(&csv_line(&[
            p.label.clone(),
            p.density.to_string(),
            p.strands.to_string(),
            p.segments.to_string(),
            p.ms.median.to_string(),
            p.ms.min.to_string(),
            p.ms.max.to_string(),
        ]));
    }
    out
}

/// Colours of the scaling chart's configurations.
const SCALING_COLORS: [chart::Color; 4] = [[31, 119, 180], [23, 190, 207], [255, 127, 14], [148, 103, 189]];

/// GPU ms against segment count, measured points and fitted lines.
pub fn scaling_chart(r: &ScalingResult) -> Chart {
    let mut series = Vec::new();
    for (i, f) in r.fits.iter().enumerate() {
        let color = SCALING_COLORS[i % SCALING_COLORS.len()];
        let pts: Vec<[f64; 2]> = r
            .points
            .iter()
            .filter(|p| p.label == f.label)
            .map(|p| [p.segments as f64, p.ms.median])
            .collect();
        let (lo, hi) = pts.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
            (lo.min(p[0]), hi.max(p[0]))
        });
        series.push(Series {
            name: format!("{} ({:.1} ns/segment)", f.label, f.ms_per_segment * 1e6),
            color,
            style: Style::Points,
            points: pts,
        });
        series.push(Series {
            name: String::new(),
            color,
            style: Style::Line,
            points: [lo, hi]
                .map(|x| [x, f.ms_per_segment * x + f.intercept_ms])
                .to_vec(),
        });
    }
    let subtitle = match &r.stats {
        Some(s) => scene_lines(&r.preset, s, " at density x1"),
        None => format!(
            "preset {}\n{}",
            r.preset,
            fit_text(&r.device, CHART_SIZE.0 - 40, 2)
        ),
    };
    Chart {
        title: "GPU time against segment count".to_string(),
        subtitle,
        x_label: "segments (strand density x 0.25 .. 4)".to_string(),
        y_label: "GPU ms per frame, method's own light passes".to_string(),
        x_log: false,
        series,
        front: Vec::new(),
        front_name: String::new(),
    }
}

/// The `bench` subcommand's arguments.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=256` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Methods to sweep, comma-separated (default: all): opaque-shadow-map, osm, dom, bom, dc, occupancy,
    /// reference.
    #[arg(long, value_delimiter = ',', value_name = "METHOD,...")]
    pub methods: Vec<String>,
    /// Timed frames per configuration (after one warm-up frame).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// Scaling mode: OSM-16, OSM-64, DOM-3 and occupancy over the strand density × 0.25..4, fitted GPU ms per
    /// segment (writes scaling.csv, scaling_points.csv, scaling.png).
    #[arg(long)]
    pub scaling: bool,
    /// Output folder (created): results.csv, results.json, speed_vs_accuracy.png.
    #[arg(long)]
    pub out: PathBuf,
}

/// A progress bar on stderr: redrawn in place (`\r`) on a terminal, one line per step otherwise.
pub struct TerminalProgress {
    tty: bool,
    drawn: bool,
    last_line: String,
}

impl TerminalProgress {
    pub fn new() -> TerminalProgress {
        use std::io::IsTerminal;
        TerminalProgress {
            tty: std::io::stderr().is_terminal(),
            drawn: false,
            last_line: String::new(),
        }
    }

    /// The line for `p`: a 24-cell bar, step i/n, the label, the elapsed time.
    pub fn line(p: &Progress) -> String {
        const CELLS: usize = 24;
        let filled = (p.done * CELLS).checked_div(p.total).unwrap_or(0).min(CELLS);
        let step = (p.done + 1).min(p.total.max(1));
        format!(
            "[{}{}] {step}/{} {:<32} {:>6.1} s",
            "#".repeat(filled),
            ".".repeat(CELLS - filled),
            p.total,
            fit_text(&p.label, 32 * 6, 1),
            p.elapsed.as_secs_f64()
        )
    }

    pub fn update(&mut self, p: &Progress) {
        if self.tty {
            eprint!("\r{}", Self::line(p));
            self.drawn = true;
            return;
        }
        let key = format!("{} {}", p.done, p.label);
        if key != self.last_line {
            eprintln!("{}", Self::line(p));
            self.last_line = key;
        }
    }
}

impl Default for TerminalProgress {
    fn default() -> Self {
        TerminalProgress::new()
    }
}

impl Drop for TerminalProgress {
    /// Ends the redrawn line so what follows starts on its own.
    fn drop(&mut self) {
        if self.drawn {
            eprintln!();
        }
    }
}

/// `hairlab bench`.
pub fn run_cli(a: &BenchArgs) -> Result<()> {
    let methods = parse_methods(&a.methods)?;
    if !(1..=1000).contains(&a.frames) {
        bail!("--frames must be in 1..=1000 (got {})", a.frames);
    }
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    prepare_out_dir(&a.out)?;
    let never = AtomicBool::new(false);
    let mut bar = TerminalProgress::new();
    let mut progress = |p: Progress| bar.update(&p);
    if a.scaling {
        let configs = scaling_configs(&methods);
        let r = run_scaling(&settings, &a.preset, &configs, a.frames, &never, &mut progress)?
            .context("the scaling run was cancelled")?;
        drop(bar);
        return write_scaling(&a.out, &r);
    }
    let result = run(
        &settings,
        &a.preset,
        &methods,
        a.frames,
        usize::MAX,
        &never,
        &mut progress,
    )?
    .context("the bench was cancelled")?;
    drop(bar);
    print_table(&result);
    for f in write_results(&a.out, &result)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}

fn print_table(result: &BenchResult) {
    let s = &result.stats;
    println!(
        "preset {}: {} strands, {} segments, map {}x{}, {} frames, on {}",
        result.preset, s.strands, s.segments, s.map_resolution, s.map_resolution, result.frames, s.device
    );
    let front = result.front();
    println!(
        "{:<42} {:>10} {:>19} {:>10} {:>11}  pareto",
        "configuration", "GPU ms", "min..max", ACCURACY_METRIC, "memory MiB"
    );
    for (i, r) in result.rows.iter().enumerate() {
        let note = match r.note.as_str() {
            "" => String::new(),
            AUTO_NOTE => " (auto ratio)".to_string(),
            other => format!(" ({other})"),
        };
        println!(
            "{:<42} {:>10.3} {:>19} {:>10.5} {:>11.2}  {}",
            format!("{}{note}", r.config.label()),
            r.total_ms.median,
            format!("{:.3}..{:.3}", r.total_ms.min, r.total_ms.max),
            r.error(),
            r.memory_bytes as f64 / (1024.0 * 1024.0),
            if front.contains(&i) { "*" } else { "" }
        );
    }
    let names: Vec<String> = front.iter().map(|&i| result.rows[i].config.label()).collect();
    println!("Pareto front (fastest first): {}", names.join(" -> "));
}

fn write_scaling(dir: &Path, r: &ScalingResult) -> Result<()> {
    println!(
        "scaling on {}: GPU ms = cost per segment x segments + fixed cost",
        r.device
    );
    println!(
        "{:<20} {:>14} {:>13} {:>9}",
        "configuration", "ns per segment", "intercept ms", "R^2"
    );
    for f in &r.fits {
        println!(
            "{:<20} {:>14.4} {:>13.4} {:>9.4}",
            f.label,
            f.ms_per_segment * 1e6,
            f.intercept_ms,
            f.r_squared
        );
    }
    let img = chart::render(&scaling_chart(r), CHART_SIZE.0, CHART_SIZE.1);
    let files = [
        ("scaling.csv", scaling_csv(r).into_bytes()),
        ("scaling_points.csv", scaling_points_csv(r).into_bytes()),
        ("scaling.png", png_bytes(&img)?),
    ];
    for (name, bytes) in files {
        let path = dir.join(name);
        crate::io::write_atomic(&path, &bytes)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sweep_has_every_configuration_once() {
        let c = sweep_configs(SWEEP_METHODS, &[(4, 0.5), (8, 0.3)]);
        // 7 OSM + 16 DOM + 8×3 BOM + 1 extra automatic ratio + 3 DC + 2 occupancy + reference + opaque.
        assert_eq!(c.len(), 7 + 16 + 24 + 1 + 3 + 2 + 1 + 1);
        let labels: Vec<String> = c.iter().map(|c| c.config.label()).collect();
        for (i, l) in labels.iter().enumerate() {
            assert!(!labels[..i].contains(l), "{l} twice");
            assert!(MethodConfig::parse(l).is_ok(), "{l} does not parse");
        }
        let auto: Vec<&str> = c
            .iter()
            .filter(|c| c.note == AUTO_NOTE)
            .map(|c| c.config.label())
            .map(|l| if l.contains("layers=4,") { "4" } else { "8" })
            .collect();
        assert_eq!(auto, ["4", "8"]);
        assert!(labels.contains(&"bom:layers=8,split_ratio=0.3".to_string()));
    }

    #[test]
    fn methods_list_is_checked() {
        assert_eq!(
            parse_methods(&["osm".into(), "occupancy".into()]).unwrap(),
            ["osm", "occupancy"]
        );
        let e = parse_methods(&["osm".into(), "osn".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown shadow method 'osn'"), "{e}");
        let e = parse_methods(&["none".into()]).unwrap_err().to_string();
        assert!(e.contains("'none' has no bench sweep"), "{e}");
    }

    #[test]
    fn fit_line_recovers_a_line() {
        let pts: Vec<(f64, f64)> = (1..6)
            .map(|i| (i as f64 * 1000.0, 0.002 * i as f64 * 1000.0 + 0.5))
            .collect();
        let (slope, intercept, r2) = fit_line(&pts).unwrap();
        assert!(
            (slope - 0.002).abs() < 1e-12 && (intercept - 0.5).abs() < 1e-9,
            "{slope} {intercept}"
        );
        assert!((r2 - 1.0).abs() < 1e-12);
        assert_eq!(fit_line(&[(1.0, 2.0), (1.0, 3.0)]), None);
    }

    #[test]
    fn spread_takes_median_min_max() {
        let s = Spread::of(&[3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.median, s.min, s.max), (3.0, 1.0, 10.0));
    }

    #[test]
    fn csv_fields_with_commas_are_quoted() {
        assert_eq!(csv_field("dom:layers=3,spacing=1"), "\"dom:layers=3,spacing=1\"");
        assert_eq!(csv_field("a,\"b\""), "\"a,\"\"b\"\"\"");
    }
}
