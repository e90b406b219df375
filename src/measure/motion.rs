//! Methods measured over a motion (`measure motion`): the preset's `[motion]` played frame by frame with one
//! renderer, the points written through `Renderer::update_points` as `hairlab render --frames` does, and each
//! frame's map error, shading error at the tracked hair points, image and GPU time compared with the exact
//! reference of the same frame; the temporal metrics ([`super::temporal`]) follow the points across frames.
//! Where the preset simulates, the simulation's own cost per frame is measured too: the CPU model's wall time and
//! the GPU compute pass's ([`crate::motion::gpu`]) timestamps.

use super::temporal::{self, Flicker, FollowedPoint, OverFrames, TrackedFrame};
use super::{IMAGE_SIZE, MethodConfig, PointSamples, TexelSamples, evaluate_all, light_samples, median};
use crate::gpu::Gpu;
use crate::gpu::timing::{Phase, phase_ms};
use crate::methods::{self, ParamValues, registry};
use crate::progress::{Outcome, Progress, share};
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use anyhow::{Result, bail};
use glam::Vec3;
use image::RgbaImage;
use serde::Serialize;

/// When a configuration's `auto` parameter is chosen by the method's analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tuning {
    /// No `auto` parameter.
    Fixed,
    /// `key=auto`: chosen once, on frame 0's reference lists, and kept.
    FirstFrame,
    /// `key=auto-per-frame`: chosen again on every frame's reference lists.
    EveryFrame,
}

/// One configuration of a motion measurement: a method configuration and, for a method with an analysis,
/// when the analysis chooses the parameter marked `auto`.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionConfig {
    /// The fixed parameters.
    pub config: MethodConfig,
    pub tuning: Tuning,
}

/// The word of [`Tuning::FirstFrame`] and [`Tuning::EveryFrame`] in a configuration.
const AUTO: &str = "auto";
const AUTO_PER_FRAME: &str = "auto-per-frame";

impl MotionConfig {
    pub fn fixed(config: MethodConfig) -> MotionConfig {
        MotionConfig {
            config,
            tuning: Tuning::Fixed,
        }
    }

    /// `name:key=value,...`, where the key the method's analysis chooses may be `auto` (chosen on frame 0) or
    /// `auto-per-frame` (chosen on every frame).
    pub fn parse(text: &str) -> Result<MotionConfig> {
        let (name, pairs) = crate::selection::split_config(text)?;
        let mut fixed = Vec::new();
        let mut tuning = Tuning::Fixed;
        for (key, value) in pairs {
            let t = match value {
                AUTO => Tuning::FirstFrame,
                AUTO_PER_FRAME => Tuning::EveryFrame,
                _ => {
                    fixed.push(format!("{key}={value}"));
                    continue;
                }
            };
            let method = registry::find(name).map_err(anyhow::Error::msg)?;
            let tunes = method.analysis().map(|a| a.tunes);
            if tunes != Some(key) || tuning != Tuning::Fixed {
                bail!(
                    "'{text}': {} cannot choose '{key}' (its analysis chooses {}, once)",
                    method.name(),
                    tunes.unwrap_or("nothing")
                );
            }
            tuning = t;
        }
        Ok(MotionConfig {
            config: MethodConfig::parse(&format!("{name}:{}", fixed.join(",")))?,
            tuning,
        })
    }

    /// The configuration as [`MotionConfig::parse`] reads it (the chosen key last).
    pub fn label(&self) -> String {
        let base = self.config.label();
        let word = match self.tuning {
            Tuning::Fixed => return base,
            Tuning::FirstFrame => AUTO,
            Tuning::EveryFrame => AUTO_PER_FRAME,
        };
        let key = registry::find(&self.config.name)
            .ok()
            .and_then(|m| m.analysis())
            .map_or("?", |a| a.tunes);
        let sep = if self.config.params.is_empty() { ':' } else { ',' };
        format!("{base}{sep}{key}={word}")
    }
}

/// The configurations `measure motion` reports when none is given: [`super::usual_configs`].
pub fn usual_configs() -> Vec<MotionConfig> {
    super::usual_configs()
        .into_iter()
        .map(MotionConfig::fixed)
        .collect()
}

