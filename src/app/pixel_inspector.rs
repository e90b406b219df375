//! The eye pixel inspector, the eye-space twin of the texel inspector: one pixel of the compare view (click it
//! there) with its exact fragment list (rank, depth, alpha, colour swatch, the exact weight `a Π(1 − a)` in front),
//! every registered technique's composite — its CPU model fed the list over the pixel's background — against the
//! reference's as swatches with |Δ|, the GPU images' colours at the pixel, and the transmittance `Π(1 − a)` along
//! the view ray plotted against depth. Where `occupancy-order` is registered, its estimated order `o` (slab map
//! and occupancy only, `transparency::occupancy_order::estimated_orders`) stands beside the true rank, with
//! `(1 − ᾱ)^o` on the plot and o against rank in a second plot. Once the compare window has decomposed the
//! error against the path-traced truth, a note gives the chain's images at the pixel (`compare_view::truth`).
//!
//! The background is the opaque image's pixel decoded from sRGB8, so composites differ from the GPU's, which
//! blends over the float colour, by that rounding (under 1/255 per channel).

use super::compare_view::CompareFrames;
use super::compare_view::truth::Decomposed;
use super::inspector::series;
use crate::bench::chart::{Axis, Chart, Mark, Point, Scale, Series};
use crate::render::transparency::registry;
use crate::transparency::occupancy_order::estimated_orders;
use crate::transparency::{EyeFragment, metrics::srgb_to_linear};
use crate::visibility::OccupancyVariant;
use egui::Color32;
use egui_plot::{Legend, Line, MarkerShape, Plot, PlotPoints, Points};

/// One technique's composite of the pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Composite {
    pub name: &'static str,
    pub label: &'static str,
    /// Linear RGB.
    pub color: [f32; 3],
    /// Largest channel |Δ| against the reference's composite (linear).
    pub delta: f32,
}

/// The occupancy order estimates of the pixel's fragments (front to back), both variants.
#[derive(Clone, Debug, PartialEq)]
pub struct Orders {
    pub slab_map: Vec<f32>,
    pub occupancy_only: Vec<f32>,
    pub hair_alpha: f32,
}

/// What the inspector shows of one pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct PixelReport {
    pub pixel: [u32; 2],
    /// The exact list, front to back (index = rank).
    pub fragments: Vec<EyeFragment>,
    /// Linear background under the hair.
    pub background: [f32; 3],
    /// `Π(1 − a)` in front of each fragment, then behind the last (`fragments.len() + 1` values).
    pub transmittance: Vec<f32>,
    /// The reference's composite (linear).
    pub reference: [f32; 3],
    /// Every registered technique's, in registry order.
    pub composites: Vec<Composite>,
    /// Each compared image's label and sRGB colour at the pixel.
    pub gpu: Vec<(&'static str, [u8; 3])>,
    pub orders: Option<Orders>,
}

/// The report of `pixel` in `frames`, `None` outside the image.
pub fn report(frames: &CompareFrames, pixel: [u32; 2]) -> Option<PixelReport> {
    let fragments = frames.list(pixel)?.to_vec();
    let [x, y] = pixel;
    let bg = frames.background.get_pixel(x, y).0;
    let background = [0, 1, 2].map(|i| srgb_to_linear(bg[i]) as f32);
    let mut transmittance = Vec::with_capacity(fragments.len() + 1);
    let mut t = 1.0f32;
    transmittance.push(t);
    for f in &fragments {
        t *= 1.0 - f.alpha;
        transmittance.push(t);
    }
    let settings = &frames.settings;
    let defaults = crate::methods::ParamValues::new();
    let composite_of = |t: &dyn crate::render::transparency::EyeTransparency| {
        let params = if t.name() == settings.transparency.name {
            &settings.transparency.params
        } else {
            &defaults
        };
        t.model(params, &frames.model).composite(&fragments, background)
    };
    let reference = composite_of(registry::reference());
    let composites = registry::all()
        .iter()
        .map(|t| {
            let color = composite_of(*t);
            Composite {
                name: t.name(),
                label: t.info().label,
                color,
                delta: (0..3)
                    .map(|i| (color[i] - reference[i]).abs())
                    .fold(0.0, f32::max),
            }
        })
        .collect();
    let gpu = frames
        .images
        .iter()
        .map(|img| {
            let p = img.image.get_pixel(x, y).0;
            (img.label, [p[0], p[1], p[2]])
        })
        .collect();
    // Sintorn & Assarsson's order estimate, the one technique that estimates each fragment's order.
    let orders = Some(Orders {
        slab_map: estimated_orders(OccupancyVariant::SlabMap, &fragments),
        occupancy_only: estimated_orders(OccupancyVariant::OccupancyOnly, &fragments),
        hair_alpha: frames.model.hair_alpha,
    });
    Some(PixelReport {
        pixel,
        fragments,
        background,
        transmittance,
        reference,
        composites,
        gpu,
        orders,
    })
}

