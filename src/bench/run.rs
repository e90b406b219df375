//! Running the bench: the configurations measured in chunks (stopping between configurations when the
//! [`Progress`] says so) and the scaling mode's densities.

use super::{
    BenchConfig, BenchResult, BenchRow, DEFAULT_ACCURACY_METRIC, MIN_SCALING_FRAMES, ScalingFit,
    ScalingPoint, ScalingRefusal, ScalingResult, Spread, all_scaling_configs, fit_line, frame_totals,
    growth_exponent, sweep_configs, tune_analysed,
};
use crate::measure::{self, MethodConfig};
use crate::progress::{Outcome, Part, Progress, share};
use crate::render::caster::Raster;
use crate::settings::Settings;
use anyhow::{Result, bail};
use std::cell::{Cell, RefCell};

/// What a bench run made: its result, [`Outcome::Stopped`] with the configurations measured before a stop
/// (`None` when it stopped before the first).
pub type BenchOutcome = Outcome<Option<BenchResult>>;

/// The bench so far, handed to a run's `finished` after each configuration (to write it): stopped (what a stop
/// now would keep) until the last configuration is in.
pub type Finished<'a> = &'a mut dyn FnMut(&Outcome<BenchResult>) -> Result<()>;

/// Measures `configs` on `settings`' scene, `chunk` configurations per `measure` call (each call renders the
/// reference again; a stop `progress` asks for takes effect after the configuration in progress). No
/// configuration is an error.
pub fn measure_configs(
    settings: &Settings,
    preset: &str,
    configs: &[BenchConfig],
    frames: u32,
    chunk: usize,
    progress: &mut dyn Progress,
) -> Result<BenchOutcome> {
    measure_configs_each(
        settings,
        preset,
        configs,
        frames,
        chunk,
        progress,
        &mut |_| Ok(()),
    )
}

/// [`measure_configs`], handing the result so far to `finished` after each configuration (to write it).
pub fn measure_configs_each(
    settings: &Settings,
    preset: &str,
    configs: &[BenchConfig],
    frames: u32,
    chunk: usize,
    progress: &mut dyn Progress,
    finished: Finished<'_>,
) -> Result<BenchOutcome> {
    let total = configs.len();
    if total == 0 {
        bail!("the bench has no configuration to measure");
    }
    let mut stats = None;
    let mut rows = Vec::with_capacity(total);
    let progress = RefCell::new(progress);
    for group in configs.chunks(chunk.max(1)) {
        let label = format!("measuring {} of {total} configurations", group.len());
        if !progress.borrow_mut().step(&label, share(rows.len(), total)) {
            break;
        }
        let methods: Vec<MethodConfig> = group.iter().map(|c| c.config.clone()).collect();
        let first = rows.len();
        let mut next = 0;
        let stopped = Cell::new(false);
        let measured = measure::measure_each(
            settings,
            &methods,
            frames,
            &mut |label: &str, _: f32| {
                // `measure` names the configuration it starts, or a phase of its own (the reference).
                if group.get(next).is_some_and(|c| c.config.label() == label) {
                    next += 1;
                }
                let done = share(first + next.saturating_sub(1), total);
                stopped.set(stopped.get() || !progress.borrow_mut().step(label, done));
                !stopped.get()
            },
            |s, so_far| {
                let partial = BenchResult {
                    preset: preset.to_string(),
                    stats: s.clone(),
                    frames,
                    rows: rows
                        .iter()
                        .cloned()
                        .chain(
                            so_far
                                .iter()
                                .zip(group)
                                .map(|(m, c)| BenchRow::from_measurement(m, &c.note, &s.device)),
                        )
                        .collect(),
                    metric: DEFAULT_ACCURACY_METRIC,
                };
                finished(&Outcome::new(partial, first + so_far.len() < total))?;
                // Told after each configuration, so a stop asked while it ran ends the run before the next.
                let label = so_far.last().map_or(String::new(), |m| m.config.label());
                let done = share(first + so_far.len(), total);
                stopped.set(stopped.get() || !progress.borrow_mut().step(&label, done));
                Ok(())
            },
        )?;
        stopped.set(stopped.get() || measured.is_stopped());
        let (s, measured) = measured.kept();
        rows.extend(
            measured
                .iter()
                .zip(group)
                .map(|(m, c)| BenchRow::from_measurement(m, &c.note, &s.device)),
        );
        stats.get_or_insert(s);
        if stopped.get() {
            break;
        }
    }
    let done = format!("measured {} of {total} configurations", rows.len());
    // The last step: every configuration is in, or the run stopped already; nothing is left to stop.
    let _ = progress.borrow_mut().step(&done, share(rows.len(), total));
    let stopped = rows.len() < total;
    let result = stats.map(|stats| BenchResult {
        preset: preset.to_string(),
        stats,
        frames,
        rows,
        metric: DEFAULT_ACCURACY_METRIC,
    });
    Ok(Outcome::new(result, stopped))
}

