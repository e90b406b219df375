//! The texel inspector: one light-map texel's exact fragments, the reference visibility `V(z)` and the methods'
//! reconstructions of it, with what each method stores drawn on the plot and the texel's error figures; or,
//! with the "V / count" toggle, the hair count `n(z)` of the reference and of each method (`count_plot`).
//!
//! A texel is chosen by clicking hair in the viewport (`scene::pick`), by clicking the light-map view
//! (`lightmap_view.rs`), or made up in the synthetic texel lab (`texel_lab.rs`). Texels can be pinned for
//! comparison, and every curve shown exported as CSV; the plotted methods' error over the whole map (its
//! distribution over the texels) is computed on demand. Parts: the fragment-list cache (`lists`), the curves
//! (`curves`), their drawing (`plot`), the whole-map statistics (`map_stats`), the ray-traced `V(z)` of the fibres
//! beside the depth-peeled reference and the `α` that fits it over the map (`traced`) and the CSV export (`csv`);
//! [`Inspector::ui`] draws the window from its own state and the [`InspectorDeps`] it is given.

mod chart;
mod count_plot;
mod csv;
mod curves;
mod lists;
mod map_stats;
mod plot;
mod traced;

pub use chart::{PlotKind, REFERENCE_COLOR};
pub use csv::export;
pub use curves::{
    MethodCurve, PlotModel, TexelCurves, TexelPlot, TracedCurve, inspected, method_color, plot_range,
};
pub use lists::{ListsKey, ReferenceLists, read_reference_lists};
pub use map_stats::{MapStats, MethodMapError};
pub(super) use plot::series;
pub use traced::{AlphaFit, FIT_RAYS, FibreScene, TRACED_COLOR, TRACED_RAYS, TracedRays, traced_label};

use super::jobs::{Job, JobGate, JobStatus, Poll};
use super::texel_lab::LabSettings;
use crate::methods::registry;
use crate::render::passes::abuffer::RefFragment;
use crate::scene::pick::Pick;
use crate::settings::Settings;
use crate::visibility::Fragment;
use curves::{CurvesInput, TexelInput, compute_curves};
use egui::Color32;
use lists::ListsCache;

/// Colours of pinned texels, in turn.
const PIN_COLORS: [Color32; 6] = [
    Color32::from_rgb(0, 200, 210),
    Color32::from_rgb(240, 200, 40),
    Color32::from_rgb(255, 120, 180),
    Color32::from_rgb(150, 220, 90),
    Color32::from_rgb(160, 160, 255),
    Color32::from_rgb(255, 160, 90),
];

/// Where the inspected fragments come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Source {
    /// A texel of the scene's light map.
    #[default]
    Scene,
    /// The synthetic texel lab.
    Synthetic,
}

/// A texel of the scene's light map and, when it was picked in the viewport, what was clicked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneTexel {
    pub texel: [u32; 2],
    pub picked: Option<Pick>,
}

/// A texel kept on the plot for comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Pin {
    pub label: String,
    pub color: Color32,
    source: PinSource,
}

impl Pin {
    /// The texel of a scene pin.
    pub fn texel(&self) -> Option<[u32; 2]> {
        match self.source {
            PinSource::Scene(t) => Some(t),
            PinSource::Synthetic { .. } => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum PinSource {
    /// A scene texel: its fragments follow the scene and the light.
    Scene([u32; 2]),
    /// A synthetic texel, frozen when pinned.
    Synthetic {
        fragments: Vec<Fragment>,
        hair_alpha: f32,
    },
}

/// What the inspector window reads besides its own state.
#[derive(Clone, Copy)]
pub struct InspectorDeps<'a> {
    /// The selected method and the map resolution.
    pub settings: &'a Settings,
    /// The light-map window is shown (else the window offers to open it).
    pub light_map_open: bool,
}

/// What the inspector window asks of the app.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InspectorAction {
    /// Choose a file and export the curves as CSV.
    ExportCsv,
    /// Write the plot (and the count plot when shown) as PNG and SVG into a folder.
    ExportPlot,
    /// Copy the plot shown to the clipboard as an image.
    CopyPlot,
    /// Show the light-map window.
    OpenLightMap,
    /// Follow the picked hair point over the motion (the time view).
    TimeView,
    /// Compute the whole-map statistics (a job).
    ComputeMapStats,
    /// Fit `α` to the ray-traced fibres over the whole map (a job, [`Inspector::start_alpha_fit`]).
    FitAlpha,
    /// Make the fitted `α` ([`Inspector::alpha_fit`]) the scene's `hair_alpha`.
    ApplyFittedAlpha,
}

/// The inspector's state (the window's contents, the cached fragment lists and curves).
#[derive(Default)]
pub struct Inspector {
    /// The inspector window is shown.
    pub open: bool,
    pub source: Source,
    /// The inspected scene texel.
    pub selected: Option<SceneTexel>,
    /// Plot every method with a CPU model, not only the selected one.
    pub show_all: bool,
    /// Plot the hair count `n(z)` in place of `V(z)`.
    pub show_count: bool,
    pub lab: LabSettings,
    pins: Vec<Pin>,
    pins_made: usize,
    lists: ListsCache,
    curves: Option<(CurvesInput, TexelCurves)>,
    lab_error: Option<String>,
    map_stats: Option<MapStats>,
    map_stats_job: Option<Job<MapStats>>,
    traced: traced::Traced,
    fit: traced::Fit,
}

impl Inspector {
    /// The curves of the last frame (or of the last export).
    pub fn curves(&self) -> Option<&TexelCurves> {
        self.curves.as_ref().map(|(_, c)| c)
    }