/// One frame of one configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameRow {
    pub config: String,
    pub frame: u32,
    pub map_error: f64,
    pub shading_error: f64,
    /// Tracked points the camera sees in this frame.
    pub tracked_points: usize,
    /// From the previous frame to this one (empty in frame 0): the pair's flicker figures and image flicker.
    pub flicker: Option<f64>,
    pub flicker_p99: Option<f64>,
    pub pop_rate: Option<f64>,
    pub max_pop: Option<f64>,
    pub image_flicker: Option<f64>,
    /// The method's own light passes, GPU milliseconds.
    pub gpu_ms: f64,
    /// FLIP of the frame's image against the reference's (mean over all pixels, as `measure`'s image column).
    pub image_flip: f64,
}

/// One configuration over the motion.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionRow {
    pub config: MotionConfig,
    pub map_error: OverFrames,
    pub shading_error: OverFrames,
    pub flicker: Flicker,
    pub image_flicker: f64,
    /// Median over the frames of the method's own light passes, GPU milliseconds.
    pub gpu_ms: f64,
    /// Mean over the frames of [`FrameRow::image_flip`].
    pub image_flip: f64,
    pub frames: Vec<FrameRow>,
    /// The method's visibility at the followed point, per frame ([`MotionOptions::follow`]; else empty).
    pub followed: Vec<f32>,
}

/// The simulation's cost per frame on this scene (a simulated motion only).
#[derive(Clone, Debug, PartialEq)]
pub struct SimCost {
    /// Median wall milliseconds of the CPU model per frame.
    pub cpu_ms: f64,
    /// Median GPU milliseconds of the compute pass per frame (its substeps), when the device has timestamps.
    pub gpu_ms: Option<f64>,
}

/// What a motion measurement found.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionMeasurement {
    pub device: String,
    pub strands: usize,
    pub segments: usize,
    pub frames: u32,
    pub rows: Vec<MotionRow>,
    pub sim: Option<SimCost>,
    /// The followed point and the reference's visibility at it, per frame.
    pub followed: Option<(FollowedPoint, Vec<f32>)>,
}

/// Told the measurement so far after each configuration finishes (to write it); its error ends the
/// measurement with it.
pub type AfterEach<'a> = &'a dyn Fn(&MotionMeasurement) -> Result<()>;

/// What a motion measurement does beyond its configurations.
#[derive(Clone, Copy, Default)]
pub struct MotionOptions<'a> {
    /// A hair point whose visibility is recorded every frame, for the reference and each configuration.
    pub follow: Option<FollowedPoint>,
    /// Called after each configuration ([`AfterEach`]).
    pub after_each: Option<AfterEach<'a>>,
}

/// The exact reference's view of one frame.
struct FrameReference {
    ids: Vec<u32>,
    samples: PointSamples,
    visibility: Vec<f32>,
    texels: TexelSamples,
    /// The analysis' choice on this frame, per configuration (empty for fixed ones).
    tuned: Vec<ParamValues>,
    /// The followed point's light sample and the reference's visibility there.
    followed: Option<(PointSamples, f32)>,
}

/// Measures `configs` over frames `0..frames` of `settings`' motion on `gpu`. A still preset is refused: there
/// is nothing temporal to measure. [`measure_motion`] with no options.
pub fn measure_motion_on(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MotionConfig],
    frames: u32,
    progress: &mut dyn Progress,
) -> Result<Outcome<MotionMeasurement>> {
    measure_motion(gpu, settings, configs, frames, MotionOptions::default(), progress)
}

