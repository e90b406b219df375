//! Measuring the eye transparency techniques against the exact reference (`sorted`) on one view: the image
//! metrics of `transparency::metrics` over all pixels and over the hair pixels (those whose exact list is not
//! empty), GPU milliseconds of the technique's own passes (median over frames), memory, geometry passes, and the
//! view's eye depth complexity. The shadow method is the preset's, the same for every technique.

use super::{IMAGE_SIZE, median};
use crate::gpu::{AdapterPreference, Gpu};
use crate::methods::registry as methods;
use crate::progress::{Progress, share};
use crate::render::method::ParamValues;
use crate::render::transparency::registry;
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use crate::transparency::metrics::{ImageMetrics, compare};
use anyhow::Result;

pub use crate::selection::TechniqueConfig;

/// Every registered technique at its defaults.
pub fn all_configs() -> Vec<TechniqueConfig> {
    registry::all()
        .iter()
        .map(|t| TechniqueConfig::new(t.name(), ParamValues::new()))
        .collect()
}

/// The view the techniques are measured on.
#[derive(Clone, Debug, PartialEq)]
pub struct EyeStats {
    pub width: u32,
    pub height: u32,
    pub strands: usize,
    pub segments: usize,
    pub hair_pixels: usize,
    pub fragments: u64,
    /// Fragments of the deepest pixel, and the mean over hair pixels.
    pub max_depth_complexity: u32,
    pub mean_depth_complexity: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct TechniqueMeasurement {
    pub config: TechniqueConfig,
    pub metrics: ImageMetrics,
    /// Median GPU milliseconds of each of the technique's own passes (everything after the meshes).
    pub pass_ms: Vec<(String, f64)>,
    pub memory_bytes: u64,
    pub geometry_passes: u32,
}

impl TechniqueMeasurement {
    pub fn total_ms(&self) -> f64 {
        self.pass_ms.iter().map(|(_, ms)| ms).sum()
    }
}

/// Measures `configs` on the view of `settings` at [`IMAGE_SIZE`] (`frames` timed frames each after one
/// warm-up) on a device opened by the adapter policy.
pub fn measure(
    settings: &Settings,
    configs: &[TechniqueConfig],
    frames: u32,
    progress: &mut dyn Progress,
) -> Result<(EyeStats, Vec<TechniqueMeasurement>)> {
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    measure_on(&gpu, settings, configs, frames, progress)
}

/// [`measure`] on `gpu`.
pub fn measure_on(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[TechniqueConfig],
    frames: u32,
    progress: &mut dyn Progress,
) -> Result<(EyeStats, Vec<TechniqueMeasurement>)> {
    measure_each_on(gpu, settings, configs, frames, progress, |_, _| Ok(()))
}

/// [`measure_on`] calling `after` with the rows so far after each configuration; the run stops, with those rows,
/// when it breaks (Ctrl-C, `crate::cli::interrupt`).
pub fn measure_each_on(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[TechniqueConfig],
    frames: u32,
    progress: &mut dyn Progress,
    mut after: impl FnMut(&EyeStats, &[TechniqueMeasurement]) -> Result<()>,
) -> Result<(EyeStats, Vec<TechniqueMeasurement>)> {
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let mut r = Renderer::new(gpu, &scene, s.render.map_resolution)?;
    let method = methods::find(&s.method.name).map_err(anyhow::Error::msg)?;
    let (width, height) = IMAGE_SIZE;
    let frame = |technique, params| FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method,
        method_params: &s.method.params,
        technique,
        technique_params: params,
        width,
        height,
    };
    // The reference runs whatever the answer: the stats need it (a stop ends before the first configuration).
    let mut go = progress.step(registry::reference().name(), 0.0);
    let empty = ParamValues::new();
    let lists = r.eye_lists(&frame(registry::reference(), &empty))?;
    r.render(&frame(registry::reference(), &empty))?;
    let reference = r.read_output()?;
    let hair: Vec<bool> = lists.iter().map(|l| !l.is_empty()).collect();
    let hair_pixels = hair.iter().filter(|&&h| h).count();
    let fragments: u64 = lists.iter().map(|l| l.len() as u64).sum();
    let stats = EyeStats {
        width,
        height,
        strands: scene.strands.strand_count(),
        segments: scene.strands.segment_count(),
        hair_pixels,
        fragments,
        max_depth_complexity: lists.iter().map(Vec::len).max().unwrap_or(0) as u32,
        mean_depth_complexity: if hair_pixels == 0 {
            0.0
        } else {
            fragments as f64 / hair_pixels as f64
        },
    };
    let mut out = Vec::with_capacity(configs.len());
    for (i, c) in configs.iter().enumerate() {
        go = go && progress.step(&c.label(), share(i, configs.len()));
        if !go {
            break;
        }
        let input = frame(c.plugin()?, &c.params);
        let mut per_pass: Vec<(String, Vec<f64>)> = Vec::new();
        for f in 0..=frames {
            r.render(&input)?;
            let times = r.wait_timings();
            if f == 0 {
                continue;
            }
            // The technique's own passes.
            for t in times.iter().filter(|t| t.phase.is_technique()) {
                match per_pass.iter_mut().find(|(n, _)| *n == t.name) {
                    Some((_, v)) => v.push(t.ms),
                    None => per_pass.push((t.name.clone(), vec![t.ms])),
                }
            }
        }
        let image = r.read_output()?;
        out.push(TechniqueMeasurement {
            config: c.clone(),
            metrics: compare(&image, &reference, &hair),
            pass_ms: per_pass.into_iter().map(|(n, v)| (n, median(v))).collect(),
            memory_bytes: r.memory().transparency_targets,
            geometry_passes: r.eye_geometry_passes(),
        });
        after(&stats, &out)?;
    }
    Ok((stats, out))
}
