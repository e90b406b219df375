//! A fresh study for a report: the scene's thumbnail, the shadow methods' bench, the transparency bench and,
//! when asked, the motion measurement, each written into the draft's `data/` folder by the writers `hairlab
//! bench` and `hairlab measure motion` use, after every configuration. A cancel (Ctrl-C) stops after the
//! configuration in progress; what finished is then read back like any `--from` folder.

use super::sections::{MOTION_DIR, SHADOWS_DIR, TRANSPARENCY_DIR};
use super::{AdapterFacts, Draft, Meta};
use crate::bench::BenchConfig;
use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::MethodConfig;
use crate::measure::motion::{MotionConfig, MotionMeasurement, MotionOptions, measure_motion};
use crate::measure::transparency::TechniqueConfig;
use crate::settings::Settings;
use anyhow::{Context, Result};
use std::cell::RefCell;
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

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

/// The folders a fresh study wrote, its meta data, and whether it ran to the end (false: cancelled).
pub struct Done {
    pub dirs: Vec<PathBuf>,
    pub meta: Meta,
    pub finished: bool,
}

/// The preset whose `[motion]` a still preset's `--motion` study plays.
pub const STILL_MOTION: &str = "stray-sweep";

/// Runs `plan` on `settings` into `draft`; `log` hears what is measured.
pub fn run(
    draft: &Draft,
    plan: &Plan,
    settings: &Settings,
    cancel: &AtomicBool,
    log: &mut dyn FnMut(&str),
) -> Result<Done> {
    // A still preset's study in motion plays the stray-strand sweep (one strand's root sliding across the hair's
    // light-facing front, the motion of Sintorn & Assarsson's Fig. 4 failure), as `stray-sweep` declares it.
    let swept;
    let settings = if plan.motion && settings.motion.source == crate::motion::MotionSource::None {
        let mut s = settings.clone();
        s.motion = Settings::load_preset(STILL_MOTION, &[])?.motion;
        log(&format!(
            "preset {} has no [motion]: --motion plays {STILL_MOTION}'s (one strand's root sweeping across the hair)",
            plan.preset
        ));
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
    log("rendering the scene's thumbnail…");
    let mut thumb = None;
    crate::animation::render_frames_on(&gpu, &mut settings.clone(), &[0], &mut |_| {}, &mut |_, image| {
        thumb = Some(image);
        Ok(())
    })?;
    if let Some(image) = thumb {
        let h = (image.height() * THUMBNAIL_WIDTH / image.width().max(1)).max(1);
        let small = image::imageops::thumbnail(&image, THUMBNAIL_WIDTH.min(image.width()), h);
        small
            .save(root.join(THUMBNAIL))
            .with_context(|| format!("{}: cannot write", root.join(THUMBNAIL).display()))?;
        meta.thumbnail = Some(THUMBNAIL.to_string());
    }
    let mut dirs = Vec::new();
    let frames = plan.frames.max(1);

    // The shadow methods: the given configurations, or every method's sweep.
    let dir = root.join(SHADOWS_DIR);
    log("measuring the shadow methods…");
    let mut progress = |p: crate::bench::Progress| log(&format!("  {}/{} {}", p.done, p.total, p.label));
    let mut written =
        |partial: &crate::bench::BenchResult| crate::bench::write_tables(&dir, partial).map(|_| ());
    let result = if plan.configs.is_empty() {
        let methods = crate::bench::parse_methods(&[])?;
        crate::bench::run_each(
            settings,
            &plan.preset,
            &methods,
            frames,
            cancel,
            &mut progress,
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
            cancel,
            &mut progress,
            &mut written,
        )?
    };
    if let Some(result) = &result {
        crate::bench::write_results(&dir, result)?;
        let configs: Vec<MethodConfig> = result.rows.iter().map(|r| r.config.clone()).collect();
        super::images::render_configs(&gpu, settings, &configs, &dir, cancel, log)?;
        if !cancel.load(Ordering::SeqCst) {
            log("  the worst texels' V(z) and the depth-complexity histogram");
            super::curves::write(&gpu, settings, &configs, &dir)?;
        }
        if plan.truth && !cancel.load(Ordering::SeqCst) {
            truth(&gpu, settings, result, &dir, cancel, log)?;
        }
        dirs.push(dir);
    }
    if cancel.load(Ordering::SeqCst) {
        return Ok(Done {
            dirs,
            meta,
            finished: false,
        });
    }

    // Eye transparency.
    let dir = root.join(TRANSPARENCY_DIR);
    log("measuring the transparency techniques…");
    let mut write_err = Ok(());
    let bench = crate::bench::transparency::TransparencyBench::run_each(
        &gpu,
        settings,
        &plan.preset,
        &techniques,
        frames,
        |what| log(&format!("  {what}")),
        |partial| {
            write_err = partial.write_tables(&dir).map(|_| ());
            if write_err.is_err() || cancel.load(Ordering::SeqCst) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )?;
    write_err?;
    if !bench.rows.is_empty() {
        bench.write(&dir)?;
        let rows: Vec<TechniqueConfig> = bench.rows.iter().map(|r| r.config.clone()).collect();
        super::images::render_techniques(&gpu, settings, &rows, &dir, cancel, log)?;
        dirs.push(dir);
    }
    if cancel.load(Ordering::SeqCst) || !plan.motion {
        let finished = !cancel.load(Ordering::SeqCst);
        return Ok(Done { dirs, meta, finished });
    }

    // Motion.
    let dir = root.join(MOTION_DIR);
    log("measuring the motion…");
    let written = RefCell::new(Ok(()));
    let after_each = |m: &MotionMeasurement| {
        let w = write_motion(&dir, m);
        let stop = w.is_err() || cancel.load(Ordering::SeqCst);
        *written.borrow_mut() = w;
        if stop {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let options = MotionOptions {
        follow: None,
        cancel: None,
        after_each: Some(&after_each),
    };
    let m = measure_motion(
        &gpu,
        settings,
        &motion_configs,
        frames.max(2),
        options,
        &mut |what, _| log(&format!("  {what}")),
    )?;
    written.into_inner()?;
    if !m.rows.is_empty() {
        let configs: Vec<MethodConfig> = m.rows.iter().map(|r| r.config.config.clone()).collect();
        super::animations::write(&gpu, settings, &configs, frames.max(2), &dir, cancel, log)?;
        dirs.push(dir);
    }
    Ok(Done {
        dirs,
        meta,
        finished: !cancel.load(Ordering::SeqCst),
    })
}

/// The path-traced truth of `settings` and the decomposition of each of `configs`' error against it under each
/// shading model, written as `measure shadows --truth path-traced --out` writes them.
fn truth(
    gpu: &Gpu,
    settings: &Settings,
    result: &crate::bench::BenchResult,
    dir: &std::path::Path,
    cancel: &AtomicBool,
    log: &mut dyn FnMut(&str),
) -> Result<()> {
    log("  path-tracing the truth…");
    let t = crate::measure::truth::path_traced(settings, &mut |n, of| {
        log(&format!("  path-traced truth: {n}/{of} spp"));
        !cancel.load(Ordering::SeqCst)
    })?;
    if cancel.load(Ordering::SeqCst) {
        return Ok(());
    }
    let models = crate::shading::ShadingModel::ALL;
    let configs: Vec<MethodConfig> = result.rows.iter().map(|r| r.config.clone()).collect();
    let table =
        crate::measure::shading::shading_errors_on(gpu, settings, &configs, &models, Some(&t), |m| {
            log(&format!("  decomposing under {m}"))
        })?;
    let decomposition = table.decomposition();
    let csv = crate::io::csv_text(super::data::DECOMPOSITION_CSV, &decomposition)?;
    crate::io::write_atomic(&dir.join(super::data::DECOMPOSITION_CSV), csv.as_bytes())?;
    crate::io::write_atomic(
        &dir.join(super::data::TRUTH_PNG),
        &crate::animation::encode_png(&t.image)?,
    )?;
    crate::bench::report::write_truth_chart(dir, result, &decomposition, settings.render.shading.word())?;
    Ok(())
}

/// `motion_summary.csv` and `motion_frames.csv` of `m`, as `hairlab measure motion` writes them.
fn write_motion(dir: &std::path::Path, m: &MotionMeasurement) -> Result<()> {
    crate::bench::report::write_files(
        dir,
        vec![
            ("motion_summary.csv".to_string(), m.summary_csv()?.into_bytes()),
            ("motion_frames.csv".to_string(), m.frames_csv()?.into_bytes()),
        ],
    )?;
    Ok(())
}
