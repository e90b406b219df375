//! The Bench window: the sweep of `hairlab bench` on the current settings, a job ([`super::jobs`]) with its
//! own headless GPU device (the job bar's Stop keeps the configurations measured, Cancel drops them), charted as
//! GPU time (log scale) against the chosen accuracy metric
//! (map error, a texel-error percentile, the share of bad texels, ...) in egui_plot —
//! the same chart model (`bench::chart`) as the PNG and SVG: one colour per method, the Pareto front connected,
//! the configuration named on hover. Clicking a point (or a configuration in the table) makes it the app's
//! shadow method.

use super::HairlabApp;
use super::jobs::{self, JobStatus, Poll};
use crate::bench::chart::{Chart, Mark};
use crate::bench::{self, BenchOutcome, BenchResult, BenchRow};
use crate::progress::Outcome;
use egui_plot::{GridMark, HoverPosition, Legend, Line, Plot, PlotPoint, Points};

/// Configurations per `measure` call: a stop takes effect after at most this many.
const CHUNK: usize = 4;
/// How near (points) a click must land to pick a configuration.
const PICK_RADIUS: f32 = 12.0;

/// State of the Bench window.
pub struct BenchPanel {
    pub open: bool,
    /// Methods to sweep, and whether each is on.
    methods: Vec<(&'static str, bool)>,
    pub(super) frames: u32,
    job: Option<jobs::Job<Result<BenchOutcome, String>>>,
    /// The last bench run to its end or stopped, with what it kept.
    result: Option<Outcome<BenchResult>>,
    /// Where each row's point was drawn in the last frame (screen points).
    on_screen: Vec<Option<egui::Pos2>>,
    /// **Export report…** under way, and its folder (`report_export.rs`).
    pub(super) report: Option<(jobs::Job<super::report_export::ReportDone>, std::path::PathBuf)>,
}

impl Default for BenchPanel {
    fn default() -> Self {
        BenchPanel {
            open: false,
            methods: bench::sweep_methods().into_iter().map(|m| (m, true)).collect(),
            frames: 3,
            job: None,
            result: None,
            on_screen: Vec::new(),
            report: None,
        }
    }
}

fn row_text(result: &BenchResult, r: &BenchRow) -> String {
    let note = if r.note.is_empty() {
        String::new()
    } else {
        format!(" ({})", r.note)
    };
    format!(
        "{}{note}\nGPU {:.3} ms (min {:.3}, max {:.3})\n{} {:.5}\n{:.2} MiB",
        r.config.label(),
        r.total_ms.median,
        r.total_ms.min,
        r.total_ms.max,
        result.metric,
        result.accuracy(r),
        r.memory_bytes as f64 / (1024.0 * 1024.0)
    )
}

impl HairlabApp {
    /// The last bench in the window, complete or stopped with what it kept (a cancelled one leaves the one
    /// before).
    pub fn bench_result(&self) -> Option<&Outcome<BenchResult>> {
        self.bench.result.as_ref()
    }

    /// Whether a sweep is running.
    pub fn bench_running(&self) -> bool {
        self.bench.job.is_some()
    }

    /// The sweep under way, for the progress bar of every job (`jobs.rs`).
    pub(super) fn bench_status(&self) -> Option<JobStatus> {
        self.bench.job.as_ref().map(jobs::Job::status)
    }

    /// Where the point of result row `row` was drawn in the last frame, in screen points.
    pub fn bench_point_position(&self, row: usize) -> Option<egui::Pos2> {
        self.bench.on_screen.get(row).copied().flatten()
    }

    /// Starts the sweep of the checked methods on a copy of the current settings.
    fn start_bench(&mut self, ctx: &egui::Context) {
        let methods: Vec<&'static str> = self
            .bench
            .methods
            .iter()
            .filter(|(_, on)| *on)
            .map(|(m, _)| *m)
            .collect();
        if methods.is_empty() {
            self.error("bench: check at least one method");
            return;
        }
        let settings = self.settings.clone();
        let frames = self.bench.frames;
        let job = jobs::Job::spawn("bench", ctx, self.job_gate.clone(), move |ctl| {
            let result = bench::run(
                &settings,
                "current settings",
                &methods,
                frames,
                CHUNK,
                &mut ctl.clone(),
            );
            Some(result.map_err(|e| format!("{e:#}")))
        })
        .stoppable();
        self.bench.job = Some(job);
        self.info("bench started");
    }

