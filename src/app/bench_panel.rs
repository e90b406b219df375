//! The Bench window: the sweep of `hairlab bench` on the current settings, run on a background thread with its
//! own headless GPU device and cancellable, charted as GPU time (log scale) against map error in egui_plot —
//! one colour per method, the Pareto front connected, the configuration named on hover. Clicking a point (or a
//! configuration in the table) makes it the app's shadow method.

use super::HairlabApp;
use crate::bench::{self, BenchResult, BenchRow, Progress};
use egui_plot::{GridInput, GridMark, HoverPosition, Legend, Line, Plot, PlotPoint, Points};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};

/// Configurations per `measure` call: a cancel takes effect after at most this many.
const CHUNK: usize = 4;
/// How near (points) a click must land to pick a configuration.
const PICK_RADIUS: f32 = 12.0;
/// The series name of the front in the plot.
const FRONT_NAME: &str = "Pareto front";

/// What the worker thread reports.
enum Report {
    Progress(Progress),
    Done(Result<Option<BenchResult>, String>),
}

/// A running sweep; dropping it asks the worker to stop.
struct Job {
    cancel: Arc<AtomicBool>,
    rx: mpsc::Receiver<Report>,
    progress: Option<Progress>,
}

impl Drop for Job {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// State of the Bench window.
pub struct BenchPanel {
    pub open: bool,
    /// Methods to sweep, and whether each is on.
    methods: Vec<(&'static str, bool)>,
    frames: u32,
    job: Option<Job>,
    result: Option<BenchResult>,
    /// Where each row's point was drawn in the last frame (screen points).
    on_screen: Vec<Option<egui::Pos2>>,
}

impl Default for BenchPanel {
    fn default() -> Self {
        BenchPanel {
            open: false,
            methods: bench::SWEEP_METHODS.iter().map(|m| (*m, true)).collect(),
            frames: 3,
            job: None,
            result: None,
            on_screen: Vec::new(),
        }
    }
}

/// Plot x of a GPU time: log10 of the milliseconds; 0 ms (nothing of the method's own to time) sits half a
/// decade left of the fastest timed configuration.
fn plot_x(ms: f64, zero_x: f64) -> f64 {
    if ms > 0.0 { ms.log10() } else { zero_x }
}

/// `10^x` milliseconds as a tick label.
fn ms_label(x: f64) -> String {
    let ms = 10f64.powf(x);
    let decimals = (-x.floor()).max(0.0) as usize;
    format!("{ms:.decimals$} ms")
}

/// Grid lines at 1, 2 and 5 × 10^k ms (the decades stronger), and at the 0 ms column `zero_x` with a gap
/// after it: the logarithmic scale starts a quarter decade to its right.
fn log_grid(input: GridInput, zero_x: f64) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let mut out = Vec::new();
    if (lo..=hi).contains(&zero_x) {
        out.push(GridMark {
            value: zero_x,
            step_size: 1.0,
        });
    }
    for k in lo.floor() as i32..=hi.ceil() as i32 {
        for (m, step) in [(1.0f64, 1.0), (2.0, 0.1), (5.0, 0.1)] {
            let value = k as f64 + m.log10();
            if (lo..=hi).contains(&value) && value > zero_x + 0.25 {
                out.push(GridMark {
                    value,
                    step_size: step,
                });
            }
        }
    }
    out
}

fn row_text(r: &BenchRow) -> String {
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
        bench::ACCURACY_METRIC,
        r.error(),
        r.memory_bytes as f64 / (1024.0 * 1024.0)
    )
}

impl HairlabApp {
    /// The last finished (or cancelled) bench in the window.
    pub fn bench_result(&self) -> Option<&BenchResult> {
        self.bench.result.as_ref()
    }

    /// Whether a sweep is running.
    pub fn bench_running(&self) -> bool {
        self.bench.job.is_some()
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
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = mpsc::channel();
        let worker_cancel = cancel.clone();
        let ctx = ctx.clone();
        std::thread::spawn(move || {
            let progress_tx = tx.clone();
            let progress_ctx = ctx.clone();
            let mut progress = move |p: Progress| {
                let _ = progress_tx.send(Report::Progress(p));
                progress_ctx.request_repaint();
            };
            let result = bench::run(
                &settings,
                "current settings",
                &methods,
                frames,
                CHUNK,
                &worker_cancel,
                &mut progress,
            )
            .map_err(|e| format!("{e:#}"));
            let _ = tx.send(Report::Done(result));
            ctx.request_repaint();
        });
        self.bench.job = Some(Job {
            cancel,
            rx,
            progress: None,
        });
        self.info("bench started");
    }

