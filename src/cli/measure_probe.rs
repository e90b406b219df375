//! `hairlab measure probe`: the fibres model's light probe against the path tracer's gather at its points
//! (`measure/probe.rs`): the ratio over every point, per colour channel and per height band, and
//! `probe_points.csv`. Ctrl-C stops after the chunk of points in progress: those are reported and written, then
//! the run exits 130.

use anyhow::Result;
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;

use crate::measure::probe::{self, ProbeCheck, Totals};
use crate::settings::Settings;

#[derive(Args, Debug, Clone)]
pub struct MeasureProbeArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set scene.generator.floor=false` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Directions the path tracer gathers over at each point (uniform over the sphere, in two halves).
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(2..=1_000_000))]
    pub directions: u32,
    /// Folder for `probe_points.csv` (one row per point), created.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

pub fn run(a: &MeasureProbeArgs) -> Result<()> {
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    if let Some(dir) = &a.out {
        crate::bench::prepare_out_dir(dir)?;
    }
    let scene = settings.scene.build()?;
    let mut bar = super::progress::TerminalProgress::new();
    let outcome = probe::check(&settings, &scene, a.directions, &mut bar)?;
    drop(bar);
    let stopped = outcome.is_stopped();
    let m = outcome.kept();
    print!("{}", report(&a.preset, &m));
    super::interrupt::write_rows_and_finish(
        a.out.as_deref(),
        "probe_points.csv",
        &m.points,
        stopped,
        "points",
    )
}

fn row(s: &mut String, name: &str, t: &Totals) {
    let red_blue = |c: glam::Vec3| c.x / c.z.max(f32::MIN_POSITIVE);
    let _ = writeln!(
        s,
        "{name:<8} {:>6} | {:>8.5} {:>8.5} | {:>6.3} | {:>5.2} {:>5.2}",
        t.points,
        probe::luminance(t.gather),
        probe::luminance(t.probe),
        t.ratio(),
        red_blue(t.gather),
        red_blue(t.probe)
    );
}

/// The printed report: the whole, the channels, the bands.
pub fn report(preset: &str, m: &ProbeCheck) -> String {
    let mut s = String::new();
    let all = m.all();
    let _ = writeln!(
        s,
        "preset {preset}: the fibres model's probe against a path-traced gather at its {} points, {} directions each",
        all.points, m.directions
    );
    let c = all.probe / all.gather.max(glam::Vec3::splat(f32::MIN_POSITIVE));
    let _ = writeln!(
        s,
        "probe / gather: {:.3} (luminance); r g b {:.3} {:.3} {:.3}; the gather's halves {:.3} of each other",
        all.ratio(),
        c.x,
        c.y,
        c.z,
        m.halves.0 / m.halves.1.max(f64::MIN_POSITIVE)
    );
    let _ = writeln!(
        s,
        "{:<8} {:>6} | {:>8} {:>8} | {:>6} | {:>5} {:>5}",
        "band", "points", "gather", "probe", "ratio", "r/b g", "r/b p"
    );
    row(&mut s, "all", &all);
    for (k, b) in m.bands().iter().enumerate() {
        row(&mut s, &format!("{} of {}", k + 1, probe::BANDS), b);
    }
    let _ = writeln!(
        s,
        "(mean linear radiance per point, luminance; bands of world height, the highest first; r/b: red over blue, \
         gather and probe)"
    );
    s
}
