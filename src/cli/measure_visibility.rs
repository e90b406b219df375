//! `hairlab measure visibility`: the depth-peeled reference against ray-traced fibres over a whole hair map
//! (`measure/fibre_visibility.rs`): where the product of `(1 − α)` departs from geometry, and the `α` that fits it.
//! Ctrl-C stops after the texel in progress: the texels measured are reported and written, then the run exits 130.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

use crate::gpu::{AdapterPreference, Gpu};
use crate::settings::Settings;

#[derive(Args, Debug, Clone)]
pub struct MeasureVisibilityArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=256` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Rays per texel side: N × N stratified rays through each texel's footprint (1..=64).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub rays: u32,
    /// Folder for `visibility_texels.csv` (one row per occupied texel), created.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

pub fn run(a: &MeasureVisibilityArgs) -> Result<()> {
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    if let Some(dir) = &a.out {
        crate::bench::prepare_out_dir(dir)?;
    }
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    // Ctrl-C answers the bar's next step with a stop: the texels done are reported and written, then the run
    // fails saying so.
    let mut bar = super::progress::TerminalProgress::new();
    let outcome = crate::measure::fibre_visibility::compare_map(&gpu, &settings, a.rays as usize, &mut bar)?;
    let stopped = outcome.is_stopped();
    let m = outcome.kept();
    drop(bar);
    let fragments: usize = m.texels.iter().map(|t| t.fragments).sum();
    println!(
        "preset {}: {}² map, {} occupied texels, {fragments} fragments, {} rays per texel (hair_alpha {}, strand width {})",
        a.preset,
        m.side,
        m.texels.len(),
        m.rays_per_texel,
        settings.render.hair_alpha,
        settings.render.strand_width
    );
    println!(
        "|V_ray − V_ref| after each fragment: mean {:.4}, p95 {:.4}, max {:.4}",
        m.mean_abs_dv, m.p95_abs_dv, m.max_abs_dv
    );
    println!(
        "best-fitting α {:.4} (the (1 − α)^k closest to the ray-traced V): mean |ΔV| {:.4} at it",
        m.best_alpha, m.mean_abs_dv_at_best
    );
    super::interrupt::write_rows_and_finish(
        a.out.as_deref(),
        "visibility_texels.csv",
        &m.texels,
        stopped,
        "texels",
    )
}
