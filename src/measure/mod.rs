//! Measuring methods against the exact reference on one scene: depth complexity, map error (design.md: the
//! mean over occupied texels of the mean |V_m - V_ref| over the texel's samples — every fragment depth and a
//! uniform grid between its nearest and furthest fragment, `visibility::metrics::sample_depths`), GPU time per
//! pass (median over frames) and memory. The method side is read through its GPU lookup (the evaluation
//! pass), so what is measured is what the GPU computes.

pub mod decompose;
pub mod fibre_slab;
pub mod fibre_visibility;
pub mod fur;
pub mod motion;
pub mod probe;
pub mod shading;
pub mod temporal;
pub mod transparency;
pub mod truth;

use crate::gpu::timing::Phase;
use crate::gpu::{AdapterPreference, Gpu};
use crate::methods::{self, ParamValues, registry};
use crate::progress::{Outcome, Progress, share};
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use crate::visibility::{self, ErrorDistribution, Fragment, TexelModel, metrics};
use anyhow::Result;

pub use crate::selection::MethodConfig;

/// The configurations `measure` reports when none is given: each registered method's
/// [`methods::ShadowMethod::usual_configs`].
pub fn usual_configs() -> Vec<MethodConfig> {
    registry::all()
        .iter()
        .flat_map(|m| {
            m.usual_configs()
                .into_iter()
                .map(|params| MethodConfig::new(m.name(), params))
        })
        .collect()
}

/// What the reference says about the scene's light view.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneStats {
    /// The adapter the measurement ran on.
    pub device: String,
    pub strands: usize,
    pub segments: usize,
    pub map_resolution: u32,
    pub fragments: usize,
    pub occupied_texels: usize,
    pub max_depth_complexity: usize,
    pub mean_depth_complexity: f64,
}

/// One configuration measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    pub config: MethodConfig,
    /// Mean texel error over occupied texels.
    pub map_error: f64,
    /// How the texel (mean) errors are spread over the occupied texels: percentiles, the worst texel, the
    /// shares above 0.05 and 0.1.
    pub texel_errors: ErrorDistribution,
    /// Median GPU milliseconds per pass of the method's own light passes, by pass name.
    pub pass_ms: Vec<(String, f64)>,
    /// GPU milliseconds of each timed frame, by pass name (the samples behind `pass_ms`).
    pub pass_frames_ms: Vec<(String, Vec<f64>)>,
    /// The method's maps (what its lookup reads, the shared light-depth maps included).
    pub memory_bytes: u64,
    /// What the method builds its maps from each frame and its lookup does not read (`MethodGpu::build_bytes`).
    pub build_memory_bytes: u64,
    pub geometry_passes: u32,
    /// Mean |V_m - V_ref| over the hair points the camera sees (design.md's shading error).
    pub shading_error: f64,
    /// RMSE (RGB in [0,1]) and PSNR (dB) of the final image against the image shaded with the reference.
    pub image_rmse: f64,
    pub image_psnr: f64,
    /// FLIP of the final image against the image shaded with the reference, the mean over all pixels.
    pub image_flip: f64,
    /// Mean frame-to-frame change of V at the visible hair points while the light turns by
    /// [`FLICKER_STEP_DEG`] per frame, minus the reference's own change (design.md's light-turn flicker; the
    /// flicker of hair in motion is [`temporal`]'s).
    pub light_turn_flicker: f64,
}

/// Light rotation per frame of the light-turn flicker measurement, in degrees of azimuth.
pub const FLICKER_STEP_DEG: f32 = 0.5;
/// Frames of the light-turn flicker measurement.
pub const FLICKER_FRAMES: usize = 5;
/// Size of the images compared for the image error.
pub const IMAGE_SIZE: (u32, u32) = (320, 240);

impl Measurement {
    pub fn total_ms(&self) -> f64 {
        self.pass_ms.iter().map(|(_, ms)| ms).sum::<f64>() + 0.0
    }
}

