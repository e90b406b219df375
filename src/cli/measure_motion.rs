//! `hairlab measure --motion`: shadow methods against the exact reference over a preset's motion, frame by
//! frame, with the temporal metrics (docs/design.md, "Temporal metrics"); a table, `motion_summary.csv` and
//! `motion_frames.csv`.

use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::motion::{MotionConfig, MotionOptions, measure_motion, usual_configs};
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
    print!("{}", m.table(&a.preset));
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
