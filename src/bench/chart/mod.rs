//! The bench's charts: one plain model ([`Chart`]: title, notes, axes, coloured series of labelled points, the
//! Pareto front), built once from the results, drawn by `plotters` as PNG and SVG and by the window's Bench panel
//! with egui_plot. Both drawings place values through the model ([`Chart::plot_x`], [`Chart::bounds`],
//! [`Chart::x_ticks`]), so they share the axes, the ticks and the palette ([`method_color`]).
//!
//! Text is set in Ubuntu Light, the proportional font egui bundles (`epaint_default_fonts`), through plotters'
//! `ab_glyph` feature: no system font is needed. SVG text names the `sans-serif` family.
//!
//! A logarithmic axis cannot show 0, and a configuration whose own passes cost nothing measurable (the opaque
//! shadow map reuses the shared light-depth pass) has 0 ms: such points sit in a "0" column left of the
//! logarithmic axis, behind an axis break.

use super::{BenchResult, ScalingResult, metric_axis};
use crate::measure::SceneStats;
use crate::progress::Outcome;
use crate::render::caster::Raster;

mod draw;
mod ticks;

pub use draw::{png, svg};
use ticks::{linear_range, linear_ticks, log_range, log_ticks, min_max};

/// The chart font's bytes: egui's bundled proportional font.
pub const FONT: &[u8] = epaint_default_fonts::UBUNTU_LIGHT;
/// The family the font is registered under (and that SVG text names).
const FAMILY: &str = "sans-serif";
/// Size of the PNG and SVG charts.
pub const CHART_SIZE: (u32, u32) = (1200, 800);

pub type Color = [u8; 3];

/// Chart colour of a method: its own ([`crate::methods::MethodInfo::color`]), grey for a name not registered.
pub fn method_color(name: &str) -> Color {
    crate::methods::registry::find(name).map_or([127, 127, 127], |m| m.info().color)
}

/// The colour of the scaling chart's fit `i`: its method's, darker for each earlier configuration of the same
/// method (OSM-16, then OSM-64 darker); a configuration's fits under both rasterisers share it.
fn scaling_color(fits: &[super::ScalingFit], i: usize) -> Color {
    let method = |label: &str| label.split(':').next().unwrap_or(label).to_string();
    let name = method(&fits[i].label);
    let mut earlier: Vec<&str> = fits[..i]
        .iter()
        .filter(|f| method(&f.label) == name && f.label != fits[i].label)
        .map(|f| f.label.as_str())
        .collect();
    earlier.dedup();
    method_color(&name).map(|c| (f32::from(c) * 0.6f32.powi(earlier.len() as i32)) as u8)
}

/// Dashes along the polyline `points`: every other piece between consecutive points drawn, as line series out
/// of the legend.
fn dashes(points: &[Point], color: Color) -> Vec<Series> {
    points
        .windows(2)
        .step_by(2)
        .map(|w| Series {
            name: String::new(),
            color,
            mark: Mark::Line,
            points: w.to_vec(),
        })
        .collect()
}

/// How an axis maps its values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    Linear,
    /// Logarithmic; values at or below 0 go to the "0" column.
    Log,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub label: String,
    pub scale: Scale,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A disc per point.
    Points,
    /// A line through the points in order (a fit).
    Line,
}

/// A data point, its label, and the result row it shows (none for a fit line's ends).
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub label: String,
    pub row: Option<usize>,
}

/// One named, coloured set of points; an empty name keeps it out of the legend.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub color: Color,
    pub mark: Mark,
    pub points: Vec<Point>,
}

impl Series {
    /// A curve through `points`: the line, unnamed, and `markers` of its points evenly spaced as markers under
    /// `name` (the legend names marked series, not lines).
    pub fn named_line(name: String, color: Color, points: Vec<Point>, markers: usize) -> [Series; 2] {
        let step = points.len().div_ceil(markers.max(1)).max(1);
        let marked = points.iter().step_by(step).cloned().collect();
        [
            Series {
                name: String::new(),
                color,
                mark: Mark::Line,
                points,
            },
            Series {
                name,
                color,
                mark: Mark::Points,
                points: marked,
            },
        ]
    }
}

