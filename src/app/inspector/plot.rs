//! The inspector's drawing: the egui_plot of the reference, the ray-traced `V` of the fibres beside it, the
//! methods' curves, what the selected method stores (slice planes, layer boundaries, cluster bins, occupied
//! slices) and the pins, and the figures table beside it.

use super::curves::{MethodCurve, TexelCurves, TexelPlot, plot_range};
use super::traced::{TRACED_COLOR, traced_label};
use crate::methods::registry;
use crate::visibility::{Stored, TexelError};
use egui::Color32;
use egui_plot::{Legend, Line, LineStyle, MarkerShape, Plot, PlotPoints, Points, Polygon, VLine};

/// A plot over normalised light depth: `id`, the y axis `y_label` spanning at least `y_range`, the legend in
/// `corner`, and hover labels `name / z / value = …` (the `V(z)` plot and the count plot).
pub(super) fn depth_plot(
    id: &str,
    y_label: &str,
    value: &'static str,
    y_range: [f64; 2],
    corner: egui_plot::Corner,
    height: f32,
) -> Plot<'static> {
    Plot::new(id)
        .legend(
            Legend::default()
                .text_style(egui::TextStyle::Small)
                .position(corner),
        )
        .height(height)
        .x_axis_label("normalised light depth z")
        .y_axis_label(y_label)
        .include_y(y_range[0])
        .include_y(y_range[1])
        .label_formatter(move |pos| {
            let (name, p) = match pos {
                egui_plot::HoverPosition::NearDataPoint {
                    plot_name, position, ..
                } => (*plot_name, position),
                egui_plot::HoverPosition::Elsewhere { position } => ("", position),
            };
            Some(format!("{name}\nz = {:.5}\n{value} = {:.5}", p.x, p.y))
        })
}

/// The methods' curves of texel `t` (`value`: the V or the count series, its name ending in `suffix`; the
/// selected method drawn wider) and the texel's fragments as ticks at height `tick_y` (the `V(z)` and count plots).
pub(super) fn method_curves(
    p: &mut egui_plot::PlotUi<'_>,
    t: &TexelPlot,
    text: Color32,
    suffix: &str,
    value: impl Fn(&MethodCurve) -> &[f32],
    tick_y: f64,
) {
    for m in &t.methods {
        let width = if m.selected { 2.0 } else { 1.5 };
        p.line(
            Line::new(format!("{}{suffix}", m.label), series(&t.depths, value(m)))
                .color(m.model.color)
                .width(width),
        );
    }
    let ticks: PlotPoints = t.fragments.iter().map(|f| [f64::from(f.depth), tick_y]).collect();
    p.points(
        Points::new("fragments", ticks)
            .shape(MarkerShape::Up)
            .radius(3.0)
            .color(text),
    );
}

/// The plot: reference, methods, stored structure, fragments, pins.
pub(super) fn plot(ui: &mut egui::Ui, curves: &TexelCurves, height: f32) {
    let text = ui.visuals().text_color();
    let corner = egui_plot::Corner::RightTop;
    depth_plot("texel_plot", "V(z)", "V", [-0.12, 1.05], corner, height).show(ui, |p| {
        if let Some(t) = &curves.current {
            if let Some(s) = &curves.stored {
                stored_items(p, s, t);
            }
            p.line(
                Line::new(registry::reference().name(), series(&t.depths, &t.reference))
                    .color(text)
                    .width(2.0),
            );
            if let Some(traced) = &t.traced {
                p.line(
                    Line::new(traced_label(), series(&t.depths, &traced.values))
                        .color(TRACED_COLOR)
                        .width(2.0)
                        .style(LineStyle::dashed_loose()),
                );
            }
            method_curves(p, t, text, "", |m| &m.values, -0.02);
        }
        for (i, t) in curves.pins.iter().enumerate() {
            let color = t.color.unwrap_or(text);
            let name = format!("pin {} {}", i + 1, t.label);
            p.line(Line::new(format!("{name} reference"), series(&t.depths, &t.reference)).color(color));
            if let Some(traced) = &t.traced {
                p.line(
                    Line::new(format!("{name} ray-traced"), series(&t.depths, &traced.values))
                        .color(color)
                        .width(2.0)
                        .style(LineStyle::dotted_dense()),
                );
            }
            for m in &t.methods {
                p.line(
                    Line::new(format!("{name} {}", m.label), series(&t.depths, &m.values))
                        .color(color)
                        .style(LineStyle::dashed_dense()),
                );
            }
        }
    });
}

