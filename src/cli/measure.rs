//! `hairlab measure`: methods, techniques or fur blendings against their exact references.

use crate::methods::registry;
use crate::progress::Outcome;
use crate::settings::Settings;
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// `hairlab measure`: a mode as a subcommand, each with only its own options; today's flags (`measure
/// --transparency`, `--fur`, or none for the shadow methods) still work, hidden, and print the new spelling.
/// A new mode is one [`MeasureMode`] variant with its `Args` and a match arm in [`measure`].
#[derive(Args, Debug)]
#[command(
    args_conflicts_with_subcommands = true,
    after_help = "`hairlab measure` with no mode measures the shadow methods, as `hairlab measure shadows`."
)]
pub struct MeasureArgs {
    #[command(subcommand)]
    pub mode: Option<MeasureMode>,
    #[command(flatten)]
    pub legacy: LegacyMeasureArgs,
}

#[derive(clap::Subcommand, Debug)]
pub enum MeasureMode {
    /// Shadow methods against the exact reference: depth complexity, map error and its spread over the texels,
    /// shading, image (RMSE, PSNR, FLIP) and flicker errors, GPU time per pass (median), memory, geometry
    /// passes.
    Shadows(ShadowsArgs),
    /// Eye transparency techniques against the exact sorted composite: image metrics over all and hair pixels
    /// (RMSE, PSNR, SSIM, FLIP, …), GPU ms, memory, geometry passes.
    Transparency(TransparencyArgs),
    /// A fur preset's blendings against the fur reference (virtual fragments of one march step, no early
    /// exit): RMSE of (H, 1 - T) and FLIP over fur pixels, fragments, and the paper's Table 1 for each.
    Fur(FurArgs),
    /// Shadow methods over a preset's motion against the exact reference of every frame: per-frame map and
    /// shading errors, flicker, pop rate, image flicker, GPU ms; `motion_summary.csv` and `motion_frames.csv`.
    Motion(super::measure_motion::MeasureMotionArgs),
    /// The exact reference's V(z) against ray-traced fibres in every occupied texel of the hair map: the mean,
    /// p95 and largest difference after each fragment, and the α that fits the fibres best.
    Visibility(super::measure_visibility::MeasureVisibilityArgs),
    /// Dual scattering's constants from the preset's fibre: the forward and backward attenuations ā_f(θ), ā_b(θ)
    /// of Chiang's BSDF by quadrature, slabs of parallel fibres path-traced at several depths, and the fitted
    /// d_f, d_b; `fibre_constants.csv` and `.json`.
    Fibres(super::measure_fibres::MeasureFibresArgs),
    /// The fibres model's light probe against the path tracer's mean radiance arriving at the probe's own
    /// points (every event, the light itself left out; for the traced probe none from the cone about the
    /// light): ratios over all points, per channel and per height band; `probe_points.csv`.
    Probe(super::measure_probe::MeasureProbeArgs),
}

/// The scene and the timing, shared by every mode.
#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=512` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Timed frames per configuration (after one warm-up frame).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
}

#[derive(Args, Debug, Clone)]
pub struct ShadowsArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Method configurations `name` or `name:key=value,...` (repeatable); `bom:layers=K,split_ratio=auto` uses
    /// the automatic split ratio. Default: the usual settings of every registered method (OSM 16/64/256, DOM 3/7,
    /// BOM 4/8, DC 4, occupancy).
    #[arg(long = "config", value_name = "METHOD[:K=V,...]")]
    pub configs: Vec<String>,
    /// Output folder (created): results.csv and results.json, rewritten after each configuration (Ctrl-C stops
    /// after the one in progress and keeps them), and the speed_vs_accuracy chart, as `bench` writes them.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Also the image error (RMSE, FLIP) of every configuration under each of these shading models
    /// (`kajiya-kay,marschner,…`), each against the reference image under the same model: a second table, and
    /// shading.csv in the output folder.
    #[arg(long, value_name = "MODEL,...", value_delimiter = ',', value_parser = parse_shading)]
    pub shading: Vec<crate::shading::ShadingModel>,
    /// What the shading table's images are judged against besides the depth-peeled reference: `path-traced`
    /// path-traces the scene (`render.spp` samples per pixel) and decomposes each configuration's image error
    /// under each shading model (every one unless `--shading` names some) into the method's, the opacity
    /// model's (the reference against the path-traced image) and their total; decomposition.csv with `--out`.
    #[arg(long, value_enum, default_value = "depth-peeled")]
    pub truth: TruthKind,
}

