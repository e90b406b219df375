//! The workbench window: an eframe app with the wgpu viewport in the centre, parameter panels on the left and a
//! status line at the bottom. Settings persist between runs; presets load and save the same struct.

mod about;
mod bench_panel;
pub mod compare_view;
pub mod export_animation;
mod exports;
mod fur_panel;
pub mod inspector;
pub mod jobs;
mod lightmap_view;
mod motion_bound;
mod panels;
pub mod pixel_inspector;
mod shader_watch;
pub mod texel_lab;
pub mod time_view;
pub mod timeline;
mod transparency_panel;
mod undo;
mod viewport;

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
    /// The picked hair point followed over the motion (`time_view.rs`).
    time_view: time_view::TimeView,
    /// The motion exported as a PNG sequence or a GIF (`export_animation.rs`).
    animation_export: export_animation::AnimationExport,
    /// The whole motion's box for `light.fit = bound`, found on a worker (`motion_bound.rs`).
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
    shaders: Option<crate::shaders::live::Watch>,
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

    /// Starts building the scene from the settings (generator or file) on a worker thread, replacing a build
    /// under way for other settings, and applies it when it is done within [`PATIENCE`] (later frames apply it
    /// otherwise). Until then the window shows the previous scene.
    fn rebuild_scene(&mut self) {
        let (scene, motion) = (self.settings.scene.clone(), self.settings.motion.clone());
        if self
            .scene_job
            .as_ref()
            .is_some_and(|j| j.scene == scene && j.motion == motion)
        {
            return;
        }
        let settings = self.settings.clone();
        let what = if scene.file.is_some() {
            "loading the strands"
        } else {
            "growing the strands"
        };
        let job = Job::spawn("scene", &self.egui_ctx, self.job_gate.clone(), move |ctl| {
            let start = Instant::now();
            if !ctl.step(what, 0.0) {
                return None;
            }
            let progress = ctl.clone();
            let built = crate::scene::progress::observed(
                move |f| progress.step(what, 0.9 * f),
                || settings.open_motion(),
            )?;
            ctl.step("preparing the motion", 0.95).then_some(())?;
            let ms = start.elapsed().as_secs_f64() * 1e3;
            Some(built.map(|(s, m)| (s, m, ms)).map_err(|e| format!("{e:#}")))
        });
        self.scene_job = Some(SceneJob { job, scene, motion });
        self.poll_scene_job(PATIENCE);
    }

    /// Applies the scene job's result when it is done (waiting up to `patience`); a cancelled job leaves the
    /// previous scene and puts back the settings it was built with.
    fn poll_scene_job(&mut self, patience: Duration) {
        let Some(j) = &self.scene_job else { return };
        match j.job.wait(patience) {
            Poll::Running => {}
            Poll::Done(result) => {
                let Some(j) = self.scene_job.take() else { return };
                match result {
                    Ok((scene, motion, ms)) => self.apply_scene(scene, motion, ms, j.scene, &j.motion),
                    Err(e) => {
                        self.error(e);
                        self.restore_built_scene();
                    }
                }
            }
            Poll::Gone => {
                let cancelled = j.job.cancelled();
                self.scene_job = None;
                self.restore_built_scene();
                if cancelled {
                    self.info("scene: cancelled; the previous scene stays");
                } else {
                    self.error("scene: the worker stopped without a result");
                }
            }
        }
    }

    /// Puts back the scene and motion settings of the scene on screen (when there is one).
    fn restore_built_scene(&mut self) {
        if let Some(prev) = self.built_scene.clone() {
            self.settings.scene = prev;
            if let Some(m) = self.timeline.opened_with() {
                self.settings.motion = m.clone();
            }
        }
    }

    /// Uploads a built scene and makes it the one on screen; on failure the previous scene stays.
    fn apply_scene(
        &mut self,
        scene: Scene,
        motion: crate::motion::Motion,
        ms: f64,
        scene_settings: SceneSettings,
        motion_settings: &crate::motion::MotionSettings,
    ) {
        self.scene_ms = ms;
        if self.settings.camera.distance <= 0.0
            || self
                .built_scene
                .as_ref()
                .is_some_and(|b| b.file != scene_settings.file)
        {
            self.settings.camera.frame(&scene.framing_bounds());
        }
        let Some(rs) = &self.render_state else {
            self.scene = Some(scene);
            self.built_scene = Some(scene_settings);
            self.timeline.set_motion(motion, motion_settings);
            return;
        };
        let gpu = gpu::Gpu::from_parts(rs.device.clone(), rs.queue.clone(), rs.adapter.get_info());
        let result = match self.renderer.as_mut() {
            Some(r) => r.set_scene(&scene),
            None => Renderer::new(&gpu, &scene, self.settings.render.map_resolution).map(|r| {
                self.renderer = Some(r);
            }),
        };
        match result {
            Ok(()) => {
                self.info(format!(
                    "scene: {} strands, {} segments, {} triangles",
                    scene.strands.strand_count(),
                    scene.strands.segment_count(),
                    scene.triangle_count()
                ));
                self.scene = Some(scene);
                self.built_scene = Some(scene_settings);
                self.timeline.set_motion(motion, motion_settings);
                self.motion_bound.scene_uploaded();
                self.last_rendered = None;
                // The fur grows on the new scene's mesh.
                self.built_fur = None;
                self.fur = None;
            }
            Err(e) => {
                self.error(format!("cannot upload the scene: {e}"));
                self.restore_built_scene();
            }
        }
    }

    /// Makes jobs started from now on wait at each of their steps until the returned gate opens: a test hook
    /// that holds a job at a point the test chooses.
    pub fn hold_jobs(&mut self) -> JobGate {
        let gate = JobGate::default();
        self.job_gate = Some(gate.clone());
        gate
    }

    /// Every job under way (scene, analysis, whole-map statistics, compare, bench), as the progress bar shows them.
    pub fn jobs(&self) -> Vec<JobStatus> {
        let mut all: Vec<JobStatus> = self.scene_job.iter().map(|j| j.job.status()).collect();
        all.extend(self.analysis_job.iter().map(|j| j.job.status()));
        all.extend(self.inspector.job_status());
        all.extend(self.motion_bound.status());
        all.extend(self.compare.job_status());
        all.extend(self.bench_status());
        all
    }

    /// Waits for the scene, analysis, whole-map statistics and compare jobs under way and applies their results (for
    /// scripts and tests that need a finished state).
    pub fn finish_jobs(&mut self) {
        const FOREVER: Duration = Duration::from_secs(24 * 3600);
        self.poll_scene_job(FOREVER);
        self.poll_analysis_job(FOREVER);
        self.poll_map_stats(FOREVER);
        self.fit_motion_bound(FOREVER);
        self.poll_compare(FOREVER);
    }

    /// Takes the results of the jobs that finished (waiting up to `patience` for each).
    fn poll_jobs(&mut self, patience: Duration) {
        self.poll_scene_job(patience);
        self.poll_analysis_job(patience);
        self.poll_map_stats(patience);
        self.fit_motion_bound(patience);
        self.poll_compare(patience);
    }

    /// Keeps the renderer's fit bound the whole motion's box while `light.fit = bound` and the scene moves
    /// (`motion_bound.rs`; the box is found on a worker).
    fn fit_motion_bound(&mut self, patience: Duration) {
        let wanted = (self.settings.light.fit == crate::scene::LightFit::Bound)
            .then(|| Some((self.built_scene.clone()?, self.timeline.opened_with()?.clone())))
            .flatten()
            .filter(|_| self.timeline.is_moving());
        let apply = self.motion_bound.update(
            wanted,
            &self.settings,
            &self.egui_ctx,
            self.job_gate.clone(),
            patience,
        );
        let bound = match apply {
            motion_bound::Apply::Nothing => return,
            motion_bound::Apply::Failed(e) => return self.error(e),
            motion_bound::Apply::Bound(b) => Some(b),
            motion_bound::Apply::Clear => None,
        };
        if let Some(r) = self.renderer.as_mut() {
            r.set_fit_bound(bound);
            self.last_rendered = None;
        }
    }

    /// Starts the whole-map statistics job of the inspector and gives it [`PATIENCE`] to finish.
    fn start_map_stats(&mut self, ctx: &egui::Context) {
        if self.inspector.compute_map_stats(ctx, self.job_gate.clone()) {
            self.poll_map_stats(PATIENCE);
        }
    }

    fn poll_map_stats(&mut self, patience: Duration) {
        if let Some(m) = self.inspector.poll_map_stats(patience) {
            self.info(m);
        }
    }

    /// Opens a native file dialog on a worker thread so the window never freezes.
    fn open_dialog(&mut self, purpose: DialogPurpose, ctx: &egui::Context) {
        if self.dialog.is_some() {
            return;
        }
        let (tx, rx) = mpsc::channel();
        let ctx = ctx.clone();
        std::thread::spawn(move || {
            type Pick = std::pin::Pin<Box<dyn std::future::Future<Output = Option<rfd::FileHandle>> + Send>>;
            let d = rfd::AsyncFileDialog::new();
            let fut: Pick = match purpose {
                DialogPurpose::OpenScene => Box::pin(
                    d.add_filter(
                        "hair, glTF, TressFX, USC-HairSalon or USD",
                        crate::scene::load::SCENE_EXTENSIONS,
                    )
                    .set_title("Load strands")
                    .pick_file(),
                ),
                DialogPurpose::SaveScreenshot => Box::pin(
                    d.add_filter("PNG", &["png"])
                        .set_file_name("hairlab.png")
                        .set_title("Export screenshot")
                        .save_file(),
                ),
                DialogPurpose::LoadPreset => Box::pin(
                    d.add_filter("preset", &["toml"])
                        .set_directory("presets")
                        .pick_file(),
                ),
                DialogPurpose::SavePreset => Box::pin(
                    d.add_filter("preset", &["toml"])
                        .set_directory("presets")
                        .set_file_name("my-preset.toml")
                        .save_file(),
                ),
                DialogPurpose::ExportCurves => Box::pin(
                    d.add_filter("CSV", &["csv"])
                        .set_file_name("texel-curves.csv")
                        .set_title("Export texel curves")
                        .save_file(),
                ),
                DialogPurpose::Export(what) => Box::pin(d.set_title(what.title()).pick_folder()),
            };
            let picked = pollster::block_on(fut).map(|h| h.path().to_path_buf());
            let _ = tx.send(picked);
            ctx.request_repaint();
        });
        self.dialog = Some((purpose, rx));
    }

    fn poll_dialog(&mut self) {
        let Some((purpose, rx)) = &self.dialog else { return };
        let purpose = *purpose;
        let picked = match rx.try_recv() {
            Ok(p) => p,
            Err(mpsc::TryRecvError::Empty) => return,
            Err(mpsc::TryRecvError::Disconnected) => None,
        };
        self.dialog = None;
        let Some(path) = picked else {
            self.info(
                "no file chosen (if no dialog appeared, no desktop portal is running: drop files on the window, \
                 press F12 for a quick screenshot, or use the CLI)",
            );
            return;
        };
        match purpose {
            DialogPurpose::OpenScene => self.open_scene_file(path),
            DialogPurpose::SaveScreenshot => self.screenshot_request = Some(path),
            DialogPurpose::LoadPreset => match Settings::load_preset(&path.to_string_lossy(), &[]) {
                Ok(s) => {
                    self.replace_settings(s);
                    self.info(format!("preset loaded: {}", path.display()));
                }
                Err(e) => self.error(format!("{e:#}")),
            },
            DialogPurpose::SavePreset => match self.settings.save_preset(&path) {
                Ok(()) => self.info(format!("preset saved: {}", path.display())),
                Err(e) => self.error(format!("{e:#}")),
            },
            DialogPurpose::ExportCurves => self.export_inspector_csv(&path),
            DialogPurpose::Export(what) => self.export(what, &path),
        }
    }

    /// Reads the exact fragment lists of the current light view and runs a method's on-demand analysis on
    /// them as a job; the parameters it picks are applied when it is done.
    fn run_analysis(
        &mut self,
        method: &'static dyn crate::methods::ShadowMethod,
        a: crate::methods::Analysis,
    ) {
        let Some(r) = self.renderer.as_mut() else { return };
        match inspector::read_reference_lists(r, &self.settings) {
            Ok(lists) => {
                let (params, run) = (self.settings.method.params.clone(), a.run);
                let job = Job::spawn(a.label, &self.egui_ctx, self.job_gate.clone(), move |ctl| {
                    ctl.step("analysing the fragment lists", 0.0).then_some(())?;
                    Some(run(&lists, &params))
                });
                self.analysis_job = Some(AnalysisJob {
                    method: method.name(),
                    label: a.label,
                    job,
                });
                self.poll_analysis_job(PATIENCE);
            }
            Err(e) => self.error(format!("{}: {e}", a.label)),
        }
    }

    /// Applies the analysis job's parameters when it is done (waiting up to `patience`) and the method is still
    /// the one it analysed.
    fn poll_analysis_job(&mut self, patience: Duration) {
        let Some(j) = &self.analysis_job else { return };
        match j.job.wait(patience) {
            Poll::Running => {}
            Poll::Done(result) => {
                let (method, label) = (j.method, j.label);
                self.analysis_job = None;
                if self.settings.method.name != method {
                    self.info(format!(
                        "{label}: the method changed meanwhile; its result is dropped"
                    ));
                    return;
                }
                self.settings.method.params.extend(result.apply.clone());
                self.info(format!("{label}: {}", result.summary));
                self.analysis = Some((method, result));
            }
            Poll::Gone => {
                let label = j.label;
                self.analysis_job = None;
                self.info(format!("{label}: cancelled"));
            }
        }
    }

    fn open_scene_file(&mut self, path: PathBuf) {
        self.settings.scene.file = Some(path);
        self.rebuild_scene();
    }

    fn save_screenshot(&mut self, path: PathBuf) {
        let Some(r) = &self.renderer else {
            self.error("no viewport to save");
            return;
        };
        let result = r.read_output().map_err(anyhow::Error::from).and_then(|img| {
            let mut png = Vec::new();
            img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
            crate::io::write_atomic(&path, &png)?;
            Ok((img.width(), img.height()))
        });
        match result {
            Ok((w, h)) => self.info(format!("screenshot saved: {} ({w}×{h})", path.display())),
            Err(e) => self.error(format!("screenshot failed: {e:#}")),
        }
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

    /// The timeline of the scene's motion.
    /// The box the renderer fits the hair maps' light frame to under the current `light.fit`.
    pub fn light_fit_box(&self) -> Option<crate::scene::Aabb> {
        Some(self.renderer.as_ref()?.fit_box(self.settings.light.fit))
    }

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

    pub fn compare(&self) -> &compare_view::CompareView {
        &self.compare
    }

    pub fn compare_mut(&mut self) -> &mut compare_view::CompareView {
        &mut self.compare
    }

    pub fn pixel_inspector(&self) -> &pixel_inspector::PixelInspector {
        &self.pixel_inspector
    }

    /// The compare window (renders when asked or, in auto mode, when the settings changed and no drag is under
    /// way) and the pixel inspector window.
    fn transparency_windows(&mut self, ctx: &egui::Context) {
        if self.compare.open {
            let area = self.viewport_rect.unwrap_or_else(|| ctx.content_rect());
            let size = self.compare.size(&self.settings.render);
            if self.compare.auto && self.settled && self.compare.stale(&self.settings, size) {
                self.render_compare(size, ctx);
            }
            let mut open = self.compare.open;
            let (settings, hide) = (&self.settings, self.snapshot_mode);
            let action = egui::Window::new("Compare")
                .open(&mut open)
                .default_pos([area.left() + 8.0, area.top() + 8.0])
                .default_size([
                    (area.width() - 16.0).max(400.0),
                    (area.height() - 16.0).max(400.0),
                ])
                .show(ctx, |ui| {
                    egui::ScrollArea::vertical()
                        .show(ui, |ui| self.compare.ui(ui, settings, hide))
                        .inner
                })
                .and_then(|r| r.inner)
                .flatten();
            self.compare.open = open;
            match action {
                Some(compare_view::CompareAction::Render) => self.render_compare(size, ctx),
                Some(compare_view::CompareAction::Pick(p)) => self.pixel_inspector.select(p),
                Some(compare_view::CompareAction::Export) => {
                    self.request_export(exports::Export::Compare, ctx)
                }
                None => {}
            }
        }
        if self.pixel_inspector.open {
            let mut open = self.pixel_inspector.open;
            let (frames, generation) = (self.compare.frames(), self.compare.generation());
            egui::Window::new("Pixel inspector")
                .open(&mut open)
                .default_size([560.0, 520.0])
                .show(ctx, |ui| self.pixel_inspector.ui(ui, frames, generation));
            self.pixel_inspector.open = open;
            if self.pixel_inspector.take_export() {
                self.request_export(exports::Export::Pixel, ctx);
            }
        }
    }

    /// Starts the compare render (a job with a renderer of its own) and gives it [`PATIENCE`] to finish.
    fn render_compare(&mut self, size: (u32, u32), ctx: &egui::Context) {
        let (Some(rs), Some(scene), Some(_)) = (&self.render_state, &self.scene, &self.renderer) else {
            return self.error("compare view: no GPU renderer");
        };
        let source = compare_view::CompareSource {
            gpu: gpu::Gpu::from_parts(rs.device.clone(), rs.queue.clone(), rs.adapter.get_info()),
            scene: scene.clone(),
            fur: self.fur.clone(),
            fit_bound: self
                .renderer
                .as_ref()
                .map(|r| r.fit_box(crate::scene::LightFit::Bound)),
            mesh_pose: self.timeline.mesh_pose(),
        };
        self.compare
            .start(source, &self.settings, size, ctx, self.job_gate.clone());
        self.poll_compare(PATIENCE);
    }

    /// Applies the compare render's outcome when it is done (waiting up to `patience`).
    fn poll_compare(&mut self, patience: Duration) {
        match self.compare.poll(patience, &self.egui_ctx) {
            Some(Ok(m)) => self.info(m),
            Some(Err(e)) => self.error(e),
            None => {}
        }
    }

    /// Opens the time view on the hair point picked for the texel inspector and measures it.
    fn open_time_view(&mut self, ctx: &egui::Context) {
        let (Some(pick), Some(scene)) = (self.inspector.shown_pick(), &self.scene) else {
            return self.error("time view: pick a hair point in the viewport first");
        };
        if !self.timeline.is_moving() {
            return self
                .error("time view: the scene has no motion (try the wind, head-turn or stray-sweep preset)");
        }
        let point = FollowedPoint::on_segment(&scene.strands.points, pick.segment, pick.world);
        self.time_view
            .follow(point, &scene.strands, self.timeline.frame_count());
        self.start_time_view(ctx);
    }

    fn start_time_view(&mut self, ctx: &egui::Context) {
        let Some(rs) = &self.render_state else {
            return self.error("time view: no GPU renderer");
        };
        let gpu = gpu::Gpu::from_parts(rs.device.clone(), rs.queue.clone(), rs.adapter.get_info());
        self.time_view.start(gpu, &self.settings, ctx);
    }

    /// The time view's window while it is open (its measurement runs on a worker thread).
    fn time_view_window(&mut self, ctx: &egui::Context) {
        self.time_view.poll();
        if !self.time_view.open {
            return;
        }
        let mut open = true;
        let (frame, count) = (self.timeline.frame(), self.timeline.frame_count());
        let area = self.viewport_rect.unwrap_or_else(|| ctx.content_rect());
        let action = egui::Window::new("Time view")
            .open(&mut open)
            .default_pos([area.left() + 8.0, area.top() + 8.0])
            .default_size([(area.width() - 16.0).clamp(400.0, 760.0), 520.0])
            .show(ctx, |ui| self.time_view.ui(ui, frame, count))
            .and_then(|r| r.inner)
            .flatten();
        if !open {
            self.time_view.cancel();
        }
        self.time_view.open = open;
        match action {
            Some(time_view::TimeViewAction::Run) => self.start_time_view(ctx),
            Some(time_view::TimeViewAction::Seek(k)) => self.timeline.seek(k),
            None => {}
        }
    }

    /// The animation export window while it is open (its frames render on a worker thread).
    fn animation_export_window(&mut self, ctx: &egui::Context) {
        self.animation_export.poll();
        if !self.animation_export.open {
            return;
        }
        let mut open = true;
        let count = self.timeline.frame_count();
        let (settings, rs) = (&self.settings, &self.render_state);
        let gpu = || {
            rs.as_ref()
                .map(|rs| gpu::Gpu::from_parts(rs.device.clone(), rs.queue.clone(), rs.adapter.get_info()))
        };
        let export = &mut self.animation_export;
        egui::Window::new("Export animation")
            .open(&mut open)
            .show(ctx, |ui| export.ui(ui, count, settings, gpu));
        if !open {
            self.animation_export.cancel();
        }
        self.animation_export.open = open;
    }

    /// The animation export (for tests and scripts).
    pub fn animation_export_mut(&mut self) -> &mut export_animation::AnimationExport {
        &mut self.animation_export
    }

    /// The time view (for tests and scripts).
    pub fn time_view(&self) -> &time_view::TimeView {
        &self.time_view
    }

    /// Writes every curve shown (see [`inspector::TexelCurves::csv`]) to `path`; the outcome goes to the status
    /// line.
    pub fn export_inspector_csv(&mut self, path: &std::path::Path) {
        self.refresh_lists(true);
        self.update_curves();
        match inspector::export(self.inspector.curves(), path) {
            Ok(m) => self.info(m),
            Err(e) => self.error(e),
        }
    }

    /// The key of the reference lists the current settings need.
    fn lists_key(&self) -> ListsKey {
        ListsKey::new(
            &self.settings,
            self.renderer.as_ref().map(Renderer::scene_generation),
        )
    }

    /// Reads the reference lists again when a window needs them and what they depend on changed (and `allow`,
    /// i.e. no drag is under way); a failed read is reported once and not retried until something changes.
    fn refresh_lists(&mut self, allow: bool) {
        if !(self.inspector.needs_lists() || self.light_map.open) {
            return;
        }
        let key = self.lists_key();
        let (renderer, settings) = (&mut self.renderer, &self.settings);
        let read = || {
            let r = renderer
                .as_mut()
                .ok_or("no GPU renderer: only the synthetic texel lab works")?;
            inspector::read_reference_lists(r, settings)
        };
        match self.inspector.refresh_lists(key, allow, read) {
            // The light pass replaced the frame's timings: render the viewport again to show its own.
            Some(Ok(())) => self.last_rendered = None,
            Some(Err(e)) => self.error(format!("texel inspector: {e}")),
            None => {}
        }
    }

    /// Recomputes the inspector's curves when their inputs changed; reports a new error in the lab's text.
    fn update_curves(&mut self) {
        if let Some(e) = self.inspector.update_curves(&self.settings) {
            self.error(e);
        }
    }

    /// The inspector and light-map windows (each frame; they do nothing while closed).
    fn inspector_windows(&mut self, ctx: &egui::Context) {
        if !(self.inspector.open || self.light_map.open) {
            return;
        }
        self.refresh_lists(self.settled);
        self.update_curves();
        // First placement: the inspector along the bottom of the viewport, the light map in its top right corner,
        // so that the hair stays in view for picking.
        let area = self.viewport_rect.unwrap_or_else(|| ctx.content_rect());
        let width = (area.width() - 16.0).clamp(300.0, 900.0);
        let mut open = self.inspector.open;
        let deps = InspectorDeps {
            settings: &self.settings,
            light_map_open: self.light_map.open,
        };
        let action = egui::Window::new("Texel inspector")
            .open(&mut open)
            .default_pos([area.left() + 8.0, (area.bottom() - 440.0).max(area.top())])
            .default_size([width, 400.0])
            .show(ctx, |ui| self.inspector.ui(ui, deps))
            .and_then(|r| r.inner)
            .flatten();
        self.inspector.open = open;
        match action {
            Some(InspectorAction::ExportCsv) => self.open_dialog(DialogPurpose::ExportCurves, ctx),
            Some(InspectorAction::ExportPlot) => self.request_export(exports::Export::Texel, ctx),
            Some(InspectorAction::CopyPlot) => self.copy_texel_plot(ctx),
            Some(InspectorAction::OpenLightMap) => self.light_map.open = true,
            Some(InspectorAction::TimeView) => self.open_time_view(ctx),
            Some(InspectorAction::ComputeMapStats) => self.start_map_stats(ctx),
            None => {}
        }
        let mut open = self.light_map.open;
        let pins = self.inspector.pinned_texels();
        let deps = LightMapDeps {
            lists: self.inspector.lists(),
            settings: &self.settings,
            selected: self.inspector.scene_texel(),
            pins: &pins,
        };
        let clicked = egui::Window::new("Light map")
            .open(&mut open)
            .default_pos([(area.right() - 350.0).max(area.left()), area.top() + 8.0])
            .default_size([340.0, (area.height() - 470.0).clamp(240.0, 420.0)])
            .show(ctx, |ui| self.light_map.ui(ui, deps))
            .and_then(|r| r.inner)
            .flatten();
        self.light_map.open = open;
        if let Some(texel) = clicked {
            self.inspector.select(SceneTexel { texel, picked: None });
        }
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
fn method_names() -> Vec<(&'static str, &'static str)> {
    registry::all().iter().map(|m| (m.name(), m.label())).collect()
}
