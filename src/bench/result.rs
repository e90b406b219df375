//! What a bench run produces: one row per measured configuration (GPU time, memory, every error metric), the
//! whole sweep, and the scaling mode's points and fits.

use super::{Spread, pareto_front};
use crate::measure::{Measurement, MethodConfig, SceneStats};
use crate::render::caster::Raster;
use std::fmt::Write as _;

/// One error metric of a measurement: its column name (CSV, JSON, `--metric`), its header in `measure`'s table,
/// the axis label when a chart plots it (`None`: not an accuracy axis, e.g. PSNR, where higher is better), and how
/// it is read from a [`Measurement`]. Adding a metric is one line in [`METRICS`] plus its computation; the CSV,
/// the JSON, the charts, the window's metric menu and `measure`'s table follow.
pub struct Metric {
    pub name: &'static str,
    pub header: &'static str,
    pub axis: Option<&'static str>,
    /// Printed as a percentage in the table.
    pub percent: bool,
    pub value: fn(&Measurement) -> f64,
}

/// Every error metric, in column order.
pub const METRICS: &[Metric] = &[
    Metric {
        name: "map_error",
        header: "map err",
        axis: Some("map error: mean |ΔV| per occupied texel"),
        percent: false,
        value: |m| m.map_error,
    },
    Metric {
        name: "texel_error_p50",
        header: "p50",
        axis: Some("median texel error (texel mean |ΔV|)"),
        percent: false,
        value: |m| m.texel_errors.p50,
    },
    Metric {
        name: "texel_error_p95",
        header: "p95",
        axis: Some("95th-percentile texel error (texel mean |ΔV|)"),
        percent: false,
        value: |m| m.texel_errors.p95,
    },
    Metric {
        name: "texel_error_p99",
        header: "p99",
        axis: Some("99th-percentile texel error (texel mean |ΔV|)"),
        percent: false,
        value: |m| m.texel_errors.p99,
    },
    Metric {
        name: "worst_texel_error",
        header: "worst",
        axis: Some("worst texel error (texel mean |ΔV|)"),
        percent: false,
        value: |m| m.texel_errors.worst,
    },
    Metric {
        name: "share_texels_over_0.05",
        header: ">0.05",
        axis: Some("share of occupied texels with error > 0.05"),
        percent: true,
        value: |m| m.texel_errors.share_over[0],
    },
    Metric {
        name: "share_texels_over_0.1",
        header: ">0.1",
        axis: Some("share of occupied texels with error > 0.1"),
        percent: true,
        value: |m| m.texel_errors.share_over[1],
    },
    Metric {
        name: "shading_error",
        header: "shading",
        axis: Some("shading error: mean |ΔV| at the visible hair points"),
        percent: false,
        value: |m| m.shading_error,
    },
    Metric {
        name: "image_rmse",
        header: "img RMSE",
        axis: Some("image RMSE against the reference image"),
        percent: false,
        value: |m| m.image_rmse,
    },
    Metric {
        name: "image_psnr",
        header: "PSNR",
        axis: None,
        percent: false,
        value: |m| m.image_psnr,
    },
    Metric {
        name: "flip",
        header: "FLIP",
        axis: Some("FLIP: mean perceived difference from the reference image"),
        percent: false,
        value: |m| m.image_flip,
    },
    Metric {
        name: "light_turn_flicker",
        header: "lt flicker",
        axis: Some("light-turn flicker: frame-to-frame change of V beyond the reference's"),
        percent: false,
        value: |m| m.light_turn_flicker,
    },
];

/// Every error metric of a measurement, by column name ([`METRICS`] order).
pub fn error_metrics(m: &Measurement) -> Vec<(&'static str, f64)> {
    METRICS.iter().map(|k| (k.name, (k.value)(m))).collect()
}

/// The metrics a chart's accuracy axis and the Pareto front can use (lower is better), with the axis label.
pub fn accuracy_metrics() -> impl Iterator<Item = (&'static str, &'static str)> {
    METRICS.iter().filter_map(|k| k.axis.map(|axis| (k.name, axis)))
}

/// The accuracy metric a new result shows.
pub const DEFAULT_ACCURACY_METRIC: &str = "map_error";

/// Metric names renamed since they were first accepted: (old, new).
pub const RENAMED_METRICS: &[(&str, &str)] = &[("flicker", "light_turn_flicker")];

/// A name that is none of the [`accuracy_metrics`].
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("unknown metric '{name}' (known: {known})")]
pub struct UnknownMetric {
    pub name: String,
    /// The accuracy metrics' names, comma-separated.
    pub known: String,
}