    /// Takes the sweep's result once it is done.
    fn poll_bench(&mut self) {
        let Some(job) = self.bench.job.as_ref() else {
            return;
        };
        let done = match job.poll() {
            Poll::Running => return,
            Poll::Done(r) => r,
            Poll::Gone => {
                self.bench.job = None;
                self.info("bench cancelled");
                return;
            }
        };
        self.bench.job = None;
        match done.map(|o| (o.is_stopped(), o.kept())) {
            Ok((stopped, Some(r))) => {
                let what = if stopped { "stopped: kept" } else { "done:" };
                self.info(format!("bench {what} {} configurations measured", r.rows.len()));
                self.bench.on_screen.clear();
                self.bench.result = Some(Outcome::new(r, stopped));
            }
            Ok((_, None)) => self.info("bench stopped before any configuration finished"),
            Err(e) => self.error(format!("bench: {e}")),
        }
    }

    /// Makes a measured configuration the app's shadow method.
    fn apply_bench_row(&mut self, row: usize) {
        let Some(r) = self.bench.result.as_ref().and_then(|res| res.rows.get(row)) else {
            return;
        };
        let (name, params, label) = (r.config.name.clone(), r.config.params.clone(), r.config.label());
        self.settings.method.name = name;
        self.settings.method.params = params;
        self.info(format!("bench: applied {label}"));
    }

    /// The Bench window, when open.
    pub(super) fn bench_window(&mut self, ctx: &egui::Context) {
        self.poll_bench();
        self.poll_report_export();
        if self.bench.job.is_some() || self.bench.report.is_some() {
            ctx.request_repaint_after(std::time::Duration::from_millis(250));
        }
        let mut open = self.bench.open;
        egui::Window::new("Bench")
            .open(&mut open)
            .default_pos([340.0, 30.0])
            .default_size([760.0, 640.0])
            .show(ctx, |ui| self.bench_ui(ui, ctx));
        self.bench.open = open;
    }