/// The pixel and the compare generation a report was made for.
type ReportKey = ([u32; 2], u64);

/// The inspector's state.
#[derive(Default)]
pub struct PixelInspector {
    pub open: bool,
    /// The inspected pixel of the compare images.
    pub pixel: Option<[u32; 2]>,
    /// The report and the (pixel, compare generation) it was made for.
    report: Option<(ReportKey, Option<PixelReport>)>,
    /// The CSV export was asked for ([`PixelInspector::take_export`]).
    export: bool,
}

impl PixelReport {
    /// The transmittance plot as a chart for the image writers (`crate::bench::chart`): the exact `Π(1 − a)`
    /// step per fragment, and the estimated `(1 − ᾱ)^o` of each order variant where the order is estimated.
    pub fn chart(&self) -> Chart {
        let point = |x: f32, y: f32| Point {
            x: f64::from(x),
            y: f64::from(y),
            label: String::new(),
            row: None,
        };
        let mut exact = Vec::with_capacity(2 * self.fragments.len());
        for (k, f) in self.fragments.iter().enumerate() {
            exact.extend([
                point(f.depth, self.transmittance[k]),
                point(f.depth, self.transmittance[k + 1]),
            ]);
        }
        let mut series = vec![Series {
            name: "exact Π(1 − a)".to_string(),
            color: [40, 40, 40],
            mark: Mark::Line,
            points: exact,
        }];
        if let Some(o) = &self.orders {
            for (name, orders, color) in [
                ("(1 − ᾱ)^o slab map", &o.slab_map, [230, 120, 40]),
                ("(1 − ᾱ)^o occupancy only", &o.occupancy_only, [60, 160, 230]),
            ] {
                series.push(Series {
                    name: name.to_string(),
                    color,
                    mark: Mark::Points,
                    points: self
                        .fragments
                        .iter()
                        .zip(orders)
                        .map(|(f, &k)| point(f.depth, (1.0 - o.hair_alpha).powf(k)))
                        .collect(),
                });
            }
        }
        let linear = |label: &str| Axis {
            label: label.to_string(),
            scale: Scale::Linear,
        };
        Chart {
            title: format!(
                "pixel ({}, {}): transmittance along the view ray",
                self.pixel[0], self.pixel[1]
            ),
            notes: vec![format!("{} fragments", self.fragments.len())],
            x: linear("eye depth"),
            y: linear("transmittance"),
            series,
            front: None,
        }
    }

