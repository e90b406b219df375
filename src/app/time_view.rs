//! The texel inspector's **time view**, the temporal twin of its `V(z)` plot: the hair point picked in the
//! viewport followed over the motion's frames by its place on its strand (strand and parametric position), each
//! method's visibility at it against the exact reference with its pops marked (`|ΔV − ΔV_ref| > 0.1` from the
//! previous frame), and under it each method's whole-map error per frame as a strip chart. A line marks the
//! timeline's frame; a click on either chart moves the timeline there. The figures are those of
//! `hairlab measure motion --point FIRST:T` (`motion_point.csv`, `motion_frames.csv`): the same
//! [`measure_motion`] runs as a [`Job`] with its own renderer, so the window keeps answering, the job bar shows
//! how far it is, and its Cancel stops it and keeps the previous figures.
//!
//! Readable at twenty configurations: the frame axis spans exactly the frames computed; the legend is a list
//! beside the charts (never over them) whose boxes hide or show a configuration; each method family has its own
//! hue with a shade per configuration; hovering a curve names it.

use super::inspector::method_color;
use super::jobs::{Job, JobGate, JobStatus, Poll};
use crate::gpu::Gpu;
use crate::measure::MethodConfig;
use crate::measure::motion::{MotionConfig, MotionMeasurement, MotionOptions, measure_motion, usual_configs};
use crate::measure::temporal::{FollowedPoint, followed_pops};
use crate::methods::registry;
use crate::progress::Outcome;
use crate::scene::Strands;
use crate::settings::Settings;
use egui::Color32;
use egui_plot::{HoverPosition, Line, MarkerShape, Plot, PlotPoints, Points, VLine};
use std::collections::BTreeSet;

/// Frames measured when the view opens, at most (the motion's own count when shorter).
const DEFAULT_FRAMES: u32 = 12;

/// What the view asks of the app.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeViewAction {
    /// Measure the followed point over the chosen frames.
    Run,
    /// Move the timeline to this frame.
    Seek(u32),
}

/// The time view's state.
#[derive(Default)]
pub struct TimeView {
    pub open: bool,
    point: Option<FollowedPoint>,
    /// The point's strand and parametric position along it.
    place: Option<(usize, f32)>,
    /// Frames `0..frames` are measured.
    frames: u32,
    /// Every method's usual configurations, or only the selected method as set.
    every_method: bool,
    /// The measurement under way (Stop keeps the configurations measured, Cancel drops them): its figures or
    /// the error.
    job: Option<Job<Result<Outcome<MotionMeasurement>, String>>>,
    result: Option<Outcome<MotionMeasurement>>,
    error: Option<String>,
    /// Configurations (labels) the legend's boxes hide.
    hidden: BTreeSet<String>,
    /// Where the last drawing put the charts and the legend.
    layout: Option<TimeViewLayout>,
}

/// Where the time view drew: the visibility chart's x bounds (frames) and data rectangle, and the legend's
/// rectangle (screen points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeViewLayout {
    pub x_bounds: [f64; 2],
    pub plot: egui::Rect,
    pub legend: egui::Rect,
}

impl TimeView {
    /// Follows the point `point` of `strands` over the first frames of a motion of `frame_count` frames.
    pub fn follow(&mut self, point: FollowedPoint, strands: &Strands, frame_count: u32) {
        self.cancel();
        self.open = true;
        self.point = Some(point);
        self.place = point.on_strand(strands);
        self.frames = frame_count.clamp(2, DEFAULT_FRAMES);
        if self.result.is_none() && self.error.is_none() {
            self.every_method = true;
        }
    }

    /// The point followed.
    pub fn point(&self) -> Option<FollowedPoint> {
        self.point
    }

    /// The last measurement, run to its end or stopped (with the configurations it kept).
    pub fn result(&self) -> Option<&Outcome<MotionMeasurement>> {
        self.result.as_ref()
    }

    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// The measurement under way, as the job bar shows it.
    pub fn job_status(&self) -> Option<JobStatus> {
        self.job.as_ref().map(Job::status)
    }

    /// The configurations measured: every method's usual ones, or the selected method as `settings` set it.
    fn configs(&self, settings: &Settings) -> Vec<MotionConfig> {
        if self.every_method {
            return usual_configs();
        }
        let m = &settings.method;
        vec![MotionConfig::fixed(MethodConfig::new(
            m.name.clone(),
            m.params.clone(),
        ))]
    }