    pub fn pins(&self) -> &[Pin] {
        &self.pins
    }

    pub fn remove_pin(&mut self, index: usize) {
        if index < self.pins.len() {
            self.pins.remove(index);
        }
    }

    /// The plotted methods' error over the whole map, when computed for the current lists and plot.
    pub fn map_stats(&self) -> Option<&MapStats> {
        let (lists, models) = (self.lists()?, self.plotted_models());
        self.map_stats.as_ref().filter(|s| s.is_of(lists, &models))
    }

    /// Starts computing [`Inspector::map_stats`] (the CPU models of the plotted methods over every texel of the
    /// lists) as a job, replacing one under way; `false` when there are no lists or no method on the plot.
    pub fn compute_map_stats(&mut self, ctx: &egui::Context, gate: Option<JobGate>) -> bool {
        let models = self.plotted_models();
        match self.lists() {
            Some(lists) if !models.is_empty() => {
                self.map_stats_job = Some(MapStats::start(lists, models, ctx, gate));
                true
            }
            _ => false,
        }
    }

    /// Takes the whole-map statistics when their job finished, waiting up to `patience`; what happened, for the
    /// status line, when the job ended.
    pub fn poll_map_stats(&mut self, patience: std::time::Duration) -> Option<String> {
        let job = self.map_stats_job.as_ref()?;
        match job.wait(patience) {
            Poll::Running => None,
            Poll::Done(stats) => {
                self.map_stats_job = None;
                self.map_stats = Some(stats);
                Some("whole-map statistics computed".to_string())
            }
            Poll::Gone => {
                let cancelled = job.cancelled();
                self.map_stats_job = None;
                Some(if cancelled {
                    "whole-map statistics cancelled".to_string()
                } else {
                    "whole-map statistics: the worker stopped without a result".to_string()
                })
            }
        }
    }

    /// The inspector's jobs under way: the whole-map statistics, the ray-traced curves, the `α` fit.
    pub fn job_status(&self) -> Vec<JobStatus> {
        let stats = self.map_stats_job.as_ref().map(Job::status);
        stats
            .into_iter()
            .chain(self.traced.status())
            .chain(self.fit.status())
            .collect()
    }

    /// Traces the rays of the inspected scene texel and the scene pins not traced yet for `fibres` (a job, one
    /// at a time; not while `allow` is false, i.e. during a drag) and takes a finished batch. Nothing under a
    /// spot light or while the window is closed.
    pub fn update_traced(
        &mut self,
        fibres: Option<FibreScene<'_>>,
        settings: &Settings,
        allow: bool,
        ctx: &egui::Context,
        gate: Option<JobGate>,
    ) {
        let wanted: Vec<[u32; 2]> = self
            .scene_texel()
            .into_iter()
            .chain(self.pins.iter().filter_map(Pin::texel))
            .collect();
        let fibres = fibres.filter(|_| self.open);
        self.traced.update(fibres, settings, &wanted, allow, ctx, gate);
    }

    /// Takes the ray-traced texels when their job finished, waiting up to `patience`.
    pub fn poll_traced(&mut self, patience: std::time::Duration) {
        self.traced.poll(patience);
    }

    /// The ray-traced rays of scene texel `texel`, when traced for the current scene, light and width.
    pub fn traced(&self, texel: [u32; 2]) -> Option<std::sync::Arc<TracedRays>> {
        self.traced.get(texel)
    }