/// The truth `measure shadows` judges images against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TruthKind {
    /// The exact reference of the shared opacity model (A-buffer / depth peeling).
    DepthPeeled,
    /// A path-traced image of the fibres (Chiang et al. 2016's BSDF, multiple scattering).
    PathTraced,
}

/// A shading model by its word (`render.shading`'s values).
fn parse_shading(word: &str) -> Result<crate::shading::ShadingModel, String> {
    use crate::shading::ShadingModel;
    ShadingModel::ALL
        .into_iter()
        .find(|m| m.word() == word)
        .ok_or_else(|| {
            let words: Vec<&str> = ShadingModel::ALL.iter().map(|m| m.word()).collect();
            format!("unknown shading model {word:?} (one of {})", words.join(", "))
        })
}

#[derive(Args, Debug, Clone)]
pub struct TransparencyArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Technique configurations `name` or `name:key=value,...` (repeatable); default: every registered
    /// technique.
    #[arg(long = "technique", value_name = "TECHNIQUE[:K=V,...]")]
    pub techniques: Vec<String>,
    /// Output folder (created): transparency.csv, transparency.json and the chart, as `bench transparency`
    /// writes them.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

#[derive(Args, Debug, Clone)]
pub struct FurArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Blendings: `naive`, `simplified` or `virtual:k=K` (repeatable); default naive, simplified, virtual
    /// k = 32, 8, 4, 2.
    #[arg(long = "fur-config", value_name = "BLENDING[:k=K]")]
    pub fur_configs: Vec<String>,
    /// Output folder (created): fur.csv and fur.json, as `bench fur` writes them.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Today's spellings of `measure` (no mode: the shadow methods; `--transparency`; `--fur`), hidden from the help.
#[derive(Args, Debug)]
pub struct LegacyMeasureArgs {
    #[arg(long, default_value = "default", hide = true)]
    pub preset: String,
    #[arg(long = "set", value_name = "KEY=VALUE", hide = true)]
    pub set: Vec<String>,
    #[arg(long = "config", hide = true, conflicts_with_all = ["transparency", "fur"])]
    pub configs: Vec<String>,
    #[arg(long, default_value_t = 5, hide = true)]
    pub frames: u32,
    #[arg(long, hide = true)]
    pub transparency: bool,
    #[arg(long = "technique", hide = true)]
    pub techniques: Vec<String>,
    #[arg(long, conflicts_with = "transparency", hide = true)]
    pub fur: bool,
    #[arg(long = "fur-config", hide = true)]
    pub fur_configs: Vec<String>,
    #[arg(long, conflicts_with_all = ["transparency", "fur"], hide = true)]
    pub motion: bool,
    #[arg(long, hide = true)]
    pub out: Option<PathBuf>,
}