    fn bench_ui(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        ui.label(
            "Sweeps each method's parameters on the current scene and settings (on its own GPU device, in the \
             background) and charts GPU time against an accuracy metric (map error unless chosen otherwise). Click a point to use that \
             configuration.",
        );
        let running = self.bench.job.is_some();
        ui.add_enabled_ui(!running, |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.label("methods:");
                for (name, on) in &mut self.bench.methods {
                    ui.checkbox(on, *name);
                }
            });
            ui.horizontal(|ui| {
                let l = ui.label("timed frames");
                ui.add(egui::DragValue::new(&mut self.bench.frames).range(1..=100))
                    .labelled_by(l.id);
            });
        });
        ui.horizontal(|ui| {
            if !running && ui.button("Run bench").clicked() {
                self.start_bench(ctx);
            }
            // Stop and Cancel are the job bar's.
            if let Some(job) = &self.bench.job {
                let s = job.status();
                ui.add(egui::ProgressBar::new(s.fraction).text(format!(
                    "{} · {:.0} s",
                    s.stage,
                    s.elapsed.as_secs_f64()
                )));
            }
            if !running && self.bench.result.is_some() {
                if ui
                    .button("Export results…")
                    .on_hover_text("results.csv, results.json, speed_vs_accuracy.png and .svg, as `hairlab bench` writes them")
                    .clicked()
                {
                    self.request_export(super::exports::Export::Bench, ctx);
                }
                if ui.button("Copy table").on_hover_text("the rows as CSV text").clicked() {
                    self.copy_bench_table(ctx);
                }
                if ui.button("Copy chart").on_hover_text("the chart as an image").clicked() {
                    self.copy_bench_chart(ctx);
                }
            }
        });
        ui.horizontal(|ui| match &self.bench.report {
            None => {
                if ui
                    .button("Export report…")
                    .on_hover_text(
                        "one HTML page of the current scene, shadow method and transparency technique (and the \
                         motion), as `hairlab report` writes it, into hairlab-report/ of a chosen folder",
                    )
                    .clicked()
                {
                    self.request_export(super::exports::Export::Report, ctx);
                }
            }
            Some((job, _)) => {
                // Stop (keeps the page of what finished) and Cancel (writes none) are the job bar's.
                let status = job.status();
                ui.add(egui::ProgressBar::new(status.fraction).text(format!("report: {}", status.stage)));
            }
        });
        let Some(result) = &mut self.bench.result else {
            return;
        };
        ui.horizontal(|ui| {
            let l = ui.label("accuracy axis");
            egui::ComboBox::from_id_salt("bench_metric")
                .selected_text(result.metric)
                .show_ui(ui, |ui| {
                    for (name, axis) in bench::accuracy_metrics() {
                        ui.selectable_value(&mut result.metric, name, name)
                            .on_hover_text(axis);
                    }
                })
                .response
                .labelled_by(l.id);
        });
        let chart = bench::speed_accuracy_chart(result);
        ui.strong(&chart.title);
        ui.label(chart.notes.join("\n"));
        let picked = self.bench_plot(ui, &chart);
        let table_pick = self.bench_table(ui);
        if let Some(row) = picked.or(table_pick) {
            self.apply_bench_row(row);
        }
    }

    /// `chart` (of the current result) in egui_plot; returns the row whose point was clicked.
    fn bench_plot(&mut self, ui: &mut egui::Ui, chart: &Chart) -> Option<usize> {
        let result = self.bench.result.as_ref()?;
        let rows = &result.rows;
        let front_color = ui.visuals().strong_text_color();
        let front_name = chart.front.as_ref().map(|f| f.name.as_str());
        let xy = |p: &bench::chart::Point| [chart.plot_x(p.x), p.y];
        let label = |pos: &HoverPosition<'_>| -> Option<String> {
            let HoverPosition::NearDataPoint { plot_name, index, .. } = pos else {
                return None;
            };
            let points = match &chart.front {
                Some(f) if f.name == *plot_name => &f.points,
                _ => &chart.series.iter().find(|s| s.name == *plot_name)?.points,
            };
            let row = points.get(*index)?.row?;
            Some(row_text(result, rows.get(row)?))
        };
        let ([x0, x1], [y0, y1]) = chart.bounds();
        let response = Plot::new("bench_plot")
            .height(400.0)
            .legend(Legend::default().follow_insertion_order(true))
            .x_axis_label(chart.x.label.as_str())
            .y_axis_label(chart.y.label.as_str())
            .x_grid_spacer(|input| {
                chart
                    .x_ticks(input.bounds.0, input.bounds.1)
                    .into_iter()
                    .map(|t| GridMark {
                        value: t.at,
                        step_size: if t.label.is_some() { 1.0 } else { 0.1 },
                    })
                    .collect()
            })
            .x_axis_formatter(|mark, range| chart.x_tick_label(mark.value, *range.start(), *range.end()))
            .label_formatter(label)
            .include_x(x0)
            .include_x(x1)
            .include_y(y0)
            .include_y(y1)
            .show(ui, |plot_ui| {
                if let (Some(f), Some(name)) = (&chart.front, front_name) {
                    let line: Vec<[f64; 2]> = f.points.iter().map(xy).collect();
                    plot_ui.line(Line::new(name, line.clone()).color(front_color).width(1.5));
                    plot_ui.points(
                        Points::new(name, line)
                            .color(front_color)
                            .radius(7.0)
                            .filled(false),
                    );
                }
                for s in &chart.series {
                    let pts: Vec<[f64; 2]> = s.points.iter().map(xy).collect();
                    let color = egui::Color32::from_rgb(s.color[0], s.color[1], s.color[2]);
                    match s.mark {
                        Mark::Points => plot_ui.points(
                            Points::new(s.name.as_str(), pts)
                                .color(color)
                                .radius(4.0)
                                .filled(true),
                        ),
                        Mark::Line => plot_ui.line(Line::new(s.name.as_str(), pts).color(color).width(1.5)),
                    }
                }
            });
        let mut on_screen = vec![None; rows.len()];
        for p in chart.series.iter().flat_map(|s| &s.points) {
            if let Some(slot) = p.row.and_then(|r| on_screen.get_mut(r)) {
                let [x, y] = xy(p);
                let at = response.transform.position_from_point(&PlotPoint::new(x, y));
                *slot = response.response.rect.contains(at).then_some(at);
            }
        }
        self.bench.on_screen = on_screen;
        if !response.response.clicked() {
            return None;
        }
        let at = response.response.interact_pointer_pos()?;
        self.bench
            .on_screen
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.map(|p| (i, p.distance(at))))
            .filter(|(_, d)| *d <= PICK_RADIUS)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }

    /// Every configuration as a row; returns the one whose button was clicked.
    fn bench_table(&self, ui: &mut egui::Ui) -> Option<usize> {
        let result = self.bench.result.as_ref()?;
        let front = result.front();
        let mut picked = None;
        egui::CollapsingHeader::new("Table").show(ui, |ui| {
            egui::ScrollArea::vertical().max_height(220.0).show(ui, |ui| {
                egui::Grid::new("bench_table").striped(true).show(ui, |ui| {
                    for h in [
                        "configuration",
                        "GPU ms",
                        "min..max",
                        result.metric,
                        "MiB",
                        "front",
                    ] {
                        ui.strong(h);
                    }
                    ui.end_row();
                    for (i, r) in result.rows.iter().enumerate() {
                        if ui
                            .button(r.config.label())
                            .on_hover_text(if r.note.is_empty() {
                                "use this configuration"
                            } else {
                                &r.note
                            })
                            .clicked()
                        {
                            picked = Some(i);
                        }
                        ui.label(format!("{:.3}", r.total_ms.median));
                        ui.label(format!("{:.3}..{:.3}", r.total_ms.min, r.total_ms.max));
                        ui.label(format!("{:.5}", result.accuracy(r)));
                        ui.label(format!("{:.2}", r.memory_bytes as f64 / (1024.0 * 1024.0)));
                        ui.label(if front.contains(&i) { "●" } else { "" });
                        ui.end_row();
                    }
                });
            });
        });
        picked
    }
}