    /// Starts measuring the followed point over frames `0..frames` of `settings`' motion on `gpu` (a job; a
    /// previous run is cancelled). `gate`: the test hook of [`Job::spawn`].
    pub fn start(&mut self, gpu: Gpu, settings: &Settings, ctx: &egui::Context, gate: Option<JobGate>) {
        let Some(point) = self.point else { return };
        self.cancel();
        self.error = None;
        let (settings, configs, frames) = (settings.clone(), self.configs(settings), self.frames);
        self.job = Some(
            Job::spawn("time view", ctx, gate, move |ctl| {
                let options = MotionOptions {
                    follow: Some(point),
                    after_each: None,
                };
                let m = measure_motion(&gpu, &settings, &configs, frames, options, &mut ctl.clone());
                Some(m.map_err(|e| format!("{e:#}")))
            })
            .stoppable(),
        );
    }

    /// Stops the measurement under way; the previous figures stay.
    pub fn cancel(&mut self) {
        self.job = None;
    }

    /// Takes the measurement once it is done: its figures (all, or those kept by Stop) replace the previous ones;
    /// a cancelled run, or one stopped before any configuration finished, leaves them.
    pub fn poll(&mut self) {
        let Some(job) = &self.job else { return };
        match job.poll() {
            Poll::Running => {}
            Poll::Done(result) => {
                self.job = None;
                match result {
                    Ok(m) if m.is_stopped() && m.rows.is_empty() => {
                        self.error =
                            Some("stopped before any configuration finished; the figures before stay".into())
                    }
                    Ok(m) => self.result = Some(m),
                    Err(e) => self.error = Some(e),
                }
            }
            Poll::Gone => {
                if !job.cancelled() {
                    self.error = Some("the measurement stopped without a result".to_string());
                }
                self.job = None;
            }
        }
    }

    /// The window's contents; `frame` is the timeline's frame and `frame_count` the motion's.
    pub fn ui(&mut self, ui: &mut egui::Ui, frame: u32, frame_count: u32) -> Option<TimeViewAction> {
        let mut action = None;
        let Some(point) = self.point else {
            ui.label(
                "Pick a hair point in the viewport (the texel inspector's click), then open the time view.",
            );
            return None;
        };
        match self.place {
            Some((strand, s)) => ui.label(format!(
                "strand {strand} at {:.0} % of its length (segment from point {}, t = {:.2})",
                100.0 * s,
                point.first,
                point.t
            )),
            None => ui.label(format!("segment from point {}, t = {:.2}", point.first, point.t)),
        };
        ui.horizontal(|ui| {
            let label = ui.label("frames 0 ..");
            ui.add(egui::DragValue::new(&mut self.frames).range(2..=frame_count.max(2)))
                .labelled_by(label.id);
            ui.checkbox(&mut self.every_method, "every method")
                .on_hover_text("every method's usual configurations; unticked, the selected method as set");
            let run = ui
                .add_enabled(!self.is_running(), egui::Button::new("Run"))
                .on_disabled_hover_text(
                    "measuring: the job bar under the viewport shows how far, with Stop and Cancel",
                );
            if run.clicked() {
                action = Some(TimeViewAction::Run);
            }
            if let Some(csv) = self.result.as_ref().and_then(|m| m.point_csv().ok().flatten())
                && ui
                    .button("Copy CSV")
                    .on_hover_text("motion_point.csv to the clipboard")
                    .clicked()
            {
                ui.ctx().copy_text(csv);
            }
        });
        if let Some(e) = &self.error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        let Some(m) = &self.result else {
            return action;
        };
        if m.is_stopped() {
            ui.label(format!("stopped: kept {} configurations", m.rows.len()));
        }
        let (seek, layout) = charts(ui, m, frame, &mut self.hidden);
        self.layout = Some(layout);
        action.or(seek.map(TimeViewAction::Seek))
    }

    /// Where the last drawing put the charts and the legend (`None` before figures were shown).
    pub fn layout(&self) -> Option<TimeViewLayout> {
        self.layout
    }
}