/// Samples per texel: every fragment depth and this many grid points across the texel's range.
pub const GRID_POINTS: usize = 16;

pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { 0.0 } else { v[v.len() / 2] }
}

/// Measures `configs` on the scene of `settings` (`frames` timed frames each, after one warm-up) on a device
/// opened by the adapter policy (hardware first, `HAIRLAB_ADAPTER` overrides).
pub fn measure(
    settings: &Settings,
    configs: &[MethodConfig],
    frames: u32,
    progress: &mut dyn Progress,
) -> Result<Outcome<(SceneStats, Vec<Measurement>)>> {
    measure_each(settings, configs, frames, progress, |_, _| Ok(()))
}

/// [`measure`], handing the measurements so far to `finished` after each configuration (to write them; its error
/// ends the run with it). A stop `progress` asks for ends the run before the next configuration:
/// [`Outcome::Stopped`] with the configurations finished so far.
pub fn measure_each(
    settings: &Settings,
    configs: &[MethodConfig],
    frames: u32,
    progress: &mut dyn Progress,
    finished: impl FnMut(&SceneStats, &[Measurement]) -> Result<()>,
) -> Result<Outcome<(SceneStats, Vec<Measurement>)>> {
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    measure_on_each(&gpu, settings, configs, frames, progress, finished)
}

/// [`measure`] on a given device (tests pass the software adapter).
pub fn measure_on(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MethodConfig],
    frames: u32,
    progress: &mut dyn Progress,
) -> Result<Outcome<(SceneStats, Vec<Measurement>)>> {
    measure_on_each(gpu, settings, configs, frames, progress, |_, _| Ok(()))
}

