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
use crate::render::caster::Raster;
use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::prelude::*;
use plotters::style::{Color as _, FontStyle, register_font};
use std::sync::OnceLock;

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

fn min_max(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// `v` with `decimals` decimals.
fn fmt_fixed(v: f64, decimals: i32) -> String {
    format!("{v:.*}", decimals.max(0) as usize)
}

/// Ticks at log10 of 1..9 × 10^k inside `lo..=hi` (plot coordinates, decades).
fn log_ticks(lo: f64, hi: f64) -> Vec<Tick> {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return Vec::new();
    }
    let few = hi - lo <= 2.5;
    let values: Vec<(i32, i32)> = (lo.floor() as i32..=hi.ceil() as i32)
        .flat_map(|k| (1..10).map(move |m| (m, k)))
        .filter(|&(m, k)| {
            let at = (m as f64 * 10f64.powi(k)).log10();
            at >= lo - 1e-9 && at <= hi + 1e-9
        })
        .collect();
    let labelled = |m: i32| m == 1 || (few && (m == 2 || m == 5));
    // Under a decade the 1-2-5 steps may leave fewer than three labels: then every tick has one.
    let all = values.iter().filter(|(m, _)| labelled(*m)).count() < 3;
    values
        .into_iter()
        .map(|(m, k)| {
            let v = m as f64 * 10f64.powi(k);
            Tick {
                at: v.log10(),
                label: (all || labelled(m)).then(|| fmt_fixed(v, -k)),
            }
        })
        .collect()
}

/// A 1-2-5 step giving about `target` intervals over `span`, and its decimal exponent.
fn nice_step(span: f64, target: f64) -> (f64, i32) {
    let raw = (span / target).max(f64::MIN_POSITIVE);
    let e = raw.log10().floor() as i32;
    let base = 10f64.powi(e);
    let m = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .find(|m| m * base >= raw)
        .unwrap_or(10.0);
    if m == 10.0 {
        (base * 10.0, e + 1)
    } else {
        (m * base, e)
    }
}

/// Labelled ticks at a 1-2-5 step (about 8 intervals) inside `lo..=hi`.
fn linear_ticks(lo: f64, hi: f64) -> Vec<Tick> {
    if !(lo.is_finite() && hi.is_finite()) || lo >= hi {
        return Vec::new();
    }
    let (step, e) = nice_step(hi - lo, 8.0);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last)
        .map(|i| {
            let v = i as f64 * step;
            Tick {
                at: v,
                label: Some(if i == 0 { "0".to_string() } else { fmt_fixed(v, -e) }),
            }
        })
        .collect()
}

/// A linear range from `min(0, lo)` to a tick at or above `hi`, and its ticks.
fn linear_range(lo: f64, hi: f64) -> (f64, f64, Vec<Tick>) {
    let lo = if lo.is_finite() { lo.min(0.0) } else { 0.0 };
    let hi = if hi.is_finite() && hi > lo { hi } else { lo + 1.0 };
    let (step, _) = nice_step(hi - lo, 8.0);
    let top = (hi / step).ceil() * step;
    let bottom = (lo / step).floor() * step;
    (bottom, top, linear_ticks(bottom, top))
}