/// The share of a bench's progress bar that tuning the analysed sweep points stands for.
const TUNE_SHARE: f32 = 0.1;

/// The whole bench of `methods` on `settings`: the analysed sweep points tuned first (e.g. Bounding Opacity
/// Maps' automatic split ratios), then every configuration.
pub fn run(
    settings: &Settings,
    preset: &str,
    methods: &[&str],
    frames: u32,
    chunk: usize,
    progress: &mut dyn Progress,
) -> Result<BenchOutcome> {
    let tuned = tune_analysed(settings, methods, &mut Part::of(&mut *progress, 0.0, TUNE_SHARE))?;
    if tuned.is_stopped() {
        return Ok(Outcome::Stopped(None));
    }
    let configs = sweep_configs(methods, &tuned);
    let mut measuring = Part::of(progress, TUNE_SHARE, 1.0);
    measure_configs(settings, preset, &configs, frames, chunk, &mut measuring)
}

/// [`run`] with [`measure_configs_each`]'s `finished`.
pub fn run_each(
    settings: &Settings,
    preset: &str,
    methods: &[&str],
    frames: u32,
    progress: &mut dyn Progress,
    finished: Finished<'_>,
) -> Result<BenchOutcome> {
    let tuned = tune_analysed(settings, methods, &mut Part::of(&mut *progress, 0.0, TUNE_SHARE))?;
    if tuned.is_stopped() {
        return Ok(Outcome::Stopped(None));
    }
    let configs = sweep_configs(methods, &tuned);
    let mut measuring = Part::of(progress, TUNE_SHARE, 1.0);
    measure_configs_each(
        settings,
        preset,
        &configs,
        frames,
        usize::MAX,
        &mut measuring,
        finished,
    )
}

/// How the scaling mode measures: `points` densities evenly spaced in segment count up to `max_segments`, under
/// each of `rasters`, each configuration timed over `frames` frames after `warmup` discarded ones.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingPlan {
    pub max_segments: usize,
    pub points: usize,
    pub frames: u32,
    pub warmup: u32,
    /// The rasterisers each density is measured under (`render.raster`), at least one.
    pub rasters: Vec<Raster>,
}

/// The strand density factors of `points` points evenly spaced in segment count, the last reaching
/// `max_segments` on a scene of `base_segments` segments at density × 1: `k · max / (points · base)` for
/// k = 1..=points.
pub fn scaling_densities(base_segments: usize, max_segments: usize, points: usize) -> Vec<f32> {
    let last = max_segments as f64 / base_segments.max(1) as f64;
    (1..=points)
        .map(|k| (last * k as f64 / points as f64) as f32)
        .collect()
}

