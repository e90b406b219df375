//! A fresh study for a report: the scene's thumbnail, the shadow methods' bench, the transparency bench and,
//! when asked, the motion measurement, each written into the draft's `data/` folder by the writers `hairlab
//! bench` and `hairlab measure motion` use, after every configuration. A stop the [`Progress`] asks for (Ctrl-C,
//! the window's Stop) takes effect after the configuration in progress: the run's [`Outcome`] is stopped, and what
//! finished is read back like any `--from` folder.

use super::sections::{MOTION_DIR, SHADOWS_DIR, TRANSPARENCY_DIR};
use super::{AdapterFacts, Draft, Meta};
use crate::bench::BenchConfig;
use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::MethodConfig;
use crate::measure::motion::{MotionConfig, MotionMeasurement, MotionOptions, measure_motion};
use crate::measure::transparency::TechniqueConfig;
use crate::progress::{Outcome, Part, Progress};
use crate::settings::Settings;
use anyhow::{Context, Result};
use std::cell::Cell;
use std::path::PathBuf;

/// The scene thumbnail's file in the report, and its width in pixels.
pub const THUMBNAIL: &str = "scene.png";
const THUMBNAIL_WIDTH: u32 = 480;

/// What a fresh study measures.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plan {
    /// The preset's name or path, for the page's title.
    pub preset: String,
    /// Shadow method configurations (`name` or `name:key=value,...`): the bench measures these, and the motion
    /// these; none means the bench's whole sweep and the motion's usual configurations.
    pub configs: Vec<String>,
    /// Transparency technique configurations; none means the transparency bench's whole sweep.
    pub techniques: Vec<String>,
    pub motion: bool,
    /// Timed frames per configuration (the motion plays frames 0..max(frames, 2)).
    pub frames: u32,
    /// Path-trace the scene and decompose each configuration's error against it (into the shadows' folder).
    pub truth: bool,
}

/// The folders a fresh study wrote and its meta data.
pub struct Done {
    pub dirs: Vec<PathBuf>,
    pub meta: Meta,
}

/// The preset whose `[motion]` a still preset's `--motion` study plays.
pub const STILL_MOTION: &str = "stray-sweep";

/// The share of a study's progress each of its phases stands for: the thumbnail, the shadow methods (bench,
/// images, curves), the truth, the transparency techniques and the motion, by rough cost.
fn phases(plan: &Plan) -> [(f32, f32); 5] {
    let weights = [
        0.2,
        4.0,
        if plan.truth { 1.0 } else { 0.0 },
        2.0,
        if plan.motion { 2.0 } else { 0.0 },
    ];
    let total: f32 = weights.iter().sum();
    let mut start = 0.0;
    weights.map(|w| {
        let range = (start / total, (start + w) / total);
        start += w;
        range
    })
}