/// [`measure_motion_on`] with `options`; `progress` is told what is measured and the share of the work done.
/// A stop it asks for returns [`Outcome::Stopped`] with the configurations finished (none when it came before
/// the first finished).
pub fn measure_motion(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MotionConfig],
    frames: u32,
    options: MotionOptions<'_>,
    progress: &mut dyn Progress,
) -> Result<Outcome<MotionMeasurement>> {
    let steps = frames as usize * (configs.len() + 2);
    let mut done = 0usize;
    let mut step = |what: &str| -> bool {
        done += 1;
        progress.step(what, share(done - 1, steps))
    };
    let mut s = settings.clone();
    let (mut scene, mut motion) = s.open_motion()?;
    if motion.is_still() {
        bail!("motion.source is \"none\": the preset has no motion to measure (try --preset wind)");
    }
    let count = motion.frame_count(&s.motion);
    if frames < 2 || frames > count {
        bail!("--frames {frames}: a motion measurement needs 2 to {count} frames (the motion's)");
    }
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    if let Some(f) = options.follow {
        f.check(&scene.strands).map_err(anyhow::Error::msg)?;
    }
    let mut points: Vec<Vec<Vec3>> = Vec::with_capacity(frames as usize);
    // The pose of the meshes on the root frame, per frame (drawn as `hairlab render --frames` draws them).
    let mut mesh_poses = Vec::with_capacity(frames as usize);
    let mut cpu_ms = Vec::with_capacity(frames as usize);
    for k in 0..frames {
        if !step(&format!("motion frame {k}")) {
            return Ok(Outcome::Stopped(nothing_measured(gpu, &scene, frames)));
        }
        let start = std::time::Instant::now();
        points.push(motion.frame(k)?.to_vec());
        mesh_poses.push(motion.mesh_pose(k).map(|(m, pose)| (m.to_vec(), pose)));
        cpu_ms.push(start.elapsed().as_secs_f64() * 1e3);
    }
    // Under `light.fit = bound` (`stable`) every frame's hair maps are fitted to the whole motion's box (its
    // bounding sphere).
    let fit_bound = match s.light.fit {
        crate::scene::LightFit::Bound | crate::scene::LightFit::Stable => Some(motion.bound(&s.motion)?),
        crate::scene::LightFit::PerFrame => None,
    };
    let sim = match motion {
        crate::motion::Motion::Simulate(sim) => Some(SimCost {
            cpu_ms: median(cpu_ms[1..].to_vec()),
            gpu_ms: gpu_sim_ms(gpu, *sim, frames)?,
        }),
        _ => None,
    };
    scene.set_strand_points(&points[0])?;
    let res = s.render.light_map_side();
    let mut r = Renderer::new(gpu, &scene, res)?;
    r.set_fit_bound(fit_bound);
    let analyses = configs
        .iter()
        .map(|c| -> Result<_> {
            if c.tuning == Tuning::Fixed {
                return Ok(None);
            }
            let method = registry::find(&c.config.name).map_err(anyhow::Error::msg)?;
            match method.analysis() {
                Some(a) => Ok(Some(a)),
                None => bail!(
                    "'{}': {} has no analysis to choose a value",
                    c.label(),
                    method.name()
                ),
            }
        })
        .collect::<Result<Vec<_>>>()?;
    // The reference, frame by frame.
    let empty = ParamValues::new();
    let mut references: Vec<FrameReference> = Vec::with_capacity(points.len());
    let mut reference_images = Vec::with_capacity(points.len());
    for (k, p) in points.iter().enumerate() {
        if !step(&format!("{} frame {k}", registry::reference().name())) {
            return Ok(Outcome::Stopped(nothing_measured(gpu, &scene, frames)));
        }
        scene.set_strand_points(p)?;
        r.update_points(p)?;
        if let Some((m, pose)) = &mesh_poses[k] {
            r.pose_meshes(m, *pose)?;
        }
        r.render(&input(&s, registry::reference(), &empty))?;
        r.wait_timings();
        reference_images.push(r.read_output()?);
        let mut tracked = super::visible_tracked_points(&r, &scene.strands, &s.camera, &r.read_eye_depth()?);
        tracked.sort_by_key(|(id, _)| *id);
        let (ids, at): (Vec<u32>, Vec<Vec3>) = tracked.into_iter().unzip();
        let lists = r.reference_lists(&s.camera, &s.light, &s.render)?;
        let samples = light_samples(&r, &s.light, &s.render, &at);
        let visibility = samples.reference(&lists, res);
        let tuned = configs
            .iter()
            .zip(&analyses)
            .enumerate()
            .map(|(i, (c, a))| match (c.tuning, a) {
                (Tuning::EveryFrame, Some(a)) => (a.run)(&lists, &c.config.params).apply,
                (Tuning::FirstFrame, Some(a)) if k == 0 => (a.run)(&lists, &c.config.params).apply,
                (Tuning::FirstFrame, Some(_)) => references[0].tuned[i].clone(),
                _ => ParamValues::new(),
            })
            .collect();
        let followed = options.follow.map(|f| {
            let sample = light_samples(&r, &s.light, &s.render, &[f.at(p)]);
            let v = sample.reference(&lists, res)[0];
            (sample, v)
        });
        references.push(FrameReference {
            ids,
            samples,
            visibility,
            texels: TexelSamples::of(&lists, res),
            tuned,
            followed,
        });
    }
    let followed = options.follow.map(|f| {
        let v = references
            .iter()
            .filter_map(|r| r.followed.as_ref().map(|(_, v)| *v))
            .collect();
        (f, v)
    });
    let (device, strands, segments) = (
        crate::gpu::describe(&gpu.info),
        scene.strands.strand_count(),
        scene.strands.segment_count(),
    );
    let measurement = |rows: Vec<MotionRow>| MotionMeasurement {
        device: device.clone(),
        strands,
        segments,
        frames,
        rows,
        sim: sim.clone(),
        followed: followed.clone(),
    };
    let mut rows = Vec::with_capacity(configs.len());
    for (ci, c) in configs.iter().enumerate() {
        let label = c.label();
        let method = registry::find(&c.config.name).map_err(anyhow::Error::msg)?;
        let (mut tracked, mut map, mut shading, mut gpu_ms) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut frame_rows: Vec<FrameRow> = Vec::with_capacity(points.len());
        let mut images: Vec<RgbaImage> = Vec::with_capacity(points.len());
        let mut followed = Vec::new();
        for (k, (p, reference)) in points.iter().zip(&references).enumerate() {
            if !step(&format!("{label} frame {k}")) {
                return Ok(Outcome::Stopped(measurement(rows)));
            }
            r.update_points(p)?;
            if let Some((m, pose)) = &mesh_poses[k] {
                r.pose_meshes(m, *pose)?;
            }
            let mut params = c.config.params.clone();
            params.extend(reference.tuned[ci].iter().map(|(k, v)| (k.clone(), *v)));
            r.render(&input(&s, method, &params))?;
            let ms = phase_ms(&r.wait_timings(), Phase::Method);
            let image = r.read_output()?;
            let texel_errors =
                reference
                    .texels
                    .errors(&evaluate_all(&mut r, method, &reference.texels.samples)?);
            let mut samples = reference.samples.samples.clone();
            if let Some((sample, _)) = &reference.followed {
                samples.extend_from_slice(&sample.samples);
            }
            let mut method_v = reference
                .samples
                .average(&evaluate_all(&mut r, method, &samples)?);
            if reference.followed.is_some() {
                followed.extend(method_v.pop());
            }
            let frame = TrackedFrame {
                ids: reference.ids.clone(),
                method: method_v,
                reference: reference.visibility.clone(),
            };
            let mut row = FrameRow {
                config: label.clone(),
                frame: k as u32,
                map_error: super::map_error(&texel_errors),
                shading_error: temporal::shading_error(&frame),
                tracked_points: frame.ids.len(),
                flicker: None,
                flicker_p99: None,
                pop_rate: None,
                max_pop: None,
                image_flicker: None,
                gpu_ms: ms,
                image_flip: crate::transparency::FlipMap::new(&image, &reference_images[k])
                    .metrics(|_, _| false)
                    .mean,
            };
            tracked.push(frame);
            images.push(image);
            if k > 0 {
                let pair = Flicker::over(&tracked[k - 1..=k]);
                row.flicker = Some(pair.mean);
                row.flicker_p99 = Some(pair.p99);
                row.pop_rate = Some(pair.pop_rate);
                row.max_pop = Some(pair.max_pop);
                row.image_flicker = Some(temporal::image_flicker(
                    &images[k - 1..=k],
                    &reference_images[k - 1..=k],
                ));
            }
            map.push(row.map_error);
            shading.push(row.shading_error);
            gpu_ms.push(ms);
            frame_rows.push(row);
        }
        rows.push(MotionRow {
            config: c.clone(),
            map_error: OverFrames::of(&map),
            shading_error: OverFrames::of(&shading),
            flicker: Flicker::over(&tracked),
            image_flicker: temporal::image_flicker(&images, &reference_images),
            gpu_ms: median(gpu_ms),
            image_flip: frame_rows.iter().map(|f| f.image_flip).sum::<f64>() / frame_rows.len().max(1) as f64,
            frames: frame_rows,
            followed,
        });
        if let Some(after) = options.after_each {
            let so_far = measurement(rows.clone());
            after(&so_far)?;
        }
    }
    Ok(Outcome::Complete(measurement(rows)))
}

