//! The viewport's path-traced view (`render.mode = path`): the scene on screen — the timeline's frame, its posed
//! meshes, the camera and light of the panels — path-traced on the CPU (`crate::pathtrace`, Chiang et al. 2016's
//! fibres) by a job that adds passes of samples to a progressive image until `render.spp` samples per pixel, and
//! shows each pass's mean as it lands, over the raster's background (`pathtrace::composite`). Any change the path
//! tracer sees (scene, frame, camera, light, strand width, hair colour, seed, `render.path` switches, background, viewport size) restarts
//! it; raising `render.spp` goes on from the samples already taken. The work runs on a worker (a job, `jobs.rs`),
//! so the window stays interactive; the caption over the image shows the samples per pixel and whether it is
//! converging. It stays out of the job bar: that bar taking and giving back its row would resize the viewport,
//! and a new size starts the image again. Switching the viewport back to raster stops it.
//!
//! On a motion, the samples of each frame the timeline leaves are kept (up to [`KEPT_FRAMES`] frames, the
//! oldest dropped first): coming back to a frame goes on from its samples instead of starting again, so a
//! scrubbed or looping timeline converges frame by frame.
//!
//! The image is the viewport's aspect with its longer side at most [`MAX_SIDE`] pixels (the CPU's budget), kept
//! through changes of the viewport's size within [`RESIZE_SLACK`]; pixel for pixel the image [`render_image`]
//! gives, which the compare view's path-traced slot shows too.

use std::sync::{Arc, Mutex};

use super::jobs::{Job, JobGate, Poll};
use crate::path_scene::PathScene;
use crate::pathtrace::composite::{coverage, over_background};
use crate::pathtrace::integrator::Accumulation;
use crate::scene::{Aabb, Scene};
use crate::settings::Settings;

/// The path-traced image's longer side at most, in pixels.
pub const MAX_SIDE: u32 = 400;
/// Camera rays per pixel side that estimate the covered share of each pixel (the background's weight).
pub const COVERAGE_RAYS: usize = 4;
/// Samples per pixel a pass adds once the first few passes (one sample each) have shown a picture.
const PASS: u32 = 4;
/// Frames whose samples the view keeps when the timeline (or any other change) leaves them: each holds its
/// pixels' sums (about 28 bytes a pixel, 3.4 MB at 400 × 300), so at most about 160 MB.
pub const KEPT_FRAMES: usize = 48;

/// The size of the path-traced image for a viewport of `width × height` pixels: the same aspect, the longer side
/// at most [`MAX_SIDE`].
pub fn image_size(width: u32, height: u32) -> (u32, u32) {
    let (w, h) = (width.max(1), height.max(1));
    let scale = (MAX_SIDE as f32 / w.max(h) as f32).min(1.0);
    (
        ((w as f32 * scale).round() as u32).max(1),
        ((h as f32 * scale).round() as u32).max(1),
    )
}

/// How much the viewport may change size (a share of each side) before the image starts again at the new
/// size; until then the image is stretched to the viewport. Panels that come and go (a job's progress row, a
/// message) change the viewport's height by a few per cent.
pub const RESIZE_SLACK: f32 = 0.05;

/// Whether `b` is within [`RESIZE_SLACK`] of `a` on both sides.
fn near(a: (u32, u32), b: (u32, u32)) -> bool {
    let close = |x: u32, y: u32| (x as f32 - y as f32).abs() <= RESIZE_SLACK * x as f32;
    close(a.0, b.0) && close(a.1, b.1)
}

/// What the path tracer sees of the window's state: a change of any of it starts the image again.
#[derive(Clone, Debug, PartialEq)]
struct Key {
    scene: crate::settings::SceneSettings,
    motion: crate::motion::MotionSettings,
    frame: u32,
    camera: crate::scene::Camera,
    light: crate::scene::Light,
    strand_width: f32,
    hair_color: [f32; 3],
    seed: u64,
    /// The path tracer's switches, and what the raster shading at the first hit reads.
    effects: crate::render::render_settings::PathEffects,
    shading: crate::shading::ShadingModel,
    hair_alpha: f32,
    background: [f32; 3],
    size: (u32, u32),
}

