//! `hairlab bench`: the arguments, the run, and the tables printed on stdout.

use crate::bench::{
    BenchResult, DEFAULT_SCALING_POINTS, DEFAULT_SCALING_SEGMENTS, DEFAULT_SCALING_WARMUP, ScalingFit,
    ScalingPlan, ScalingResult, parse_methods, parse_metric, prepare_out_dir, run_each, run_scaling,
    scaling_configs, write_results, write_scaling, write_scaling_tables, write_tables,
};
use crate::progress::Outcome;
use crate::render::caster::Raster;
use crate::settings::Settings;
use anyhow::{Context, Result, bail};
use std::path::PathBuf;

/// `hairlab bench`: a mode as a subcommand, each with only its own options; today's flags (`bench --scaling`,
/// `--transparency`, `--fur`, or none for the shadow methods' sweep) still work, hidden, and print the new
/// spelling.
#[derive(clap::Args, Debug)]
#[command(
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    after_help = "`hairlab bench --out DIR` with no mode sweeps the shadow methods, as `hairlab bench shadows`."
)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub mode: Option<BenchMode>,
    #[command(flatten)]
    pub legacy: LegacyBenchArgs,
}

#[derive(clap::Subcommand, Debug)]
pub enum BenchMode {
    /// Sweep every method's parameters and chart GPU time against an accuracy metric: results.csv,
    /// results.json, speed_vs_accuracy.png/.svg (Pareto front marked).
    Shadows(ShadowsBenchArgs),
    /// Every eye transparency technique's sweep against the exact sorted composite (GPU ms of its own passes
    /// against hair-pixel RMSE), and the speed ratio of depth peeling to occupancy ordering: transparency.csv,
    /// transparency.json, transparency_speed_vs_accuracy.png/.svg.
    Transparency(ModeBenchArgs),
    /// A fur preset's blendings against the fur reference (`measure fur`'s rows): fur.csv and fur.json, with
    /// the paper's Table 1 rows per blending.
    Fur(ModeBenchArgs),
    /// Each method's scaling configurations timed (light passes only) at --points strand densities evenly
    /// spaced in segments up to --max-segments (the median of --frames ≥ 3 timed frames after --warmup
    /// discarded ones per point); GPU ms = fixed cost + cost per segment × segments fitted with R² and the
    /// log-log exponent, per rasteriser with --raster hardware,compute: scaling.csv, scaling_points.csv,
    /// scaling.png, scaling.svg (rewritten whole after each density: Ctrl-C keeps the finished ones).
    Scaling(ScalingBenchArgs),
    /// Each configuration over a preset's motion (`measure motion`'s rows) charted as GPU time against a
    /// temporal metric (--metric: flicker, flicker-p99, pop-rate, image-flicker) with the Pareto front:
    /// motion_summary.csv, motion_frames.csv, motion_speed_vs_<metric>.png/.svg.
    Motion(crate::bench::motion::MotionBenchArgs),
}