/// The measurement of a run stopped before any configuration finished.
fn nothing_measured(gpu: &Gpu, scene: &crate::scene::Scene, frames: u32) -> MotionMeasurement {
    MotionMeasurement {
        device: crate::gpu::describe(&gpu.info),
        strands: scene.strands.strand_count(),
        segments: scene.strands.segment_count(),
        frames,
        rows: Vec::new(),
        sim: None,
        followed: None,
    }
}

/// A frame of `s`'s view at [`IMAGE_SIZE`] shaded with `method`, composited exactly (the reference technique),
/// so that an image's error is its shadows' alone.
fn input<'a>(
    s: &'a Settings,
    method: &'a dyn methods::ShadowMethod,
    params: &'a ParamValues,
) -> FrameInput<'a> {
    let (width, height) = IMAGE_SIZE;
    FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method,
        method_params: params,
        technique: crate::render::transparency::registry::reference(),
        technique_params: &s.transparency.params,
        width,
        height,
    }
}

/// Median GPU milliseconds per frame of the simulation's compute pass ([`Phase::Simulation`]) over `frames − 1`
/// steps from `sim`'s rest pose (`None` without timestamp queries).
pub fn gpu_sim_ms(gpu: &Gpu, sim: crate::motion::Simulation, frames: u32) -> Result<Option<f64>> {
    let mut g = crate::motion::gpu::GpuSimulation::new(gpu, sim)?;
    let mut ms = Vec::with_capacity(frames as usize);
    for _ in 1..frames {
        g.step_frame(gpu);
        ms.extend(g.wait_timings(gpu).map(|t| phase_ms(&t, Phase::Simulation)));
    }
    Ok((!ms.is_empty()).then(|| median(ms)))
}