    /// The fragment table as CSV, front to back: `rank,depth,segment,alpha,r,g,b,transmittance,weight` (linear
    /// colour, the transmittance `Π(1 − a)` in front of the fragment, the weight `a·T`), then
    /// `order_slab_map,order_occupancy_only` where the occupancy order is estimated.
    pub fn csv(&self) -> anyhow::Result<String> {
        let mut header = [
            "rank",
            "depth",
            "segment",
            "alpha",
            "r",
            "g",
            "b",
            "transmittance",
            "weight",
        ]
        .map(String::from)
        .to_vec();
        if self.orders.is_some() {
            header.extend(["order_slab_map", "order_occupancy_only"].map(String::from));
        }
        let rows = self.fragments.iter().enumerate().map(|(k, f)| {
            let t = self.transmittance[k];
            let [r, g, b] = f.color;
            let mut row = vec![k.to_string(), f.depth.to_string(), f.segment.to_string()];
            row.extend([f.alpha, r, g, b, t, f.alpha * t].map(|v| v.to_string()));
            if let Some(o) = &self.orders {
                row.extend([o.slab_map[k].to_string(), o.occupancy_only[k].to_string()]);
            }
            row
        });
        crate::io::csv_table("pixel.csv", &header, rows)
    }
}

impl PixelInspector {
    /// Whether the CSV export was asked for since the last call.
    pub fn take_export(&mut self) -> bool {
        std::mem::take(&mut self.export)
    }

    /// Inspects `pixel` and opens the window.
    pub fn select(&mut self, pixel: [u32; 2]) {
        self.pixel = Some(pixel);
        self.open = true;
    }

    /// The report shown (after the window was drawn once for the current pixel).
    pub fn report(&self) -> Option<&PixelReport> {
        self.report.as_ref().and_then(|(_, r)| r.as_ref())
    }

    /// Makes the report again when the pixel or the compare images changed.
    fn refresh(&mut self, frames: Option<&CompareFrames>, generation: u64) {
        let (Some(pixel), Some(frames)) = (self.pixel, frames) else {
            self.report = None;
            return;
        };
        let key = (pixel, generation);
        if self.report.as_ref().is_none_or(|(k, _)| *k != key) {
            self.report = Some((key, report(frames, pixel)));
        }
    }

    /// The window's contents; `truth`: the compare window's last decomposition, whose chain the note reads.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        frames: Option<&CompareFrames>,
        generation: u64,
        truth: Option<&Decomposed>,
    ) {
        self.refresh(frames, generation);
        let Some(frames) = frames else {
            ui.label("open the compare view and render it, then click hair in one of its images");
            return;
        };
        let Some(r) = self.report() else {
            ui.label(format!(
                "click hair in one of the compare view's {}×{} images",
                frames.width, frames.height
            ));
            return;
        };
        ui.strong(format!(
            "pixel ({}, {}) · {} fragments",
            r.pixel[0],
            r.pixel[1],
            r.fragments.len()
        ));
        if r.fragments.is_empty() {
            ui.label("no hair at this pixel: every technique shows the background");
            return;
        }
        composites_ui(ui, r);
        if let Some(t) = truth {
            truth_note(ui, t, r.pixel, (frames.width, frames.height));
        }
        ui.separator();
        let height = 200.0;
        ui.horizontal_top(|ui| {
            let width = if r.orders.is_some() {
                ui.available_width() * 0.62
            } else {
                ui.available_width()
            };
            ui.allocate_ui(egui::vec2(width, height), |ui| transmittance_plot(ui, r, height));
            if let Some(o) = &r.orders {
                order_plot(ui, o, height);
            }
        });
        ui.separator();
        let mut export = false;
        ui.horizontal(|ui| {
            if ui
                .button("Export table and plot…")
                .on_hover_text("pixel.csv (the fragment table) and the transmittance plot as PNG and SVG")
                .clicked()
            {
                export = true;
            }
            if ui
                .button("Copy table")
                .on_hover_text("the fragment table as CSV text")
                .clicked()
            {
                match r.csv() {
                    Ok(text) => ui.ctx().copy_text(text),
                    Err(e) => {
                        ui.colored_label(ui.visuals().error_fg_color, format!("{e:#}"));
                    }
                }
            }
        });
        fragment_table(ui, r);
        self.export |= export;
    }
}