/// The scene, the timing and the output folder, shared by every mode.
#[derive(clap::Args, Debug, Clone)]
pub struct BenchScene {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=256` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Timed frames per configuration (after one warm-up frame; `bench scaling`: at least 3, after --warmup).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// Output folder (created).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

#[derive(clap::Args, Debug, Clone)]
pub struct ShadowsBenchArgs {
    #[command(flatten)]
    pub scene: BenchScene,
    /// Methods to sweep, comma-separated (default: every registered method with a sweep; an unknown name is
    /// answered with the list).
    #[arg(long, value_delimiter = ',', value_name = "METHOD,...")]
    pub methods: Vec<String>,
    /// The accuracy metric of the chart, the table and the Pareto front (every metric is in the CSV and the
    /// JSON whichever is chosen).
    #[arg(long, default_value = crate::bench::DEFAULT_ACCURACY_METRIC,
          value_parser = clap::builder::PossibleValuesParser::new(crate::bench::accuracy_metrics().map(|(n, _)| n)))]
    pub metric: String,
}

#[derive(clap::Args, Debug, Clone)]
pub struct ModeBenchArgs {
    #[command(flatten)]
    pub scene: BenchScene,
}

#[derive(clap::Args, Debug, Clone)]
pub struct ScalingBenchArgs {
    #[command(flatten)]
    pub scene: BenchScene,
    /// Methods whose scaling configurations are timed, comma-separated (default: all).
    #[arg(long, value_delimiter = ',', value_name = "METHOD,...")]
    pub methods: Vec<String>,
    /// The segment count the densities reach.
    #[arg(long, default_value_t = DEFAULT_SCALING_SEGMENTS)]
    pub max_segments: usize,
    /// Densities measured, evenly spaced in segments up to --max-segments.
    #[arg(long, default_value_t = DEFAULT_SCALING_POINTS)]
    pub points: usize,
    /// Frames rendered and discarded before timing each configuration at each density.
    #[arg(long, default_value_t = DEFAULT_SCALING_WARMUP)]
    pub warmup: u32,
    /// Rasterisers each density is measured under, comma-separated: hardware, compute, or both (default: the
    /// preset's render.raster).
    #[arg(long, value_delimiter = ',', value_name = "RASTER,...")]
    pub raster: Vec<String>,
}

/// Today's spellings of `bench`, hidden from the help; every mode runs through them. A flag that the chosen
/// mode would ignore is refused, naming both.
#[derive(clap::Args, Debug, Clone)]
pub struct LegacyBenchArgs {
    #[arg(long, default_value = "default", hide = true)]
    pub preset: String,
    #[arg(long = "set", hide = true)]
    pub set: Vec<String>,
    #[arg(long, value_delimiter = ',', hide = true, conflicts_with_all = ["transparency", "fur"])]
    pub methods: Vec<String>,
    #[arg(long, default_value = crate::bench::DEFAULT_ACCURACY_METRIC, hide = true,
          conflicts_with_all = ["scaling", "transparency", "fur"],
          value_parser = clap::builder::PossibleValuesParser::new(crate::bench::accuracy_metrics().map(|(n, _)| n)))]
    pub metric: String,
    #[arg(long, default_value_t = 5, hide = true)]
    pub frames: u32,
    #[arg(long, hide = true)]
    pub scaling: bool,
    #[arg(long, conflicts_with = "scaling", hide = true)]
    pub transparency: bool,
    #[arg(long, conflicts_with_all = ["scaling", "transparency"], hide = true)]
    pub fur: bool,
    #[arg(long, hide = true)]
    pub max_segments: Option<usize>,
    #[arg(long, hide = true, requires = "scaling")]
    pub points: Option<usize>,
    #[arg(long, hide = true, requires = "scaling")]
    pub warmup: Option<u32>,
    #[arg(long, value_delimiter = ',', hide = true, requires = "scaling")]
    pub raster: Vec<String>,
    #[arg(long, hide = true, required = true)]
    pub out: Option<PathBuf>,
}

impl LegacyBenchArgs {
    fn of(scene: &BenchScene) -> LegacyBenchArgs {
        LegacyBenchArgs {
            preset: scene.preset.clone(),
            set: scene.set.clone(),
            methods: Vec::new(),
            metric: crate::bench::DEFAULT_ACCURACY_METRIC.to_string(),
            frames: scene.frames,
            scaling: false,
            transparency: false,
            fur: false,
            max_segments: None,
            points: None,
            warmup: None,
            raster: Vec::new(),
            out: Some(scene.out.clone()),
        }
    }

    /// The line naming the new spelling of these flags (none for the plain sweep).
    fn note(&self) -> Option<&'static str> {
        if self.scaling {
            Some("`hairlab bench --scaling` is now `hairlab bench scaling`")
        } else if self.transparency {
            Some("`hairlab bench --transparency` is now `hairlab bench transparency`")
        } else if self.fur {
            Some("`hairlab bench --fur` is now `hairlab bench fur`")
        } else {
            None
        }
    }
}

impl BenchMode {
    /// The mode as the flags that run it (none for a mode that has no flag spelling: motion).
    fn flags(&self) -> Option<LegacyBenchArgs> {
        Some(match self {
            BenchMode::Motion(_) => return None,
            BenchMode::Shadows(a) => LegacyBenchArgs {
                methods: a.methods.clone(),
                metric: a.metric.clone(),
                ..LegacyBenchArgs::of(&a.scene)
            },
            BenchMode::Transparency(a) => LegacyBenchArgs {
                transparency: true,
                ..LegacyBenchArgs::of(&a.scene)
            },
            BenchMode::Fur(a) => LegacyBenchArgs {
                fur: true,
                ..LegacyBenchArgs::of(&a.scene)
            },
            BenchMode::Scaling(a) => LegacyBenchArgs {
                scaling: true,
                methods: a.methods.clone(),
                max_segments: Some(a.max_segments),
                points: Some(a.points),
                warmup: Some(a.warmup),
                raster: a.raster.clone(),
                ..LegacyBenchArgs::of(&a.scene)
            },
        })
    }
}

/// `hairlab bench`.
pub fn run_cli(args: &BenchArgs) -> Result<()> {
    let a = match &args.mode {
        Some(BenchMode::Motion(m)) => {
            let kept =
                crate::bench::motion::run(m, &mut super::progress::TerminalProgress::uninterruptible())?;
            return super::interrupt::finish(&kept, *kept);
        }
        Some(mode) => mode.flags().context("a bench mode without flags")?,
        None => {
            if args.legacy.max_segments.is_some() && !args.legacy.scaling {
                bail!("--max-segments needs --scaling (now `hairlab bench scaling --max-segments N`)");
            }
            if let Some(note) = args.legacy.note() {
                eprintln!("note: {note}");
            }
            args.legacy.clone()
        }
    };
    let a = &a;
    let out = a
        .out
        .clone()
        .context("--out DIR: the output folder is required")?;
    let max_segments = a.max_segments.unwrap_or(DEFAULT_SCALING_SEGMENTS);
    let methods = parse_methods(&a.methods)?;
    let metric = parse_metric(&a.metric).map_err(|e| anyhow::anyhow!("--metric: {e}"))?;
    if !(1..=1000).contains(&a.frames) {
        bail!("--frames must be in 1..=1000 (got {})", a.frames);
    }
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    prepare_out_dir(&out)?;
    // Ctrl-C answers the bar's next step with a stop.
    let mut bar = super::progress::TerminalProgress::new();
    if a.fur {
        // Ctrl-C stops after the configuration in progress; fur.csv and fur.json are rewritten whole after each
        // one.
        let configs = crate::measure::fur::usual_configs();
        let b = crate::bench::fur::FurBench::run_each(
            &settings,
            &a.preset,
            &configs,
            a.frames,
            &mut bar,
            |partial| partial.write(&out).map(|_| ()),
        )?;
        drop(bar);
        for f in b.write(&out)? {
            println!("wrote {}", f.display());
        }
        return super::interrupt::finish(&b, b.rows.len());
    }
    if a.transparency {
        // Ctrl-C stops after the configuration in progress; transparency.csv and transparency.json are rewritten
        // whole after each one.
        let gpu = crate::gpu::Gpu::headless(crate::gpu::AdapterPreference::from_env_or(
            crate::gpu::AdapterPreference::Hardware,
        ))?;
        let configs = crate::bench::transparency::sweep_configs();
        let b = crate::bench::transparency::TransparencyBench::run_each(
            &gpu,
            &settings,
            &a.preset,
            &configs,
            a.frames,
            &mut bar,
            |partial| partial.write_tables(&out).map(|_| ()),
        )?;
        drop(bar);
        print_transparency(&b);
        for f in b.write(&out)? {
            println!("wrote {}", f.display());
        }
        return super::interrupt::finish(&b, b.rows.len());
    }
    if a.scaling {
        // Ctrl-C stops after the density in progress; scaling.csv and scaling_points.csv are rewritten whole
        // after each one.
        let configs = scaling_configs(&methods);
        let plan = ScalingPlan {
            max_segments,
            points: a.points.unwrap_or(DEFAULT_SCALING_POINTS),
            frames: a.frames,
            warmup: a.warmup.unwrap_or(DEFAULT_SCALING_WARMUP),
            rasters: parse_rasters(&a.raster, settings.render.raster)?,
        };
        let mut written = |partial: &ScalingResult| write_scaling_tables(&out, partial).map(|_| ());
        let r = run_scaling(&settings, &a.preset, &configs, &plan, &mut bar, &mut written)?;
        drop(bar);
        print_scaling(&r);
        for f in write_scaling(&out, &r)? {
            println!("wrote {}", f.display());
        }
        return super::interrupt::finish(&r, r.densities.len() * plan.rasters.len() * configs.len());
    }
    // Ctrl-C stops after the configuration in progress; results.csv and results.json are rewritten whole after
    // each one.
    let mut write = |partial: &Outcome<BenchResult>| {
        let mut partial = partial.clone();
        partial.metric = metric;
        write_tables(&out, &partial).map(|_| ())
    };
    let outcome = run_each(&settings, &a.preset, &methods, a.frames, &mut bar, &mut write)?;
    drop(bar);
    let stopped = outcome.is_stopped();
    let Some(mut result) = outcome.kept() else {
        return Err(super::interrupt::Interrupted { done: 0 }.into());
    };
    result.metric = metric;
    print_table(&result);
    let result = Outcome::new(result, stopped);
    for f in write_results(&out, &result)? {
        println!("wrote {}", f.display());
    }
    super::interrupt::finish(&result, result.rows.len())
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

fn print_transparency(b: &crate::bench::transparency::TransparencyBench) {
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
            crate::bench::transparency::PAPER_PEEL_RATIO,
            crate::bench::transparency::PAPER_PEEL_LAYERS
        ),
        None => println!("t(depth peel) / t(occupancy order): not measured (no timestamps on this device?)"),
    }
}

/// The `--raster` list: each of [`Raster::ALL`] by its word, or `both`; empty means `preset` (the preset's
/// `render.raster`) alone.
fn parse_rasters(words: &[String], preset: Raster) -> Result<Vec<Raster>> {
    if words.is_empty() {
        return Ok(vec![preset]);
    }
    let mut out = Vec::new();
    for w in words.iter().map(|w| w.trim()) {
        let named: Vec<Raster> = match Raster::ALL.iter().find(|r| r.word() == w) {
            Some(&r) => vec![r],
            None if w == "both" => Raster::ALL.to_vec(),
            None => {
                let known: Vec<&str> = Raster::ALL.iter().map(|r| r.word()).collect();
                bail!(
                    "--raster: '{w}' is not a rasteriser; {} or both",
                    known.join(", ")
                );
            }
        };
        for r in named {
            if !out.contains(&r) {
                out.push(r);
            }
        }
    }
    Ok(out)
}

fn print_scaling(r: &ScalingResult) {
    println!(
        "scaling on {} (map {}², {} points, median of {} frames after {} warm-up): GPU ms = fixed cost + cost per \
         segment × segments",
        r.device,
        r.map_resolution,
        r.densities.len(),
        r.frames,
        r.warmup
    );
    println!(
        "{:<20} {:<8} {:>14} {:>13} {:>9} {:>9}  verdict",
        "configuration", "raster", "ns per segment", "intercept ms", "R²", "exponent"
    );
    for f in &r.fits {
        println!(
            "{:<20} {:<8} {:>14.4} {:>13.4} {:>9.4} {:>9.3}  {}",
            f.label,
            f.raster.word(),
            f.ms_per_segment * 1e6,
            f.intercept_ms,
            f.r_squared,
            f.exponent,
            f.verdict()
        );
    }
    let nonlinear: Vec<&ScalingFit> = r.fits.iter().filter(|f| !f.linear()).collect();
    if nonlinear
        .iter()
        .any(|f| !r.pass_growth(&f.label, f.raster).is_empty())
    {
        println!(
            "where the costs that are not linear grow (each pass: exponent, share at the largest density):"
        );
        for f in nonlinear {
            let growth = r.pass_growth(&f.label, f.raster);
            if growth.is_empty() {
                continue;
            }
            let passes: Vec<String> = growth
                .iter()
                .map(|g| format!("{} {:.2} ({:.0} %)", g.pass, g.exponent, g.share * 100.0))
                .collect();
            println!("  {:<20} {:<8} {}", f.label, f.raster.word(), passes.join(", "));
        }
    }
    let ratios = r.raster_ratios();
    if !ratios.is_empty() {
        println!("compute / hardware raster, light-pass GPU ms (medians):");
        for (density, label, ratio) in ratios {
            let segments = r
                .points
                .iter()
                .find(|p| p.density == density && p.label == label)
                .map_or(0, |p| p.segments);
            println!("  {label:<20} x{density:<8.3} {segments:>10} segments  {ratio:>7.3}");
        }
    }
    for x in &r.refused {
        println!(
            "{} ({} raster) refused at {} segments: {}",
            x.label,
            x.raster.word(),
            x.segments,
            x.reason
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rasters_parse_by_word_or_both() {
        assert_eq!(parse_rasters(&[], Raster::Compute).unwrap(), [Raster::Compute]);
        let words = |w: &[&str]| w.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(
            parse_rasters(&words(&["compute", "hardware", "compute"]), Raster::Hardware).unwrap(),
            [Raster::Compute, Raster::Hardware]
        );
        assert_eq!(
            parse_rasters(&words(&["both"]), Raster::Hardware).unwrap(),
            Raster::ALL
        );
        let e = parse_rasters(&words(&["software"]), Raster::Hardware).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--raster: 'software' is not a rasteriser; hardware, compute or both"
        );
    }
}