/// [`measure_each`] on a given device.
pub fn measure_on_each(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MethodConfig],
    frames: u32,
    progress: &mut dyn Progress,
    mut finished: impl FnMut(&SceneStats, &[Measurement]) -> Result<()>,
) -> Result<Outcome<(SceneStats, Vec<Measurement>)>> {
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let res = s.render.light_map_side();
    let mut r = Renderer::new(gpu, &scene, res)?;
    // Every image is composited exactly, so the image error is the shadows' alone: against exact shadows and
    // exact transparency.
    let technique = crate::render::transparency::registry::reference();
    let input = |method: &'static dyn methods::ShadowMethod, params| FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method,
        method_params: params,
        technique,
        technique_params: &s.transparency.params,
        width: 8,
        height: 8,
    };
    // The reference runs whatever the answer: the stats need it (a stop ends before the first configuration).
    let mut go = progress.step(registry::reference().name(), 0.0);
    let empty = ParamValues::new();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render)?;
    let occupied: Vec<usize> = (0..lists.len()).filter(|&t| !lists[t].is_empty()).collect();
    let fragments: usize = lists.iter().map(Vec::len).sum();
    let stats = SceneStats {
        device: crate::gpu::describe(&gpu.info),
        strands: scene.strands.strand_count(),
        segments: scene.strands.segment_count(),
        map_resolution: res,
        fragments,
        occupied_texels: occupied.len(),
        max_depth_complexity: lists.iter().map(Vec::len).max().unwrap_or(0),
        mean_depth_complexity: if occupied.is_empty() {
            0.0
        } else {
            fragments as f64 / occupied.len() as f64
        },
    };
    let texels = TexelSamples::of(&lists, res);
    // The hair points the camera sees, their reference visibility, the reference image, and the reference's
    // own frame-to-frame change under the turning light.
    let (w, h) = IMAGE_SIZE;
    let full = |method: &'static dyn methods::ShadowMethod, params, light| FrameInput {
        camera: &s.camera,
        light,
        render: &s.render,
        method,
        method_params: params,
        technique,
        technique_params: &s.transparency.params,
        width: w,
        height: h,
    };
    let reference_method = registry::reference();
    r.render(&full(reference_method, &empty, &s.light))?;
    let reference_image = r.read_output()?;
    let points = visible_hair_points(&r, &scene, &s, &r.read_eye_depth()?);
    let lights = turning_lights(&s);
    let mut reference_frames = Vec::with_capacity(lights.len());
    for light in &lights {
        let lists = r.reference_lists(&s.camera, light, &s.render)?;
        let samples = light_samples(&r, light, &s.render, &points);
        reference_frames.push(samples.reference(&lists, res));
    }
    let reference_shading = &reference_frames[0];
    let reference_change = mean_change(&reference_frames);
    let mut out = Vec::new();
    for (i, c) in configs.iter().enumerate() {
        go = go && progress.step(&c.label(), share(i, configs.len()));
        if !go {
            break;
        }
        let method = registry::find(&c.name).map_err(anyhow::Error::msg)?;
        let per_pass = time_light_passes(&mut r, &input(method, &c.params), frames, 1)?.method;
        let texel_errors = texels.errors(&evaluate_all(&mut r, method, &texels.samples)?);
        let (memory_bytes, build_memory_bytes, geometry_passes) =
            r.method_gpu(method).map_or((0, 0, 0), |g| {
                (g.memory_bytes(), g.build_bytes(), g.geometry_passes())
            });
        // Flicker: the method's visibility at the visible points, frame by frame (frame 0 gives the shading
        // error).
        let mut frames_v = Vec::with_capacity(lights.len());
        for light in &lights {
            r.render_light(&full(method, &c.params, light))?;
            let samples = light_samples(&r, light, &s.render, &points);
            frames_v.push(samples.average(&evaluate_all(&mut r, method, &samples.samples)?));
        }
        let shading_error = mean_abs_diff(&frames_v[0], reference_shading);
        r.render(&full(method, &c.params, &s.light))?;
        let image = r.read_output()?;
        let (image_rmse, image_psnr) = image_error(&image, &reference_image);
        let image_flip = crate::transparency::FlipMap::new(&image, &reference_image)
            .metrics(|_, _| false)
            .mean;
        out.push(Measurement {
            config: c.clone(),
            map_error: map_error(&texel_errors),
            texel_errors: ErrorDistribution::of(&texel_errors),
            pass_ms: per_pass
                .iter()
                .map(|(n, v)| (n.clone(), median(v.clone())))
                .collect(),
            pass_frames_ms: per_pass,
            memory_bytes,
            build_memory_bytes,
            geometry_passes,
            shading_error,
            image_rmse,
            image_psnr,
            image_flip,
            light_turn_flicker: mean_change(&frames_v) - reference_change,
        });
        finished(&stats, &out)?;
    }
    Ok(Outcome::new((stats, out), !go))
}

/// GPU milliseconds of each of the method's own light passes (the shared light-depth and mesh shadow passes
/// left out), frame by frame over `frames` timed frames after `warmup` discarded frames.
fn time_light_passes(
    r: &mut Renderer,
    input: &FrameInput,
    frames: u32,
    warmup: u32,
) -> Result<LightPassTimes> {
    let mut t = LightPassTimes::default();
    for frame in 0..warmup + frames {
        r.render_light(input)?;
        let times = r.wait_timings();
        if frame < warmup {
            continue;
        }
        for pass in times {
            let passes = match pass.phase {
                Phase::Method => &mut t.method,
                Phase::SharedLight => &mut t.shared,
                _ => continue,
            };
            match passes.iter_mut().find(|(n, _)| *n == pass.name) {
                Some((_, v)) => v.push(pass.ms),
                None => passes.push((pass.name, vec![pass.ms])),
            }
        }
    }
    Ok(t)
}

/// GPU milliseconds of the timed frames of a light frame, by pass name: the method's own passes, and the passes
/// every method shares (light depth, the meshes' shadow map, the compute rasteriser's).
#[derive(Clone, Debug, Default, PartialEq)]
struct LightPassTimes {
    method: Vec<(String, Vec<f64>)>,
    shared: Vec<(String, Vec<f64>)>,
}