/// One row of `motion_point.csv`.
#[derive(Serialize)]
struct PointRow {
    config: String,
    frame: u32,
    v: f32,
    reference: f32,
    pop: Option<f64>,
}

/// One row of `motion_summary.csv`.
#[derive(Serialize)]
struct SummaryRow {
    config: String,
    map_error: f64,
    shading_error: f64,
    flicker: f64,
    flicker_p99: f64,
    pop_rate: f64,
    max_pop: f64,
    image_flicker: f64,
    gpu_ms: f64,
    image_flip: f64,
}

impl MotionMeasurement {
    /// `motion_summary.csv`: one row per configuration (the per-frame errors' means over the frames, the
    /// flicker figures pooled over the frame pairs, the median GPU ms).
    pub fn summary_csv(&self) -> Result<String> {
        crate::io::csv_text(
            "motion_summary.csv",
            self.rows.iter().map(|r| SummaryRow {
                config: r.config.label(),
                map_error: r.map_error.mean,
                shading_error: r.shading_error.mean,
                flicker: r.flicker.mean,
                flicker_p99: r.flicker.p99,
                pop_rate: r.flicker.pop_rate,
                max_pop: r.flicker.max_pop,
                image_flicker: r.image_flicker,
                gpu_ms: r.gpu_ms,
                image_flip: r.image_flip,
            }),
        )
    }

    /// `motion_frames.csv`: one row per configuration and frame.
    pub fn frames_csv(&self) -> Result<String> {
        crate::io::csv_text("motion_frames.csv", self.rows.iter().flat_map(|r| &r.frames))
    }

    /// `motion_point.csv` (with a followed point): one row per configuration and frame, the method's and the
    /// reference's visibility at the point and the pop from the previous frame (empty in frame 0).
    pub fn point_csv(&self) -> Result<Option<String>> {
        let Some((_, reference)) = &self.followed else {
            return Ok(None);
        };
        let rows = self.rows.iter().flat_map(|r| {
            let label = r.config.label();
            r.followed.iter().enumerate().map(move |(f, &v)| PointRow {
                config: label.clone(),
                frame: f as u32,
                v,
                reference: reference[f],
                pop: (f > 0)
                    .then(|| super::temporal::pop((r.followed[f - 1], reference[f - 1]), (v, reference[f]))),
            })
        });
        crate::io::csv_text("motion_point.csv", rows).map(Some)
    }

    /// The files of a motion measurement, as `(name, bytes)` for `bench::report::write_files`: `motion_summary.csv`,
    /// `motion_frames.csv` and, with a followed point, `motion_point.csv` (what `measure motion`, `bench motion`
    /// and a report write).
    pub fn csv_files(&self) -> Result<Vec<(String, Vec<u8>)>> {
        let mut files = vec![
            ("motion_summary.csv".to_string(), self.summary_csv()?.into_bytes()),
            ("motion_frames.csv".to_string(), self.frames_csv()?.into_bytes()),
        ];
        if let Some(csv) = self.point_csv()? {
            files.push(("motion_point.csv".to_string(), csv.into_bytes()));
        }
        Ok(files)
    }

