//! The compare view's frames: the four slots rendered on a worker with a renderer of their own, the exact per-pixel
//! lists and the opaque image read beside them, and the difference heat map between two images.

use super::{PATH_TRACED, Slot};
use crate::app::jobs::JobCtl;
use crate::app::path_view;
use crate::gpu::Gpu;
use crate::gpu::timing::PassTime;
use crate::methods::{LightMethod, ParamValues, registry as methods};
use crate::progress::Progress;
use crate::render::transparency::{EyeTransparency, registry};
use crate::render::{FrameInput, Renderer};
use crate::scene::Scene;
use crate::settings::Settings;
pub use crate::transparency::metrics::{difference_image, heat};
use crate::transparency::{EyeFragment, ImageMetrics, ModelContext, metrics};
use image::RgbaImage;

/// One rendered image.
pub struct CompareImage {
    pub name: &'static str,
    pub label: &'static str,
    pub image: RgbaImage,
    /// The frame's GPU passes (empty without timestamp queries).
    pub passes: Vec<PassTime>,
    pub geometry_passes: u32,
    /// Against the first image.
    pub metrics: ImageMetrics,
    /// The path-traced slot's CPU time (the raster slots have their GPU passes).
    pub cpu_seconds: Option<f64>,
}

impl CompareImage {
    /// The frame's GPU time, all passes.
    pub fn gpu_ms(&self) -> Option<f64> {
        (!self.passes.is_empty()).then(|| self.passes.iter().map(|p| p.ms).sum())
    }
}

/// Eye depth complexity of the compared view, from the exact lists.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthComplexity {
    pub width: u32,
    pub height: u32,
    /// Fragments at the deepest pixel.
    pub max: usize,
    pub total: u64,
    /// Mean over the hair pixels (those with a fragment).
    pub mean_hair: f64,
}

/// Everything one compare render produced.
pub struct CompareFrames {
    pub width: u32,
    pub height: u32,
    pub images: Vec<CompareImage>,
    /// The exact reference's lists, row-major, each front to back on (depth, segment).
    pub lists: Vec<Vec<EyeFragment>>,
    /// The opaque meshes alone (sRGB): the background every pixel's hair is composited over.
    pub background: RgbaImage,
    /// Pixels whose exact list is non-empty.
    pub hair: Vec<bool>,
    /// What the techniques' CPU models need of the frame.
    pub model: ModelContext,
    /// The settings rendered.
    pub settings: Settings,
}

impl CompareFrames {
    /// The exact fragment list of pixel `(x, y)`.
    pub fn list(&self, [x, y]: [u32; 2]) -> Option<&[EyeFragment]> {
        (x < self.width && y < self.height)
            .then(|| self.lists.get((y * self.width + x) as usize).map(Vec::as_slice))
            .flatten()
    }

    pub fn depth_complexity(&self) -> DepthComplexity {
        let max = self.lists.iter().map(Vec::len).max().unwrap_or(0);
        let total: u64 = self.lists.iter().map(|l| l.len() as u64).sum();
        let hair = self.hair.iter().filter(|&&h| h).count();
        DepthComplexity {
            width: self.width,
            height: self.height,
            max,
            total,
            mean_hair: if hair == 0 {
                0.0
            } else {
                total as f64 / hair as f64
            },
        }
    }
}

/// Renders the four `slots` at `width`×`height` with `settings`, reads the exact lists and the opaque image;
/// `scene` (as on screen, meshes posed) is what a path-traced slot traces.
pub fn render_compare(
    r: &mut Renderer,
    scene: &Scene,
    settings: &Settings,
    slots: &[Slot; 4],
    width: u32,
    height: u32,
) -> Result<CompareFrames, String> {
    render_compare_steps(
        r,
        scene,
        settings,
        slots,
        width,
        height,
        &mut crate::progress::Quiet,
    )
    .and_then(|frames| frames.ok_or_else(|| "compare view: stopped".to_string()))
}

/// Steps of a compare render: four slots, the exact lists, the opaque image.
pub(super) const STEPS: f32 = 6.0;

