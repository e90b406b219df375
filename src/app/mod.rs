//! The workbench window: an eframe app with the wgpu viewport in the centre, parameter panels on the left and a
//! status line at the bottom. Settings persist between runs; presets load and save the same struct.

mod about;
mod bench_panel;
pub mod compare_view;
mod dialogs;
pub mod export_animation;
mod exports;
mod fur_panel;
pub mod inspector;
pub mod jobs;
mod lightmap_view;
mod motion_bound;
mod panels;
pub mod path_view;
pub mod pixel_inspector;
mod report_export;
mod scene_jobs;
mod shader_watch;
pub mod texel_lab;
pub mod time_view;
pub mod timeline;
mod transparency_panel;
mod undo;
mod viewport;
mod windows;

use crate::gpu::timing::{PassTime, Phase, phase_ms};
use crate::gpu::{self, AdapterPreference};
use crate::measure::temporal::FollowedPoint;
use crate::methods::registry;
use crate::render::Renderer;
use crate::scene::Scene;
use crate::settings::SceneSettings;
use crate::settings::Settings;
use inspector::{Inspector, InspectorAction, InspectorDeps, ListsKey, SceneTexel};
use jobs::{Job, JobGate, JobStatus, PATIENCE, Poll};
use lightmap_view::{LightMapDeps, LightMapView};
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

const SETTINGS_KEY: &str = "hairlab.settings";

/// The wgpu setup hairlab asks eframe (and the UI tests) for: the adapter policy and the features its passes need.
pub fn wgpu_setup(pref: AdapterPreference) -> egui_wgpu::WgpuSetup {
    let mut setup = egui_wgpu::WgpuSetupCreateNew::without_display_handle();
    setup.instance_descriptor.backends = gpu::backends();
    setup.native_adapter_selector = Some(Arc::new(move |adapters, _surface| {
        gpu::select_adapter(adapters, AdapterPreference::from_env_or(pref)).map_err(|e| e.to_string())
    }));
    setup.device_descriptor = Arc::new(|adapter| {
        let mut d = gpu::device_descriptor(adapter);
        d.required_limits.max_texture_dimension_2d = d.required_limits.max_texture_dimension_2d.max(8192);
        d
    });
    egui_wgpu::WgpuSetup::CreateNew(setup)
}