/// A logarithmic range from the largest m × 10^k (m = 1..9, a tick) below `lo` to the smallest above `hi`
/// (positive), with a little room on both sides: the axis spans the data, not the decades around them.
fn log_range(lo: f64, hi: f64) -> (f64, f64) {
    let ticks = |k: i32| (1..10).map(move |m| m as f64 * 10f64.powi(k));
    let (lo, hi) = (lo / 1.15, hi * 1.15);
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let below = (k0..=k0 + 1)
        .flat_map(ticks)
        .filter(|v| *v <= lo)
        .fold(10f64.powi(k0), f64::max);
    let above = (k1 - 1..=k1)
        .flat_map(ticks)
        .filter(|v| *v >= hi)
        .fold(10f64.powi(k1), f64::min);
    (below, above.max(below * 2.0))
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

/// The speed-against-accuracy chart of a result: one colour per method, the Pareto front connected.
pub fn speed_accuracy_chart(result: &BenchResult) -> Chart {
    let mut series: Vec<Series> = Vec::new();
    let point = |i: usize| {
        let r = &result.rows[i];
        Point {
            x: r.total_ms.median,
            y: result.accuracy(r),
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
    let front = Front {
        name: "Pareto front".to_string(),
        points: result.front().into_iter().map(point).collect(),
    };
    let partial = if result.cancelled { " (cancelled)" } else { "" };
    Chart {
        title: format!("Speed vs accuracy{partial}"),
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
            label: metric_axis(result.metric).to_string(),
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

/// Registers [`FONT`] with plotters (once).
fn font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    ok.then_some(())
        .ok_or_else(|| anyhow!("the chart font (egui's Ubuntu Light) does not load"))
}

/// Renders `chart` as a `width`×`height` PNG.
pub fn png(chart: &Chart, width: u32, height: u32) -> Result<Vec<u8>> {
    font()?;
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        draw(chart, &root).map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
        root.present()
            .map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
    }
    let img = image::RgbImage::from_raw(width, height, rgb)
        .ok_or_else(|| anyhow!("cannot encode the chart as PNG: wrong buffer size"))?;
    let mut out = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
        .map_err(|e| anyhow!("cannot encode the chart as PNG: {e}"))?;
    Ok(out)
}

/// Renders `chart` as a `width`×`height` SVG document.
pub fn svg(chart: &Chart, width: u32, height: u32) -> Result<String> {
    font()?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        draw(chart, &root).map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
        root.present()
            .map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
    }
    Ok(out)
}

fn rgb(c: Color) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

const INK: RGBColor = RGBColor(30, 30, 30);
const NOTE: RGBColor = RGBColor(90, 90, 90);
const FRONT: RGBColor = RGBColor(0, 0, 0);
const POINT_RADIUS: i32 = 5;
const RING_RADIUS: i32 = 9;
const TITLE_SIZE: f64 = 30.0;
const TEXT_SIZE: f64 = 19.0;
const LABEL_SIZE: f64 = 16.0;

/// A linear plot axis over `lo..hi` (plot coordinates) with the model's ticks: labelled ones as plotters' bold
/// key points, every one as a light grid line.
struct TickedAxis {
    lo: f64,
    hi: f64,
    major: Vec<f64>,
    all: Vec<f64>,
}

impl TickedAxis {
    fn new(lo: f64, hi: f64, ticks: &[Tick]) -> TickedAxis {
        TickedAxis {
            lo,
            hi,
            major: ticks.iter().filter(|t| t.label.is_some()).map(|t| t.at).collect(),
            all: ticks.iter().map(|t| t.at).collect(),
        }
    }
}

impl Ranged for TickedAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let t = (v - self.lo) / (self.hi - self.lo);
        limit.0 + (t * (limit.1 - limit.0) as f64).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.all.clone()
        } else {
            self.major.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A pixel box `[x0, y0, x1, y1]`.
type PxBox = [i32; 4];

fn overlaps(a: PxBox, b: PxBox) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// `text` cut to `max` pixels wide in `style`, ending in `...` when cut.
fn fit_text<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
    max: u32,
) -> String {
    let width = |t: &str| area.estimate_text_size(t, style).map_or(0, |s| s.0);
    if width(text) <= max {
        return text.to_string();
    }
    let mut t: Vec<char> = text.chars().collect();
    while !t.is_empty() && width(&format!("{}...", t.iter().collect::<String>())) > max {
        t.pop();
    }
    format!("{}...", t.into_iter().collect::<String>())
}

/// The legend's entries (the named series with points, then the front) and its box size in pixels.
struct Legend<'a> {
    names: Vec<&'a str>,
    style: TextStyle<'a>,
    size: (i32, i32),
}

/// Height of a legend row.
const LEGEND_ROW: i32 = 24;