/// The GPU cost of one configuration, without its error (what the bench's scaling mode fits).
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    pub config: MethodConfig,
    /// GPU milliseconds of each timed frame, by pass name; or why the method refused the scene (e.g. a list
    /// longer than a CPU adapter's compressor takes), one line.
    pub pass_frames_ms: Result<Vec<(String, Vec<f64>)>, String>,
    /// GPU milliseconds of each timed frame of the passes every method shares (light depth, the meshes' shadow
    /// map, the compute rasteriser's), by pass name (none when refused).
    pub shared_pass_frames_ms: Vec<(String, Vec<f64>)>,
    pub memory_bytes: u64,
}

/// What [`time_configs`] measured, and on what.
#[derive(Clone, Debug, PartialEq)]
pub struct Timings {
    pub device: String,
    pub strands: usize,
    pub segments: usize,
    pub rows: Vec<Timing>,
}

/// Times `configs` on the scene of `settings` (`frames` timed frames each, after `warmup` discarded) on a device
/// opened by the adapter policy: the light passes only, no reference and no error, so that it scales to
/// millions of segments. A configuration the renderer refuses is recorded with its error and the others go on.
pub fn time_configs(
    settings: &Settings,
    configs: &[MethodConfig],
    frames: u32,
    warmup: u32,
    progress: &mut dyn Progress,
) -> Result<Timings> {
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution)?;
    let technique = s.transparency.technique()?;
    let mut out = Vec::with_capacity(configs.len());
    for (i, c) in configs.iter().enumerate() {
        if !progress.step(&c.label(), share(i, configs.len())) {
            break;
        }
        let method = registry::find(&c.name).map_err(anyhow::Error::msg)?;
        let input = FrameInput {
            camera: &s.camera,
            light: &s.light,
            render: &s.render,
            method,
            method_params: &c.params,
            technique,
            technique_params: &s.transparency.params,
            width: 8,
            height: 8,
        };
        let times = time_light_passes(&mut r, &input, frames, warmup).map_err(|e| format!("{e:#}"));
        out.push(Timing {
            config: c.clone(),
            shared_pass_frames_ms: times.as_ref().map_or(Vec::new(), |t| t.shared.clone()),
            pass_frames_ms: times.map(|t| t.method),
            memory_bytes: r.method_gpu(method).map_or(0, |g| g.memory_bytes()),
        });
    }
    Ok(Timings {
        device: crate::gpu::describe(&gpu.info),
        strands: scene.strands.strand_count(),
        segments: scene.strands.segment_count(),
        rows: out,
    })
}

pub(crate) fn evaluate_all(
    r: &mut Renderer,
    method: &dyn methods::ShadowMethod,
    samples: &[[f32; 3]],
) -> Result<Vec<f32>> {
    let mut v = Vec::with_capacity(samples.len());
    for chunk in samples.chunks(1 << 20) {
        v.extend(r.evaluate(method, chunk)?);
    }
    Ok(v)
}

/// The light turned by `FLICKER_STEP_DEG` per frame, `FLICKER_FRAMES` frames from the settings' light.
fn turning_lights(s: &Settings) -> Vec<crate::scene::Light> {
    (0..FLICKER_FRAMES)
        .map(|f| crate::scene::Light {
            azimuth_deg: s.light.azimuth_deg + f as f32 * FLICKER_STEP_DEG,
            ..s.light
        })
        .collect()
}

/// The hair points the camera sees: every strand point and segment midpoint inside the view of an
/// `IMAGE_SIZE` image and in front of the opaque meshes (`eye_depth`, the mesh-only depth buffer). Hair is
/// semi-transparent, so hair behind hair still counts: every such point is a hair fragment on screen.
pub fn visible_hair_points(
    r: &Renderer,
    scene: &crate::scene::Scene,
    s: &Settings,
    eye_depth: &[f32],
) -> Vec<glam::Vec3> {
    visible_tracked_points(r, &scene.strands, &s.camera, eye_depth)
        .into_iter()
        .map(|(_, p)| p)
        .collect()
}