/// `name` as one of the [`accuracy_metrics`] (a [`RENAMED_METRICS`] old name as its new one, saying so on
/// stderr in one line), or an error listing them.
pub fn parse_metric(name: &str) -> Result<&'static str, UnknownMetric> {
    if let Some((old, new)) = RENAMED_METRICS.iter().find(|(old, _)| *old == name) {
        eprintln!("metric '{old}' is now named '{new}' (the flicker under a turning light)");
        return parse_metric(new);
    }
    accuracy_metrics()
        .find(|(n, _)| *n == name)
        .map(|(n, _)| n)
        .ok_or_else(|| UnknownMetric {
            name: name.to_owned(),
            known: accuracy_metrics().map(|(n, _)| n).collect::<Vec<_>>().join(", "),
        })
}

/// The axis label of an [`accuracy_metrics`] name.
pub fn metric_axis(name: &str) -> &'static str {
    accuracy_metrics()
        .find(|(n, _)| *n == name)
        .map_or("error", |(_, axis)| axis)
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

/// A bench's configurations measured (all of them, or those kept when stopped: the run returns an
/// [`crate::progress::Outcome`] that says which).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchResult {
    /// The preset's name or path, for titles.
    pub preset: String,
    pub stats: SceneStats,
    pub frames: u32,
    pub rows: Vec<BenchRow>,
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
    /// The rasteriser the light passes ran under (`render.raster`).
    pub raster: Raster,
    pub density: f32,
    pub strands: usize,
    pub segments: usize,
    /// Over the timed frames (the fit takes the median).
    pub ms: Spread,
    /// Timed frames behind `ms`.
    pub frames: usize,
    /// Each of the configuration's passes and its median GPU ms over the timed frames (none for the shared
    /// light passes): where a cost that is not linear grows.
    pub passes: Vec<(String, f64)>,
}

/// How one pass of a configuration grows over a scaling run.
#[derive(Clone, Debug, PartialEq)]
pub struct PassGrowth {
    pub pass: String,
    /// `p` of the pass's median GPU ms ∝ segments^p ([`super::growth_exponent`]), NaN when it cannot be fitted.
    pub exponent: f64,
    /// Its part of the configuration's passes at the largest density (the sum of the passes' medians).
    pub share: f64,
}

/// A configuration the renderer refused at one density (e.g. lists too long for a CPU adapter's compressor).
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingRefusal {
    pub label: String,
    pub raster: Raster,
    pub segments: usize,
    pub reason: String,
}

/// R² from which the scaling mode calls a configuration's cost linear in segments...
pub const LINEAR_R_SQUARED: f64 = 0.98;
/// ... when its log-log exponent is also at most this: a line through few points can fit a quadratic cost
/// closely (R² 0.996 over three points of a cost growing as segments^2.9), while a linear cost with a fixed part
/// has an exponent of at most 1.
pub const LINEAR_MAX_EXPONENT: f64 = 1.2;

/// GPU ms ≈ `ms_per_segment` · segments + `intercept_ms`, fitted over the densities' medians.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingFit {
    pub label: String,
    pub raster: Raster,
    pub ms_per_segment: f64,
    pub intercept_ms: f64,
    pub r_squared: f64,
    /// `p` of GPU ms ∝ segments^p (log-log least squares; [`super::growth_exponent`]), NaN when it cannot be
    /// fitted: what a cost that is not linear is reported with.
    pub exponent: f64,
    /// The largest distance of a point's median from the line, over the line's value there.
    pub max_residual: f64,
    /// The largest spread of a point's timed frames, (max − min) / median: the measurement's own scatter.
    pub max_spread: f64,
}

impl ScalingFit {
    /// Whether the line holds: R² at least [`LINEAR_R_SQUARED`] and the exponent at most
    /// [`LINEAR_MAX_EXPONENT`].
    pub fn linear(&self) -> bool {
        self.r_squared >= LINEAR_R_SQUARED && self.exponent <= LINEAR_MAX_EXPONENT
    }