impl<'a> Legend<'a> {
    fn of<DB: DrawingBackend>(chart: &'a Chart, root: &DrawingArea<DB, Shift>, style: TextStyle<'a>) -> Self {
        let names: Vec<&str> = chart
            .series
            .iter()
            .filter(|s| !s.name.is_empty() && !s.points.is_empty())
            .map(|s| s.name.as_str())
            .chain(chart.front.iter().map(|f| f.name.as_str()))
            .collect();
        let text_w = names
            .iter()
            .map(|n| root.estimate_text_size(n, &style).map_or(0, |s| s.0 as i32))
            .max()
            .unwrap_or(0);
        let size = (text_w + 60, names.len() as i32 * LEGEND_ROW + 16);
        Legend { names, style, size }
    }

    /// The plot corner (and the legend's box there) clear of every point and every line of `chart` drawn in
    /// `cc`; `None` when no corner is, or there is nothing to list.
    fn corner<DB: DrawingBackend>(
        &self,
        chart: &Chart,
        cc: &ChartContext<DB, Cartesian2d<TickedAxis, TickedAxis>>,
    ) -> Option<(SeriesLabelPosition, PxBox)> {
        if self.names.is_empty() {
            return None;
        }
        let ([x0, x1], [y0, y1]) = chart.bounds();
        let (ax, ay) = cc.backend_coord(&(x0, y1));
        let (bx, by) = cc.backend_coord(&(x1, y0));
        let (lw, lh) = self.size;
        let px = |p: &Point| {
            let (x, y) = (chart.plot_x(p.x), chart.plot_y(p.y));
            (x.is_finite() && y.is_finite()).then(|| cc.backend_coord(&(x, y)))
        };
        // Every point, and every line (the fits, the front) sampled every 8 pixels along it.
        let mut marks: Vec<(i32, i32)> = Vec::new();
        let lines = chart.series.iter().map(|s| (s.mark == Mark::Line, &s.points));
        for (line, points) in lines.chain(chart.front.iter().map(|f| (true, &f.points))) {
            let pts: Vec<_> = points.iter().filter_map(px).collect();
            if line {
                for w in pts.windows(2) {
                    let (dx, dy) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
                    let n = (f64::from(dx).hypot(f64::from(dy)) / 8.0).ceil().max(1.0) as i32;
                    marks.extend((0..n).map(|i| (w[0].0 + dx * i / n, w[0].1 + dy * i / n)));
                }
            }
            marks.extend(pts);
        }
        let r = RING_RADIUS;
        [
            (SeriesLabelPosition::UpperRight, [bx - lw - 12, ay + 12]),
            (SeriesLabelPosition::UpperLeft, [ax + 12, ay + 12]),
            (SeriesLabelPosition::LowerRight, [bx - lw - 12, by - lh - 12]),
            (SeriesLabelPosition::LowerLeft, [ax + 12, by - lh - 12]),
        ]
        .into_iter()
        .map(|(position, [x, y])| (position, [x, y, x + lw, y + lh]))
        .find(|(_, b)| {
            b[0] >= ax
                && b[2] <= bx
                && b[3] <= by
                && !marks
                    .iter()
                    .any(|&(x, y)| overlaps(*b, [x - r, y - r, x + r, y + r]))
        })
    }

    /// The legend in `area` beside the plot, level with the plot's top `top` (a backend pixel row): each
    /// series' marker and name, then the front's.
    fn draw_beside<DB: DrawingBackend>(
        &self,
        chart: &Chart,
        area: &DrawingArea<DB, Shift>,
        top: i32,
    ) -> DrawResult<DB> {
        let (_, area_top) = area.get_base_pixel();
        let mut y = (top - area_top).max(0) + 12;
        let label = |name: &str, y: i32| Text::new(name.to_string(), (28, y - 9), self.style.clone());
        for s in chart
            .series
            .iter()
            .filter(|s| !s.name.is_empty() && !s.points.is_empty())
        {
            area.draw(&Circle::new((14, y), POINT_RADIUS, rgb(s.color).filled()))?;
            area.draw(&label(&s.name, y))?;
            y += LEGEND_ROW;
        }
        if let Some(f) = &chart.front {
            area.draw(&PathElement::new(vec![(4, y), (24, y)], FRONT.stroke_width(2)))?;
            area.draw(&Circle::new((14, y), RING_RADIUS, FRONT.stroke_width(2)))?;
            area.draw(&label(&f.name, y))?;
        }
        Ok(())
    }
}

