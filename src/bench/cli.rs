//! `hairlab bench`: the arguments, the run, and the tables printed on stdout.

use super::{
    ACCURACY_METRIC, BenchResult, Progress, ScalingResult, TerminalProgress, parse_methods, prepare_out_dir,
    run, run_scaling, scaling_configs, write_results, write_scaling,
};
use crate::settings::Settings;
use anyhow::{Context, Result, bail};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// The `bench` subcommand's arguments.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=256` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Methods to sweep, comma-separated (default: all): opaque-shadow-map, osm, dom, bom, dc, occupancy,
    /// reference.
    #[arg(long, value_delimiter = ',', value_name = "METHOD,...")]
    pub methods: Vec<String>,
    /// Timed frames per configuration (after one warm-up frame).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// Scaling mode: OSM-16, OSM-64, DOM-3 and occupancy over the strand density × 0.25..4, fitted GPU ms per
    /// segment (writes scaling.csv, scaling_points.csv, scaling.png, scaling.svg).
    #[arg(long)]
    pub scaling: bool,
    /// Output folder (created): results.csv, results.json, speed_vs_accuracy.png, speed_vs_accuracy.svg.
    #[arg(long)]
    pub out: PathBuf,
}

/// `hairlab bench`.
pub fn run_cli(a: &BenchArgs) -> Result<()> {
    let methods = parse_methods(&a.methods)?;
    if !(1..=1000).contains(&a.frames) {
        bail!("--frames must be in 1..=1000 (got {})", a.frames);
    }
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    prepare_out_dir(&a.out)?;
    let never = AtomicBool::new(false);
    let mut bar = TerminalProgress::new();
    let mut progress = |p: Progress| bar.update(&p);
    if a.scaling {
        let configs = scaling_configs(&methods);
        let r = run_scaling(&settings, &a.preset, &configs, a.frames, &never, &mut progress)?
            .context("the scaling run was cancelled")?;
        drop(bar);
        print_scaling(&r);
        for f in write_scaling(&a.out, &r)? {
            println!("wrote {}", f.display());
        }
        return Ok(());
    }
    let result = run(
        &settings,
        &a.preset,
        &methods,
        a.frames,
        usize::MAX,
        &never,
        &mut progress,
    )?
    .context("the bench was cancelled")?;
    drop(bar);
    print_table(&result);
    for f in write_results(&a.out, &result)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}

fn print_table(result: &BenchResult) {
    let s = &result.stats;
    println!(
        "preset {}: {} strands, {} segments, map {}x{}, {} frames, on {}",
        result.preset, s.strands, s.segments, s.map_resolution, s.map_resolution, result.frames, s.device
    );
    let front = result.front();
    println!(
        "{:<42} {:>10} {:>19} {:>10} {:>11}  pareto",
        "configuration", "GPU ms", "min..max", ACCURACY_METRIC, "memory MiB"
    );
    for (i, r) in result.rows.iter().enumerate() {
        let note = match r.note.as_str() {
            "" => String::new(),
            other => format!(" ({other})"),
        };
        println!(
            "{:<42} {:>10.3} {:>19} {:>10.5} {:>11.2}  {}",
            format!("{}{note}", r.config.label()),
            r.total_ms.median,
            format!("{:.3}..{:.3}", r.total_ms.min, r.total_ms.max),
            r.error(),
            r.memory_bytes as f64 / (1024.0 * 1024.0),
            if front.contains(&i) { "*" } else { "" }
        );
    }
    let names: Vec<String> = front.iter().map(|&i| result.rows[i].config.label()).collect();
    println!("Pareto front (fastest first): {}", names.join(" -> "));
}

fn print_scaling(r: &ScalingResult) {
    println!(
        "scaling on {}: GPU ms = cost per segment × segments + fixed cost",
        r.device
    );
    println!(
        "{:<20} {:>14} {:>13} {:>9}",
        "configuration", "ns per segment", "intercept ms", "R²"
    );
    for f in &r.fits {
        println!(
            "{:<20} {:>14.4} {:>13.4} {:>9.4}",
            f.label,
            f.ms_per_segment * 1e6,
            f.intercept_ms,
            f.r_squared
        );
    }
}