    /// The table's verdict: "linear"; or, for a cost that is not, its measured growth when the exponent is
    /// above [`LINEAR_MAX_EXPONENT`]; otherwise (R² below [`LINEAR_R_SQUARED`] at a linear exponent) how far
    /// the points lie off the line against how far a point's own frames spread: "scattered" when no point is
    /// further off the line than the widest spread of frames, "not linear" when one is.
    pub fn verdict(&self) -> String {
        let percent = |x: f64| 100.0 * x;
        if self.linear() {
            "linear".to_string()
        } else if self.exponent.is_nan() || self.exponent > LINEAR_MAX_EXPONENT {
            format!("not linear: GPU ms grows as segments^{:.2}", self.exponent)
        } else if self.max_residual <= self.max_spread {
            format!(
                "scattered: off the line by up to {:.0} %, frames spread up to {:.0} %",
                percent(self.max_residual),
                percent(self.max_spread)
            )
        } else {
            format!(
                "not linear: off the line by up to {:.0} %, beyond the frames' spread of {:.0} %",
                percent(self.max_residual),
                percent(self.max_spread)
            )
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct ScalingResult {
    pub preset: String,
    pub device: String,
    pub map_resolution: u32,
    /// The strand density factors measured, smallest first (those finished when the run was stopped).
    pub densities: Vec<f32>,
    /// The rasterisers each density was measured under.
    pub rasters: Vec<Raster>,
    /// Timed frames per point, and the warm-up frames discarded before them.
    pub frames: u32,
    pub warmup: u32,
    pub points: Vec<ScalingPoint>,
    /// Configurations refused at some densities (left out of the points and the fits there).
    pub refused: Vec<ScalingRefusal>,
    pub fits: Vec<ScalingFit>,
}

impl ScalingResult {
    /// Each pass of `label` under `raster`, in the order the frame runs them: its growth over the densities and
    /// its share at the largest.
    pub fn pass_growth(&self, label: &str, raster: Raster) -> Vec<PassGrowth> {
        let points: Vec<&ScalingPoint> = self
            .points
            .iter()
            .filter(|p| p.label == label && p.raster == raster)
            .collect();
        let Some(last) = points.iter().max_by_key(|p| p.segments) else {
            return Vec::new();
        };
        let total: f64 = last.passes.iter().map(|(_, ms)| ms).sum();
        last.passes
            .iter()
            .map(|(pass, last_ms)| {
                let xy: Vec<(f64, f64)> = points
                    .iter()
                    .filter_map(|p| {
                        let ms = p.passes.iter().find(|(n, _)| n == pass)?.1;
                        Some((p.segments as f64, ms))
                    })
                    .collect();
                PassGrowth {
                    pass: pass.clone(),
                    exponent: super::growth_exponent(&xy).unwrap_or(f64::NAN),
                    share: last_ms / total,
                }
            })
            .collect()
    }

    /// Per density measured and configuration, the compute rasteriser's light-pass GPU ms over the hardware
    /// one's (medians): `(density, label, ratio)`, for the pairs measured under both.
    pub fn raster_ratios(&self) -> Vec<(f32, String, f64)> {
        let at = |raster: Raster, p: &ScalingPoint| {
            self.points
                .iter()
                .find(|q| q.raster == raster && q.label == p.label && q.density == p.density)
                .map(|q| q.ms.median)
        };
        self.points
            .iter()
            .filter(|p| p.raster == Raster::Hardware)
            .filter_map(|p| {
                let compute = at(Raster::Compute, p)?;
                Some((p.density, p.label.clone(), compute / p.ms.median))
            })
            .collect()
    }
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
            config: MethodConfig::new(
                name.to_string(),
                params.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            ),
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
    fn the_old_flicker_name_is_read_as_the_light_turn_flicker() {
        assert_eq!(parse_metric("flicker"), Ok("light_turn_flicker"));
        assert_eq!(parse_metric("light_turn_flicker"), Ok("light_turn_flicker"));
        assert!(accuracy_metrics().all(|(n, _)| n != "flicker"));
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

    /// The verdict names growth above the exponent cap, and otherwise sets the points' distance from the line
    /// against the frames' own spread.
    #[test]
    fn verdicts_tell_growth_from_scatter() {
        let fit = |r_squared, exponent, max_residual, max_spread| ScalingFit {
            label: "m".to_string(),
            raster: Raster::Hardware,
            ms_per_segment: 1e-6,
            intercept_ms: 0.0,
            r_squared,
            exponent,
            max_residual,
            max_spread,
        };
        assert_eq!(fit(0.99, 1.1, 0.3, 0.0).verdict(), "linear");
        assert_eq!(
            fit(0.99, 1.33, 0.1, 0.2).verdict(),
            "not linear: GPU ms grows as segments^1.33"
        );
        assert_eq!(
            fit(0.95, f64::NAN, 0.1, 0.2).verdict(),
            "not linear: GPU ms grows as segments^NaN"
        );
        assert_eq!(
            fit(0.94, 0.99, 0.12, 0.30).verdict(),
            "scattered: off the line by up to 12 %, frames spread up to 30 %"
        );
        assert_eq!(
            fit(0.94, 0.99, 0.25, 0.05).verdict(),
            "not linear: off the line by up to 25 %, beyond the frames' spread of 5 %"
        );
    }
}
