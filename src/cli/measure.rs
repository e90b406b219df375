//! `hairlab measure`: methods, techniques or fur blendings against their exact references.

use crate::methods::registry;
use crate::settings::Settings;
use anyhow::Result;
use clap::Args;

#[derive(Args, Debug)]
pub struct MeasureArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=512` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Method configurations `name` or `name:key=value,...` (repeatable); `bom:layers=K,split_ratio=auto` uses
    /// the automatic split ratio. Default: the usual settings of every registered method (OSM 16/64/256, DOM 3/7,
    /// BOM 4/8, DC 4, occupancy).
    #[arg(long = "config", value_name = "METHOD[:K=V,...]")]
    pub configs: Vec<String>,
    /// Timed frames per configuration (after one warm-up frame).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// Measure the eye transparency techniques against the exact reference (`sorted`) instead of the shadow
    /// methods: image metrics over all and hair pixels, GPU ms, memory, geometry passes.
    #[arg(long)]
    pub transparency: bool,
    /// Technique configurations `name` or `name:key=value,...` for `--transparency` (repeatable); default: every
    /// registered technique.
    #[arg(
        long = "technique",
        value_name = "TECHNIQUE[:K=V,...]",
        requires = "transparency"
    )]
    pub techniques: Vec<String>,
    /// Measure a fur preset's blendings against the fur reference (virtual fragments of one march step, no
    /// early exit): RMSE of (H, 1 - T) over fur pixels, fragments, and the paper's Table 1 for each.
    #[arg(long, conflicts_with = "transparency")]
    pub fur: bool,
    /// Blendings for `--fur`: `naive`, `simplified` or `virtual:k=K` (repeatable); default naive, simplified,
    /// virtual k = 32, 8, 4, 2.
    #[arg(long = "fur-config", value_name = "BLENDING[:k=K]", requires = "fur")]
    pub fur_configs: Vec<String>,
}

/// A `--config` with `key=auto` pairs, resolved by the method's analysis to `name:key=value,...`; `None` when
/// it has none.
pub(super) fn auto_config(settings: &Settings, text: &str) -> Result<Option<String>> {
    let (name, rest) = text.split_once(':').unwrap_or((text, ""));
    let pairs: Vec<&str> = rest.split(',').filter(|kv| !kv.trim().is_empty()).collect();
    let is_auto = |kv: &&str| kv.split_once('=').is_some_and(|(_, v)| v.trim() == "auto");
    if !pairs.iter().any(is_auto) {
        return Ok(None);
    }
    let method = registry::find(name.trim()).map_err(anyhow::Error::msg)?;
    let tunes = method.analysis().map(|a| a.tunes);
    for kv in pairs.iter().filter(|kv| is_auto(kv)) {
        let key = kv.split_once('=').map_or("", |(k, _)| k.trim());
        if Some(key) != tunes {
            anyhow::bail!(
                "'{text}': {} cannot choose '{key}' (its analysis chooses {})",
                method.name(),
                tunes.unwrap_or("nothing")
            );
        }
    }
    let fixed: Vec<&str> = pairs.iter().copied().filter(|kv| !is_auto(kv)).collect();
    let base = crate::measure::MethodConfig::parse(&format!("{name}:{}", fixed.join(",")))?;
    let values = crate::bench::tune(settings, method, &base.params)?;
    Ok(Some(crate::measure::MethodConfig::new(base.name, values).label()))
}

pub(super) fn measure_transparency(a: &MeasureArgs, settings: &Settings) -> Result<()> {
    use crate::measure::transparency::{TechniqueConfig, all_configs, measure};
    let configs = if a.techniques.is_empty() {
        all_configs()
    } else {
        a.techniques
            .iter()
            .map(|t| TechniqueConfig::parse(t))
            .collect::<Result<_>>()?
    };
    let (stats, rows) = measure(settings, &configs, a.frames, |what| {
        eprintln!("measuring {what}…")
    })?;
    println!(
        "preset {}: {} strands, {} segments; view {}x{} (shadows: {}): {} hair pixels, {} fragments, eye depth \
         complexity max {} mean {:.1}",
        a.preset,
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
        "{:<width$} {:>9} {:>7} {:>9} {:>7} {:>6} {:>6} {:>5} {:>6} {:>6} {:>6} {:>6} {:>9} {:>8} {:>5}  passes",
        "technique",
        "hair RMSE",
        "PSNR",
        "all RMSE",
        "SSIM",
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
    for m in &rows {
        let e = &m.metrics;
        let passes: Vec<String> = m.pass_ms.iter().map(|(n, ms)| format!("{n} {ms:.2}")).collect();
        println!(
            "{:<width$} {:>9.5} {:>7.2} {:>9.5} {:>7.4} {:>6.0} {:>6.0} {:>4.1}% {:>5.1}% {:>5.1}% {:>6.3} {:>6.3} {:>9.3} \
             {:>8.2} {:>5}  {}",
            m.config.label(),
            e.rmse_hair,
            e.psnr_hair,
            e.rmse,
            e.ssim_hair,
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
    Ok(())
}

pub(super) fn measure_fur(a: &MeasureArgs, settings: &Settings) -> Result<()> {
    use crate::measure::fur::{FurConfig, measure, usual_configs};
    if !a.configs.is_empty() {
        anyhow::bail!("--config names shadow methods; with --fur use --fur-config");
    }
    let configs = if a.fur_configs.is_empty() {
        usual_configs()
    } else {
        a.fur_configs
            .iter()
            .map(|c| FurConfig::parse(c))
            .collect::<Result<_>>()?
    };
    let (stats, rows) = measure(settings, &configs, a.frames)?;
    println!(
        "preset {}: {} triangles, {} sub-elements, {} guard hairs; view {}x{}: {} fur pixels; mode {}, \
         reference virtual k=1 with no early exit",
        a.preset,
        stats.triangles,
        stats.sub_elements,
        stats.strands,
        stats.width,
        stats.height,
        stats.fur_pixels,
        settings.fur.mode.word()
    );
    println!(
        "{:<16} {:>10} {:>8} {:>10} {:>10} {:>7} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "blending",
        "RMSE",
        "max",
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
    for r in &rows {
        let t = &r.table;
        println!(
            "{:<16} {:>10.6} {:>8.5} {:>10} {:>10} {:>7} {:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>10.3}",
            r.config.label(),
            r.rmse,
            r.max_error,
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
    Ok(())
}

pub(super) fn measure(a: &MeasureArgs) -> Result<()> {
    use crate::measure::{MethodConfig, usual_configs};
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    if a.fur {
        return measure_fur(a, &settings);
    }
    if a.transparency {
        if !a.configs.is_empty() {
            anyhow::bail!("--config names shadow methods; with --transparency use --technique");
        }
        return measure_transparency(a, &settings);
    }
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
    let (stats, rows) = crate::measure::measure(&settings, &configs, a.frames, |what| {
        eprintln!("measuring {what}…")
    })?;
    println!(
        "preset {} (shading {}): {} strands, {} segments; map {}²: {} fragments in {} texels, depth complexity \
         max {} mean {:.1}",
        a.preset,
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
    for m in &rows {
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
    Ok(())
}
