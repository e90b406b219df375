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
        ("texel_error_p50", m.texel_errors.p50),
        ("texel_error_p95", m.texel_errors.p95),
        ("texel_error_p99", m.texel_errors.p99),
        ("worst_texel_error", m.texel_errors.worst),
        ("share_texels_over_0.05", m.texel_errors.share_over[0]),
        ("share_texels_over_0.1", m.texel_errors.share_over[1]),
        ("shading_error", m.shading_error),
        ("image_rmse", m.image_rmse),
        ("image_psnr", m.image_psnr),
        ("flicker", m.flicker),
    ]
}

/// The metrics a chart's accuracy axis and the Pareto front can use (lower is better), with the axis label.
pub const ACCURACY_METRICS: &[(&str, &str)] = &[
    ("map_error", "map error: mean |ΔV| per occupied texel"),
    ("texel_error_p50", "median texel error (texel mean |ΔV|)"),
    ("texel_error_p95", "95th-percentile texel error (texel mean |ΔV|)"),
    ("texel_error_p99", "99th-percentile texel error (texel mean |ΔV|)"),
    ("worst_texel_error", "worst texel error (texel mean |ΔV|)"),
    (
        "share_texels_over_0.05",
        "share of occupied texels with error > 0.05",
    ),
    (
        "share_texels_over_0.1",
        "share of occupied texels with error > 0.1",
    ),
    (
        "shading_error",
        "shading error: mean |ΔV| at the visible hair points",
    ),
    ("image_rmse", "image RMSE against the reference image"),
    (
        "flicker",
        "flicker: frame-to-frame change of V beyond the reference's",
    ),
];

/// The accuracy metric a new result shows.
pub const DEFAULT_ACCURACY_METRIC: &str = "map_error";

/// `name` as one of [`ACCURACY_METRICS`], or an error listing them.
pub fn parse_metric(name: &str) -> Result<&'static str, String> {
    ACCURACY_METRICS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(n, _)| *n)
        .ok_or_else(|| {
            let names: Vec<_> = ACCURACY_METRICS.iter().map(|(n, _)| *n).collect();
            format!("unknown metric '{name}' (known: {})", names.join(", "))
        })
}

/// The axis label of an [`ACCURACY_METRICS`] name.
pub fn metric_axis(name: &str) -> &'static str {
    ACCURACY_METRICS
        .iter()
        .find(|(n, _)| *n == name)
        .map_or("error", |(_, axis)| *axis)
}

/// The GPU milliseconds of each timed frame, all passes summed, from per-pass frame times.
pub fn frame_totals(pass_frames_ms: &[(String, Vec<f64>)]) -> Vec<f64> {
    let frames = pass_frames_ms.iter().map(|(_, v)| v.len()).max().unwrap_or(0);
    (0..frames)
        .map(|f| pass_frames_ms.iter().filter_map(|(_, v)| v.get(f)).sum())
        .collect()
}

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
    /// What the method builds its maps from each frame (e.g. the fragment lists AVSM and DSM compress).
    pub build_memory_bytes: u64,
    pub geometry_passes: u32,
    /// [`error_metrics`].
    pub metrics: Vec<(&'static str, f64)>,
    pub device: String,
}

impl BenchRow {
    pub fn from_measurement(m: &Measurement, note: &str, device: &str) -> BenchRow {
        BenchRow {
            config: m.config.clone(),
            note: note.to_string(),
            total_ms: Spread::of(&frame_totals(&m.pass_frames_ms)),
            passes: m
                .pass_frames_ms
                .iter()
                .map(|(n, v)| (n.clone(), Spread::of(v)))
                .collect(),
            memory_bytes: m.memory_bytes,
            build_memory_bytes: m.build_memory_bytes,
            geometry_passes: m.geometry_passes,
            metrics: error_metrics(m),
            device: device.to_string(),
        }
    }

    pub fn metric(&self, name: &str) -> Option<f64> {
        self.metrics.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }

    /// `osm 64`, `dom 3 spacing=uniform`, `bom 4 split_ratio=0.5 auto`, `fom 16 window=none`: short enough for
    /// a chart label. The method's first parameter (its main one: slices, layers, terms, nodes, ...) shows as
    /// its value alone, the others as `key=value`, choices by their word; `auto` marks an analysed point.
    pub fn short_label(&self) -> String {
        let method = crate::methods::registry::find(&self.config.name).ok();
        let first = method.and_then(|m| m.params().first()).map(|p| p.key);
        let mut out = self.config.name.clone();
        // In the method's parameter order (then any key it does not have).
        let rank = |k: &str| method.and_then(|m| m.params().iter().position(|p| p.key == k));
        let mut params: Vec<(&String, &f32)> = self.config.params.iter().collect();
        params.sort_by_key(|(k, _)| rank(k).unwrap_or(usize::MAX));
        for (k, v) in params {
            let value = method
                .and_then(|m| crate::methods::spec(m, k).ok())
                .map_or_else(|| v.to_string(), |p| p.format(*v));
            if Some(k.as_str()) == first {
                let _ = write!(out, " {value}");
            } else {
                let _ = write!(out, " {k}={value}");
            }
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
    /// The [`ACCURACY_METRICS`] name the chart, the tables and the Pareto front use.
    pub metric: &'static str,
}

impl BenchResult {
    /// `row`'s value of the result's accuracy metric.
    pub fn accuracy(&self, row: &BenchRow) -> f64 {
        row.metric(self.metric).unwrap_or(f64::NAN)
    }

    /// (median GPU ms, accuracy) of every row.
    pub fn points(&self) -> Vec<[f64; 2]> {
        self.rows
            .iter()
            .map(|r| [r.total_ms.median, self.accuracy(r)])
            .collect()
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

/// A configuration the renderer refused at one density (e.g. lists too long for a CPU adapter's compressor).
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingRefusal {
    pub label: String,
    pub segments: usize,
    pub reason: String,
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
    pub map_resolution: u32,
    /// The strand density factors measured, smallest first.
    pub densities: Vec<f32>,
    pub points: Vec<ScalingPoint>,
    /// Configurations refused at some densities (left out of the points and the fits there).
    pub refused: Vec<ScalingRefusal>,
    pub fits: Vec<ScalingFit>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::LightMethod;
    use crate::methods::dom::Dom;
    use crate::methods::osm::Osm;

    fn row(name: &str, params: &[(&str, f32)], note: &str) -> BenchRow {
        let spread = Spread {
            median: 1.0,
            min: 1.0,
            max: 1.0,
        };
        BenchRow {
            config: MethodConfig {
                name: name.to_string(),
                params: params.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            },
            note: note.to_string(),
            total_ms: spread,
            passes: Vec::new(),
            memory_bytes: 0,
            build_memory_bytes: 0,
            geometry_passes: 1,
            metrics: Vec::new(),
            device: String::new(),
        }
    }

    #[test]
    fn short_labels_show_the_main_parameter_bare_and_choices_as_words() {
        assert_eq!(
            row(Osm.name(), &[("slices", 64.0)], "").short_label(),
            format!("{} 64", Osm.name())
        );
        assert_eq!(
            row(Dom.name(), &[("layers", 3.0), ("spacing", 1.0)], "").short_label(),
            format!("{} 3 spacing=uniform", Dom.name())
        );
        assert_eq!(
            row(Dom.name(), &[("layers", 4.0)], "tuned").short_label(),
            format!("{} 4 auto", Dom.name())
        );
        assert_eq!(
            row("unregistered", &[("k", 0.5)], "").short_label(),
            "unregistered k=0.5"
        );
    }
}
