//! `hairlab bench`: the arguments, the run, and the tables printed on stdout.

use super::{
    BenchResult, DEFAULT_SCALING_SEGMENTS, Progress, ScalingResult, TerminalProgress, parse_methods,
    parse_metric, prepare_out_dir, run_each, run_scaling, scaling_configs, write_results, write_scaling,
    write_tables,
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
    /// Methods to sweep, comma-separated (default: every registered method with a sweep; an unknown name is
    /// answered with the list).
    #[arg(long, value_delimiter = ',', value_name = "METHOD,...")]
    pub methods: Vec<String>,
    /// The accuracy metric of the chart, the table and the Pareto front (every metric is in the CSV and the
    /// JSON whichever is chosen).
    #[arg(long, default_value = super::DEFAULT_ACCURACY_METRIC,
          value_parser = clap::builder::PossibleValuesParser::new(super::accuracy_metrics().map(|(n, _)| n)))]
    pub metric: String,
    /// Timed frames per configuration (after one warm-up frame).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// Scaling mode: each method's scaling configurations timed (light passes only) over the strand density
    /// from × 0.25, doubled until the scene has --max-segments segments (and at least to × 4); fitted GPU ms
    /// per segment with R² (writes scaling.csv, scaling_points.csv, scaling.png, scaling.svg).
    #[arg(long)]
    pub scaling: bool,
    /// Eye transparency mode: every technique's sweep against the exact sorted composite on the preset's view
    /// (GPU ms of its own passes against hair-pixel RMSE; writes transparency.csv, transparency.json,
    /// transparency_speed_vs_accuracy.png/.svg) and the speed ratio of depth peeling to occupancy ordering.
    #[arg(long, conflicts_with = "scaling")]
    pub transparency: bool,
    /// Measure a fur preset's blendings against the fur reference (`measure --fur`'s rows) into `fur.csv` and
    /// `fur.json`: error, fragments and the paper's Table 1 rows per blending.
    #[arg(long, conflicts_with_all = ["scaling", "transparency"])]
    pub fur: bool,
    /// The segment count the scaling mode reaches.
    #[arg(long, default_value_t = DEFAULT_SCALING_SEGMENTS)]
    pub max_segments: usize,
    /// Output folder (created): results.csv, results.json, speed_vs_accuracy.png, speed_vs_accuracy.svg.
    #[arg(long)]
    pub out: PathBuf,
}

/// `hairlab bench`.
pub fn run_cli(a: &BenchArgs) -> Result<()> {
    let methods = parse_methods(&a.methods)?;
    let metric = parse_metric(&a.metric).map_err(|e| anyhow::anyhow!("--metric: {e}"))?;
    if !(1..=1000).contains(&a.frames) {
        bail!("--frames must be in 1..=1000 (got {})", a.frames);
    }
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    prepare_out_dir(&a.out)?;
    let never = AtomicBool::new(false);
    let mut bar = TerminalProgress::new();
    let mut progress = |p: Progress| bar.update(&p);
    if a.fur {
        let b = super::fur::FurBench::run(&settings, &a.preset, a.frames)?;
        for f in b.write(&a.out)? {
            println!("wrote {}", f.display());
        }
        return Ok(());
    }
    if a.transparency {
        let b = super::transparency::TransparencyBench::run(&settings, &a.preset, a.frames, |what| {
            eprintln!("measuring {what}…")
        })?;
        print_transparency(&b);
        for f in b.write(&a.out)? {
            println!("wrote {}", f.display());
        }
        return Ok(());
    }
    if a.scaling {
        let configs = scaling_configs(&methods);
        let r = run_scaling(
            &settings,
            &a.preset,
            &configs,
            a.frames,
            a.max_segments,
            &never,
            &mut progress,
        )?
        .context("the scaling run was cancelled")?;
        drop(bar);
        print_scaling(&r);
        for f in write_scaling(&a.out, &r)? {
            println!("wrote {}", f.display());
        }
        return Ok(());
    }
    // Ctrl-C stops after the configuration in progress; results.csv and results.json are rewritten whole after
    // each one.
    let interrupted = crate::cli::interrupt::flag();
    let mut write = |partial: &BenchResult| {
        let mut partial = partial.clone();
        partial.metric = metric;
        write_tables(&a.out, &partial).map(|_| ())
    };
    let result = run_each(
        &settings,
        &a.preset,
        &methods,
        a.frames,
        interrupted,
        &mut progress,
        &mut write,
    )?;
    drop(bar);
    let Some(mut result) = result else {
        return Err(crate::cli::interrupt::Interrupted { done: 0 }.into());
    };
    result.metric = metric;
    print_table(&result);
    for f in write_results(&a.out, &result)? {
        println!("wrote {}", f.display());
    }
    if result.cancelled {
        return Err(crate::cli::interrupt::Interrupted {
            done: result.rows.len(),
        }
        .into());
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
        "configuration", "GPU ms", "min..max", result.metric, "memory MiB"
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
            result.accuracy(r),
            r.memory_bytes as f64 / (1024.0 * 1024.0),
            if front.contains(&i) { "*" } else { "" }
        );
    }
    let names: Vec<String> = front.iter().map(|&i| result.rows[i].config.label()).collect();
    println!("Pareto front (fastest first): {}", names.join(" -> "));
}

fn print_transparency(b: &super::transparency::TransparencyBench) {
    let s = &b.stats;
    println!(
        "preset {}: {} strands, {} segments, view {}x{}, eye depth complexity max {} mean {:.1}, {} frames, on {}",
        b.preset,
        s.strands,
        s.segments,
        s.width,
        s.height,
        s.max_depth_complexity,
        s.mean_depth_complexity,
        b.frames,
        b.device
    );
    let front = b.front();
    println!(
        "{:<40} {:>10} {:>10} {:>8} {:>9} {:>10} {:>5}  pareto",
        "configuration", "GPU ms", "hair RMSE", "SSIM", "FLIP hair", "memory MiB", "geom"
    );
    for (i, r) in b.rows.iter().enumerate() {
        println!(
            "{:<40} {:>10.3} {:>10.5} {:>8.4} {:>9.4} {:>10.2} {:>5}  {}",
            r.config.label(),
            r.total_ms(),
            r.metrics.rmse_hair,
            r.metrics.ssim_hair,
            r.metrics.flip.mean_hair,
            r.memory_bytes as f64 / (1024.0 * 1024.0),
            r.geometry_passes,
            if front.contains(&i) { "*" } else { "" }
        );
    }
    let names: Vec<String> = front.iter().map(|&i| b.rows[i].config.label()).collect();
    println!("Pareto front (fastest first): {}", names.join(" -> "));
    match b.peel_ratio() {
        Some(ratio) => println!(
            "t(depth peel) / t(occupancy order) = {ratio:.2} at {} layers (the deepest pixel); the paper: {:.2} at {} \
             layers (Fig. 2, 51 / 4.01 fps)",
            s.max_depth_complexity,
            super::transparency::PAPER_PEEL_RATIO,
            super::transparency::PAPER_PEEL_LAYERS
        ),
        None => println!("t(depth peel) / t(occupancy order): not measured (no timestamps on this device?)"),
    }
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
    for r in &r.refused {
        println!("{} refused at {} segments: {}", r.label, r.segments, r.reason);
    }
}