impl Key {
    fn new(settings: &Settings, frame: u32, size: (u32, u32)) -> Key {
        let r = &settings.render;
        Key {
            scene: settings.scene.clone(),
            motion: settings.motion.clone(),
            frame,
            camera: settings.camera,
            light: settings.light,
            strand_width: r.strand_width,
            hair_color: r.hair_color,
            seed: r.seed,
            effects: r.path,
            shading: r.shading,
            hair_alpha: r.hair_alpha,
            background: r.background,
            size,
        }
    }
}

/// What the view keeps of a frame it left.
struct Kept {
    acc: Accumulation,
    coverage: Arc<Vec<f32>>,
}

/// A path-traced scene ready for more samples: the BVH, each pixel's coverage and the samples so far.
#[derive(Clone)]
struct TracedView {
    path: Arc<PathScene>,
    coverage: Arc<Vec<f32>>,
    acc: Accumulation,
}

impl TracedView {
    fn image(&self, background: [f32; 3]) -> image::RgbaImage {
        let s = &self.path.settings;
        over_background(
            &self.acc.mean(),
            &self.coverage,
            background,
            s.width as u32,
            s.height as u32,
        )
    }
}

/// `scene` under `settings` at `size`, ready for samples (no samples yet), its light placed around `around`
/// (the renderer's [`crate::render::Renderer::light_around`]).
fn prepare(
    settings: &Settings,
    scene: &Scene,
    around: &Aabb,
    size: (u32, u32),
) -> anyhow::Result<TracedView> {
    let mut s = settings.clone();
    (s.render.width, s.render.height) = size;
    let path = PathScene::placed(&s, scene, around)?;
    let coverage = coverage(
        &path.bvh,
        &path.camera,
        size.0 as usize,
        size.1 as usize,
        COVERAGE_RAYS,
    );
    let acc = path.accumulation();
    Ok(TracedView {
        path: Arc::new(path),
        coverage: Arc::new(coverage),
        acc,
    })
}

/// The path-traced image of `scene` under `settings` at `size` and `render.spp` samples per pixel, over
/// `render.background`: what the view shows once it has converged.
pub fn render_image(
    settings: &Settings,
    scene: &Scene,
    around: &Aabb,
    size: (u32, u32),
) -> anyhow::Result<image::RgbaImage> {
    Ok(render_image_steps(settings, scene, around, size, &mut crate::progress::Quiet)?.unwrap_or_default())
}

/// [`render_image`] one sample per pixel at a time, telling `progress` after each; `Ok(None)` once that answers
/// `false`.
pub fn render_image_steps(
    settings: &Settings,
    scene: &Scene,
    around: &Aabb,
    size: (u32, u32),
    progress: &mut dyn crate::progress::Progress,
) -> anyhow::Result<Option<image::RgbaImage>> {
    let mut p = prepare(settings, scene, around, size)?;
    let (spp, path) = (settings.render.spp, p.path.clone());
    while p.acc.samples() < spp {
        path.add_samples(&mut p.acc, 1);
        let done = p.acc.samples();
        let label = format!("{done}/{spp} spp");
        if !progress.step(&label, crate::progress::share(done as usize, spp as usize)) {
            return Ok(None);
        }
    }
    Ok(Some(p.image(settings.render.background)))
}

/// The newest image a pass published.
#[derive(Clone)]
pub struct Shown {
    pub image: image::RgbaImage,
    pub spp: u32,
}

