//! `hairlab measure motion`: shadow methods against the exact reference over a preset's motion, frame by
//! frame, with the temporal metrics (docs/design.md, "Temporal metrics"); a table, `motion_summary.csv` and
//! `motion_frames.csv`, written whole after each configuration, so that Ctrl-C (which stops at the next frame,
//! leaving the configuration in progress out, exit code 130) leaves every finished one.

use crate::bench::motion::MotionRun;
use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::motion::{MotionMeasurement, MotionOptions, measure_motion};
use crate::measure::temporal::FollowedPoint;
use anyhow::Result;
use clap::Args;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

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

/// Measures, prints the table and writes the CSV files (after each configuration too).
pub fn run(a: &MeasureMotionArgs) -> Result<()> {
    let (settings, configs) = a.run.resolve()?;
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let written = RefCell::new(Vec::new());
    let after_each = |m: &MotionMeasurement| -> Result<()> {
        *written.borrow_mut() = write(&a.out, m)?;
        Ok(())
    };
    let options = MotionOptions {
        follow: a.point,
        after_each: Some(&after_each),
    };
    // Ctrl-C answers the bar's next step with a stop: the configurations finished are kept.
    let mut bar = super::progress::TerminalProgress::new();
    let m = measure_motion(&gpu, &settings, &configs, a.run.frames, options, &mut bar)?;
    drop(bar);
    let files = written.into_inner();
    print!("{}", m.table(&a.run.preset));
    for path in files {
        println!("wrote {}", path.display());
    }
    crate::cli::interrupt::finish(&m, m.rows.len())
}

/// Writes `motion_summary.csv`, `motion_frames.csv` and, with a followed point, `motion_point.csv` of `m` into
/// `out`, each whole.
fn write(out: &Path, m: &MotionMeasurement) -> Result<Vec<PathBuf>> {
    crate::bench::report::write_files(out, m.csv_files()?)
}