impl LegacyMeasureArgs {
    /// The mode these flags spell, and the line naming its new spelling (none for plain `measure`); a mode's
    /// option without its mode flag is refused, naming both.
    pub fn mode(&self) -> Result<(MeasureMode, Option<&'static str>)> {
        if !self.techniques.is_empty() && !self.transparency {
            anyhow::bail!(
                "--technique needs --transparency (now `hairlab measure transparency --technique …`)"
            );
        }
        if !self.fur_configs.is_empty() && !self.fur {
            anyhow::bail!("--fur-config needs --fur (now `hairlab measure fur --fur-config …`)");
        }
        let scene = SceneArgs {
            preset: self.preset.clone(),
            set: self.set.clone(),
            frames: self.frames,
        };
        let out = self.out.clone();
        if self.motion {
            let out = out.ok_or_else(|| {
                anyhow::anyhow!("--motion needs --out DIR (now `hairlab measure motion --out DIR`)")
            })?;
            let a = super::measure_motion::MeasureMotionArgs {
                run: crate::bench::motion::MotionRun {
                    preset: scene.preset,
                    set: scene.set,
                    configs: self.configs.clone(),
                    frames: scene.frames,
                },
                point: None,
                out,
            };
            return Ok((
                MeasureMode::Motion(a),
                Some("`hairlab measure --motion` is now `hairlab measure motion`"),
            ));
        }
        if self.transparency {
            let a = TransparencyArgs {
                scene,
                techniques: self.techniques.clone(),
                out,
            };
            Ok((
                MeasureMode::Transparency(a),
                Some("`hairlab measure --transparency` is now `hairlab measure transparency`"),
            ))
        } else if self.fur {
            let a = FurArgs {
                scene,
                fur_configs: self.fur_configs.clone(),
                out,
            };
            Ok((
                MeasureMode::Fur(a),
                Some("`hairlab measure --fur` is now `hairlab measure fur`"),
            ))
        } else {
            let a = ShadowsArgs {
                scene,
                configs: self.configs.clone(),
                out,
                shading: Vec::new(),
                truth: TruthKind::DepthPeeled,
            };
            Ok((MeasureMode::Shadows(a), None))
        }
    }
}

/// Prints the paths of files written.
fn print_written(files: &[PathBuf]) {
    for f in files {
        println!("wrote {}", f.display());
    }
}

/// A `--config` with `key=auto` pairs, resolved by the method's analysis to `name:key=value,...`; `None` when
/// it has none.
pub(super) fn auto_config(settings: &Settings, text: &str) -> Result<Option<String>> {
    let (name, pairs) = crate::selection::split_config(text)?;
    if !pairs.iter().any(|(_, v)| *v == "auto") {
        return Ok(None);
    }
    let method = registry::find(name).map_err(anyhow::Error::msg)?;
    let tunes = method.analysis().map(|a| a.tunes);
    for (key, _) in pairs.iter().filter(|(_, v)| *v == "auto") {
        if Some(*key) != tunes {
            anyhow::bail!(
                "'{text}': {} cannot choose '{key}' (its analysis chooses {})",
                method.name(),
                tunes.unwrap_or("nothing")
            );
        }
    }
    let fixed: Vec<String> = pairs
        .iter()
        .filter(|(_, v)| *v != "auto")
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    let base = crate::measure::MethodConfig::parse(&format!("{name}:{}", fixed.join(",")))?;
    let values = crate::bench::tune(settings, method, &base.params)?;
    Ok(Some(crate::measure::MethodConfig::new(base.name, values).label()))
}