/// The highlighted front: its points connected in order, ringed and labelled.
#[derive(Clone, Debug, PartialEq)]
pub struct Front {
    pub name: String,
    pub points: Vec<Point>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    pub title: String,
    /// Smaller lines under the title: the scene, the device.
    pub notes: Vec<String>,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
    pub front: Option<Front>,
}

/// A tick in plot coordinates, with its label when it is a major (labelled) one.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    pub at: f64,
    pub label: Option<String>,
}

/// The distance in decades between the "0" column and the start of the logarithmic axis.
const ZERO_GAP: f64 = 0.35;

impl Chart {
    /// Every finite point of the series and the front.
    fn all_points(&self) -> impl Iterator<Item = &Point> {
        self.series
            .iter()
            .flat_map(|s| &s.points)
            .chain(self.front.iter().flat_map(|f| &f.points))
            .filter(|p| p.x.is_finite() && p.y.is_finite())
    }

    /// The logarithmic x range (log10 of 1, 2 or 5 × 10^k around the positive x values).
    fn log_x_range(&self) -> (f64, f64) {
        let pos = self.all_points().map(|p| p.x).filter(|x| *x > 0.0);
        let (lo, hi) = min_max(pos);
        let (lo, hi) = if lo.is_finite() {
            log_range(lo, hi)
        } else {
            (0.1, 10.0)
        };
        (lo.log10(), hi.log10())
    }

    /// The plot x of the "0" column of a logarithmic axis, when some point has x <= 0.
    fn zero_column(&self) -> Option<f64> {
        (self.x.scale == Scale::Log && self.all_points().any(|p| p.x <= 0.0))
            .then(|| self.log_x_range().0 - ZERO_GAP)
    }

    /// Where `x` sits on the plot's x axis: itself on a linear axis, its log10 on a logarithmic one (the "0"
    /// column for x <= 0).
    pub fn plot_x(&self, x: f64) -> f64 {
        match self.x.scale {
            Scale::Linear => x,
            Scale::Log if x > 0.0 => x.log10(),
            Scale::Log => self.zero_column().unwrap_or(f64::NAN),
        }
    }

    /// Where `y` sits on the plot's y axis: itself on a linear axis, its log10 on a logarithmic one (not drawn at
    /// or below 0).
    pub fn plot_y(&self, y: f64) -> f64 {
        match self.y.scale {
            Scale::Linear => y,
            Scale::Log if y > 0.0 => y.log10(),
            Scale::Log => f64::NAN,
        }
    }

    /// The plot's x and y ranges in plot coordinates, spanning every point with a little room.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let x = match self.x.scale {
            Scale::Log => {
                let (lo, hi) = self.log_x_range();
                [self.zero_column().map_or(lo, |z| z - ZERO_GAP * 0.5), hi]
            }
            Scale::Linear => {
                let (lo, hi) = min_max(self.all_points().map(|p| p.x));
                let (lo, hi, _) = linear_range(lo, hi);
                [lo, hi]
            }
        };
        let y = match self.y.scale {
            Scale::Log => {
                let (lo, hi) = min_max(self.all_points().map(|p| p.y).filter(|y| *y > 0.0));
                let (lo, hi) = if lo.is_finite() {
                    log_range(lo, hi)
                } else {
                    (0.1, 10.0)
                };
                [lo.log10(), hi.log10()]
            }
            Scale::Linear => {
                let (lo, hi) = min_max(self.all_points().map(|p| p.y));
                let (lo, hi, _) = linear_range(lo, hi * 1.05);
                [lo, hi]
            }
        };
        (x, y)
    }

    /// The x ticks over `lo..=hi` (plot coordinates): 1..9 × 10^k on a logarithmic axis (decades labelled, and
    /// 2 and 5 too over at most 2.5 decades) after the "0" column's; 1-2-5 steps on a linear one.
    pub fn x_ticks(&self, lo: f64, hi: f64) -> Vec<Tick> {
        match self.x.scale {
            Scale::Linear => linear_ticks(lo, hi),
            Scale::Log => {
                let zero = self.zero_column();
                let mut out: Vec<Tick> = zero
                    .filter(|z| (lo..=hi).contains(z))
                    .map(|at| Tick {
                        at,
                        label: Some("0".to_string()),
                    })
                    .into_iter()
                    .collect();
                let start = zero.map_or(lo, |z| lo.max(z + ZERO_GAP * 0.75));
                out.extend(log_ticks(start, hi));
                out
            }
        }
    }

    /// The y ticks over `lo..=hi`: 1-2-5 steps, or 1..9 × 10^k on a logarithmic axis.
    pub fn y_ticks(&self, lo: f64, hi: f64) -> Vec<Tick> {
        match self.y.scale {
            Scale::Linear => linear_ticks(lo, hi),
            Scale::Log => log_ticks(lo, hi),
        }
    }

    /// The label of the x tick at `at`, if any.
    pub fn x_tick_label(&self, at: f64, lo: f64, hi: f64) -> String {
        self.x_ticks(lo, hi)
            .into_iter()
            .find(|t| (t.at - at).abs() < 1e-9)
            .and_then(|t| t.label)
            .unwrap_or_default()
    }
}