    /// The summary table: one line per configuration.
    pub fn table(&self, preset: &str) -> String {
        let m = self;
        let mut out = format!(
            "preset {preset}: {} strands, {} segments, frames 0..{} on {}\n",
            m.strands, m.segments, m.frames, m.device
        );
        if let Some(sim) = &m.sim {
            out += &format!(
                "simulation per frame: CPU model {:.3} ms, GPU compute {}\n",
                sim.cpu_ms,
                sim.gpu_ms
                    .map_or("n/a (no timestamp queries)".to_string(), |ms| format!(
                        "{ms:.3} ms"
                    ))
            );
        }
        let width = m
            .rows
            .iter()
            .map(|r| r.config.label().chars().count())
            .max()
            .unwrap_or(0)
            .max(6);
        out += &format!(
            "{:<width$} {:>8} {:>8} {:>12} {:>8} {:>8} {:>12} {:>8} {:>8} {:>7} {:>8} {:>8} {:>8} {:>8}\n",
            "method",
            "map err",
            "map p95",
            "map worst@f",
            "shading",
            "sh. p95",
            "sh. worst@f",
            "flicker",
            "flk p99",
            "pops",
            "max pop",
            "img flk",
            "GPU ms",
            "FLIP"
        );
        for r in &m.rows {
            let worst =
                |o: &crate::measure::temporal::OverFrames| format!("{:.5}@{}", o.worst, o.worst_frame);
            out += &format!(
                "{:<width$} {:>8.5} {:>8.5} {:>12} {:>8.5} {:>8.5} {:>12} {:>8.5} {:>8.5} {:>6.2}% {:>8.4} {:>8.5} \
                 {:>8.3} {:>8.5}\n",
                r.config.label(),
                r.map_error.mean,
                r.map_error.p95,
                worst(&r.map_error),
                r.shading_error.mean,
                r.shading_error.p95,
                worst(&r.shading_error),
                r.flicker.mean,
                r.flicker.p99,
                100.0 * r.flicker.pop_rate,
                r.flicker.max_pop,
                r.image_flicker,
                r.gpu_ms,
                r.image_flip
            );
        }
        out += "map err, shading: mean over the frames (p95, worst and its frame beside); flicker: mean |ΔV − ΔV_ref| \
                between consecutive frames at the tracked points (p99 beside); pops: share of tracked points per frame \
                pair with |ΔV − ΔV_ref| > 0.1; img flk: RMSE of the image's frame-to-frame change against the \
                reference's; GPU ms: the method's light passes, median over the frames; FLIP: the image's FLIP against the reference's, \
                mean over the pixels and the frames\n";
        out
    }

    /// The row of `config` (its [`MotionConfig::label`]).
    pub fn row(&self, label: &str) -> Option<&MotionRow> {
        self.rows.iter().find(|r| r.config.label() == label)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::LightMethod;
    use crate::methods::bom::Bom;
    use crate::methods::osm::Osm;

    #[test]
    fn configurations_mark_when_the_analysis_chooses() {
        let (bom, osm) = (Bom.name(), Osm.name());
        let c = MotionConfig::parse(&format!("{bom}:layers=4,split_ratio=auto")).unwrap();
        assert_eq!(c.tuning, Tuning::FirstFrame);
        assert_eq!(c.label(), format!("{bom}:layers=4,split_ratio=auto"));
        let c = MotionConfig::parse(&format!("{bom}:split_ratio=auto-per-frame,layers=4")).unwrap();
        assert_eq!(c.tuning, Tuning::EveryFrame);
        assert_eq!(c.label(), format!("{bom}:layers=4,split_ratio=auto-per-frame"));
        assert_eq!(MotionConfig::parse(&c.label()).unwrap(), c);
        let c = MotionConfig::parse(&format!("{osm}:slices=16")).unwrap();
        assert_eq!((c.tuning, c.label()), (Tuning::Fixed, format!("{osm}:slices=16")));
        let e = MotionConfig::parse(&format!("{osm}:slices=auto"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot choose 'slices'"), "{e}");
        let e = MotionConfig::parse(&format!("{bom}:layers=auto"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("chooses split_ratio"), "{e}");
    }
}