pub(super) fn measure_transparency(a: &TransparencyArgs) -> Result<()> {
    let settings = &Settings::load_preset(&a.scene.preset, &a.scene.set)?;
    use crate::measure::transparency::{TechniqueConfig, all_configs};
    let configs = if a.techniques.is_empty() {
        all_configs()
    } else {
        a.techniques
            .iter()
            .map(|t| TechniqueConfig::parse(t))
            .collect::<Result<_>>()?
    };
    if let Some(dir) = &a.out {
        crate::bench::prepare_out_dir(dir)?;
    }
    let gpu = crate::gpu::Gpu::headless(crate::gpu::AdapterPreference::from_env_or(
        crate::gpu::AdapterPreference::Hardware,
    ))?;
    // Ctrl-C stops after the configuration in progress; with --out, transparency.csv and transparency.json are
    // rewritten whole after each one.
    let mut bar = super::progress::TerminalProgress::new();
    let bench = crate::bench::transparency::TransparencyBench::run_each(
        &gpu,
        settings,
        &a.scene.preset,
        &configs,
        a.scene.frames,
        &mut bar,
        |partial| {
            if let Some(dir) = &a.out {
                partial.write_tables(dir)?;
            }
            Ok(())
        },
    )?;
    drop(bar);
    let (stats, rows) = (&bench.stats, &bench.rows);
    println!(
        "preset {}: {} strands, {} segments; view {}x{} (shadows: {}): {} hair pixels, {} fragments, eye depth \
         complexity max {} mean {:.1}",
        a.scene.preset,
        stats.strands,
        stats.segments,
        stats.width,
        stats.height,
        settings.method.name,
        stats.hair_pixels,
        stats.fragments,
        stats.max_depth_complexity,
        stats.mean_depth_complexity
    );
    let width = rows
        .iter()
        .map(|m| m.config.label().chars().count())
        .max()
        .unwrap_or(0)
        .max(9);
    println!(
        "{:<width$} {:>9} {:>7} {:>9} {:>7} {:>7} {:>9} {:>7} {:>7} {:>6} {:>6} {:>5} {:>6} {:>6} {:>6} {:>6} {:>9} {:>8} {:>5}  passes",
        "technique",
        "hair RMSE",
        "PSNR",
        "all RMSE",
        "SSIM",
        "FLIP",
        "FLIP hair",
        "F p95",
        "F p99",
        "max",
        "p99",
        ">1",
        ">4",
        ">8",
        "κ",
        "lum",
        "GPU ms",
        "MiB",
        "geom"
    );
    for m in rows {
        let e = &m.metrics;
        let passes: Vec<String> = m.pass_ms.iter().map(|(n, ms)| format!("{n} {ms:.2}")).collect();
        println!(
            "{:<width$} {:>9.5} {:>7.2} {:>9.5} {:>7.4} {:>7.4} {:>9.4} {:>7.4} {:>7.4} {:>6.0} {:>6.0} {:>4.1}% {:>5.1}% \
             {:>5.1}% {:>6.3} {:>6.3} {:>9.3} {:>8.2} {:>5}  {}",
            m.config.label(),
            e.rmse_hair,
            e.psnr_hair,
            e.rmse,
            e.ssim_hair,
            e.flip.mean,
            e.flip.mean_hair,
            e.flip.p95_hair,
            e.flip.p99_hair,
            e.max_error,
            e.p99,
            100.0 * e.share_over[0],
            100.0 * e.share_over[1],
            100.0 * e.share_over[2],
            e.contrast_retention,
            e.mean_luminance_ratio,
            m.total_ms(),
            m.memory_bytes as f64 / (1024.0 * 1024.0),
            m.geometry_passes,
            passes.join(", ")
        );
    }
    if let Some(dir) = &a.out {
        print_written(&bench.write(dir)?);
    }
    crate::cli::interrupt::finish(&bench, rows.len())
}