/// [`visible_hair_points`] of `strands` (as the renderer holds them) seen by `camera`, each with its
/// tracked-point id ([`temporal::point_id`], [`temporal::midpoint_id`]); per strand its points, then its
/// midpoints.
pub fn visible_tracked_points(
    r: &Renderer,
    strands: &crate::scene::Strands,
    camera: &crate::scene::Camera,
    eye_depth: &[f32],
) -> Vec<(u32, glam::Vec3)> {
    let (w, h) = IMAGE_SIZE;
    let clip = r.world_to_clip(camera, w, h);
    let mut out = Vec::new();
    for (start, n) in strands.ranges() {
        let pts = &strands.points[start..start + n];
        let ids = (start..start + n).map(temporal::point_id);
        let mid_ids = (start..start + n.saturating_sub(1)).map(temporal::midpoint_id);
        let mids = pts.windows(2).map(|p| (p[0] + p[1]) * 0.5);
        for (id, p) in ids.zip(pts.iter().copied()).chain(mid_ids.zip(mids)) {
            let c = clip.project_point3(p);
            if c.x.abs() >= 1.0 || c.y.abs() >= 1.0 || !(0.0..=1.0).contains(&c.z) {
                continue;
            }
            let px = (((c.x * 0.5 + 0.5) * w as f32) as usize).min(w as usize - 1);
            let py = (((0.5 - c.y * 0.5) * h as f32) as usize).min(h as usize - 1);
            if eye_depth.get(py * w as usize + px).is_some_and(|d| c.z <= *d) {
                out.push((id, p));
            }
        }
    }
    out
}

/// The map error's samples of one light view: every occupied texel's sample depths
/// (`metrics::sample_depths` with [`GRID_POINTS`]) as `(texel x, texel y, depth)`, the reference's visibility
/// at each, and each texel's range of samples.
pub(crate) struct TexelSamples {
    pub samples: Vec<[f32; 3]>,
    pub reference: Vec<f32>,
    pub spans: Vec<std::ops::Range<usize>>,
}

impl TexelSamples {
    /// From the reference's per-texel lists of a `res`² map.
    pub fn of(lists: &[Vec<crate::render::passes::abuffer::RefFragment>], res: u32) -> TexelSamples {
        let mut out = TexelSamples {
            samples: Vec::new(),
            reference: Vec::new(),
            spans: Vec::new(),
        };
        for (t, list) in lists.iter().enumerate().filter(|(_, l)| !l.is_empty()) {
            let frags: Vec<Fragment> = list.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect();
            let zs = metrics::sample_depths(&frags, GRID_POINTS);
            let start = out.samples.len();
            let (x, y) = ((t as u32 % res) as f32, (t as u32 / res) as f32);
            out.samples.extend(zs.iter().map(|&z| [x, y, z]));
            out.reference.extend(visibility::Reference.curve(&frags, &zs));
            out.spans.push(start..out.samples.len());
        }
        out
    }

    /// Each occupied texel's mean `|V_m − V_ref|` over its samples, given the method's `v` at the samples.
    pub fn errors(&self, v: &[f32]) -> Vec<f64> {
        self.spans
            .iter()
            .map(|span| {
                span.clone()
                    .map(|i| (v[i] - self.reference[i]).abs() as f64)
                    .sum::<f64>()
                    / span.len() as f64
            })
            .collect()
    }
}

/// The map error: the mean of the texel errors (0 when no texel holds fragments).
pub(crate) fn map_error(texel_errors: &[f64]) -> f64 {
    if texel_errors.is_empty() {
        0.0
    } else {
        texel_errors.iter().sum::<f64>() / texel_errors.len() as f64
    }
}

