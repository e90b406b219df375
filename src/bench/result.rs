//! What a bench run produces: one row per measured configuration (GPU time, memory, every error metric), the
//! whole sweep, and the scaling mode's points and fits.

use super::{Spread, pareto_front};
use crate::measure::{Measurement, MethodConfig, SceneStats};
use std::fmt::Write as _;

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
        if !self.note.is_empty() {
            out.push_str(" auto");
        }
        out
    }
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
