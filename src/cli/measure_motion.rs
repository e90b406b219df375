//! `hairlab measure motion`: shadow methods against the exact reference over a preset's motion, frame by
//! frame, with the temporal metrics (docs/design.md, "Temporal metrics"); a table, `motion_summary.csv` and
//! `motion_frames.csv`.

use crate::bench::motion::MotionRun;
use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::motion::{MotionOptions, measure_motion};
use crate::measure::temporal::FollowedPoint;
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct MeasureMotionArgs {
    #[command(flatten)]
    pub run: MotionRun,
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
    let (settings, configs) = a.run.resolve()?;
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let options = MotionOptions {
        follow: a.point,
        cancel: None,
    };
    let m = measure_motion(
        &gpu,
        &settings,
        &configs,
        a.run.frames,
        options,
        &mut |what, _| eprintln!("measuring {what}…"),
    )?;
    print!("{}", m.table(&a.run.preset));
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