/// What the selected method stores, over the plotted range of texel `t`.
fn stored_items(p: &mut egui_plot::PlotUi<'_>, s: &Stored, t: &TexelPlot) {
    let Some(model) = t.methods.iter().find(|m| m.selected) else {
        return;
    };
    let color = model.model.color;
    let (lo, hi) = plot_range(t.near, t.far);
    let inside = |z: f32| (lo..=hi).contains(&z);
    for &z in s.boundaries.iter().filter(|z| inside(**z)) {
        p.vline(
            VLine::new(format!("{} boundaries", s.label), z)
                .color(color.gamma_multiply(0.6))
                .style(LineStyle::dashed_loose()),
        );
    }
    let knots: PlotPoints = s
        .knots
        .iter()
        .filter(|k| inside(k[0]))
        .map(|&[z, v]| [f64::from(z), f64::from(v)])
        .collect();
    p.points(
        Points::new(format!("{} stored values", s.label), knots)
            .shape(MarkerShape::Diamond)
            .radius(4.0)
            .color(color),
    );
    for &b in &s.bins {
        p.polygon(band(&format!("{} bins", s.label), b, (-0.1, -0.06), color));
    }
    let means: PlotPoints = s.means.iter().map(|&m| [f64::from(m), -0.08]).collect();
    p.points(
        Points::new(format!("{} means", s.label), means)
            .shape(MarkerShape::Asterisk)
            .radius(5.0)
            .color(color),
    );
    for &o in &s.occupied {
        p.polygon(band(
            &format!("{} occupied slices", s.label),
            o,
            (-0.1, -0.06),
            color,
        ));
    }
    for z in [t.near, t.far] {
        p.vline(
            VLine::new("near / far", z)
                .color(Color32::GRAY)
                .style(LineStyle::dotted_dense()),
        );
    }
}

/// Beside the plot: the texel's figures, error table and stored values.
pub(super) fn figures(ui: &mut egui::Ui, curves: &TexelCurves) {
    let Some(t) = &curves.current else {
        ui.label("no texel");
        return;
    };
    ui.strong(&t.label);
    if t.fragments.is_empty() {
        ui.label("this texel holds no fragment");
        return;
    }
    let total: f64 = t.fragments.iter().map(|f| f64::from(f.optical_depth())).sum();
    egui::Grid::new("texel_figures").num_columns(2).show(ui, |ui| {
        ui.label("depth complexity");
        ui.label(t.depth_complexity().to_string());
        ui.end_row();
        ui.label("near / far");
        ui.label(format!("{:.5} / {:.5}", t.near, t.far));
        ui.end_row();
        ui.label("V beyond far");
        ui.label(format!("{:.5}", (-total).exp()));
        ui.end_row();
        if let Some(traced) = &t.traced {
            ui.colored_label(TRACED_COLOR, "ray-traced, beyond");
            ui.label(format!("{:.5}", traced.values.last().copied().unwrap_or(1.0)))
                .on_hover_text(format!(
                    "the share of the texel's {} rays no fibre blocks before the last plotted depth",
                    traced.rays.first.len()
                ));
            ui.end_row();
        }
    });
    ui.add_space(4.0);
    egui::Grid::new("texel_errors")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            ui.strong("|ΔV|");
            ui.strong("mean");
            ui.strong("max");
            ui.end_row();
            let (mean, max) = error_text(t.reference_error);
            ui.label(registry::reference().name());
            ui.label(mean);
            ui.label(max);
            ui.end_row();
            for m in &t.methods {
                let (mean, max) = error_text(m.error);
                ui.colored_label(m.model.color, &m.label);
                ui.label(mean);
                ui.label(max);
                ui.end_row();
            }
        });
    if let Some(s) = &curves.stored {
        ui.add_space(4.0);
        ui.strong(format!("{} stores", s.label));
        for line in &s.summary {
            ui.label(egui::RichText::new(line).small());
        }
    }
}

/// `(depth, value)` pairs as plot points (the eye pixel inspector's too).
pub(in crate::app) fn series(depths: &[f32], values: &[f32]) -> PlotPoints<'static> {
    depths
        .iter()
        .zip(values)
        .map(|(&z, &v)| [f64::from(z), f64::from(v)])
        .collect()
}

/// A filled box from `x0` to `x1` between `y0` and `y1`.
fn band(name: &str, [x0, x1]: [f32; 2], (y0, y1): (f64, f64), color: Color32) -> Polygon<'static> {
    let (x0, x1) = (f64::from(x0), f64::from(x1));
    Polygon::new(name, vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
        .fill_color(color.gamma_multiply(0.45))
        .stroke(egui::Stroke::new(1.0, color))
}

fn error_text(e: Option<TexelError>) -> (String, String) {
    match e {
        Some(e) => (format!("{:.5}", e.mean), format!("{:.5}", e.max)),
        None => ("–".into(), "–".into()),
    }
}