/// The view's state.
#[derive(Default)]
pub struct PathView {
    key: Option<Key>,
    /// The samples per pixel the running (or last) job goes to.
    target: u32,
    job: Option<Job<Result<TracedView, String>>>,
    /// A finished job's scene and samples, to go on from when `render.spp` rises.
    done: Option<TracedView>,
    /// The running job's samples after its latest pass (it writes, the window takes them when the key changes).
    partial: Arc<Mutex<Option<TracedView>>>,
    /// The samples of keys the view left (a motion's other frames), oldest first, at most [`KEPT_FRAMES`]; only
    /// the sums and the pixels' coverage are kept, the scene is built again on return.
    kept: Vec<(Key, Kept)>,
    /// What the worker published last (it writes, the window reads).
    latest: Arc<Mutex<Option<Shown>>>,
    /// The texture of the image shown, and that image's samples per pixel.
    texture: Option<(egui::TextureHandle, u32)>,
    error: Option<String>,
}

impl PathView {
    /// Keeps the view on `settings` at the timeline's `frame` for a viewport of `viewport` pixels: starts the
    /// image again when anything the path tracer sees changed, goes on when only `render.spp` rose. `scene`
    /// gives the scene on screen (strands at the frame, meshes posed) only when a job starts.
    pub fn sync(
        &mut self,
        settings: &Settings,
        frame: u32,
        viewport: (u32, u32),
        scene: impl FnOnce() -> Option<Result<(Scene, Aabb), String>>,
        ctx: &egui::Context,
        gate: Option<JobGate>,
    ) {
        let mut size = image_size(viewport.0, viewport.1);
        if let Some(old) = &self.key
            && near(old.size, size)
        {
            size = old.size;
        }
        let key = Key::new(settings, frame, size);
        let spp = settings.render.spp;
        let same = self.key.as_ref() == Some(&key);
        if same && (self.job.is_some() || self.error.is_some() || spp <= self.target) {
            return;
        }
        let resume = if same { self.done.take() } else { None };
        let mut returning = None;
        if !same {
            self.job = None;
            let left = self
                .done
                .take()
                .or_else(|| self.partial.lock().unwrap_or_else(|e| e.into_inner()).take());
            if let (Some(old), Some(p)) = (self.key.take(), left) {
                self.keep(
                    old,
                    Kept {
                        acc: p.acc,
                        coverage: p.coverage,
                    },
                );
            }
            returning = self
                .kept
                .iter()
                .position(|(k, _)| *k == key)
                .map(|i| self.kept.remove(i).1);
            self.texture = None;
            *self.latest.lock().unwrap_or_else(|e| e.into_inner()) = None;
        }
        self.key = Some(key.clone());
        self.target = spp;
        self.error = None;
        let start = match resume {
            Some(p) => Ok(p),
            None => match scene() {
                Some(Ok(scene)) => Err((settings.clone(), scene)),
                Some(Err(e)) => {
                    self.error = Some(e);
                    return;
                }
                None => return,
            },
        };
        let (latest, background) = (self.latest.clone(), settings.render.background);
        let partial = self.partial.clone();
        *partial.lock().unwrap_or_else(|e| e.into_inner()) = None;
        self.job = Some(Job::spawn("path-traced view", ctx, gate, move |ctl| {
            let mut p = match start {
                Ok(p) => p,
                Err((settings, (scene, around))) => {
                    ctl.step("building the BVH and the coverage", 0.0).then_some(())?;
                    let mut p = match prepare(&settings, &scene, &around, key.size) {
                        Ok(p) => p,
                        Err(e) => return Some(Err(format!("{e:#}"))),
                    };
                    if let Some(kept) = returning {
                        // Back on a frame the view left: its samples go on.
                        (p.acc, p.coverage) = (kept.acc, kept.coverage);
                        let shown = Shown {
                            image: p.image(background),
                            spp: p.acc.samples(),
                        };
                        *latest.lock().unwrap_or_else(|e| e.into_inner()) = Some(shown);
                    }
                    p
                }
            };
            let path = p.path.clone();
            while p.acc.samples() < spp {
                let done = p.acc.samples();
                let label = format!("{done} / {spp} samples per pixel");
                ctl.step(&label, done as f32 / spp as f32).then_some(())?;
                let n = if done < PASS { 1 } else { PASS }.min(spp - done);
                path.add_samples(&mut p.acc, n);
                let shown = Shown {
                    image: p.image(background),
                    spp: p.acc.samples(),
                };
                *latest.lock().unwrap_or_else(|e| e.into_inner()) = Some(shown);
                *partial.lock().unwrap_or_else(|e| e.into_inner()) = Some(p.clone());
            }
            Some(Ok(p))
        }));
    }

