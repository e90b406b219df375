//! `hairlab bench transparency`: every eye transparency technique's sweep ([`EyeTransparency::sweep`])
//! measured against the exact reference on one view ([`crate::measure::transparency`]), GPU time of the
//! technique's own passes charted against hair-pixel RMSE with the Pareto front, and the speed ratio of depth
//! peeling to occupancy ordering beside the deepest pixel's layer count (Sintorn & Assarsson 2009 Fig. 2: 51 fps
//! against 4.01 fps at 112 layers, 12.72×). Writes `transparency.csv`, `transparency.json` and
//! `transparency_speed_vs_accuracy.png`/`.svg`.

use super::chart::{Axis, Chart, Front, Mark, Point, Scale, Series};
use super::report::{chart_files, write_files};
use super::stats::pareto_front;
use crate::io::csv_text;
use crate::measure::transparency::{EyeStats, TechniqueConfig, TechniqueMeasurement, measure_each_on};
use crate::progress::Outcome;
use crate::render::transparency::{EyeTransparency, registry};
use crate::settings::Settings;
use anyhow::{Context, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The paper's speed-up of occupancy ordering over depth peeling (Fig. 2: 51 fps / 4.01 fps) and its layers.
pub const PAPER_PEEL_RATIO: f64 = 51.0 / 4.01;
pub const PAPER_PEEL_LAYERS: u32 = 112;

pub struct TransparencyBench {
    pub preset: String,
    pub device: String,
    pub frames: u32,
    pub stats: EyeStats,
    pub rows: Vec<TechniqueMeasurement>,
}

/// Every registered technique's sweep, in registry order.
pub fn sweep_configs() -> Vec<TechniqueConfig> {
    registry::all()
        .iter()
        .flat_map(|t| {
            t.sweep()
                .into_iter()
                .map(|params| TechniqueConfig::new(t.name(), params))
        })
        .collect()
}

impl TransparencyBench {
    /// The whole sweep on a device opened by the adapter policy: [`TransparencyBench::run_each`].
    pub fn run(
        settings: &Settings,
        preset: &str,
        frames: u32,
        progress: &mut dyn crate::progress::Progress,
    ) -> Result<Outcome<Self>> {
        let gpu = crate::gpu::Gpu::headless(crate::gpu::AdapterPreference::from_env_or(
            crate::gpu::AdapterPreference::Hardware,
        ))?;
        Self::run_each(&gpu, settings, preset, &sweep_configs(), frames, progress, |_| {
            Ok(())
        })
    }

    /// `configs` measured on `gpu`, `progress` told each as it starts, `after` called with the bench so far after
    /// each (to write it); its error ends the run with it; a stop `progress` asks for (Ctrl-C) ends it:
    /// [`Outcome::Stopped`] with the rows so far.
    pub fn run_each(
        gpu: &crate::gpu::Gpu,
        settings: &Settings,
        preset: &str,
        configs: &[TechniqueConfig],
        frames: u32,
        progress: &mut dyn crate::progress::Progress,
        mut after: impl FnMut(&TransparencyBench) -> Result<()>,
    ) -> Result<Outcome<Self>> {
        let bench = |stats: &EyeStats, rows: &[TechniqueMeasurement]| TransparencyBench {
            preset: preset.to_string(),
            device: crate::gpu::describe(&gpu.info),
            frames,
            stats: stats.clone(),
            rows: rows.to_vec(),
        };
        let (stats, rows) = measure_each_on(gpu, settings, configs, frames, progress, |stats, rows| {
            after(&bench(stats, rows))
        })?;
        // `measure_each_on` ends early only when stopped.
        Ok(Outcome::new(bench(&stats, &rows), rows.len() < configs.len()))
    }

    /// Indices of the Pareto front (GPU ms against hair RMSE), fastest first.
    pub fn front(&self) -> Vec<usize> {
        let points: Vec<[f64; 2]> = self
            .rows
            .iter()
            .map(|r| [r.total_ms(), r.metrics.rmse_hair])
            .collect();
        pareto_front(&points)
    }

    /// `t(depth peel) / t(occupancy order)` at the techniques' defaults, when both were measured.
    pub fn peel_ratio(&self) -> Option<f64> {
        let time = |t: &dyn EyeTransparency| {
            self.rows
                .iter()
                .find(|r| r.config.name == t.name() && r.config.params.is_empty())
                .map(TechniqueMeasurement::total_ms)
        };
        let (paper, baseline) = registry::paper_and_baseline();
        let peel = time(baseline)?;
        let occupancy = time(paper)?;
        (occupancy > 0.0).then(|| peel / occupancy)
    }

    pub fn chart(&self) -> Chart {
        let mut series: Vec<Series> = Vec::new();
        let point = |i: usize| {
            let r = &self.rows[i];
            Point {
                x: r.total_ms(),
                y: r.metrics.rmse_hair,
                label: r.config.label(),
                row: Some(i),
            }
        };
        for (i, r) in self.rows.iter().enumerate() {
            match series.iter_mut().find(|s| s.name == r.config.name) {
                Some(s) => s.points.push(point(i)),
                None => series.push(Series {
                    name: r.config.name.clone(),
                    color: registry::find(&r.config.name).map_or([128; 3], |t| t.info().color),
                    mark: Mark::Points,
                    points: vec![point(i)],
                }),
            }
        }
        let front = Front {
            name: "Pareto front".to_string(),
            points: self.front().into_iter().map(point).collect(),
        };
        let s = &self.stats;
        Chart {
            title: "Eye transparency: speed vs accuracy".to_string(),
            notes: vec![
                format!(
                    "preset {}: {} strands, {} segments, {}×{} view, eye depth complexity max {} mean {:.1}",
                    self.preset,
                    s.strands,
                    s.segments,
                    s.width,
                    s.height,
                    s.max_depth_complexity,
                    s.mean_depth_complexity
                ),
                self.device.clone(),
            ],
            x: Axis {
                label: format!(
                    "GPU ms per frame, the technique's own passes (log scale, median of {} frames)",
                    self.frames
                ),
                scale: Scale::Log,
            },
            y: Axis {
                label: "hair-pixel RMSE against the exact sorted composite".to_string(),
                scale: Scale::Linear,
            },
            series,
            front: (!front.points.is_empty()).then_some(front),
        }
    }

    pub fn to_csv(&self) -> Result<String> {
        let front = self.front();
        csv_text(
            "transparency.csv",
            self.rows
                .iter()
                .enumerate()
                .map(|(i, r)| Row::of(r, front.contains(&i))),
        )
    }

    pub fn to_json(&self) -> Result<String> {
        let front = self.front();
        let s = &self.stats;
        let json = Json {
            preset: &self.preset,
            device: &self.device,
            frames: self.frames,
            view: [s.width, s.height],
            hair_pixels: s.hair_pixels,
            fragments: s.fragments,
            max_depth_complexity: s.max_depth_complexity,
            mean_depth_complexity: s.mean_depth_complexity,
            peel_over_occupancy: self.peel_ratio(),
            paper_peel_over_occupancy: PAPER_PEEL_RATIO,
            rows: self
                .rows
                .iter()
                .enumerate()
                .map(|(i, r)| Row::of(r, front.contains(&i)))
                .collect(),
        };
        serde_json::to_string_pretty(&json).context("cannot encode transparency.json")
    }

    /// Writes the CSV, the JSON and the chart into `dir` (created), each atomically.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        let mut files = self.tables()?;
        files.extend(chart_files("transparency_speed_vs_accuracy", &self.chart())?);
        write_files(dir, files)
    }

    /// Writes `transparency.csv` and `transparency.json` alone, each atomically: what a run writes after each
    /// configuration, so that an interrupted run leaves every finished one.
    pub fn write_tables(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        write_files(dir, self.tables()?)
    }

    fn tables(&self) -> Result<Vec<(String, Vec<u8>)>> {
        Ok(vec![
            ("transparency.csv".to_string(), self.to_csv()?.into_bytes()),
            ("transparency.json".to_string(), self.to_json()?.into_bytes()),
        ])
    }
}