/// Draws `chart` on `root`: titles, axes and ticks, fit lines, the front line, the points, the front's rings,
/// the legend in a clear corner of the plot (beside it when none is), and the front's labels where they overlap
/// nothing.
fn draw<DB: DrawingBackend>(chart: &Chart, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (width, _) = root.dim_in_pixel();
    let text = |size: f64| TextStyle::from((FAMILY, size).into_font()).color(&INK);
    root.draw(&Text::new(chart.title.clone(), (24, 14), text(TITLE_SIZE)))?;
    let note_style = text(TEXT_SIZE).color(&NOTE);
    let mut top = 52;
    for n in &chart.notes {
        let line = fit_text(root, n, &note_style, width.saturating_sub(48));
        root.draw(&Text::new(line, (24, top), note_style.clone()))?;
        top += 24;
    }
    let (_, body) = root.split_vertically(top + 6);

    let ([x0, x1], [y0, y1]) = chart.bounds();
    let x_ticks = chart.x_ticks(x0, x1);
    let y_ticks = chart.y_ticks(y0, y1);
    let build = |area: &DrawingArea<DB, Shift>| {
        ChartBuilder::on(area)
            .margin_left(16)
            .margin_right(32)
            .margin_bottom(12)
            .x_label_area_size(64)
            .y_label_area_size(88)
            .build_cartesian_2d(
                TickedAxis::new(x0, x1, &x_ticks),
                TickedAxis::new(y0, y1, &y_ticks),
            )
    };
    let legend = Legend::of(chart, root, text(LABEL_SIZE));
    // The legend sits in a corner of the plot when one is clear of every point and line, else beside it.
    let corner = legend.corner(chart, &build(&body)?);
    let (plot_area, side) = match corner {
        Some(_) => (body.clone(), None),
        None => {
            let (w, _) = body.dim_in_pixel();
            let (plot, side) = body.split_horizontally(w.saturating_sub(legend.size.0 as u32 + 24));
            (plot, Some(side))
        }
    };
    let mut cc = build(&plot_area)?;
    let x_label = |v: &f64| chart.x_tick_label(*v, x0, x1);
    let y_label = |v: &f64| {
        y_ticks
            .iter()
            .find(|t| (t.at - v).abs() < 1e-12)
            .and_then(|t| t.label.clone())
            .unwrap_or_default()
    };
    cc.configure_mesh()
        .x_desc(chart.x.label.as_str())
        .y_desc(chart.y.label.as_str())
        .x_label_formatter(&x_label)
        .y_label_formatter(&y_label)
        .label_style(text(LABEL_SIZE))
        .axis_desc_style(text(TEXT_SIZE))
        .bold_line_style(RGBColor(215, 215, 215))
        .light_line_style(RGBColor(240, 240, 240))
        .axis_style(INK)
        .draw()?;

    let at = |p: &Point| (chart.plot_x(p.x), chart.plot_y(p.y));
    let finite = |p: &&Point| chart.plot_x(p.x).is_finite() && chart.plot_y(p.y).is_finite();
    // The break between the "0" column and the logarithmic axis.
    if let Some(z) = chart.zero_column() {
        let bx = z + ZERO_GAP * 0.5;
        let (px, py) = cc.backend_coord(&(bx, y0));
        let (_, ptop) = cc.backend_coord(&(bx, y1));
        root.draw(&Rectangle::new(
            [(px - 4, ptop), (px + 4, py + 3)],
            WHITE.filled(),
        ))?;
        for dx in [-4, 3] {
            root.draw(&PathElement::new(
                vec![(px + dx - 3, py + 6), (px + dx + 3, py - 6)],
                INK.stroke_width(2),
            ))?;
        }
    }
    for s in chart.series.iter().filter(|s| s.mark == Mark::Line) {
        let pts: Vec<(f64, f64)> = s.points.iter().filter(finite).map(at).collect();
        cc.draw_series(std::iter::once(PathElement::new(
            pts,
            rgb(s.color).stroke_width(2),
        )))?;
    }
    let front_pts: Vec<&Point> = chart
        .front
        .iter()
        .flat_map(|f| &f.points)
        .filter(finite)
        .collect();
    if let Some(f) = &chart.front {
        let line: Vec<(f64, f64)> = front_pts.iter().map(|p| at(p)).collect();
        cc.draw_series(std::iter::once(PathElement::new(line, FRONT.stroke_width(2))))?
            .label(f.name.clone())
            .legend(|(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(-12, 0), (12, 0)], FRONT.stroke_width(2))
                    + Circle::new((0, 0), RING_RADIUS, FRONT.stroke_width(2))
            });
    }
    let mut occupied: Vec<PxBox> = Vec::new();
    for s in chart.series.iter().filter(|s| s.mark == Mark::Points) {
        let color = rgb(s.color);
        let pts: Vec<(f64, f64)> = s.points.iter().filter(finite).map(at).collect();
        for p in &pts {
            let (x, y) = cc.backend_coord(p);
            occupied.push([
                x - POINT_RADIUS,
                y - POINT_RADIUS,
                x + POINT_RADIUS,
                y + POINT_RADIUS,
            ]);
        }
        let drawn = cc.draw_series(
            pts.into_iter()
                .map(|p| Circle::new(p, POINT_RADIUS, color.filled())),
        )?;
        if !s.name.is_empty() {
            drawn
                .label(s.name.clone())
                .legend(move |(x, y)| Circle::new((x, y), POINT_RADIUS, color.filled()));
        }
    }
    let front_px: Vec<(i32, i32)> = front_pts.iter().map(|p| cc.backend_coord(&at(p))).collect();
    cc.draw_series(
        front_pts
            .iter()
            .map(|p| Circle::new(at(p), RING_RADIUS, FRONT.stroke_width(2))),
    )?;
    for &(x, y) in &front_px {
        let r = RING_RADIUS + 1;
        occupied.push([x - r, y - r, x + r, y + r]);
    }

    let (ax, ay) = cc.backend_coord(&(x0, y1));
    let (bx, by) = cc.backend_coord(&(x1, y0));
    match (corner, side) {
        (Some((position, b)), _) => {
            cc.configure_series_labels()
                .position(position)
                .margin(12)
                .legend_area_size(36)
                .label_font(legend.style.clone())
                .background_style(WHITE.mix(0.92))
                .border_style(RGBColor(160, 160, 160))
                .draw()?;
            occupied.push(b);
        }
        (None, Some(side)) => legend.draw_beside(chart, &side, ay)?,
        (None, None) => {}
    }

    // Labels keep off the front line: sample it every 2 pixels.
    let line_samples: Vec<(i32, i32)> = front_px
        .windows(2)
        .flat_map(|w| {
            let (dx, dy) = ((w[1].0 - w[0].0) as f64, (w[1].1 - w[0].1) as f64);
            let n = (dx.hypot(dy) / 2.0).ceil().max(1.0) as i32;
            (0..=n).map(move |i| {
                let t = i as f64 / n as f64;
                (w[0].0 + (t * dx) as i32, w[0].1 + (t * dy) as i32)
            })
        })
        .collect();
    let plot = [ax, ay, bx, by];
    for (p, &(x, y)) in front_pts.iter().zip(&front_px) {
        place_label(root, plot, &mut occupied, &line_samples, (x, y), &p.label)?;
    }
    Ok(())
}