/// Runs `plan` on `settings` into `draft`; `progress` hears what is measured and may stop the study after the
/// configuration in progress ([`Outcome::Stopped`] with the folders of what finished).
pub fn run(
    draft: &Draft,
    plan: &Plan,
    settings: &Settings,
    progress: &mut dyn Progress,
) -> Result<Outcome<Done>> {
    let [thumbnail, shadows, truth_phase, transparency, motion] = phases(plan);
    // A still preset's study in motion plays the stray-strand sweep (one strand's root sliding across the hair's
    // light-facing front, the motion of Sintorn & Assarsson's Fig. 4 failure), as `stray-sweep` declares it.
    let swept;
    let mut go = true;
    let settings = if plan.motion && settings.motion.source == crate::motion::MotionSource::None {
        let mut s = settings.clone();
        s.motion = Settings::load_preset(STILL_MOTION, &[])?.motion;
        let note = format!(
            "preset {} has no [motion]: --motion plays {STILL_MOTION}'s (one strand's root sweeping across the hair)",
            plan.preset
        );
        go = progress.step(&note, 0.0);
        swept = s;
        &swept
    } else {
        settings
    };
    let motion_configs: Vec<MotionConfig> = if plan.configs.is_empty() {
        crate::measure::motion::usual_configs()
    } else {
        plan.configs
            .iter()
            .map(|c| MotionConfig::parse(c).with_context(|| format!("--config {c}")))
            .collect::<Result<_>>()?
    };
    let techniques: Vec<TechniqueConfig> = if plan.techniques.is_empty() {
        crate::bench::transparency::sweep_configs()
    } else {
        plan.techniques
            .iter()
            .map(|t| TechniqueConfig::parse(t).with_context(|| format!("--technique {t}")))
            .collect::<Result<_>>()?
    };
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let l = settings.light;
    let mut meta = Meta {
        version: env!("CARGO_PKG_VERSION"),
        preset: Some(plan.preset.clone()),
        light: Some(format!(
            "{:?}, azimuth {}°, elevation {}°, intensity {}",
            l.kind, l.azimuth_deg, l.elevation_deg, l.intensity
        )),
        adapter: Some(AdapterFacts::of(&gpu.info)),
        ..Meta::default()
    };
    let root = draft.path();
    if !(go && progress.step("rendering the scene's thumbnail…", thumbnail.0)) {
        return Ok(Outcome::Stopped(Done {
            dirs: Vec::new(),
            meta,
        }));
    }
    let image = super::images::render(&gpu, settings.clone())?;
    let h = (image.height() * THUMBNAIL_WIDTH / image.width().max(1)).max(1);
    let small = image::imageops::thumbnail(&image, THUMBNAIL_WIDTH.min(image.width()), h);
    crate::io::write_png(&root.join(THUMBNAIL), &small)?;
    meta.thumbnail = Some(THUMBNAIL.to_string());
    let mut dirs = Vec::new();
    let frames = plan.frames.max(1);

    // The shadow methods: the given configurations, or every method's sweep.
    let dir = root.join(SHADOWS_DIR);
    // The bench takes the first 70 % of the shadow methods' share, their images the rest.
    let bench_end = shadows.0 + 0.7 * (shadows.1 - shadows.0);
    let mut bench_progress = Part::of(&mut *progress, shadows.0, bench_end);
    let mut written =
        |partial: &Outcome<crate::bench::BenchResult>| crate::bench::write_tables(&dir, partial).map(|_| ());
    let result = if plan.configs.is_empty() {
        let methods = crate::bench::parse_methods(&[])?;
        crate::bench::run_each(
            settings,
            &plan.preset,
            &methods,
            frames,
            &mut bench_progress,
            &mut written,
        )?
    } else {
        let configs: Vec<BenchConfig> = motion_configs
            .iter()
            .map(|m| BenchConfig {
                config: m.config.clone(),
                note: String::new(),
            })
            .collect();
        crate::bench::measure_configs_each(
            settings,
            &plan.preset,
            &configs,
            frames,
            usize::MAX,
            &mut bench_progress,
            &mut written,
        )?
    };
    let bench_stopped = result.is_stopped();
    if let Some(result) = result.kept() {
        let result = Outcome::new(result, bench_stopped);
        crate::bench::write_results(&dir, &result)?;
        let configs: Vec<MethodConfig> = result.rows.iter().map(|r| r.config.clone()).collect();
        let mut images = Part::of(&mut *progress, bench_end, shadows.1);
        if super::images::render_configs(&gpu, settings, &configs, &dir, &mut images)?
            && progress.step(
                "the worst texels' V(z) and the depth-complexity histogram",
                shadows.1,
            )
        {
            super::curves::write(&gpu, settings, &configs, &dir)?;
            if plan.truth {
                let mut phase = Part::of(&mut *progress, truth_phase.0, truth_phase.1);
                truth(&gpu, settings, &result, &dir, &mut phase)?;
            }
        }
        dirs.push(dir);
    }
    if bench_stopped || !progress.step("measuring the transparency techniques…", transparency.0) {
        return Ok(Outcome::Stopped(Done { dirs, meta }));
    }

    // Eye transparency.
    let dir = root.join(TRANSPARENCY_DIR);
    // The bench takes the first 70 % of the techniques' share, their images the rest.
    let bench_end = transparency.0 + 0.7 * (transparency.1 - transparency.0);
    let stopped = Cell::new(false);
    let bench = crate::bench::transparency::TransparencyBench::run_each(
        &gpu,
        settings,
        &plan.preset,
        &techniques,
        frames,
        &mut |what: &str, f: f32| {
            let at = transparency.0 + f * (bench_end - transparency.0);
            stopped.set(stopped.get() || !progress.step(what, at));
            !stopped.get()
        },
        |partial| partial.write_tables(&dir).map(|_| ()),
    )?;
    if !bench.rows.is_empty() {
        bench.write(&dir)?;
        let rows: Vec<TechniqueConfig> = bench.rows.iter().map(|r| r.config.clone()).collect();
        let mut images = Part::of(&mut *progress, bench_end, transparency.1);
        let all = super::images::render_techniques(&gpu, settings, &rows, &dir, &mut images)?;
        stopped.set(stopped.get() || !all);
        dirs.push(dir);
    }
    let stopped = stopped.get() || !progress.step("measured the transparency techniques", transparency.1);
    if stopped || !plan.motion {
        return Ok(Outcome::new(Done { dirs, meta }, stopped));
    }

    // Motion.
    let dir = root.join(MOTION_DIR);
    // The measurement takes the first 70 % of the motion's share, the animations the rest.
    let measure_end = motion.0 + 0.7 * (motion.1 - motion.0);
    let after_each = |m: &MotionMeasurement| write_motion(&dir, m);
    let options = MotionOptions {
        follow: None,
        after_each: Some(&after_each),
    };
    let m = measure_motion(
        &gpu,
        settings,
        &motion_configs,
        frames.max(2),
        options,
        &mut Part::of(&mut *progress, motion.0, measure_end),
    )?;
    let mut stopped = m.is_stopped();
    if !m.rows.is_empty() {
        let configs: Vec<MethodConfig> = m.rows.iter().map(|r| r.config.config.clone()).collect();
        let mut animating = Part::of(&mut *progress, measure_end, motion.1);
        stopped |= !super::animations::write(&gpu, settings, &configs, frames.max(2), &dir, &mut animating)?;
        dirs.push(dir);
    }
    Ok(Outcome::new(Done { dirs, meta }, stopped))
}

/// The path-traced truth of `settings` and the decomposition of each of `configs`' error against it under each
/// shading model, written as `measure shadows --truth path-traced --out` writes them.
fn truth(
    gpu: &Gpu,
    settings: &Settings,
    result: &crate::bench::BenchResult,
    dir: &std::path::Path,
    progress: &mut dyn Progress,
) -> Result<()> {
    let models = crate::shading::ShadingModel::ALL;
    let configs: Vec<MethodConfig> = result.rows.iter().map(|r| r.config.clone()).collect();
    let Some((t, table)) =
        crate::measure::shading::against_truth(gpu, settings, &configs, &models, progress)?
    else {
        return Ok(());
    };
    let shading = crate::measure::truth::chart_shading(settings, &models);
    crate::bench::truth_chart::write_truth(dir, &t, &table.decomposition, result, shading)?;
    Ok(())
}

/// The motion's CSV files of `m`, as `hairlab measure motion` writes them.
fn write_motion(dir: &std::path::Path, m: &MotionMeasurement) -> Result<()> {
    crate::bench::report::write_files(dir, m.csv_files()?)?;
    Ok(())
}
