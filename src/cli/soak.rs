//! `hairlab soak`: many frames while the light turns and the method changes (and a preset's motion plays); memory
//! must not grow, and a simulation's invariants and energy are reported over the run.

use crate::settings::Settings;
use anyhow::Result;
use clap::Args;

#[derive(Args, Debug)]
pub struct SoakArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.width=320` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Frames to render (at least two full cycles of methods).
    #[arg(long, default_value_t = 10_000)]
    pub frames: u64,
    /// Frames between method switches.
    #[arg(long, default_value_t = 250)]
    pub switch_every: u64,
}

pub(super) fn soak(a: &SoakArgs) -> Result<()> {
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
    println!("{:>8} {:>14} {:>10}", "frame", "resident MiB", "GPU MiB");
    let r = crate::soak::soak(&settings, a.frames, a.switch_every, |s| {
        let resident = s
            .resident_bytes
            .map_or("n/a".to_string(), |b| format!("{:.1}", mib(b)));
        println!("{:>8} {resident:>14} {:>10.1}", s.frame, mib(s.gpu_bytes));
    })?;
    for (name, reason) in &r.refused {
        println!("{name} refused on this scene: {reason}");
    }
    if let Some(m) = &r.motion {
        println!(
            "simulation over {} frames: kinetic energy per point at most {:.4} (frame {}), {:.4} in the last cycle; \
             worst relative segment-length error {:.2e}, depth inside the head {:.2e}, root error {:.2e}",
            r.frames,
            m.max_energy_per_point,
            m.max_energy_frame,
            m.last_cycle_max_energy_per_point,
            m.max_length_error,
            m.max_depth,
            m.max_root_error
        );
        if !m.finite {
            anyhow::bail!("the simulation produced a non-finite point");
        }
    }
    let (resident, gpu) = r.growth();
    let pct = |g: f64| format!("{:+.2} %", 100.0 * g);
    println!(
        "growth from the first cycle's end to the last's: resident {}, GPU {}",
        resident.map_or("n/a".to_string(), pct),
        pct(gpu)
    );
    let limit = crate::soak::MAX_GROWTH;
    if resident.is_some_and(|g| g > limit) || gpu > limit {
        anyhow::bail!("memory grew by more than {} % over the soak", 100.0 * limit);
    }
    Ok(())
}