#[derive(Serialize)]
struct Row {
    configuration: String,
    gpu_ms: f64,
    rmse_hair: f64,
    psnr_hair: f64,
    rmse: f64,
    ssim_hair: f64,
    flip: f64,
    flip_hair: f64,
    flip_p95_hair: f64,
    flip_p99_hair: f64,
    max_error: f64,
    p99: f64,
    share_over_1: f64,
    share_over_4: f64,
    share_over_8: f64,
    contrast_retention: f64,
    mean_luminance_ratio: f64,
    memory_bytes: u64,
    geometry_passes: u32,
    pareto: bool,
}

impl Row {
    fn of(r: &TechniqueMeasurement, pareto: bool) -> Row {
        let m = &r.metrics;
        Row {
            configuration: r.config.label(),
            gpu_ms: r.total_ms(),
            rmse_hair: m.rmse_hair,
            psnr_hair: m.psnr_hair,
            rmse: m.rmse,
            ssim_hair: m.ssim_hair,
            flip: m.flip.mean,
            flip_hair: m.flip.mean_hair,
            flip_p95_hair: m.flip.p95_hair,
            flip_p99_hair: m.flip.p99_hair,
            max_error: m.max_error,
            p99: m.p99,
            share_over_1: m.share_over[0],
            share_over_4: m.share_over[1],
            share_over_8: m.share_over[2],
            contrast_retention: m.contrast_retention,
            mean_luminance_ratio: m.mean_luminance_ratio,
            memory_bytes: r.memory_bytes,
            geometry_passes: r.geometry_passes,
            pareto,
        }
    }
}

#[derive(Serialize)]
struct Json<'a> {
    preset: &'a str,
    device: &'a str,
    frames: u32,
    view: [u32; 2],
    hair_pixels: usize,
    fragments: u64,
    max_depth_complexity: u32,
    mean_depth_complexity: f64,
    peel_over_occupancy: Option<f64>,
    paper_peel_over_occupancy: f64,
    rows: Vec<Row>,
}
