//! The inspector's second plot: the hair count `n(z)` (strands in front of depth `z`, what dual scattering
//! reads, Zinke et al. 2008) of the reference and of each method, beside the `V(z)` plot (the "V / count"
//! toggle). The reference's count is exact; each method's is its `TexelModel::count_curve`.

use super::curves::TexelCurves;
use super::plot::{depth_plot, method_curves, series};
use crate::methods::registry;
use egui_plot::{Line, LineStyle};

/// The count plot: reference, methods, fragments, pins.
pub(super) fn plot(ui: &mut egui::Ui, curves: &TexelCurves, height: f32) {
    let text = ui.visuals().text_color();
    let corner = egui_plot::Corner::LeftTop;
    depth_plot(
        "texel_count_plot",
        "hair count n(z)",
        "n",
        [-0.5, 1.0],
        corner,
        height,
    )
    .show(ui, |p| {
        if let Some(t) = &curves.current {
            p.line(
                Line::new(
                    format!("{} count", registry::reference().name()),
                    series(&t.depths, &t.reference_count),
                )
                .color(text)
                .width(2.0),
            );
            method_curves(p, t, text, " count", |m| &m.counts, -0.2);
        }
        for (i, t) in curves.pins.iter().enumerate() {
            let color = t.color.unwrap_or(text);
            let name = format!("pin {} {}", i + 1, t.label);
            p.line(
                Line::new(
                    format!("{name} reference count"),
                    series(&t.depths, &t.reference_count),
                )
                .color(color),
            );
            for m in &t.methods {
                p.line(
                    Line::new(format!("{name} {} count", m.label), series(&t.depths, &m.counts))
                        .color(color)
                        .style(LineStyle::dashed_dense()),
                );
            }
        }
    });
}