    /// Keeps the samples of `key` (a frame or state the view leaves), dropping the oldest beyond
    /// [`KEPT_FRAMES`]; none are kept of an image with no samples yet.
    fn keep(&mut self, key: Key, kept: Kept) {
        if kept.acc.samples() == 0 {
            return;
        }
        self.kept.retain(|(k, _)| *k != key);
        self.kept.push((key, kept));
        if self.kept.len() > KEPT_FRAMES {
            self.kept.remove(0);
        }
    }

    /// How many left frames' samples are kept.
    pub fn kept_frames(&self) -> usize {
        self.kept.len()
    }

    /// Takes the job's outcome from `poll`: its samples (to go on from later) or its error.
    fn take(&mut self, poll: Poll<Result<TracedView, String>>) {
        match poll {
            Poll::Running => return,
            Poll::Done(Ok(p)) => self.done = Some(p),
            Poll::Done(Err(e)) => self.error = Some(e),
            Poll::Gone => {}
        }
        self.job = None;
    }

    /// Takes a finished job (its samples, for going on later) and the newest published image; `true` when there
    /// is an image to show (before the first pass the caller shows the raster image under [`PathView::paint`]'s
    /// caption).
    pub fn update(&mut self, ctx: &egui::Context) -> bool {
        if let Some(poll) = self.job.as_ref().map(Job::poll) {
            self.take(poll);
        }
        let latest = self.latest.lock().unwrap_or_else(|e| e.into_inner()).clone();
        if let Some(shown) = latest
            && self.texture.as_ref().is_none_or(|(_, spp)| *spp != shown.spp)
        {
            let image = egui::ColorImage::from_rgba_unmultiplied(
                [shown.image.width() as usize, shown.image.height() as usize],
                shown.image.as_raw(),
            );
            let options = egui::TextureOptions::LINEAR;
            match &mut self.texture {
                Some((tex, spp)) => {
                    tex.set(image, options);
                    *spp = shown.spp;
                }
                None => {
                    self.texture = Some((ctx.load_texture("path-traced view", image, options), shown.spp))
                }
            }
        }
        self.error.is_none() && self.texture.is_some()
    }

    /// Draws the image into `rect` with a caption: its samples per pixel, size and state, or the error, or that
    /// the first samples are on their way.
    pub fn paint(&self, ui: &egui::Ui, rect: egui::Rect) {
        let painter = ui.painter();
        let caption = |text: String, color| {
            let at = rect.left_top() + egui::vec2(8.0, 8.0);
            let galley = painter.layout_no_wrap(text, egui::FontId::proportional(14.0), color);
            painter.rect_filled(
                egui::Rect::from_min_size(at, galley.size()).expand(4.0),
                3.0,
                egui::Color32::from_black_alpha(160),
            );
            painter.galley(at, galley, color);
        };
        if let Some(e) = &self.error {
            return caption(format!("path-traced view: {e}"), ui.visuals().error_fg_color);
        }
        let Some((tex, spp)) = &self.texture else {
            return caption(
                "path-traced view: tracing the first samples…".to_string(),
                egui::Color32::WHITE,
            );
        };
        let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        painter.image(tex.id(), rect, uv, egui::Color32::WHITE);
        let size = tex.size();
        let state = if self.job.is_some() {
            "converging"
        } else if *spp < self.target {
            "stopped"
        } else {
            "converged"
        };
        let kept = match self.kept.len() {
            0 => String::new(),
            n => format!(" · samples of {n} other frames kept"),
        };
        caption(
            format!(
                "path-traced · {spp} / {} spp · {}×{} · {state}{kept}",
                self.target, size[0], size[1]
            ),
            egui::Color32::WHITE,
        );
    }