/// Each configuration's colour: its method family's hue (lightened to [`MIN_LUMINANCE`] where darker), a shade per
/// configuration of the family (the hue first, then lighter).
fn colors(labels: &[String]) -> Vec<Color32> {
    let family = |l: &str| l.split(':').next().unwrap_or(l).to_string();
    labels
        .iter()
        .map(|label| {
            let name = family(label);
            let base = readable(registry::find(&name).map_or(Color32::GRAY, method_color));
            let siblings: Vec<&String> = labels.iter().filter(|l| family(l) == name).collect();
            let k = siblings.iter().position(|l| *l == label).unwrap_or(0);
            if siblings.len() < 2 {
                return base;
            }
            // From the hue itself to a mix 60 % of the way to white: every shade at least as bright as the hue,
            // so none sinks into the dark plot background.
            let t = k as f32 / (siblings.len() - 1) as f32;
            let shade = |c: u8| {
                let c = f32::from(c);
                (c + (255.0 - c) * 0.6 * t).round() as u8
            };
            Color32::from_rgb(shade(base.r()), shade(base.g()), shade(base.b()))
        })
        .collect()
}

/// The least luminance (Rec. 709 weights of the 8-bit channels, 0..1) a curve or legend colour may have on the
/// dark plot: fom's slate (0.24) and dsm's purple (0.30) were hard to read there.
const MIN_LUMINANCE: f32 = 0.45;

fn luminance(c: Color32) -> f32 {
    (0.2126 * f32::from(c.r()) + 0.7152 * f32::from(c.g()) + 0.0722 * f32::from(c.b())) / 255.0
}

/// `c` mixed towards white just enough to reach [`MIN_LUMINANCE`] (unchanged when it does).
fn readable(c: Color32) -> Color32 {
    let l = luminance(c);
    if l >= MIN_LUMINANCE {
        return c;
    }
    let t = (MIN_LUMINANCE - l) / (1.0 - l);
    let mix = |v: u8| (f32::from(v) + (255.0 - f32::from(v)) * t).ceil().min(255.0) as u8;
    Color32::from_rgb(mix(c.r()), mix(c.g()), mix(c.b()))
}

fn frame_series(values: impl Iterator<Item = f64>) -> PlotPoints<'static> {
    values.enumerate().map(|(f, v)| [f as f64, v]).collect()
}

/// Width of the legend list beside the charts.
const LEGEND_WIDTH: f32 = 230.0;