/// A filled colour square of `size` points.
fn swatch(ui: &mut egui::Ui, color: Color32, size: f32) -> egui::Response {
    let (rect, response) = ui.allocate_exact_size(egui::vec2(size, size), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, color);
    ui.painter().rect_stroke(
        rect,
        2.0,
        egui::Stroke::new(1.0, Color32::GRAY),
        egui::StrokeKind::Inside,
    );
    response
}

fn linear(c: [f32; 3]) -> Color32 {
    egui::Rgba::from_rgb(c[0].max(0.0), c[1].max(0.0), c[2].max(0.0)).into()
}

/// The truth chain at the pixel: each stage's linear colour, from the truth to the reference's image.
fn truth_note(ui: &mut egui::Ui, t: &Decomposed, pixel: [u32; 2], size: (u32, u32)) {
    ui.horizontal_wrapped(|ui| {
        ui.label("path-traced chain here:").on_hover_text(
            "the compare window's decomposition against the truth, read at this pixel (docs/truth.md): each \
             image turns one effect of the real-time model on",
        );
        for (label, c) in t.at(pixel, size) {
            swatch(ui, linear(c), 14.0);
            ui.label(format!("{label} ({})", rgb_text(c)));
        }
    });
}

/// Every technique's composite against the reference's, and the GPU images' pixel.
fn composites_ui(ui: &mut egui::Ui, r: &PixelReport) {
    egui::Grid::new("pixel_composites").striped(true).show(ui, |ui| {
        ui.strong("CPU model");
        ui.strong("");
        ui.strong("linear RGB");
        ui.strong("|Δ| vs reference");
        ui.end_row();
        ui.label("background");
        swatch(ui, linear(r.background), 16.0);
        ui.label(rgb_text(r.background));
        ui.label("");
        ui.end_row();
        for c in &r.composites {
            ui.label(c.label);
            swatch(ui, linear(c.color), 16.0).on_hover_text(c.name);
            ui.label(rgb_text(c.color));
            ui.label(format!(
                "{:.5} ({:.1}/255 sRGB)",
                c.delta,
                srgb_steps(c.color, r.reference)
            ));
            ui.end_row();
        }
    });
    ui.horizontal_wrapped(|ui| {
        ui.label("GPU images:");
        for (label, [red, g, b]) in &r.gpu {
            swatch(ui, Color32::from_rgb(*red, *g, *b), 14.0);
            ui.label(format!("{label} ({red}, {g}, {b})"));
        }
    });
}

fn rgb_text(c: [f32; 3]) -> String {
    format!("{:.4}, {:.4}, {:.4}", c[0], c[1], c[2])
}

/// Largest channel difference of two linear colours after sRGB encoding, in 1/255 steps.
fn srgb_steps(a: [f32; 3], b: [f32; 3]) -> f32 {
    let (a, b) = (linear(a), linear(b));
    [
        a.r().abs_diff(b.r()),
        a.g().abs_diff(b.g()),
        a.b().abs_diff(b.b()),
    ]
    .into_iter()
    .max()
    .map_or(0.0, f32::from)
}