/// The notes under a chart's title: the scene, then the device.
fn scene_notes(preset: &str, s: &SceneStats, extra: &str) -> Vec<String> {
    vec![
        format!(
            "preset {preset}: {} strands, {} segments, {res}×{res} light map{extra}",
            s.strands,
            s.segments,
            res = s.map_resolution
        ),
        s.device.clone(),
    ]
}

/// The speed-against-accuracy chart of a result: one colour per method, the Pareto front connected; the title
/// says "(stopped)" when the run was.
pub fn speed_accuracy_chart(result: &Outcome<BenchResult>) -> Chart {
    let title = if result.is_stopped() {
        "Speed vs accuracy (stopped)"
    } else {
        "Speed vs accuracy"
    };
    speed_chart_by(result, &|r| result.accuracy(r), metric_axis(result.metric), title)
}

/// The speed chart of a result against another accuracy than its metric: `error(row)` on the y axis (NaN keeps
/// a row off the chart) under `y_label`, e.g. each configuration's image error against the path-traced truth.
pub fn speed_chart_by(
    result: &BenchResult,
    error: &dyn Fn(&super::BenchRow) -> f64,
    y_label: &str,
    title: &str,
) -> Chart {
    let mut series: Vec<Series> = Vec::new();
    let point = |i: usize| {
        let r = &result.rows[i];
        Point {
            x: r.total_ms.median,
            y: error(r),
            label: r.short_label(),
            row: Some(i),
        }
    };
    for (i, r) in result.rows.iter().enumerate() {
        match series.iter_mut().find(|s| s.name == r.config.name) {
            Some(s) => s.points.push(point(i)),
            None => series.push(Series {
                name: r.config.name.clone(),
                color: method_color(&r.config.name),
                mark: Mark::Points,
                points: vec![point(i)],
            }),
        }
    }
    let xy: Vec<[f64; 2]> = (0..result.rows.len()).map(&point).map(|p| [p.x, p.y]).collect();
    let front = Front {
        name: "Pareto front".to_string(),
        points: super::pareto_front(&xy).into_iter().map(point).collect(),
    };
    Chart {
        title: title.to_string(),
        notes: scene_notes(&result.preset, &result.stats, ""),
        x: Axis {
            label: format!(
                "GPU ms per frame, method's own light passes (log scale, {})",
                if result.frames == 1 {
                    "1 frame".to_string()
                } else {
                    format!("median of {} frames", result.frames)
                }
            ),
            scale: Scale::Log,
        },
        y: Axis {
            label: y_label.to_string(),
            scale: Scale::Linear,
        },
        series,
        front: (!front.points.is_empty()).then_some(front),
    }
}

/// Dashes per fit line of the compute rasteriser.
/// Pieces of a fitted curve in the scaling chart (a dashed one draws every other).
const FIT_SAMPLES: usize = 25;