/// The visibility-over-time chart and the whole-map error strip chart, with the legend list beside them; a click
/// on either chart gives its frame.
fn charts(
    ui: &mut egui::Ui,
    m: &MotionMeasurement,
    frame: u32,
    hidden: &mut BTreeSet<String>,
) -> (Option<u32>, TimeViewLayout) {
    let text = ui.visuals().text_color();
    let labels: Vec<String> = m.rows.iter().map(|r| r.config.label()).collect();
    let colors = colors(&labels);
    let last = f64::from(m.frames.max(2) - 1);
    let mut seek = None;
    let mut plot_rect = egui::Rect::NOTHING;
    let mut legend_rect = egui::Rect::NOTHING;
    let mut x_bounds = [0.0, 0.0];
    let height = ui.available_height();
    ui.horizontal_top(|ui| {
        let width = (ui.available_width() - LEGEND_WIDTH - 12.0).max(200.0);
        ui.vertical(|ui| {
            ui.set_width(width);
            let mut clicked = |p: &egui_plot::PlotUi<'_>| {
                if p.response().clicked()
                    && let Some(c) = p.pointer_coordinate()
                {
                    seek = Some(c.x.round().clamp(0.0, last) as u32);
                }
            };
            // The timeline's frame is marked only when it lies among the frames computed.
            let marker = (frame < m.frames)
                .then(|| VLine::new("timeline frame", f64::from(frame)).color(Color32::YELLOW));
            let plot = |id: &str| {
                Plot::new((id.to_string(), m.frames))
                    .width(width)
                    .default_x_bounds(0.0, last)
                    .x_axis_label("frame")
                    // A grid line on every frame, labelled every frame where they fit, else every fifth.
                    .x_grid_spacer(egui_plot::uniform_grid_spacer(|_| [1.0, 5.0, 10.0]))
                    .label_formatter(|pos| {
                        Some(match pos {
                            HoverPosition::NearDataPoint {
                                plot_name, position, ..
                            } if !plot_name.is_empty() => {
                                format!("{plot_name}\nframe {:.0}: {:.3}", position.x, position.y)
                            }
                            HoverPosition::NearDataPoint { position, .. }
                            | HoverPosition::Elsewhere { position } => {
                                format!("frame {:.0}: {:.3}", position.x, position.y)
                            }
                        })
                    })
            };
            let r = plot("time_view_visibility")
                .height((height * 0.62).max(160.0))
                .y_axis_label("V at the point")
                .include_y(0.0)
                .include_y(1.05)
                .show(ui, |p| {
                    if let Some((_, reference)) = &m.followed {
                        p.line(
                            Line::new(
                                registry::reference().name(),
                                frame_series(reference.iter().map(|&v| f64::from(v))),
                            )
                            .color(text)
                            .width(2.0),
                        );
                        for ((r, label), &color) in m.rows.iter().zip(&labels).zip(&colors) {
                            if hidden.contains(label) {
                                continue;
                            }
                            p.line(
                                Line::new(
                                    label.clone(),
                                    frame_series(r.followed.iter().map(|&v| f64::from(v))),
                                )
                                .color(color)
                                .width(1.5),
                            );
                            let pops: PlotPoints = followed_pops(&r.followed, reference)
                                .into_iter()
                                .map(|(f, _)| [f as f64, f64::from(r.followed[f])])
                                .collect();
                            // Unnamed: the pops share their configuration's colour.
                            p.points(
                                Points::new("", pops)
                                    .shape(MarkerShape::Circle)
                                    .filled(false)
                                    .radius(6.0)
                                    .color(color),
                            );
                        }
                    }
                    if let Some(v) = marker.clone() {
                        p.vline(v);
                    }
                    clicked(p);
                });
            plot_rect = *r.transform.frame();
            let b = r.transform.bounds();
            x_bounds = [b.min()[0], b.max()[0]];
            plot("time_view_map_error")
                .height((ui.available_height() - 8.0).max(100.0))
                .y_axis_label("map error")
                .include_y(0.0)
                .show(ui, |p| {
                    for ((r, label), &color) in m.rows.iter().zip(&labels).zip(&colors) {
                        if !hidden.contains(label) {
                            p.line(
                                Line::new(label.clone(), frame_series(r.frames.iter().map(|f| f.map_error)))
                                    .color(color),
                            );
                        }
                    }
                    if let Some(v) = marker {
                        p.vline(v);
                    }
                    clicked(p);
                });
        });
        legend_rect = ui
            .vertical(|ui| {
                ui.set_width(LEGEND_WIDTH);
                egui::ScrollArea::vertical()
                    .id_salt("time_view_legend")
                    .show(ui, |ui| {
                        ui.label(
                            egui::RichText::new(registry::reference().name())
                                .color(text)
                                .strong(),
                        );
                        for (label, &color) in labels.iter().zip(&colors) {
                            let mut shown = !hidden.contains(label);
                            if ui
                                .checkbox(&mut shown, egui::RichText::new(label).color(color).small())
                                .on_hover_text("show or hide this configuration")
                                .changed()
                            {
                                if shown {
                                    hidden.remove(label);
                                } else {
                                    hidden.insert(label.clone());
                                }
                            }
                        }
                    });
            })
            .response
            .rect;
    });
    let layout = TimeViewLayout {
        x_bounds,
        plot: plot_rect,
        legend: legend_rect,
    };
    (seek, layout)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_familys_shades_are_distinct_and_never_darker_than_its_hue() {
        use crate::methods::{LightMethod, occupancy::Occupancy, osm::Osm};
        let (osm, occupancy) = (Osm.name(), Occupancy.name());
        let mut labels: Vec<String> = [16, 64, 256].map(|n| format!("{osm}:slices={n}")).to_vec();
        labels.push(occupancy.to_string());
        let c = colors(&labels);
        let hue = |name| method_color(registry::find(name).unwrap());
        let sum = |c: Color32| u32::from(c.r()) + u32::from(c.g()) + u32::from(c.b());
        assert_eq!(
            c[0],
            readable(hue(osm)),
            "the first configuration has the family's hue"
        );
        assert!(
            sum(c[1]) > sum(c[0]) && sum(c[2]) > sum(c[1]),
            "lighter in turn: {c:?}"
        );
        assert_eq!(c[3], readable(hue(occupancy)), "a family of one keeps its hue");
    }

    #[test]
    fn every_methods_colour_is_bright_enough_for_the_dark_plot() {
        for m in registry::all() {
            let c = readable(method_color(*m));
            assert!(luminance(c) >= MIN_LUMINANCE - 1e-3, "{}: {c:?}", m.name());
        }
        // A bright hue is left alone; a dark one keeps its hue (its channels' order).
        let bright = Color32::from_rgb(255, 200, 0);
        assert_eq!(readable(bright), bright);
        let dark = readable(Color32::from_rgb(0x39, 0x3b, 0x79));
        assert!(dark.b() > dark.g() && dark.g() >= dark.r(), "{dark:?}");
    }
}