    /// Starts fitting `α` to the ray-traced fibres over the whole map of `settings` on `gpu` (a job,
    /// `measure::fibre_visibility::compare_map` at [`FIT_RAYS`]² rays a texel), replacing a fit under way.
    pub fn start_alpha_fit(
        &mut self,
        gpu: crate::gpu::Gpu,
        settings: &Settings,
        ctx: &egui::Context,
        gate: Option<JobGate>,
    ) {
        self.fit.start(gpu, settings, ctx, gate);
    }

    /// Takes the `α` fit when its job finished, waiting up to `patience`: the status line's message when it ended.
    pub fn poll_alpha_fit(&mut self, patience: std::time::Duration) -> Option<Result<String, String>> {
        self.fit.poll(patience)
    }

    /// The last `α` fit, when it is of the scene, light and map of `settings`.
    pub fn alpha_fit(&self, settings: &Settings) -> Option<&AlphaFit> {
        self.fit.fit.as_ref().filter(|f| f.is_of(settings))
    }

    /// The models of the methods on the plot.
    fn plotted_models(&self) -> Vec<curves::PlotModel> {
        self.curves()
            .and_then(|c| c.current.as_ref())
            .map(|t| t.methods.iter().map(|m| m.model.clone()).collect())
            .unwrap_or_default()
    }

    /// The cached reference lists, if read.
    pub fn lists(&self) -> Option<&ReferenceLists> {
        self.lists.lists.as_ref()
    }

    /// The cached reference lists when they were read for `key` (the current settings).
    pub fn current_lists(&self, key: &ListsKey) -> Option<&ReferenceLists> {
        self.lists.current(key)
    }

    /// Pins the inspected texel (a scene texel, or the lab's fragments as they are now).
    pub fn pin_current(&mut self) {
        let source = match self.source {
            Source::Scene => match self.selected {
                Some(s) => PinSource::Scene(s.texel),
                None => return,
            },
            Source::Synthetic => match self.lab.fragments() {
                Ok(fragments) => PinSource::Synthetic {
                    hair_alpha: self.lab.hair_alpha(&fragments),
                    fragments,
                },
                Err(_) => return,
            },
        };
        if self.pins.iter().any(|p| p.source == source) {
            return;
        }
        let label = match &source {
            PinSource::Scene([x, y]) => format!("texel ({x}, {y})"),
            PinSource::Synthetic { .. } => self.lab.label(),
        };
        let color = PIN_COLORS[self.pins_made % PIN_COLORS.len()];
        self.pins_made += 1;
        self.pins.push(Pin { label, color, source });
    }

    /// Inspects scene texel `texel` (opens the window).
    pub fn select(&mut self, texel: SceneTexel) {
        self.selected = Some(texel);
        self.source = Source::Scene;
        self.open = true;
    }

    /// The inspected scene texel, while the inspector shows the scene's texel.
    pub fn scene_texel(&self) -> Option<[u32; 2]> {
        self.selected
            .filter(|_| self.source == Source::Scene)
            .map(|s| s.texel)
    }

    /// The point picked in the viewport, while the window is open on its texel.
    pub fn shown_pick(&self) -> Option<Pick> {
        match (self.open, self.source, self.selected) {
            (true, Source::Scene, Some(SceneTexel { picked, .. })) => picked,
            _ => None,
        }
    }

    /// The scene pins' texels and colours.
    pub fn pinned_texels(&self) -> Vec<([u32; 2], Color32)> {
        self.pins
            .iter()
            .filter_map(|p| p.texel().map(|t| (t, p.color)))
            .collect()
    }

    /// Whether the window needs the scene's fragment lists this frame.
    pub fn needs_lists(&self) -> bool {
        self.open
            && (self.source == Source::Scene
                || self.pins.iter().any(|p| matches!(p.source, PinSource::Scene(_))))
    }

    /// Reads the reference lists again with `read` when `key` (the current settings) differs from theirs and
    /// `allow` (no drag is under way); a failed read is not retried until the key changes. `Some` when a read was
    /// made: its outcome.
    pub fn refresh_lists(
        &mut self,
        key: ListsKey,
        allow: bool,
        read: impl FnOnce() -> Result<Vec<Vec<RefFragment>>, String>,
    ) -> Option<Result<(), String>> {
        self.lists.refresh(key, allow, read)
    }