/// Times `configs` at each density of `plan` under each of its rasterisers and fits each (configuration,
/// rasteriser)'s GPU ms against segments. After each density, `written` gets the result so far (its fits over
/// the densities done); a stop `progress` asks for (Ctrl-C) ends the run after the density in progress:
/// [`Outcome::Stopped`] with the densities done.
pub fn run_scaling(
    settings: &Settings,
    preset: &str,
    configs: &[MethodConfig],
    plan: &ScalingPlan,
    progress: &mut dyn Progress,
    written: &mut dyn FnMut(&ScalingResult) -> Result<()>,
) -> Result<Outcome<ScalingResult>> {
    if let Some(f) = &settings.scene.file {
        bail!(
            "--scaling varies the generator's strand density, and this preset loads {}",
            f.display()
        );
    }
    if configs.is_empty() {
        bail!(
            "--scaling measures {}: --methods names none of them",
            all_scaling_configs().join(", ")
        );
    }
    if plan.frames < MIN_SCALING_FRAMES {
        bail!(
            "--frames {}: the scaling mode takes the median of at least {MIN_SCALING_FRAMES} timed frames per point",
            plan.frames
        );
    }
    if plan.points < 2 {
        bail!("--points {}: a line needs at least 2 points", plan.points);
    }
    if plan.rasters.is_empty() {
        bail!("--raster: no rasteriser to measure under");
    }
    let base = settings.scene.build()?.strands.segment_count();
    if base == 0 {
        bail!("--scaling: the preset's generator makes no segments at density × 1");
    }
    let densities = scaling_densities(base, plan.max_segments, plan.points);
    let mut r = ScalingResult {
        preset: preset.to_string(),
        device: String::new(),
        map_resolution: settings.render.map_resolution,
        densities: Vec::new(),
        rasters: plan.rasters.clone(),
        frames: plan.frames,
        warmup: plan.warmup,
        points: Vec::new(),
        refused: Vec::new(),
        fits: Vec::new(),
    };
    let total = densities.len() * plan.rasters.len() * configs.len();
    let mut stopped = false;
    for (i, &factor) in densities.iter().enumerate() {
        let label = format!("density x{factor:.3}");
        if stopped || !progress.step(&label, share(i * plan.rasters.len() * configs.len(), total)) {
            return Ok(Outcome::Stopped(r));
        }
        for (j, &raster) in plan.rasters.iter().enumerate() {
            let mut s = settings.clone();
            s.scene.generator.density *= factor;
            s.render.raster = raster;
            let done = (i * plan.rasters.len() + j) * configs.len();
            let mut n = 0;
            // A stop takes effect after the density: its point is measured whole.
            let mut timing = |label: &str, _: f32| {
                let what = format!("density x{factor:.3}, {} raster: {label}", raster.word());
                stopped |= !progress.step(&what, share(done + n, total));
                n += 1;
                true
            };
            let t = measure::time_configs(&s, configs, plan.frames, plan.warmup, &mut timing)?;
            // Every configuration's frames pooled: per frame the shared passes' total, and per pass its times.
            let mut shared: Vec<f64> = Vec::new();
            let mut shared_passes: Vec<(String, Vec<f64>)> = Vec::new();
            for row in &t.rows {
                shared.extend(frame_totals(&row.shared_pass_frames_ms));
                for (name, frames) in &row.shared_pass_frames_ms {
                    match shared_passes.iter_mut().find(|(n, _)| n == name) {
                        Some((_, v)) => v.extend(frames),
                        None => shared_passes.push((name.clone(), frames.clone())),
                    }
                }
            }
            if !shared.is_empty() {
                r.points.push(ScalingPoint {
                    label: SHARED_LIGHT_LABEL.to_string(),
                    raster,
                    density: s.scene.generator.density,
                    strands: t.strands,
                    segments: t.segments,
                    ms: Spread::of(&shared),
                    frames: shared.len(),
                    passes: shared_passes
                        .iter()
                        .map(|(name, frames)| (name.clone(), Spread::of(frames).median))
                        .collect(),
                });
            }
            for row in &t.rows {
                match &row.pass_frames_ms {
                    Ok(passes) => {
                        let totals = frame_totals(passes);
                        r.points.push(ScalingPoint {
                            label: row.config.label(),
                            raster,
                            density: s.scene.generator.density,
                            strands: t.strands,
                            segments: t.segments,
                            ms: Spread::of(&totals),
                            frames: totals.len(),
                            passes: passes
                                .iter()
                                .map(|(name, frames)| (name.clone(), Spread::of(frames).median))
                                .collect(),
                        })
                    }
                    Err(e) => r.refused.push(ScalingRefusal {
                        label: row.config.label(),
                        raster,
                        segments: t.segments,
                        reason: e.clone(),
                    }),
                }
            }
            r.device = t.device;
        }
        r.densities.push(factor);
        r.fits = scaling_fits(configs, &plan.rasters, &r.points);
        written(&r)?;
    }
    Ok(Outcome::Complete(r))
}

/// The scaling points of the passes every method shares (light depth, the meshes' shadow map and, under the
/// compute rasteriser, its count, scan and fill), pooled over the configurations' timed frames at each density:
/// what ADSM costs (it has no pass of its own), and what a method's own passes add to.
pub const SHARED_LIGHT_LABEL: &str = "shared light passes";

/// The fit of each (configuration, rasteriser) with at least two points, configurations first, then the shared
/// light passes.
fn scaling_fits(configs: &[MethodConfig], rasters: &[Raster], points: &[ScalingPoint]) -> Vec<ScalingFit> {
    configs
        .iter()
        .map(MethodConfig::label)
        .chain([SHARED_LIGHT_LABEL.to_string()])
        .flat_map(|label| rasters.iter().map(move |&raster| (label.clone(), raster)))
        .filter_map(|(label, raster)| {
            let of: Vec<&ScalingPoint> = points
                .iter()
                .filter(|p| p.label == label && p.raster == raster)
                .collect();
            let xy: Vec<(f64, f64)> = of.iter().map(|p| (p.segments as f64, p.ms.median)).collect();
            fit_line(&xy).map(|(slope, intercept, r2)| ScalingFit {
                max_residual: xy
                    .iter()
                    .map(|(x, y)| {
                        let line = slope * x + intercept;
                        (y - line).abs() / line.abs()
                    })
                    .fold(0.0, f64::max),
                max_spread: of
                    .iter()
                    .map(|p| (p.ms.max - p.ms.min) / p.ms.median)
                    .fold(0.0, f64::max),
                label,
                raster,
                ms_per_segment: slope,
                intercept_ms: intercept,
                r_squared: r2,
                exponent: growth_exponent(&xy).unwrap_or(f64::NAN),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_densities_are_evenly_spaced_up_to_the_last() {
        // 4800 segments at × 1, 30,000 wanted: × 6.25 last, 6 points 1.0417 apart.
        let d = scaling_densities(4800, 30_000, 6);
        assert_eq!(d.len(), 6);
        assert!((d[5] - 6.25).abs() < 1e-6, "{d:?}");
        for w in d.windows(2) {
            assert!((w[1] - w[0] - 6.25 / 6.0).abs() < 1e-5, "{d:?}");
        }
    }
}