pub(super) fn measure_fur(a: &FurArgs) -> Result<()> {
    let settings = &Settings::load_preset(&a.scene.preset, &a.scene.set)?;
    use crate::measure::fur::{FurConfig, usual_configs};
    let configs = if a.fur_configs.is_empty() {
        usual_configs()
    } else {
        a.fur_configs
            .iter()
            .map(|c| FurConfig::parse(c))
            .collect::<Result<_>>()?
    };
    if let Some(dir) = &a.out {
        crate::bench::prepare_out_dir(dir)?;
    }
    // Ctrl-C stops after the configuration in progress; with --out, fur.csv and fur.json are rewritten whole
    // after each one.
    let mut bar = super::progress::TerminalProgress::new();
    let bench = crate::bench::fur::FurBench::run_each(
        settings,
        &a.scene.preset,
        &configs,
        a.scene.frames,
        &mut bar,
        |partial| {
            if let Some(dir) = &a.out {
                partial.write(dir)?;
            }
            Ok(())
        },
    )?;
    drop(bar);
    let (stats, rows) = (&bench.stats, &bench.rows);
    println!(
        "preset {}: {} triangles, {} sub-elements, {} guard hairs; view {}x{}: {} fur pixels; mode {}, \
         reference virtual k=1 with no early exit",
        a.scene.preset,
        stats.triangles,
        stats.sub_elements,
        stats.strands,
        stats.width,
        stats.height,
        stats.fur_pixels,
        settings.fur.mode.word()
    );
    println!(
        "{:<16} {:>10} {:>8} {:>7} {:>9} {:>7} {:>7} {:>10} {:>10} {:>7} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "blending",
        "RMSE",
        "max",
        "FLIP",
        "FLIP fur",
        "F p95",
        "F p99",
        "explicit",
        "shell",
        "deepest",
        "shell ms",
        "expl. ms",
        "OIT ms",
        "online ms",
        "MiB"
    );
    let mib = |b: u64| b as f64 / (1 << 20) as f64;
    let reference = &stats.reference;
    for r in rows {
        let t = &r.table;
        println!(
            "{:<16} {:>10.6} {:>8.5} {:>7.4} {:>9.4} {:>7.4} {:>7.4} {:>10} {:>10} {:>7} {:>10.3} {:>10.3} {:>10.3} \
             {:>10.3} {:>10.3}",
            r.config.label(),
            r.rmse,
            r.max_error,
            r.flip.mean,
            r.flip.mean_hair,
            r.flip.p95_hair,
            r.flip.p99_hair,
            r.explicit_fragments,
            r.shell_fragments,
            r.deepest,
            t.times[3],
            t.times[5],
            t.times[6],
            t.online_ms(),
            mib(t.total_bytes())
        );
    }
    println!(
        "Table 1 of the reference ({}x{}):\n{}",
        stats.width,
        stats.height,
        reference.render(None)
    );
    if let Some(dir) = &a.out {
        print_written(&bench.write(dir)?);
    }
    crate::cli::interrupt::finish(&bench, rows.len())
}

pub(super) fn measure(a: &MeasureArgs) -> Result<()> {
    let legacy;
    let mode = match &a.mode {
        Some(mode) => mode,
        None => {
            let (mode, note) = a.legacy.mode()?;
            if let Some(note) = note {
                eprintln!("note: {note}");
            }
            legacy = mode;
            &legacy
        }
    };
    match mode {
        MeasureMode::Shadows(a) => measure_shadows(a),
        MeasureMode::Transparency(a) => measure_transparency(a),
        MeasureMode::Fur(a) => measure_fur(a),
        MeasureMode::Motion(a) => super::measure_motion::run(a),
        MeasureMode::Visibility(a) => super::measure_visibility::run(a),
        MeasureMode::Fibres(a) => super::measure_fibres::run(a),
        MeasureMode::Probe(a) => super::measure_probe::run(a),
    }
}