    /// Recomputes the curves when their inputs (this state and `settings`' method and hair alpha) changed.
    /// Returns the lab's typed-fragment error when it is new, for the status line.
    pub fn update_curves(&mut self, settings: &Settings) -> Option<String> {
        let lab_error = match self.source {
            Source::Synthetic => self.lab.fragments().err(),
            Source::Scene => None,
        };
        let report = if lab_error != self.lab_error {
            self.lab_error = lab_error;
            self.lab_error.clone()
        } else {
            None
        };
        let input = self.curves_input(settings);
        if !self.curves.as_ref().is_some_and(|(i, _)| *i == input) {
            let curves = compute_curves(&input);
            self.curves = Some((input, curves));
        }
        report
    }

    fn curves_input(&self, settings: &Settings) -> CurvesInput {
        let alpha = settings.render.hair_alpha;
        let scene_fragments = |t: [u32; 2]| self.lists().and_then(|l| l.fragments(t));
        let current = match self.source {
            Source::Scene => self.selected.and_then(|s| {
                Some(TexelInput {
                    label: format!("texel ({}, {})", s.texel[0], s.texel[1]),
                    fragments: scene_fragments(s.texel)?,
                    hair_alpha: alpha,
                    color: None,
                    traced: self.traced.get(s.texel),
                })
            }),
            Source::Synthetic => self.lab.fragments().ok().map(|fragments| TexelInput {
                label: self.lab.label(),
                hair_alpha: self.lab.hair_alpha(&fragments),
                fragments,
                color: None,
                traced: None,
            }),
        };
        // Every pin, so that the plot, the CSV and the list number them alike (a scene pin without fragment
        // lists, or outside the map, is empty).
        let pins = self
            .pins
            .iter()
            .map(|p| {
                let (fragments, hair_alpha, traced) = match &p.source {
                    PinSource::Scene(t) => (
                        scene_fragments(*t).unwrap_or_default(),
                        alpha,
                        self.traced.get(*t),
                    ),
                    PinSource::Synthetic {
                        fragments,
                        hair_alpha,
                    } => (fragments.clone(), *hair_alpha, None),
                };
                TexelInput {
                    label: p.label.clone(),
                    fragments,
                    hair_alpha,
                    color: Some(p.color),
                    traced,
                }
            })
            .collect();
        CurvesInput {
            current,
            pins,
            method: settings.method.name.clone(),
            params: settings.method.params.clone(),
            show_all: self.show_all,
        }
    }