/// [`render_compare`] telling `progress` what it renders next and the share done before each image; `Ok(None)`
/// once it answers `false` (cancelled).
pub(super) fn render_compare_steps(
    r: &mut Renderer,
    scene: &Scene,
    settings: &Settings,
    slots: &[Slot; 4],
    width: u32,
    height: u32,
    progress: &mut dyn Progress,
) -> Result<Option<CompareFrames>, String> {
    let method = methods::find(&settings.method.name).map_err(|e| format!("method.name: {e}"))?;
    let defaults = ParamValues::new();
    let reference = registry::reference();
    let input = |technique, technique_params| {
        frame_input(settings, method, technique, technique_params, width, height)
    };
    let gpu_error = |what: &str, e: crate::gpu::GpuError| format!("compare view: {what}: {e}");
    let mut rendered = Vec::with_capacity(4);
    for (k, slot) in slots.iter().enumerate() {
        if *slot == Slot::PathTraced {
            let start = std::time::Instant::now();
            let mut pass = |spp: &str, f: f32| {
                let label = format!("slot {} · {} · {spp}", k + 1, PATH_TRACED.1);
                progress.step(&label, (k as f32 + f) / STEPS)
            };
            let around = r.light_around(settings.light.fit);
            let image = path_view::render_image_steps(settings, scene, &around, (width, height), &mut pass)
                .map_err(|e| format!("compare view: {}: {e:#}", PATH_TRACED.0))?;
            let Some(image) = image else { return Ok(None) };
            rendered.push(Rendered {
                name: PATH_TRACED.0,
                label: PATH_TRACED.1,
                image,
                passes: Vec::new(),
                geometry_passes: 0,
                cpu_seconds: Some(start.elapsed().as_secs_f64()),
            });
            continue;
        }
        let (technique, params) = slot.resolve(settings, &defaults)?;
        if !progress.step(
            &format!("slot {} · {}", k + 1, technique.info().label),
            k as f32 / STEPS,
        ) {
            return Ok(None);
        }
        r.render(&input(technique, params))
            .map_err(|e| gpu_error(technique.name(), e))?;
        let passes = r.wait_timings();
        let image = r.read_output().map_err(|e| gpu_error(technique.name(), e))?;
        rendered.push(Rendered {
            name: technique.name(),
            label: technique.info().label,
            image,
            passes,
            geometry_passes: r.eye_geometry_passes(),
            cpu_seconds: None,
        });
    }
    if !progress.step("exact lists", 4.0 / STEPS) {
        return Ok(None);
    }
    let lists = r
        .eye_lists(&input(reference, &defaults))
        .map_err(|e| gpu_error("exact lists", e))?;
    if !progress.step("opaque image", 5.0 / STEPS) {
        return Ok(None);
    }
    r.render_capture(&input(reference, &defaults))
        .map_err(|e| gpu_error("opaque image", e))?;
    let background = r.read_output().map_err(|e| gpu_error("opaque image", e))?;
    // Drain these frames' timings: the timer keeps the newest finished readback, and the viewport's frame
    // must not finish together with them.
    r.wait_timings();
    let hair: Vec<bool> = lists.iter().map(|l| !l.is_empty()).collect();
    let first = rendered[0].image.clone();
    let images = rendered
        .into_iter()
        .map(|r| CompareImage {
            name: r.name,
            label: r.label,
            metrics: metrics::compare(&r.image, &first, &hair),
            image: r.image,
            passes: r.passes,
            geometry_passes: r.geometry_passes,
            cpu_seconds: r.cpu_seconds,
        })
        .collect();
    Ok(Some(CompareFrames {
        width,
        height,
        images,
        lists,
        background,
        hair,
        model: ModelContext {
            hair_alpha: settings.render.opacity(),
            depth_range: r.eye_depth_range(&settings.camera),
        },
        settings: settings.clone(),
    }))
}

/// One slot's image before the metrics against the first.
struct Rendered {
    name: &'static str,
    label: &'static str,
    image: RgbaImage,
    passes: Vec<PassTime>,
    geometry_passes: u32,
    cpu_seconds: Option<f64>,
}

/// What a compare render takes from the window: its GPU (a clone: the same device and queue), the scene on
/// screen (at the timeline's frame) and the fur built on it.
pub struct CompareSource {
    pub gpu: Gpu,
    pub scene: Scene,
    pub fur: Option<crate::fur::settings::FurScene>,
    /// The box the window's renderer fits the hair maps to under `light.fit = bound` or `stable` (the whole motion's once
    /// it is known), so the compare images fit the same light frame as the viewport.
    pub fit_bound: Option<crate::scene::Aabb>,
    /// The meshes riding on the motion's root frame and their pose at the timeline's frame (the turned head).
    pub mesh_pose: Option<(Vec<usize>, glam::Affine3A)>,
}

/// The worker of a compare job: a renderer of its own from `source`, then [`render_compare_steps`] reporting
/// through `ctl`; `None` when cancelled.
pub(super) fn render_job(
    source: &CompareSource,
    settings: &Settings,
    slots: &[Slot; 4],
    (width, height): (u32, u32),
    ctl: &JobCtl,
) -> Option<Result<CompareFrames, String>> {
    ctl.step("a renderer for the compare view", 0.0).then_some(())?;
    let renderer = Renderer::new(&source.gpu, &source.scene, settings.render.map_resolution)
        .map_err(|e| format!("compare view: renderer: {e}"))
        .and_then(|mut r| {
            r.set_fit_bound(source.fit_bound);
            if let Some((meshes, pose)) = &source.mesh_pose {
                r.pose_meshes(meshes, *pose)
                    .map_err(|e| format!("compare view: meshes: {e}"))?;
            }
            if let Some(fur) = &source.fur {
                r.set_fur(Some((fur, &settings.fur)))
                    .map_err(|e| format!("compare view: fur: {e}"))?;
            }
            Ok(r)
        });
    let mut r = match renderer {
        Ok(r) => r,
        Err(e) => return Some(Err(e)),
    };
    let scene = match &source.mesh_pose {
        Some((meshes, pose)) => match source.scene.posed(meshes, *pose) {
            Ok(s) => s,
            Err(e) => return Some(Err(format!("compare view: meshes: {e}"))),
        },
        None => source.scene.clone(),
    };
    render_compare_steps(&mut r, &scene, settings, slots, width, height, &mut ctl.clone()).transpose()
}

/// The frame of `settings` with `technique` at `width`×`height`.
pub(super) fn frame_input<'a>(
    settings: &'a Settings,
    method: &'a dyn LightMethod,
    technique: &'a dyn EyeTransparency,
    technique_params: &'a ParamValues,
    width: u32,
    height: u32,
) -> FrameInput<'a> {
    FrameInput {
        camera: &settings.camera,
        light: &settings.light,
        render: &settings.render,
        method,
        method_params: &settings.method.params,
        technique,
        technique_params,
        width,
        height,
    }
}