/// Puts `label` beside the point at `at` where it stays inside `plot` and overlaps nothing placed yet nor any
/// of `avoid` (right, left, above, below, then diagonally); leaves it out when every place is taken.
fn place_label<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: PxBox,
    occupied: &mut Vec<PxBox>,
    avoid: &[(i32, i32)],
    (x, y): (i32, i32),
    label: &str,
) -> DrawResult<DB> {
    let style = TextStyle::from((FAMILY, LABEL_SIZE).into_font()).color(&INK);
    let (tw, th) = root
        .estimate_text_size(label, &style)
        .map(|(w, h)| (w as i32, h as i32))
        .unwrap_or((0, 0));
    let (pad, d) = (2, RING_RADIUS + 4);
    let candidates = [
        (x + d, y - th / 2),
        (x - d - tw, y - th / 2),
        (x - tw / 2, y - d - th),
        (x - tw / 2, y + d),
        (x + d, y - d - th),
        (x + d, y + d),
        (x - d - tw, y - d - th),
        (x - d - tw, y + d),
    ];
    for (lx, ly) in candidates {
        let r = [lx - pad, ly - pad, lx + tw + pad, ly + th + pad];
        let inside = r[0] > plot[0] && r[1] > plot[1] && r[2] < plot[2] && r[3] < plot[3];
        let clear = !occupied.iter().any(|o| overlaps(*o, r))
            && !avoid
                .iter()
                .any(|&(ax, ay)| (r[0]..=r[2]).contains(&ax) && (r[1]..=r[3]).contains(&ay));
        if inside && clear {
            root.draw(&Rectangle::new(
                [(r[0], r[1]), (r[2], r[3])],
                WHITE.mix(0.85).filled(),
            ))?;
            root.draw(&Text::new(label.to_string(), (lx, ly), style))?;
            occupied.push(r);
            return Ok(());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn font_has_the_glyphs_the_charts_print() {
        use ab_glyph::Font;
        let font = ab_glyph::FontRef::try_from_slice(FONT).unwrap();
        for c in ['×', '²', 'Δ', 'σ', 'A', 'z', '0', '|', '.'] {
            assert_ne!(font.glyph_id(c).0, 0, "no glyph for {c}");
        }
    }

    #[test]
    fn log_ticks_label_decades() {
        let t = log_ticks(-1.0, 2.0);
        let labels: Vec<_> = t.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0.1", "1", "10", "100"]);
        assert_eq!(t.len(), 28);
        let few: Vec<_> = log_ticks(0.0, 1.0).into_iter().filter_map(|t| t.label).collect();
        assert_eq!(few, ["1", "2", "5", "10"]);
        // 400 k .. 3 M (the scaling chart's 0.5 M .. 2 M): 1-2-5 would label 500 k, 1 M and 2 M.
        let (lo, hi) = log_range(5e5, 2e6);
        assert_eq!((lo, hi), (4e5, 3e6));
        let scaling: Vec<_> = log_ticks(lo.log10(), hi.log10())
            .into_iter()
            .filter_map(|t| t.label)
            .collect();
        assert_eq!(scaling, ["500000", "1000000", "2000000"]);
        // Within a decade with one 1-2-5 value, every tick is labelled.
        let (lo, hi) = log_range(3.5e5, 7e5);
        assert_eq!((lo, hi), (3e5, 9e5));
        let narrow: Vec<_> = log_ticks(lo.log10(), hi.log10())
            .into_iter()
            .filter_map(|t| t.label)
            .collect();
        assert_eq!(
            narrow,
            [
                "300000", "400000", "500000", "600000", "700000", "800000", "900000"
            ]
        );
    }

    #[test]
    fn linear_range_ends_on_ticks() {
        let (lo, hi, t) = linear_range(0.0, 0.27);
        assert_eq!(lo, 0.0);
        assert!((hi - 0.3).abs() < 1e-12, "{hi}");
        let labels: Vec<_> = t.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0", "0.05", "0.10", "0.15", "0.20", "0.25", "0.30"]);
    }

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
