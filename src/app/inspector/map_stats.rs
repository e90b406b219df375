//! The inspector's map statistics: how each plotted method's texel errors spread over the whole light map
//! (`visibility::metrics::map_error` and its `ErrorDistribution`: mean, 50th/95th/99th percentile, worst texel,
//! share of texels above 0.05 and 0.1), computed on demand (a job, `app/jobs.rs`) from the CPU models on the exact fragment lists —
//! the figures `measure` reads through the GPU lookups, for the methods on the plot.

use super::curves::PlotModel;
use super::lists::ReferenceLists;
use crate::app::jobs::{Job, JobGate};
use crate::visibility::{Fragment, MapError, metrics};
use egui::Color32;

/// Samples per texel, as `measure` takes them.
const GRID_POINTS: usize = crate::measure::GRID_POINTS;

/// One method's map error.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodMapError {
    pub label: String,
    pub color: Color32,
    /// `None` when no texel holds fragments.
    pub error: Option<MapError>,
}

/// The map statistics of one set of lists and models.
#[derive(Clone, Debug, PartialEq)]
pub struct MapStats {
    /// [`ReferenceLists::generation`] they were computed from.
    pub generation: u64,
    pub rows: Vec<MethodMapError>,
}

impl MapStats {
    /// Starts computing the map error of each of `models` over `lists` on a worker thread, one method per
    /// step of its progress.
    pub fn start(
        lists: &ReferenceLists,
        models: Vec<PlotModel>,
        ctx: &egui::Context,
        gate: Option<JobGate>,
    ) -> Job<MapStats> {
        let map: Vec<Vec<Fragment>> = lists
            .lists
            .iter()
            .map(|l| l.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect())
            .collect();
        let generation = lists.generation;
        Job::spawn("whole-map statistics", ctx, gate, move |ctl| {
            let mut rows = Vec::with_capacity(models.len());
            for (i, m) in models.iter().enumerate() {
                let label = m.model.label();
                if !ctl.step(&label, i as f32 / models.len() as f32) {
                    return None;
                }
                rows.push(MethodMapError {
                    error: metrics::map_error(m.model.as_ref(), &map, GRID_POINTS),
                    label,
                    color: m.color,
                });
            }
            Some(MapStats { generation, rows })
        })
    }

    /// Whether these statistics are of `models` (by label) on `lists`.
    pub fn is_of(&self, lists: &ReferenceLists, models: &[PlotModel]) -> bool {
        self.generation == lists.generation
            && self.rows.len() == models.len()
            && self
                .rows
                .iter()
                .zip(models)
                .all(|(r, m)| r.label == m.model.label())
    }
}

/// The "Whole map" section: `stats` (when computed for the current lists and plot) and a button to compute
/// them; whether it was clicked.
pub(super) fn section(ui: &mut egui::Ui, stats: Option<&MapStats>) -> bool {
    let mut clicked = false;
    egui::CollapsingHeader::new("Whole map").show(ui, |ui| {
        clicked = ui
            .button("Compute")
            .on_hover_text(
                "texel error (mean |V - V_ref| over each texel's samples) of the plotted methods over every \
                 occupied texel, from their CPU models: mean, percentiles, worst, share above 0.05 and 0.1",
            )
            .clicked();
        match stats {
            Some(stats) => {
                egui::ScrollArea::horizontal().show(ui, |ui| table(ui, stats));
            }
            None => {
                ui.weak("not computed for these fragment lists and methods");
            }
        }
    });
    clicked
}

/// The statistics as a table: one row per method.
fn table(ui: &mut egui::Ui, stats: &MapStats) {
    egui::Grid::new("map_stats").striped(true).show(ui, |ui| {
        for h in ["method", "mean", "p50", "p95", "p99", "worst", ">0.05", ">0.1"] {
            ui.strong(h);
        }
        ui.end_row();
        for r in &stats.rows {
            ui.colored_label(r.color, &r.label);
            match &r.error {
                Some(e) => {
                    let d = &e.distribution;
                    for v in [f64::from(e.mean), d.p50, d.p95, d.p99, d.worst] {
                        ui.label(format!("{v:.4}"));
                    }
                    for s in d.share_over {
                        ui.label(format!("{:.1}%", 100.0 * s));
                    }
                }
                None => {
                    ui.label("no occupied texel");
                }
            }
            ui.end_row();
        }
    });
}