/// Window options: wgpu renderer with [`wgpu_setup`].
pub fn native_options() -> eframe::NativeOptions {
    eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default()
            .with_title("hairlab")
            .with_inner_size([1280.0, 800.0]),
        wgpu_options: egui_wgpu::WgpuConfiguration {
            wgpu_setup: wgpu_setup(AdapterPreference::Hardware),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// What a pending file dialog is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DialogPurpose {
    OpenScene,
    SaveScreenshot,
    LoadPreset,
    SavePreset,
    ExportCurves,
    /// A window's results into a folder (`exports.rs`).
    Export(exports::Export),
}

/// A scene being built (`open_motion`) on a worker thread: what it builds and, when done, the scene and its
/// motion with the time taken (ms), or the error.
struct SceneJob {
    job: Job<Result<(Scene, crate::motion::Motion, f64), String>>,
    scene: SceneSettings,
    motion: crate::motion::MotionSettings,
}

/// A method's analysis on a worker thread: the method, the analysis' label, and its job.
struct AnalysisJob {
    method: &'static str,
    label: &'static str,
    job: Job<crate::methods::AnalysisResult>,
}

/// A message for the status line.
#[derive(Clone, Debug)]
struct Message {
    text: String,
    error: bool,
}

pub struct HairlabApp {
    settings: Settings,
    render_state: Option<egui_wgpu::RenderState>,
    renderer: Option<Renderer>,
    scene: Option<Scene>,
    /// Settings of the scene currently loaded (to notice when it must be rebuilt).
    built_scene: Option<SceneSettings>,
    /// The viewport texture registered with egui, and the renderer's target generation it shows.
    texture: Option<(egui::TextureId, u64)>,
    last_rendered: Option<(Settings, u32, u32)>,
    /// Whether the last frame was drawn while its path-traced probe baked (`Renderer::probe_pending`): drawn
    /// again once it is kept.
    probe_baking: bool,
    adapter: String,
    message: Option<Message>,
    dialog: Option<(DialogPurpose, mpsc::Receiver<Option<PathBuf>>)>,
    screenshot_request: Option<PathBuf>,
    frame_ms: VecDeque<f64>,
    /// CPU milliseconds of the last motion frame the timeline produced (the simulation's steps to it, or reading a
    /// recorded frame), shown in the status line while the scene moves.
    motion_ms: Option<f64>,
    pass_times: Vec<PassTime>,
    continuous: bool,
    last_frame: Option<Instant>,
    /// The last on-demand method analysis: the method's name and what it found.
    analysis: Option<(&'static str, crate::methods::AnalysisResult)>,
    /// Why the last frame could not be rendered (shown in place of the image).
    viewport_error: Option<String>,
    /// Hides measured times (they differ run to run) so UI snapshots are reproducible.
    snapshot_mode: bool,
    /// The texel inspector window.
    inspector: Inspector,
    /// The light-map window.
    light_map: LightMapView,
    /// Where the viewport is (the inspector windows' first placement).
    viewport_rect: Option<egui::Rect>,
    /// The Bench window: speed against accuracy of every method's sweep.
    bench: bench_panel::BenchPanel,
    /// The eye transparency compare window (four techniques, their difference and metrics).
    compare: compare_view::CompareView,
    /// The eye pixel inspector window.
    pixel_inspector: pixel_inspector::PixelInspector,
    /// The scene's fur and the settings it was built with (`fur_panel.rs`).
    fur: Option<crate::fur::settings::FurScene>,
    built_fur: Option<crate::fur::settings::FurSettings>,
    /// How long the scene took to build (Table 1 row 3).
    scene_ms: f64,
    /// Undo and redo of settings changes (`undo.rs`).
    undoer: egui::util::undoer::Undoer<Settings>,
    /// Whether the Help window (shortcuts) is open.
    help_open: bool,
    /// Whether the About window (version, adapter, citations) is open (`about.rs`).
    about_open: bool,
    /// The scene's motion and its playback (`timeline.rs`).
    timeline: timeline::Timeline,
    /// The viewport path-traced under `render.mode = path` (`path_view.rs`).
    path_view: path_view::PathView,
    /// The picked hair point followed over the motion (`time_view.rs`).
    time_view: time_view::TimeView,
    /// The motion exported as a PNG sequence or a GIF (`export_animation.rs`).
    animation_export: export_animation::AnimationExport,
    /// The whole motion's box for `light.fit = bound` or `stable`, found on a worker (`motion_bound.rs`).
    motion_bound: motion_bound::MotionBound,
    /// The context the jobs' workers wake when they report (`jobs.rs`).
    egui_ctx: egui::Context,
    /// The scene being built, and the analysis being run, off the UI thread.
    scene_job: Option<SceneJob>,
    analysis_job: Option<AnalysisJob>,
    /// Jobs started while this is set wait for it to open (a test hook).
    job_gate: Option<JobGate>,
    /// When the input settled (`jobs::Settle`), and whether it has this frame.
    settle: jobs::Settle,
    settled: bool,
    /// The `--shaders` folder polled for changes (`shader_watch.rs`).
    shaders: Option<crate::live_shaders::Watch>,
    /// Where exports go without a dialog (`exports.rs`).
    export_dir: Option<PathBuf>,
}

impl HairlabApp {
    /// Starts with `settings`, or the persisted settings when `settings` is `None`.
    pub fn new(cc: &eframe::CreationContext<'_>, settings: Option<Settings>) -> HairlabApp {
        let mut message = None;
        let persisted: Option<Settings> = cc.storage.and_then(|s| eframe::get_value(s, SETTINGS_KEY));
        let settings = settings
            .or_else(|| persisted.filter(|s| s.validate().is_ok()))
            .unwrap_or_else(|| {
                Settings::load_preset("default", &[]).unwrap_or_else(|e| {
                    message = Some(Message {
                        text: format!("{e:#}"),
                        error: true,
                    });
                    Settings::default()
                })
            });
        let adapter = match &cc.wgpu_render_state {
            Some(rs) => gpu::describe(&rs.adapter.get_info()),
            None => "no wgpu renderer".to_string(),
        };
        log::info!("GPU: {adapter}");
        let mut app = HairlabApp {
            settings,
            render_state: cc.wgpu_render_state.clone(),
            renderer: None,
            scene: None,
            built_scene: None,
            fur: None,
            built_fur: None,
            scene_ms: 0.0,
            texture: None,
            last_rendered: None,
            probe_baking: false,
            adapter,
            message,
            dialog: None,
            screenshot_request: None,
            frame_ms: VecDeque::new(),
            motion_ms: None,
            pass_times: Vec::new(),
            continuous: false,
            last_frame: None,
            snapshot_mode: false,
            viewport_error: None,
            analysis: None,
            inspector: Default::default(),
            light_map: Default::default(),
            viewport_rect: None,
            bench: Default::default(),
            compare: Default::default(),
            pixel_inspector: Default::default(),
            undoer: undo::new_undoer(),
            help_open: false,
            about_open: false,
            timeline: Default::default(),
            path_view: Default::default(),
            time_view: Default::default(),
            animation_export: Default::default(),
            motion_bound: Default::default(),
            egui_ctx: cc.egui_ctx.clone(),
            scene_job: None,
            analysis_job: None,
            job_gate: None,
            settle: Default::default(),
            settled: true,
            shaders: None,
            export_dir: None,
        };
        app.rebuild_scene();
        app
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// The scene on screen, if one loaded.
    pub fn scene(&self) -> Option<&Scene> {
        self.scene.as_ref()
    }

    /// The current status-line message and whether it is an error.
    pub fn message(&self) -> Option<(&str, bool)> {
        self.message.as_ref().map(|m| (m.text.as_str(), m.error))
    }

    /// Saves the viewport to `path` as PNG after the next frame (the path the screenshot dialog and shortcut use).
    pub fn request_screenshot(&mut self, path: PathBuf) {
        self.screenshot_request = Some(path);
    }

    /// Replaces measured times in the UI by a placeholder, for reproducible snapshots.
    pub fn set_snapshot_mode(&mut self, on: bool) {
        self.snapshot_mode = on;
    }

    fn info(&mut self, text: impl Into<String>) {
        let text = text.into();
        log::info!("{text}");
        self.message = Some(Message { text, error: false });
    }

    fn error(&mut self, text: impl Into<String>) {
        let text = text.into();
        log::error!("{text}");
        self.message = Some(Message { text, error: true });
    }

    fn handle_input(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .collect()
        });
        if let Some(path) = dropped.into_iter().next() {
            if path.extension().is_some_and(|e| e == "toml") {
                match Settings::load_preset(&path.to_string_lossy(), &[]) {
                    Ok(s) => self.replace_settings(s),
                    Err(e) => self.error(format!("{e:#}")),
                }
            } else {
                self.open_scene_file(path);
            }
        }
        let (save_dialog, quick_save, frame) = ctx.input_mut(|i| {
            (
                i.consume_key(egui::Modifiers::COMMAND, egui::Key::S),
                i.consume_key(egui::Modifiers::NONE, egui::Key::F12),
                i.consume_key(egui::Modifiers::NONE, egui::Key::F),
            )
        });
        if save_dialog {
            self.open_dialog(DialogPurpose::SaveScreenshot, ctx);
        }
        if quick_save {
            let stamp = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_secs())
                .unwrap_or(0);
            self.screenshot_request = Some(PathBuf::from(format!("hairlab-{stamp}.png")));
        }
        if frame && !ctx.egui_wants_keyboard_input() {
            self.frame_scene();
        }
    }

    /// Advances the timeline and moves the renderer's and the scene's strands to the frame it shows.
    fn play_motion(&mut self, ctx: &egui::Context) {
        self.timeline.keys(ctx);
        self.timeline.advance(ctx.input(|i| i.stable_dt) as f64);
        let frame = self.timeline.frame();
        let start = Instant::now();
        let mesh_pose = self.timeline.mesh_pose();
        if let Some(points) = self.timeline.pending() {
            self.motion_ms = Some(start.elapsed().as_secs_f64() * 1e3);
            let (renderer, scene) = (&mut self.renderer, &mut self.scene);
            let result = points.and_then(|p| {
                if let Some(r) = renderer.as_mut() {
                    r.update_points(p)?;
                    if let Some((meshes, pose)) = &mesh_pose {
                        r.pose_meshes(meshes, *pose)?;
                    }
                }
                if let Some(s) = scene.as_mut() {
                    s.set_strand_points(p)?;
                }
                Ok(())
            });
            match result {
                Ok(()) => {
                    self.timeline.uploaded();
                    self.last_rendered = None;
                }
                Err(e) => {
                    self.timeline.failed();
                    self.error(format!("motion frame {frame}: {e:#}"));
                }
            }
        }
        if self.timeline.is_playing() {
            ctx.request_repaint();
        }
    }

    /// The viewport's last frame, read back from the renderer (sRGB RGBA8).
    pub fn viewport_image(&self) -> Option<image::RgbaImage> {
        self.renderer.as_ref().and_then(|r| r.read_output().ok())
    }

    /// Where the world point `p` shows in the viewport (window points), when it lies in front of the camera.
    pub fn viewport_position(&self, p: glam::Vec3) -> Option<egui::Pos2> {
        let (rect, r) = (self.viewport_rect?, self.renderer.as_ref()?);
        let size = rect.size();
        let c = r.world_to_clip(
            &self.settings.camera,
            size.x.max(1.0) as u32,
            size.y.max(1.0) as u32,
        ) * p.extend(1.0);
        (c.w > 0.0).then(|| {
            let ndc = c.truncate() / c.w;
            rect.min + egui::vec2((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y)
        })
    }

    /// The box the renderer fits the hair maps' light frame to under the current `light.fit`.
    pub fn light_fit_box(&self) -> Option<crate::scene::Aabb> {
        Some(self.renderer.as_ref()?.fit_box(self.settings.light.fit))
    }

    /// The timeline of the scene's motion.
    pub fn timeline(&self) -> &timeline::Timeline {
        &self.timeline
    }

    pub fn timeline_mut(&mut self) -> &mut timeline::Timeline {
        &mut self.timeline
    }

    fn frame_scene(&mut self) {
        if let Some(s) = &self.scene {
            self.settings.camera.frame(&s.framing_bounds());
        }
    }

    /// Inspects texel `(x, y)` of the scene's light map (row 0 at the top) and opens the inspector.
    pub fn select_texel(&mut self, x: u32, y: u32) {
        self.inspector.select(SceneTexel {
            texel: [x, y],
            picked: None,
        });
    }

    pub fn inspector(&self) -> &Inspector {
        &self.inspector
    }

    pub fn inspector_mut(&mut self) -> &mut Inspector {
        &mut self.inspector
    }

    /// The path-traced view (`render.mode = path`).
    pub fn path_view(&self) -> &path_view::PathView {
        &self.path_view
    }

    pub fn compare(&self) -> &compare_view::CompareView {
        &self.compare
    }

    pub fn compare_mut(&mut self) -> &mut compare_view::CompareView {
        &mut self.compare
    }

    pub fn pixel_inspector(&self) -> &pixel_inspector::PixelInspector {
        &self.pixel_inspector
    }

    /// Decides, once per frame, whether the input has settled (`jobs::Settle`): the one place that holds back
    /// the exact reference lists and the compare renders during a drag, an orbit or a run of changes, and
    /// asks for the frame that runs them once it settles.
    fn note_input(&mut self, ctx: &egui::Context) {
        let (down, now) = ctx.input(|i| (i.pointer.any_down(), i.time));
        let left = self.settle.note(&self.settings, down, now);
        self.settled = left == 0.0;
        if !self.settled && !down {
            ctx.request_repaint_after(Duration::from_secs_f64(left));
        }
    }

    fn status_line(&self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            if self.snapshot_mode {
                ui.label("timings hidden (snapshot mode)");
                return;
            }
            let mut sorted: Vec<f64> = self.frame_ms.iter().copied().collect();
            sorted.sort_by(f64::total_cmp);
            if let Some(median) = sorted.get(sorted.len() / 2) {
                // Continuous: wall time between frames. On demand: CPU time to record and submit a frame.
                let what = if self.continuous { "frame" } else { "submit" };
                ui.label(format!("{what} {median:.1} ms (median of {})", sorted.len()));
            }
            if self.pass_times.is_empty() {
                ui.label("GPU: no timestamp queries");
            } else {
                let total: f64 = self.pass_times.iter().map(|p| p.ms).sum();
                let parts: Vec<String> = Phase::ALL
                    .iter()
                    .filter(|&&phase| self.pass_times.iter().any(|p| p.phase == phase))
                    .map(|&phase| format!("{} {:.2}", phase.label(), phase_ms(&self.pass_times, phase)))
                    .collect();
                ui.label(format!("GPU {total:.2} ms: {}", parts.join(" · ")));
            }
            if let Some(ms) = self.motion_ms.filter(|_| self.timeline.is_moving()) {
                ui.label(format!("simulation (CPU) {ms:.1} ms"));
            }
            if self.probe_baking {
                ui.label("path-traced probe: baking on the CPU, drawn meanwhile with the last one");
            }
            ui.separator();
            ui.label(&self.adapter);
            if let Some(m) = &self.message {
                ui.separator();
                let color = if m.error {
                    ui.visuals().error_fg_color
                } else {
                    ui.visuals().text_color()
                };
                ui.colored_label(color, &m.text);
            }
        });
    }
}