    /// The window's contents: source, lab or scene texel, pins, the plot and its figures (the curves of the last
    /// [`Inspector::update_curves`]). Returns what the window asks of the app.
    pub fn ui(&mut self, ui: &mut egui::Ui, deps: InspectorDeps<'_>) -> Option<InspectorAction> {
        let mut action = None;
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.source, Source::Scene, "Scene texel");
            ui.selectable_value(&mut self.source, Source::Synthetic, "Synthetic texel");
            ui.separator();
            ui.checkbox(&mut self.show_all, "every method")
                .on_hover_text("plot every method with a CPU model (the others at their default parameters)");
            ui.selectable_value(&mut self.show_count, false, "V")
                .on_hover_text("plot the visibility V(z)");
            ui.selectable_value(&mut self.show_count, true, "count").on_hover_text(
                "plot the hair count n(z): strands in front (exact for the reference; occupancy maps count \
                 occupied slots; the others -ln V / b(α) at the scene's hair alpha)",
            );
            if ui
                .button("Pin")
                .on_hover_text("keep this texel's curves on the plot")
                .clicked()
            {
                self.pin_current();
            }
            if ui
                .button("Export CSV…")
                .on_hover_text("depth, reference and every curve shown")
                .clicked()
            {
                action = Some(InspectorAction::ExportCsv);
            }
            if ui
                .button("Export plot…")
                .on_hover_text("the V(z) plot (and the count plot when shown) as PNG and SVG, into a folder")
                .clicked()
            {
                action = Some(InspectorAction::ExportPlot);
            }
            if ui
                .button("Copy plot")
                .on_hover_text("the plot shown, as an image, to the clipboard")
                .clicked()
            {
                action = Some(InspectorAction::CopyPlot);
            }
            if self.shown_pick().is_some()
                && ui
                    .button("Time view")
                    .on_hover_text("the picked hair point's V over the motion's frames, every method against the reference")
                    .clicked()
            {
                action = Some(InspectorAction::TimeView);
            }
        });
        match self.source {
            Source::Scene => {
                if self.scene_source_ui(ui, deps) {
                    action = Some(InspectorAction::OpenLightMap);
                }
                match self.traced_ui(ui, deps) {
                    Some(traced::FitClick::Start) => action = Some(InspectorAction::FitAlpha),
                    Some(traced::FitClick::Apply) => action = Some(InspectorAction::ApplyFittedAlpha),
                    None => {}
                }
            }
            Source::Synthetic => self.lab.ui(ui, self.lab_error.as_deref()),
        }
        let method = registry::find(&deps.settings.method.name).ok();
        if let Some(m) = method.filter(|m| !inspected(*m)) {
            ui.label(format!(
                "{} has no per-texel model: tick \"every method\" to compare the others",
                m.label()
            ));
        }
        self.pins_ui(ui);
        ui.separator();
        // The plot takes the height left, so that resizing the window resizes it.
        let height = ui.available_height().max(220.0);
        let Some((_, curves)) = &self.curves else {
            return action;
        };
        let stats = self.map_stats();
        let scene = self.source == Source::Scene;
        let show_count = self.show_count;
        let mut compute = false;
        ui.horizontal_top(|ui| {
            let side = 250.0;
            let width = (ui.available_width() - side).max(200.0);
            ui.vertical(|ui| {
                ui.set_width(width);
                if show_count {
                    count_plot::plot(ui, curves, height);
                } else {
                    plot::plot(ui, curves, height);
                }
            });
            ui.vertical(|ui| {
                ui.set_width(side - 10.0);
                // As tall as the plot: many methods scroll rather than grow the window.
                if scene {
                    compute = map_stats::section(ui, stats);
                }
                egui::ScrollArea::both().max_height(height).show(ui, |ui| {
                    plot::figures(ui, curves);
                });
            });
        });
        if compute {
            action = Some(InspectorAction::ComputeMapStats);
        }
        action
    }

    /// The scene texel's line and the lists' state; whether "Open light map" was clicked.
    fn scene_source_ui(&self, ui: &mut egui::Ui, deps: InspectorDeps<'_>) -> bool {
        let res = deps.settings.render.light_map_side();
        let mut open_light_map = false;
        ui.horizontal_wrapped(|ui| {
            match self.selected {
                Some(s) if s.texel[0] < res && s.texel[1] < res => {
                    ui.label(format!(
                        "texel ({}, {}) of the {res}² light map",
                        s.texel[0], s.texel[1]
                    ));
                }
                Some(_) => {
                    ui.label(format!(
                        "the selected texel lies outside the {res}² map: pick another"
                    ));
                }
                None => {
                    ui.label("no texel yet: click hair in the viewport, or a texel in the light map");
                }
            }
            if !deps.light_map_open && ui.button("Open light map").clicked() {
                open_light_map = true;
            }
        });
        match self.lists() {
            Some(l) => {
                let fragments: usize = l.lists.iter().map(Vec::len).sum();
                let stale = if self.lists.stale {
                    " (from before the drag; updates on release)"
                } else {
                    ""
                };
                ui.weak(format!("exact fragment lists: {fragments} fragments{stale}"));
            }
            None => {
                ui.weak("no fragment lists (see the status line)");
            }
        }
        open_light_map
    }

    /// The ray-traced curve's state when it is not on the plot, and the `α` fit's row; what the row asks for.
    fn traced_ui(&self, ui: &mut egui::Ui, deps: InspectorDeps<'_>) -> Option<traced::FitClick> {
        let settings = deps.settings;
        if settings.light.kind != crate::scene::LightKind::Directional {
            ui.weak(traced::SPOT_NOTE);
        } else if let Some(t) = self.scene_texel().filter(|t| self.traced.get(*t).is_none()) {
            let inside = t[0] < settings.render.light_map_side() && t[1] < settings.render.light_map_side();
            if inside {
                ui.weak(if self.traced.running() {
                    "ray-traced V(z): tracing the texel's fibres (see the job bar)"
                } else {
                    "ray-traced V(z): not traced yet (it traces once the view settles)"
                });
            }
        }
        traced::fit_row(ui, &self.fit, settings)
    }

    fn pins_ui(&mut self, ui: &mut egui::Ui) {
        if self.pins.is_empty() {
            return;
        }
        ui.separator();
        let mut remove = None;
        ui.horizontal_wrapped(|ui| {
            ui.label("Pinned:");
            for (i, p) in self.pins.iter().enumerate() {
                let (rect, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
                ui.painter().rect_filled(rect, 2.0, p.color);
                ui.label(format!("{} {}", i + 1, p.label));
                if ui.small_button("remove").clicked() {
                    remove = Some(i);
                }
                ui.separator();
            }
        });
        if let Some(i) = remove {
            self.remove_pin(i);
        }
    }
}
