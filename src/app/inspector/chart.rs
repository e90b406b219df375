//! The inspector's plots as charts for the image writers of the bench (`crate::bench::chart`, drawn by
//! `plotters` as PNG and SVG): the `V(z)` plot (with the ray-traced `V` of the fibres where traced) and the hair
//! count plot `n(z)` of the inspected texel and of each pin, the curves in the colours the window gives them (each with a few named markers, which the chart's legend
//! lists), the fragments as marks under the curves.

use super::curves::{TexelCurves, TexelPlot};
use super::traced::{TRACED_COLOR, traced_label};
use crate::bench::chart::{Axis, Chart, Mark, Point, Scale, Series};
use crate::methods::registry;
use egui::Color32;

/// The reference's colour in the charts (the window draws it in the theme's text colour).
pub const REFERENCE_COLOR: [u8; 3] = [40, 40, 40];
/// The fragments' marks.
const FRAGMENT_COLOR: [u8; 3] = [150, 150, 150];

/// Which of the inspector's two plots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlotKind {
    /// Visibility `V(z)`.
    Visibility,
    /// Hair count `n(z)`.
    Count,
}

impl PlotKind {
    /// The stem of the plot's files (`texel_v.png`, `texel_count.png`).
    pub fn stem(self) -> &'static str {
        match self {
            PlotKind::Visibility => "texel_v",
            PlotKind::Count => "texel_count",
        }
    }
}

fn rgb(c: Color32) -> [u8; 3] {
    [c.r(), c.g(), c.b()]
}

/// Markers on each curve: the chart writer's legend names marked series, not lines.
const MARKERS: usize = 8;

/// A curve through `(depths, values)`: the line, unnamed, and [`MARKERS`] evenly spaced markers named `name`.
fn line(name: String, color: [u8; 3], depths: &[f32], values: &[f32]) -> [Series; 2] {
    let points: Vec<Point> = depths
        .iter()
        .zip(values)
        .map(|(&z, &v)| Point {
            x: f64::from(z),
            y: f64::from(v),
            label: String::new(),
            row: None,
        })
        .collect();
    Series::named_line(name, color, points, MARKERS)
}

/// The reference's and each method's curve of `t` (`kind`'s values), named with `prefix`, in `color` when given
/// (a pin) or else in each curve's own colour.
fn texel_series(t: &TexelPlot, kind: PlotKind, prefix: &str, color: Option<[u8; 3]>) -> Vec<Series> {
    let reference = registry::reference().name();
    let (suffix, reference_values) = match kind {
        PlotKind::Visibility => ("", &t.reference),
        PlotKind::Count => (" count", &t.reference_count),
    };
    let mut series = Vec::from(line(
        format!("{prefix}{reference}{suffix}"),
        color.unwrap_or(REFERENCE_COLOR),
        &t.depths,
        reference_values,
    ));
    if let (PlotKind::Visibility, Some(traced)) = (kind, &t.traced) {
        series.extend(line(
            format!("{prefix}{}", traced_label()),
            color.unwrap_or(rgb(TRACED_COLOR)),
            &t.depths,
            &traced.values,
        ));
    }
    for m in &t.methods {
        let values = match kind {
            PlotKind::Visibility => &m.values,
            PlotKind::Count => &m.counts,
        };
        series.extend(line(
            format!("{prefix}{}{suffix}", m.label),
            color.unwrap_or(rgb(m.model.color)),
            &t.depths,
            values,
        ));
    }
    series
}

impl TexelCurves {
    /// The plot `kind` as a chart: the inspected texel's curves and fragments, then each pin's curves in the
    /// pin's colour; `None` when there is nothing to plot.
    pub fn chart(&self, kind: PlotKind) -> Option<Chart> {
        let texel = self.current.as_ref().or(self.pins.first())?;
        let mut series = Vec::new();
        if let Some(t) = &self.current {
            series.extend(texel_series(t, kind, "", None));
            let mark_at = match kind {
                PlotKind::Visibility => -0.02,
                PlotKind::Count => -0.2,
            };
            series.push(Series {
                name: "fragments".to_string(),
                color: FRAGMENT_COLOR,
                mark: Mark::Points,
                points: t
                    .fragments
                    .iter()
                    .map(|f| Point {
                        x: f64::from(f.depth),
                        y: mark_at,
                        label: String::new(),
                        row: None,
                    })
                    .collect(),
            });
        }
        for (i, t) in self.pins.iter().enumerate() {
            let prefix = format!("pin {} {} ", i + 1, t.label);
            series.extend(texel_series(
                t,
                kind,
                &prefix,
                Some(t.color.map_or(REFERENCE_COLOR, rgb)),
            ));
        }
        let (what, y) = match kind {
            PlotKind::Visibility => ("visibility", "V(z)"),
            PlotKind::Count => ("hair count", "hair count n(z)"),
        };
        Some(Chart {
            title: format!("{}: {what} along the light ray", texel.label),
            notes: vec![format!(
                "{} fragments, {} pins",
                texel.depth_complexity(),
                self.pins.len()
            )],
            x: Axis {
                label: "normalised light depth z".to_string(),
                scale: Scale::Linear,
            },
            y: Axis {
                label: y.to_string(),
                scale: Scale::Linear,
            },
            series,
            front: None,
        })
    }
}