pub(super) fn measure_shadows(a: &ShadowsArgs) -> Result<()> {
    use crate::measure::{MethodConfig, usual_configs};
    let settings = Settings::load_preset(&a.scene.preset, &a.scene.set)?;
    let mut configs = Vec::new();
    for c in &a.configs {
        // `name:...,key=auto`: the method's analysis chooses `key` on this scene (e.g. Bounding Opacity Maps'
        // automatic split ratio, `split_ratio=auto`).
        let text = match auto_config(&settings, c)? {
            Some(tuned) => {
                eprintln!("{c}: {tuned}");
                tuned
            }
            None => c.clone(),
        };
        configs.push(MethodConfig::parse(&text)?);
    }
    if configs.is_empty() {
        configs = usual_configs();
    }
    if let Some(dir) = &a.out {
        crate::bench::prepare_out_dir(dir)?;
    }
    // Ctrl-C stops after the configuration in progress; with --out, results.csv and results.json are rewritten
    // whole after each one.
    let mut bar = super::progress::TerminalProgress::new();
    let measured =
        crate::measure::measure_each(&settings, &configs, a.scene.frames, &mut bar, |stats, so_far| {
            if let Some(dir) = &a.out {
                let partial = Outcome::new(bench_result(a, stats, so_far), so_far.len() < configs.len());
                crate::bench::write_tables(dir, &partial)?;
            }
            Ok(())
        })?;
    drop(bar);
    let (stats, rows) = &*measured;
    println!(
        "preset {} (shading {}): {} strands, {} segments; map {}²: {} fragments in {} texels, depth complexity \
         max {} mean {:.1}",
        a.scene.preset,
        settings.render.shading.word(),
        stats.strands,
        stats.segments,
        stats.map_resolution,
        stats.fragments,
        stats.occupied_texels,
        stats.max_depth_complexity,
        stats.mean_depth_complexity
    );
    let width = rows
        .iter()
        .map(|m| m.config.label().chars().count())
        .max()
        .unwrap_or(0)
        .max(6);
    // The error columns come from the one metric list; the cost columns follow.
    let metrics = crate::bench::METRICS;
    let cell = |text: &str, header: &str| format!("{text:>w$}", w = header.chars().count().max(8));
    let mut header = format!("{:<width$}", "method");
    for k in metrics {
        header += &format!(" {}", cell(k.header, k.header));
    }
    println!(
        "{header} {:>9} {:>10} {:>9} {:>5}  passes",
        "GPU ms", "memory MiB", "build MiB", "geom"
    );
    for m in rows {
        let passes: Vec<String> = m.pass_ms.iter().map(|(n, ms)| format!("{n} {ms:.2}")).collect();
        let mut line = format!("{:<width$}", m.config.label());
        for k in metrics {
            let v = (k.value)(m);
            let text = if k.percent {
                format!("{:.1}%", 100.0 * v)
            } else {
                format!("{v:.5}")
            };
            line += &format!(" {}", cell(&text, k.header));
        }
        println!(
            "{line} {:>9.3} {:>10.2} {:>9.2} {:>5}  {}",
            m.total_ms(),
            m.memory_bytes as f64 / (1024.0 * 1024.0),
            m.build_memory_bytes as f64 / (1024.0 * 1024.0),
            m.geometry_passes,
            passes.join(" · ")
        );
    }
    println!(
        "texel error = mean |V - V_ref| over a texel's samples; p50/p95/p99/worst over the occupied texels; \
         >0.05, >0.1: share of occupied texels above; \
         build: what the method builds its maps from each frame; img RMSE: against the reference image under \
         the same shading model"
    );
    let result = measured
        .as_ref()
        .map(|(stats, rows)| bench_result(a, stats, rows));
    if let Some(dir) = &a.out {
        print_written(&crate::bench::write_results(dir, &result)?);
    }
    if !result.is_stopped() && (!a.shading.is_empty() || a.truth == TruthKind::PathTraced) {
        let path_traced = a.truth == TruthKind::PathTraced;
        let written = super::measure_shading::shading_table(
            &a.shading,
            path_traced,
            a.out.as_deref(),
            &settings,
            &configs,
            &result,
        )?;
        print_written(&written);
    }
    crate::cli::interrupt::finish(&result, rows.len())
}

/// `measure`'s rows as a bench result, for `bench`'s writers.
fn bench_result(
    a: &ShadowsArgs,
    stats: &crate::measure::SceneStats,
    rows: &[crate::measure::Measurement],
) -> crate::bench::BenchResult {
    crate::bench::BenchResult {
        preset: a.scene.preset.clone(),
        stats: stats.clone(),
        frames: a.scene.frames,
        rows: rows
            .iter()
            .map(|m| crate::bench::BenchRow::from_measurement(m, "", &stats.device))
            .collect(),
        metric: crate::bench::DEFAULT_ACCURACY_METRIC,
    }
}