/// The samples of the eye lookup at hair points: per point, the `(texel x, texel y, light depth)` of each texel
/// of the maps as built that the lookup averages ([`crate::visibility::lookup`]: the `s × s` sub-texels of the
/// point's base texel under `render.light_supersample = s`, one texel at 1), `per_point` consecutive samples a
/// point. The PCF and jitter filters are not applied: the measurement reads the methods' maps.
pub(crate) struct PointSamples {
    pub samples: Vec<[f32; 3]>,
    pub per_point: usize,
}

impl PointSamples {
    /// Each point's mean of `v`, the values at [`PointSamples::samples`] (and at any whole points' samples
    /// appended after them).
    pub fn average(&self, v: &[f32]) -> Vec<f32> {
        if self.per_point == 1 {
            return v.to_vec();
        }
        v.chunks(self.per_point)
            .map(|c| c.iter().sum::<f32>() / c.len() as f32)
            .collect()
    }

    /// Each point's exact visibility from the reference lists of the maps as built, `side` texels a side.
    pub fn reference(
        &self,
        lists: &[Vec<crate::render::passes::abuffer::RefFragment>],
        side: u32,
    ) -> Vec<f32> {
        let v: Vec<f32> = self
            .samples
            .iter()
            .map(|x| reference_visibility(lists, side, x))
            .collect();
        self.average(&v)
    }
}

/// [`PointSamples`] of each point in the hair light frame of `light`, under `render`'s supersampling. The frame
/// is fitted to the strands, so every hair point lies inside the map (the clamp only guards the edge texel).
pub(crate) fn light_samples(
    r: &Renderer,
    light: &crate::scene::Light,
    render: &crate::render::RenderSettings,
    points: &[glam::Vec3],
) -> PointSamples {
    let frame = r.hair_light_frame(light);
    let clip = frame.world_to_clip();
    let supersample = render.light_supersample.max(1);
    let lookup = crate::visibility::lookup::Lookup {
        base: r.map_resolution() / supersample,
        supersample,
        pcf: false,
    };
    let res = lookup.base as f32;
    let mut samples = Vec::with_capacity(points.len() * (supersample * supersample) as usize);
    for p in points {
        let c = clip.project_point3(*p);
        let uv = glam::Vec2::new(c.x * 0.5 + 0.5, 0.5 - c.y * 0.5);
        let t = (uv * res)
            .floor()
            .clamp(glam::Vec2::ZERO, glam::Vec2::splat(res - 1.0));
        let z = frame.depth(*p);
        let texels = lookup.around([t.x as u32, t.y as u32]);
        samples.extend(texels.iter().map(|t| [t[0] as f32, t[1] as f32, z]));
    }
    PointSamples {
        samples,
        per_point: (supersample * supersample) as usize,
    }
}

/// Exact visibility at a sample from the reference lists.
pub(crate) fn reference_visibility(
    lists: &[Vec<crate::render::passes::abuffer::RefFragment>],
    res: u32,
    sample: &[f32; 3],
) -> f32 {
    let t = sample[1] as usize * res as usize + sample[0] as usize;
    let frags: Vec<Fragment> = lists[t].iter().map(|f| Fragment::new(f.depth, f.alpha)).collect();
    crate::visibility::reference::visibility(&frags, sample[2])
}

fn mean_abs_diff(a: &[f32], b: &[f32]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    a.iter().zip(b).map(|(x, y)| (x - y).abs() as f64).sum::<f64>() / a.len() as f64
}

/// Mean |V(f+1) - V(f)| over points and successive frames.
fn mean_change(frames: &[Vec<f32>]) -> f64 {
    let pairs: Vec<f64> = frames.windows(2).map(|f| mean_abs_diff(&f[1], &f[0])).collect();
    if pairs.is_empty() {
        0.0
    } else {
        pairs.iter().sum::<f64>() / pairs.len() as f64
    }
}

/// The image error, defined once with the other image metrics.
pub use crate::transparency::metrics::image_error;