/// `Π(1 − a)` against depth (a step at each fragment), and `(1 − ᾱ)^o` at each fragment when known.
fn transmittance_plot(ui: &mut egui::Ui, r: &PixelReport, height: f32) {
    let text = ui.visuals().text_color();
    let mut depths = Vec::with_capacity(2 * r.fragments.len());
    let mut values = Vec::with_capacity(2 * r.fragments.len());
    for (k, f) in r.fragments.iter().enumerate() {
        depths.extend([f.depth, f.depth]);
        values.extend([r.transmittance[k], r.transmittance[k + 1]]);
    }
    Plot::new("pixel_transmittance")
        .legend(Legend::default().text_style(egui::TextStyle::Small))
        .height(height)
        .x_axis_label("eye depth")
        .y_axis_label("transmittance")
        .include_y(0.0)
        .include_y(1.05)
        .show(ui, |p| {
            // One step per fragment, never merged into a band.
            p.line(
                Line::new("exact Π(1 − a)", series(&depths, &values))
                    .color(text)
                    .width(2.0)
                    .allow_band(false),
            );
            if let Some(o) = &r.orders {
                let estimate = |orders: &[f32]| -> PlotPoints<'static> {
                    r.fragments
                        .iter()
                        .zip(orders)
                        .map(|(f, &k)| [f64::from(f.depth), f64::from((1.0 - o.hair_alpha).powf(k))])
                        .collect()
                };
                p.points(
                    Points::new("(1 − ᾱ)^o slab map", estimate(&o.slab_map))
                        .shape(MarkerShape::Circle)
                        .radius(3.0)
                        .color(Color32::from_rgb(230, 120, 40)),
                );
                p.points(
                    Points::new("(1 − ᾱ)^o occupancy only", estimate(&o.occupancy_only))
                        .shape(MarkerShape::Diamond)
                        .radius(3.0)
                        .color(Color32::from_rgb(60, 160, 230)),
                );
            }
            let ticks: PlotPoints = r.fragments.iter().map(|f| [f64::from(f.depth), -0.02]).collect();
            p.points(
                Points::new("fragments", ticks)
                    .shape(MarkerShape::Up)
                    .radius(3.0)
                    .color(text),
            );
        });
}

/// Estimated order against the true rank (the diagonal is exact).
fn order_plot(ui: &mut egui::Ui, o: &Orders, height: f32) {
    let n = o.slab_map.len();
    let scatter = |orders: &[f32]| -> PlotPoints<'static> {
        orders
            .iter()
            .enumerate()
            .map(|(rank, &o)| [rank as f64, f64::from(o)])
            .collect()
    };
    Plot::new("pixel_orders")
        .legend(Legend::default().text_style(egui::TextStyle::Small))
        .height(height)
        .x_axis_label("true rank")
        .y_axis_label("estimated o")
        .show(ui, |p| {
            p.line(
                Line::new("o = rank", vec![[0.0, 0.0], [n as f64, n as f64]])
                    .color(Color32::GRAY)
                    .style(egui_plot::LineStyle::dashed_dense()),
            );
            p.points(
                Points::new("slab map", scatter(&o.slab_map))
                    .radius(2.5)
                    .color(Color32::from_rgb(230, 120, 40)),
            );
            p.points(
                Points::new("occupancy only", scatter(&o.occupancy_only))
                    .radius(2.5)
                    .color(Color32::from_rgb(60, 160, 230)),
            );
        });
}

/// The exact list: rank, depth, alpha, colour, exact weight (and the order estimates when known).
fn fragment_table(ui: &mut egui::Ui, r: &PixelReport) {
    egui::ScrollArea::vertical()
        .id_salt("pixel_fragments")
        .max_height(220.0)
        .show(ui, |ui| {
            egui::Grid::new("pixel_fragment_grid")
                .striped(true)
                .show(ui, |ui| {
                    for h in ["rank", "depth", "alpha", "colour", "segment", "weight a·T"] {
                        ui.strong(h);
                    }
                    if r.orders.is_some() {
                        ui.strong("o slab map");
                        ui.strong("o occupancy only");
                    }
                    ui.end_row();
                    for (k, f) in r.fragments.iter().enumerate() {
                        ui.label(k.to_string());
                        ui.label(format!("{:.5}", f.depth));
                        ui.label(format!("{:.3}", f.alpha));
                        swatch(ui, linear(f.color), 14.0).on_hover_text(rgb_text(f.color));
                        ui.label(f.segment.to_string());
                        ui.label(format!("{:.4}", f.alpha * r.transmittance[k]));
                        if let Some(o) = &r.orders {
                            ui.label(format!("{:.2}", o.slab_map[k]));
                            ui.label(format!("{:.2}", o.occupancy_only[k]));
                        }
                        ui.end_row();
                    }
                });
        });
}