impl eframe::App for HairlabApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.poll_jobs(Duration::ZERO);
        self.poll_dialog();
        self.poll_shaders(&ctx);
        self.handle_input(&ctx);
        self.undo_input(&ctx);
        self.play_motion(&ctx);
        egui::Panel::bottom("status").show(ui, |ui| self.status_line(ui));
        let jobs = self.jobs();
        if !jobs.is_empty() {
            egui::Panel::bottom("jobs").show(ui, |ui| jobs::jobs_bar(ui, &jobs, self.snapshot_mode));
            // The time left counts down between the workers' reports.
            ctx.request_repaint_after(Duration::from_millis(250));
        }
        if self.timeline.is_moving() {
            let export = egui::Panel::bottom("timeline")
                .show(ui, |ui| self.timeline.ui(ui))
                .inner;
            if export {
                self.animation_export
                    .show(self.timeline.frame_count(), &self.settings);
            }
        }
        egui::Panel::left("controls")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls(ui, &ctx));
            });
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.viewport(ui));
        self.note_input(&ctx);
        self.inspector_windows(&ctx);
        self.time_view_window(&ctx);
        self.animation_export_window(&ctx);
        self.bench_window(&ctx);
        self.transparency_windows(&ctx);
        self.help_window(&ctx);
        self.about_window(&ctx);
        self.feed_undoer(&ctx);
        if let Some(path) = self.screenshot_request.take() {
            self.save_screenshot(path);
        }
        if self.continuous || self.dialog.is_some() {
            ctx.request_repaint();
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, SETTINGS_KEY, &self.settings);
    }
}

/// Names of registered methods, for the UI.
/// The window's GPU (its device, queue and adapter) as a [`gpu::Gpu`] for work beside the window's renderer: the
/// compare view, the time view, the α fit, the animation export.
fn window_gpu(rs: Option<&egui_wgpu::RenderState>) -> Option<gpu::Gpu> {
    rs.map(|rs| gpu::Gpu::from_parts(rs.device.clone(), rs.queue.clone(), rs.adapter.get_info()))
}

fn method_names() -> Vec<(&'static str, &'static str)> {
    registry::all().iter().map(|m| (m.name(), m.label())).collect()
}