    /// Whether the view holds anything (a job, an image or an error).
    pub fn active(&self) -> bool {
        self.key.is_some()
    }

    /// The newest image and its samples per pixel (the screenshot in path mode, tests).
    pub fn latest(&self) -> Option<Shown> {
        self.latest.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// Why the view has no image (the scene could not be path-traced), if so.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Whether samples are still being added.
    pub fn is_converging(&self) -> bool {
        self.job.is_some()
    }

    /// Waits up to `patience` for the job under way, then takes its outcome as [`PathView::show`] does.
    pub fn wait(&mut self, patience: std::time::Duration) {
        if let Some(poll) = self.job.as_ref().map(|j| j.wait(patience)) {
            self.take(poll);
        }
    }

    /// Forgets the image, so the next [`PathView::sync`] starts again (the raster mode shown meanwhile).
    pub fn clear(&mut self) {
        *self = PathView::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Leaving frame 0 for frame 1 keeps frame 0's samples; back on frame 0 the view goes on from them: with
    /// `render.spp` already reached it shows the first image again bit for bit, although the scene it is
    /// handed now has its strands moved (a restart would trace those).
    #[test]
    fn coming_back_to_a_frame_goes_on_from_its_samples() {
        let overrides: Vec<String> = [
            "scene.generator.strands=40",
            "scene.generator.segments=4",
            "render.spp=2",
        ]
        .map(String::from)
        .to_vec();
        let settings = Settings::load_preset("stray-strand", &overrides).unwrap();
        let scene = settings.scene.build().unwrap();
        let mut moved = scene.clone();
        moved.strands.points.iter_mut().for_each(|p| p.x += 0.01);
        let ctx = egui::Context::default();
        let mut view = PathView::default();
        let show = |view: &mut PathView, frame: u32, scene: &Scene| {
            let (scene, around) = (scene.clone(), scene.bounds());
            view.sync(
                &settings,
                frame,
                (24, 18),
                move || Some(Ok((scene, around))),
                &ctx,
                None,
            );
            view.wait(std::time::Duration::from_secs(120));
            view.latest().expect("an image")
        };
        let first = show(&mut view, 0, &scene);
        assert_eq!(first.spp, 2);
        let other = show(&mut view, 1, &moved);
        assert_eq!((other.spp, view.kept_frames()), (2, 1));
        assert_ne!(other.image, first.image, "frame 1 traces the moved strands");
        let back = show(&mut view, 0, &moved);
        assert_eq!(back.spp, 2);
        assert!(back.image == first.image, "frame 0's samples were traced again");
        assert_eq!(view.kept_frames(), 1, "frame 1 kept, frame 0 shown");
    }

    #[test]
    fn a_small_change_of_the_viewport_keeps_the_image_size() {
        assert!(near((400, 350), (400, 343)), "a progress row coming and going");
        assert!(!near((400, 350), (400, 300)), "a real resize");
        assert!(!near((400, 350), (360, 350)));
    }

    #[test]
    fn the_image_keeps_the_viewport_aspect_within_the_budget() {
        assert_eq!(image_size(800, 600), (400, 300));
        assert_eq!(image_size(300, 900), (133, 400));
        assert_eq!(
            image_size(320, 240),
            (320, 240),
            "a small viewport is traced at its own size"
        );
        assert_eq!(image_size(0, 0), (1, 1));
    }
}