    /// Takes the worker's reports.
    fn poll_bench(&mut self) {
        let Some(job) = self.bench.job.as_mut() else {
            return;
        };
        let mut done = None;
        loop {
            match job.rx.try_recv() {
                Ok(Report::Progress(p)) => job.progress = Some(p),
                Ok(Report::Done(r)) => {
                    done = Some(r);
                    break;
                }
                Err(mpsc::TryRecvError::Empty) => break,
                Err(mpsc::TryRecvError::Disconnected) => {
                    done = Some(Err("the bench thread stopped without a result".to_string()));
                    break;
                }
            }
        }
        let Some(done) = done else { return };
        self.bench.job = None;
        match done {
            Ok(Some(r)) => {
                let what = if r.cancelled { "cancelled after" } else { "done:" };
                self.info(format!("bench {what} {} configurations measured", r.rows.len()));
                self.bench.on_screen.clear();
                self.bench.result = Some(r);
            }
            Ok(None) => self.info("bench cancelled"),
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
        if self.bench.job.is_some() {
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
             background) and charts GPU time against map error. Click a point to use that configuration.",
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
            if !running {
                if ui.button("Run bench").clicked() {
                    self.start_bench(ctx);
                }
            } else if ui.button("Cancel").clicked()
                && let Some(job) = &self.bench.job
            {
                job.cancel.store(true, Ordering::Relaxed);
                self.info("bench: cancelling after the configurations under way");
            }
            if let Some(p) = self.bench.job.as_ref().and_then(|j| j.progress.as_ref()) {
                let fraction = if p.total > 0 {
                    p.done as f32 / p.total as f32
                } else {
                    0.0
                };
                ui.add(egui::ProgressBar::new(fraction).text(format!(
                    "{}/{} {} · {:.0} s",
                    (p.done + 1).min(p.total.max(1)),
                    p.total,
                    p.label,
                    p.elapsed.as_secs_f64()
                )));
            } else if running {
                ui.spinner();
            }
        });
        let Some(result) = &self.bench.result else { return };
        let s = &result.stats;
        ui.label(format!(
            "{} strands · {} segments · {res}×{res} light map · {} frames · {}{}",
            s.strands,
            s.segments,
            result.frames,
            s.device,
            if result.cancelled { " · cancelled" } else { "" },
            res = s.map_resolution
        ));
        let picked = self.bench_plot(ui);
        let table_pick = self.bench_table(ui);
        if let Some(row) = picked.or(table_pick) {
            self.apply_bench_row(row);
        }
    }

    /// The chart; returns the row whose point was clicked.
    fn bench_plot(&mut self, ui: &mut egui::Ui) -> Option<usize> {
        let result = self.bench.result.as_ref()?;
        let front = result.front();
        let min_ms = result
            .rows
            .iter()
            .map(|r| r.total_ms.median)
            .filter(|ms| *ms > 0.0)
            .fold(f64::INFINITY, f64::min);
        let zero_x = if min_ms.is_finite() {
            min_ms.log10().floor() - 0.5
        } else {
            -1.0
        };
        // Row indices of each method's series, in series order.
        let mut series: Vec<(String, Vec<usize>)> = Vec::new();
        for (i, r) in result.rows.iter().enumerate() {
            match series.iter_mut().find(|(n, _)| *n == r.config.name) {
                Some((_, v)) => v.push(i),
                None => series.push((r.config.name.clone(), vec![i])),
            }
        }
        let point = |i: usize| {
            let r = &result.rows[i];
            [plot_x(r.total_ms.median, zero_x), r.error()]
        };
        let front_color = ui.visuals().strong_text_color();
        let rows = &result.rows;
        let series_ref = &series;
        let front_ref = &front;
        let label = move |pos: &HoverPosition<'_>| -> Option<String> {
            let HoverPosition::NearDataPoint { plot_name, index, .. } = pos else {
                return None;
            };
            let row = if *plot_name == FRONT_NAME {
                front_ref.get(*index).copied()
            } else {
                series_ref
                    .iter()
                    .find(|(n, _)| n == plot_name)
                    .and_then(|(_, v)| v.get(*index).copied())
            }?;
            Some(row_text(&rows[row]))
        };
        let response = Plot::new("bench_plot")
            .height(400.0)
            .legend(Legend::default().follow_insertion_order(true))
            .x_axis_label("GPU ms per frame, method's own light passes (log scale)")
            .y_axis_label(bench::ACCURACY_METRIC)
            .x_grid_spacer(move |input| log_grid(input, zero_x))
            .x_axis_formatter(move |mark, _| {
                if (mark.value - zero_x).abs() < 1e-9 {
                    "0 ms".to_string()
                } else {
                    ms_label(mark.value)
                }
            })
            .label_formatter(label)
            .include_y(0.0)
            .show(ui, |plot_ui| {
                let line: Vec<[f64; 2]> = front.iter().map(|&i| point(i)).collect();
                plot_ui.line(Line::new(FRONT_NAME, line.clone()).color(front_color).width(1.5));
                plot_ui.points(
                    Points::new(FRONT_NAME, line)
                        .color(front_color)
                        .radius(7.0)
                        .filled(false),
                );
                for (name, idx) in &series {
                    let c = bench::method_color(name);
                    plot_ui.points(
                        Points::new(name.clone(), idx.iter().map(|&i| point(i)).collect::<Vec<_>>())
                            .color(egui::Color32::from_rgb(c[0], c[1], c[2]))
                            .radius(4.0)
                            .filled(true),
                    );
                }
            });
        self.bench.on_screen = (0..result.rows.len())
            .map(|i| {
                let [x, y] = point(i);
                let p = response.transform.position_from_point(&PlotPoint::new(x, y));
                response.response.rect.contains(p).then_some(p)
            })
            .collect();
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
                        bench::ACCURACY_METRIC,
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
                        ui.label(format!("{:.5}", r.error()));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_read_in_milliseconds() {
        assert_eq!(ms_label(0.0), "1 ms");
        assert_eq!(ms_label(1.0), "10 ms");
        assert_eq!(ms_label(-1.0), "0.1 ms");
        assert_eq!(ms_label(2f64.log10() - 2.0), "0.02 ms");
    }
}