/// GPU ms against segment count on log-log axes (a cost linear in segments climbs one decade of time per decade
/// of segments; the methods' times span three decades), measured points and fitted lines: solid under the
/// hardware rasteriser, dashed under the compute one.
pub fn scaling_chart(r: &ScalingResult) -> Chart {
    let mut series = Vec::new();
    let both = r.rasters.len() > 1;
    for (i, f) in r.fits.iter().enumerate() {
        let color = scaling_color(&r.fits, i);
        let pts: Vec<Point> = r
            .points
            .iter()
            .filter(|p| p.label == f.label && p.raster == f.raster)
            .map(|p| Point {
                x: p.segments as f64,
                y: p.ms.median,
                label: format!("{} ×{:.3}", p.label, p.density),
                row: None,
            })
            .collect();
        // The fit, a curve on these axes: FIT_SAMPLES points evenly spaced in log x.
        let (lo, hi) = min_max(pts.iter().map(|p| p.x));
        let curve: Vec<Point> = (0..=FIT_SAMPLES)
            .map(|k| {
                let x = lo * (hi / lo).powf(k as f64 / FIT_SAMPLES as f64);
                Point {
                    x,
                    y: f.ms_per_segment * x + f.intercept_ms,
                    label: String::new(),
                    row: None,
                }
            })
            .collect();
        let raster = match (both, f.raster) {
            (false, _) => String::new(),
            (true, Raster::Hardware) => ", hardware".to_string(),
            (true, Raster::Compute) => ", compute, dashed".to_string(),
        };
        series.push(Series {
            name: format!(
                "{} ({:.1} ns/segment, R² {:.3}{raster})",
                f.label,
                f.ms_per_segment * 1e6,
                f.r_squared
            ),
            color,
            mark: Mark::Points,
            points: pts,
        });
        match f.raster {
            Raster::Hardware => series.push(Series {
                name: String::new(),
                color,
                mark: Mark::Line,
                points: curve,
            }),
            Raster::Compute => series.extend(dashes(&curve, color)),
        }
    }
    let segments = r.points.iter().map(|p| p.segments).max().unwrap_or(0);
    let mut notes = vec![
        format!(
            "preset {}: {res}×{res} light map, up to {segments} segments",
            r.preset,
            res = r.map_resolution
        ),
        r.device.clone(),
    ];
    let mut refused: Vec<(String, usize)> = Vec::new();
    for x in &r.refused {
        let label = if both {
            format!("{} ({} raster)", x.label, x.raster.word())
        } else {
            x.label.clone()
        };
        match refused.iter_mut().find(|(l, _)| *l == label) {
            Some((_, s)) => *s = (*s).min(x.segments),
            None => refused.push((label, x.segments)),
        }
    }
    notes.extend(
        refused
            .iter()
            .map(|(l, s)| format!("{l}: refused from {s} segments (see the table)")),
    );
    let (first, last) = (
        r.densities.first().copied().unwrap_or(0.0),
        r.densities.last().copied().unwrap_or(0.0),
    );
    Chart {
        title: "GPU time against segment count".to_string(),
        notes,
        x: Axis {
            label: format!("segments (strand density × {first:.2} .. {last:.2})"),
            scale: Scale::Log,
        },
        y: Axis {
            label: "GPU ms per frame, method's own light passes".to_string(),
            scale: Scale::Log,
        },
        series,
        front: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f64, y: f64) -> Point {
        Point {
            x,
            y,
            label: format!("{x}"),
            row: None,
        }
    }

    #[test]
    fn zero_sits_in_its_own_column_left_of_the_log_axis() {
        let chart = Chart {
            title: String::new(),
            notes: Vec::new(),
            x: Axis {
                label: String::new(),
                scale: Scale::Log,
            },
            y: Axis {
                label: String::new(),
                scale: Scale::Linear,
            },
            series: vec![Series {
                name: "a".to_string(),
                color: [0, 0, 0],
                mark: Mark::Points,
                points: vec![point(0.0, 1.0), point(1.0, 0.5), point(10.0, 0.1)],
            }],
            front: None,
        };
        // 1..10 ms with 15 % room (0.87..11.5 ms) out to the ticks around: 0.8..20 ms.
        let ([lo, hi], [ylo, yhi]) = chart.bounds();
        let zero = chart.plot_x(0.0);
        assert!((hi - 20f64.log10()).abs() < 1e-12, "{hi}");
        assert!((zero - (0.8f64.log10() - ZERO_GAP)).abs() < 1e-12, "{zero}");
        assert!(lo < zero && zero < 0.8f64.log10());
        assert_eq!(chart.plot_x(10.0), 1.0);
        assert!(ylo == 0.0 && (yhi - 1.2).abs() < 1e-12, "{ylo} {yhi}");
        let ticks = chart.x_ticks(lo, hi);
        assert_eq!(ticks[0].label.as_deref(), Some("0"));
        assert_eq!(chart.x_tick_label(1.0, lo, hi), "10");
        // No tick between the "0" column and the logarithmic axis.
        assert!(ticks[1..].iter().all(|t| t.at > zero + ZERO_GAP * 0.5));
    }
}
