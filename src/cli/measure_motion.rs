//! `hairlab measure --motion`: shadow methods against the exact reference over a preset's motion, frame by
//! frame, with the temporal metrics (docs/design.md, "Temporal metrics"); a table, `motion_summary.csv` and
//! `motion_frames.csv`.

use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::motion::{MotionConfig, MotionMeasurement, MotionOptions, measure_motion, usual_configs};
use crate::measure::temporal::FollowedPoint;
use crate::settings::Settings;
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct MeasureMotionArgs {
    /// Preset with a `[motion]`: built-in name (`wind`, `head-turn`, `stray-sweep`, `straight-motion`),
    /// `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "wind")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=256` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Method configurations `name` or `name:key=value,...` (repeatable); the key a method's analysis chooses
    /// may be `auto` (chosen on frame 0 and kept) or `auto-per-frame` (chosen again every frame), e.g.
    /// `bom:layers=4,split_ratio=auto-per-frame`. Default: the usual settings of every registered method.
    #[arg(long = "config", value_name = "METHOD[:K=V,...]")]
    pub configs: Vec<String>,
    /// Frames of the motion played, 0..N (at least 2).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// Follow one hair point over the frames (the window's time view): the segment starting at global strand
    /// point FIRST, at parameter T in [0, 1] along it (default 0.5). Writes `motion_point.csv`: each
    /// configuration's and the reference's visibility at the point per frame, and the pops.
    #[arg(long, value_name = "FIRST[:T]", value_parser = FollowedPoint::parse)]
    pub point: Option<FollowedPoint>,
    /// Folder for `motion_summary.csv` and `motion_frames.csv` (created).
    #[arg(long)]
    pub out: PathBuf,
}

/// Measures, prints the table and writes the two CSV files.
pub fn run(a: &MeasureMotionArgs) -> Result<()> {
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    let configs = if a.configs.is_empty() {
        usual_configs()
    } else {
        a.configs
            .iter()
            .map(|c| MotionConfig::parse(c))
            .collect::<Result<_>>()?
    };
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let options = MotionOptions {
        follow: a.point,
        cancel: None,
    };
    let m = measure_motion(&gpu, &settings, &configs, a.frames, options, &mut |what, _| {
        eprintln!("measuring {what}…")
    })?;
    print!("{}", table(&a.preset, &m));
    let mut files = vec![
        ("motion_summary.csv".to_string(), m.summary_csv()?.into_bytes()),
        ("motion_frames.csv".to_string(), m.frames_csv()?.into_bytes()),
    ];
    if let Some(csv) = m.point_csv()? {
        files.push(("motion_point.csv".to_string(), csv.into_bytes()));
    }
    for path in crate::bench::report::write_files(&a.out, files)? {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The summary table: one line per configuration.
pub fn table(preset: &str, m: &MotionMeasurement) -> String {
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
        let worst = |o: &crate::measure::temporal::OverFrames| format!("{:.5}@{}", o.worst, o.worst_frame);
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
