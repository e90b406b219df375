//! The headless command line: `render`, `info`, `gen`. With no subcommand, `hairlab` opens the workbench window.
//! Every failure is one line naming the file and the problem, and a non-zero exit; outputs are written whole.

use crate::gpu::{self, AdapterPreference, Gpu};
use crate::methods::registry;
use crate::render::{FrameInput, Renderer};
use crate::scene::generate::{GenKind, GenParams, HairStyle};
use crate::scene::hair;
use crate::settings::{Settings, apply_override};
use crate::visibility::Fragment;
use anyhow::{Context, Result};
use clap::builder::PossibleValuesParser;
use clap::{Args, Parser, Subcommand, ValueEnum};
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Parser, Debug)]
#[command(
    name = "hairlab",
    version,
    about = "A workbench for real-time hair self-shadowing methods."
)]
#[command(after_help = "With no subcommand, hairlab opens the workbench window.")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Preset for the window (built-in name, `presets/<name>.toml`, or a path); default: the last session's.
    #[arg(long, global = false)]
    pub preset: Option<String>,
    /// Override a preset value for the window, e.g. `--set render.hair_alpha=0.2` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a preset headlessly to a PNG: the same image the window shows.
    Render(RenderArgs),
    /// Print what a `.hair` / glTF / `.tfx` / `.data` file holds: strands, points, segments, bounds, arrays, and
    /// what hairlab drops of it.
    Info(InfoArgs),
    /// Generate procedural hair and write it as a `.hair` file.
    Gen(GenArgs),
    /// Convert strands between formats: any file `info` reads in, `.hair`, TressFX `.tfx` or USC-HairSalon
    /// `.data` out (written whole or not at all); prints what the output cannot hold.
    Convert(ConvertArgs),
    /// Evaluate a method's CPU model on one texel's fragments (CSV rows `depth,alpha`, depth in [0,1]) and
    /// print CSV `depth,reference,<method>`: the papers' texel experiments, in a script.
    Curve(CurveArgs),
    /// Composite one pixel's eye fragments (CSV rows `depth,r,g,b,alpha`, linear colour) through a transparency
    /// technique's CPU model and print the linear RGB result `r,g,b`: the eye-space twin of `curve`.
    Composite(CompositeArgs),
    /// Measure methods against the exact reference on a preset's scene: depth complexity, map error, GPU time
    /// per pass (median), memory, geometry passes.
    Measure(MeasureArgs),
    /// Sweep every method's parameters on a preset's scene and chart GPU time against map error: results.csv,
    /// results.json and speed_vs_accuracy.png/.svg (Pareto front marked); `--scaling` fits GPU time per segment.
    Bench(crate::bench::BenchArgs),
    /// Render many frames while the light turns and the method changes, and check that neither the process's
    /// resident memory nor the GPU memory grows (last cycle of methods against the first, at most 5 %).
    Soak(SoakArgs),
}

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

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Preset: built-in name (default, patch), `presets/<name>.toml`, or a path to a TOML file.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value by dotted key, e.g. `--set method.name=none --set light.azimuth_deg=90`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Image width in pixels (overrides render.width).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides render.height).
    #[arg(long)]
    pub height: Option<u32>,
    /// Output PNG path.
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// A `.hair`, `.gltf`, `.glb`, TressFX `.tfx` or USC-HairSalon `.data` file.
    pub file: PathBuf,
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input: `.hair`, `.gltf`, `.glb`, `.tfx` or `.data`.
    pub input: PathBuf,
    /// Output: `.hair`, `.tfx` or `.data`.
    pub output: PathBuf,
}

#[derive(Args, Debug)]
pub struct GenArgs {
    /// What to grow: a head, a patch, or a stress scene (see the presets of the same names).
    pub kind: GenKind,
    /// Shape of each strand (default: the generator's, wavy).
    #[arg(long)]
    pub style: Option<HairStyle>,
    /// Number of strands.
    #[arg(long)]
    pub strands: Option<u32>,
    /// Segments per strand (1..=65535).
    #[arg(long)]
    pub segments: Option<u32>,
    /// Strand length in world units.
    #[arg(long)]
    pub length: Option<f32>,
    /// Number of clumps (0: none).
    #[arg(long)]
    pub clumps: Option<u32>,
    /// Random seed (same seed, same hair).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Grow the hair on this glTF mesh's triangles instead of the built-in ellipsoid (`head` kind).
    #[arg(long)]
    pub scalp: Option<PathBuf>,
    /// Any other generator parameter, e.g. `--set curl_radius=0.01` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output `.hair` path.
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
#[command(after_long_help = curve_params_help())]
pub struct CurveArgs {
    /// CSV of the texel's fragments: one `depth,alpha` row each (depth in [0, 1], alpha in [0, 1)); an optional
    /// `depth,alpha` header, blank lines and `#` comment lines are skipped.
    #[arg(long)]
    pub fragments: PathBuf,
    /// Method name (see `--help` for every method's parameters).
    #[arg(long, value_parser = method_names())]
    pub method: String,
    /// Method parameter, e.g. `--param slices=64` (repeatable).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// Number of depths, uniform over [0, 1].
    #[arg(long, default_value_t = 256)]
    pub samples: usize,
    /// Global hair alpha for methods that assume one (occupancy); default: the mean alpha of the fragments.
    #[arg(long)]
    pub hair_alpha: Option<f32>,
}

#[derive(Args, Debug)]
#[command(after_long_help = composite_params_help())]
pub struct CompositeArgs {
    /// CSV of the pixel's fragments: one `depth,r,g,b,alpha` row each (depth >= 0 in units of the
    /// camera-to-target distance, linear colour >= 0, alpha in [0, 1]); an optional header naming those five
    /// columns as the first row, blank lines and `#` comment lines are skipped. Rows are segments 0, 1, ... in
    /// file order (which orders exact-depth ties).
    #[arg(long)]
    pub fragments: PathBuf,
    /// Technique name (see `--help` for every technique's parameters).
    #[arg(long, value_parser = technique_names())]
    pub method: String,
    /// Technique parameter, e.g. `--param k=4` (repeatable).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// Linear background colour `r,g,b` (the opaque image at the pixel).
    #[arg(long, default_value = "0,0,0")]
    pub background: String,
    /// Global hair alpha for techniques that assume one (occupancy order); default: the mean alpha of the
    /// fragments.
    #[arg(long)]
    pub hair_alpha: Option<f32>,
}

/// The registered transparency techniques' names, so clap lists them and rejects any other.
fn technique_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        crate::render::transparency::registry::all()
            .iter()
            .map(|t| t.name()),
    )
}

/// Every transparency technique's parameters, for `hairlab composite --help`.
fn composite_params_help() -> String {
    let mut out = String::from("Techniques and their parameters:\n");
    for t in crate::render::transparency::registry::all() {
        out.push_str(&format!("  {} — {}\n", t.name(), t.info().paper));
        for p in t.info().params {
            out.push_str(&format!(
                "      {} (default {}): {}\n",
                p.key,
                p.format(p.default),
                p.help
            ));
        }
    }
    out
}

/// The registered methods' names, so clap lists them and rejects any other.
fn method_names() -> PossibleValuesParser {
    PossibleValuesParser::new(registry::all().iter().map(|m| m.name()))
}

/// Every method's parameters, for `hairlab curve --help`.
fn curve_params_help() -> String {
    let mut out = String::from("Methods and their parameters:\n");
    for m in crate::methods::registry::all() {
        out.push_str(&format!("  {} — {}\n", m.name(), m.info().paper));
        for p in m.params() {
            out.push_str(&format!(
                "      {} (default {}): {}\n",
                p.key,
                p.format(p.default),
                p.help
            ));
        }
    }
    out
}

/// Runs a subcommand.
pub fn run(cmd: Command) -> Result<()> {
    match cmd {
        Command::Render(a) => render(&a),
        Command::Info(a) => info(&a.file),
        Command::Gen(a) => gen_hair(&a),
        Command::Convert(a) => convert(&a),
        Command::Curve(a) => curve(&a),
        Command::Composite(a) => composite(&a),
        Command::Measure(a) => measure(&a),
        Command::Bench(a) => crate::bench::run_cli(&a),
        Command::Soak(a) => soak(&a),
    }
}

fn render(a: &RenderArgs) -> Result<()> {
    crate::io::check_output(&a.out, "png")?;
    let mut settings = Settings::load_preset(&a.preset, &a.set)?;
    // The image size flags apply after the preset and its overrides, and are checked as themselves.
    settings.render.width = a.width.unwrap_or(settings.render.width);
    settings.render.height = a.height.unwrap_or(settings.render.height);
    settings.validate().context("--width/--height")?;
    let image = render_image(&mut settings)?;
    let mut png = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    crate::io::write_atomic(&a.out, &png)?;
    println!("wrote {} ({}×{})", a.out.display(), image.width(), image.height());
    Ok(())
}

/// Renders `settings` headlessly (framing the camera when its distance is 0) and returns the image. Prints the
/// scene, the adapter and per-pass GPU times on stderr.
pub fn render_image(settings: &mut Settings) -> Result<image::RgbaImage> {
    let start = std::time::Instant::now();
    let scene = settings.scene.build()?;
    let scene_ms = start.elapsed().as_secs_f64() * 1e3;
    let fur = crate::fur::settings::FurScene::build(&scene, &settings.fur).map_err(anyhow::Error::msg)?;
    for w in fur.iter().flat_map(|f| &f.warnings) {
        eprintln!("warning: {w}");
    }
    if settings.camera.distance <= 0.0 {
        settings.camera.frame(&scene.framing_bounds());
    }
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut renderer = Renderer::new(&gpu, &scene, settings.render.map_resolution)?;
    renderer.set_fur(fur.as_ref().map(|f| (f, &settings.fur)))?;
    let method = registry::find(&settings.method.name).map_err(anyhow::Error::msg)?;
    let input = FrameInput {
        camera: &settings.camera,
        light: &settings.light,
        render: &settings.render,
        method,
        method_params: &settings.method.params,
        technique: settings.transparency.technique()?,
        technique_params: &settings.transparency.params,
        width: settings.render.width,
        height: settings.render.height,
    };
    renderer.render(&input)?;
    let times = renderer.wait_timings();
    let image = renderer.read_output()?;
    eprintln!(
        "{} strands, {} segments, {} triangles on {}",
        scene.strands.strand_count(),
        scene.strands.segment_count(),
        scene.triangle_count(),
        gpu::describe(&gpu.info)
    );
    for t in &times {
        eprintln!("  {:>16}: {:.3} ms", t.name, t.ms);
    }
    if let Some(f) = &fur {
        let table = crate::measure::fur::table1(&renderer, f, scene_ms, &times)?;
        let march = match renderer.fur_state() {
            Some(state) => state.shell.read_stats(&gpu)?,
            None => Default::default(),
        };
        eprintln!(
            "fur ({}, {} blending): {} triangles, {} sub-elements; march: {} rays, {} steps, {} hops, {} light \
             steps, {} rays lost at the hop cap, {} capped at fur.max_steps, {} light marches lost\n{}",
            settings.fur.mode.word(),
            settings.fur.blending.word(),
            f.shell.mesh.faces.len(),
            f.shell.sub_elements,
            march.rays,
            march.steps,
            march.hops,
            march.light_steps,
            march.lost,
            march.capped,
            march.light_lost,
            table.render(None)
        );
    }
    Ok(image)
}

fn info(path: &Path) -> Result<()> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    // A .hair file is read once (its warnings print once), for its arrays and its strands.
    let hair_file = match ext.as_deref() {
        Some("hair") => Some(hair::read_hair_file(path)?),
        _ => None,
    };
    // For the strand-only formats: the arrays the file holds and what hairlab drops of it.
    let mut arrays_dropped: Option<(Vec<&str>, Vec<String>)> = None;
    let scene = match (&hair_file, ext.as_deref()) {
        (Some(h), _) => crate::scene::Scene::new(
            h.to_strands()
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
            Vec::new(),
        ),
        (None, Some("tfx")) => {
            let f = crate::scene::tfx::read_tfx_file(path)?;
            let mut arrays = vec!["positions"];
            let mut dropped = vec!["position w (TressFX's simulation flag)".to_owned()];
            for (present, name, drop) in [
                (f.strand_uvs, "strand UVs", true),
                (f.vertex_uvs, "vertex UVs", true),
                (f.strand_thickness.is_some(), "strand thickness", false),
                (f.vertex_color.is_some(), "vertex colours", false),
            ] {
                if present {
                    arrays.push(name);
                    if drop {
                        dropped.push(format!("{name} (hairlab has no texture coordinates)"));
                    }
                }
            }
            arrays_dropped = Some((arrays, dropped));
            crate::scene::Scene::new(f.to_strands(), Vec::new())
        }
        (None, Some("data")) => {
            let f = crate::scene::usc_data::read_data_file(path)?;
            let dropped = (f.empty_strands > 0).then(|| format!("{} strands of 0 vertices", f.empty_strands));
            arrays_dropped = Some((vec!["positions"], dropped.into_iter().collect()));
            crate::scene::Scene::new(f.strands, Vec::new())
        }
        (None, _) => crate::scene::load::load_scene(path)?,
    };
    println!("file:      {}", path.display());
    if let Some((arrays, dropped)) = &arrays_dropped {
        println!("arrays:    {}", arrays.join(", "));
        for d in dropped {
            println!("dropped:   {d}");
        }
    } else if let Some(h) = &hair_file {
        let present: Vec<&str> = [
            ("segments", h.segments.is_some()),
            ("points", h.points.is_some()),
            ("thickness", h.thickness.is_some()),
            ("transparency", h.transparency.is_some()),
            ("colors", h.color.is_some()),
        ]
        .iter()
        .filter(|(_, p)| *p)
        .map(|(n, _)| *n)
        .collect();
        println!("arrays:    {}", present.join(", "));
        if !h.info.is_empty() {
            println!("info:      {}", h.info);
        }
    } else {
        println!(
            "meshes:    {} ({} triangles)",
            scene.meshes.len(),
            scene.triangle_count()
        );
    }
    let s = &scene.strands;
    println!("strands:   {}", s.strand_count());
    println!("points:    {}", s.point_count());
    println!("segments:  {}", s.segment_count());
    let b = scene.strand_bounds();
    if b.is_empty() {
        println!("bounds:    (no strands)");
    } else {
        println!(
            "bounds:    min ({:.4}, {:.4}, {:.4}) max ({:.4}, {:.4}, {:.4})",
            b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
        );
    }
    Ok(())
}

fn convert(a: &ConvertArgs) -> Result<()> {
    use crate::scene::load::{STRAND_EXTENSIONS, load_scene, save_strands};
    let ext = a
        .output
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let Some(ext) = ext.filter(|e| STRAND_EXTENSIONS.contains(&e.as_str())) else {
        anyhow::bail!(
            "{}: the output must be one of .{}",
            a.output.display(),
            STRAND_EXTENSIONS.join(", .")
        );
    };
    crate::io::check_output(&a.output, &ext)?;
    let scene = load_scene(&a.input)?;
    let name = a.input.file_name().unwrap_or_default().to_string_lossy();
    save_strands(&a.output, &scene.strands, &format!("hairlab convert {name}"))?;
    let s = &scene.strands;
    println!(
        "wrote {}: {} strands, {} points, {} segments",
        a.output.display(),
        s.strand_count(),
        s.point_count(),
        s.segment_count()
    );
    if !scene.meshes.is_empty() {
        println!(
            "dropped:   {} meshes (the output holds strands only)",
            scene.meshes.len()
        );
    }
    if ext == "data" {
        for (present, name) in [
            (s.thickness.is_some(), "thickness"),
            (s.alpha.is_some(), "alpha"),
            (s.color.is_some(), "colour"),
        ] {
            if present {
                println!("dropped:   {name} (a .data file holds positions only)");
            }
        }
    }
    Ok(())
}

fn gen_hair(a: &GenArgs) -> Result<()> {
    crate::io::check_output(&a.out, "hair")?;
    let mut p = GenParams {
        kind: a.kind,
        ..GenParams::default()
    };
    p.style = a.style.unwrap_or(p.style);
    p.strands = a.strands.unwrap_or(p.strands);
    p.segments = a.segments.unwrap_or(p.segments);
    p.length = a.length.unwrap_or(p.length);
    p.clumps = a.clumps.unwrap_or(p.clumps);
    p.seed = a.seed.unwrap_or(p.seed);
    if !a.set.is_empty() {
        let mut tree = toml::Table::try_from(&p).context("generator parameters")?;
        for o in &a.set {
            apply_override(&mut tree, o)?;
        }
        p = GenParams::deserialize(toml::Value::Table(tree)).context("generator parameters")?;
    }
    let scene = crate::settings::SceneSettings {
        file: None,
        scalp: a.scalp.clone(),
        generator: p.clone(),
    }
    .build()?;
    let kind = a.kind.to_possible_value().map(|v| v.get_name().to_owned());
    let info = format!("hairlab gen {} seed {}", kind.unwrap_or_default(), p.seed);
    let file = hair::HairFile::from_strands(&scene.strands, &info)?;
    hair::write_hair_file(&a.out, &file)?;
    println!(
        "wrote {}: {} strands, {} points, {} segments",
        a.out.display(),
        scene.strands.strand_count(),
        scene.strands.point_count(),
        scene.strands.segment_count()
    );
    Ok(())
}

/// Reads a fragment CSV ([`parse_fragments_csv`]); errors name the file.
pub fn read_fragments_csv(path: &Path) -> Result<Vec<Fragment>> {
    let text =
        crate::io::read_regular_text(path).with_context(|| format!("{}: cannot read", path.display()))?;
    parse_fragments_csv(&text, &path.display().to_string())
}

/// One fragment row; with a header its columns are matched by name.
#[derive(Deserialize)]
struct FragmentRow {
    depth: f32,
    alpha: f32,
}

/// Parses one texel's fragments: `depth,alpha` rows, depth in [0, 1] and alpha in [0, 1). Blank lines and `#`
/// comment lines are skipped wherever they appear; the first other line may be the header `depth,alpha`
/// (either order, any case). Every other line must be a row: errors name `source`, the line and the value,
/// and a text without rows is an error too.
pub fn parse_fragments_csv(text: &str, source: &str) -> Result<Vec<Fragment>> {
    let mut header: Option<csv::StringRecord> = None;
    let mut first = true;
    let mut out = Vec::new();
    // Line by line, so that line numbers count blank and comment lines (the reader's own count skips them).
    for (i, text_line) in text.lines().enumerate() {
        let line = i + 1;
        let row_text = text_line.trim();
        if row_text.is_empty() || row_text.starts_with('#') {
            continue;
        }
        let record = csv::ReaderBuilder::new()
            .has_headers(false)
            .trim(csv::Trim::All)
            .from_reader(row_text.as_bytes())
            .records()
            .next();
        let Some(Ok(record)) = record else {
            anyhow::bail!("{source}:{line}: cannot read `{row_text}` as CSV");
        };
        if std::mem::replace(&mut first, false) {
            let names: csv::StringRecord = record.iter().map(str::to_ascii_lowercase).collect();
            let mut sorted: Vec<&str> = names.iter().collect();
            sorted.sort_unstable();
            if sorted == ["alpha", "depth"] {
                header = Some(names);
                continue;
            }
        }
        let row: FragmentRow = match record.deserialize(header.as_ref()) {
            Ok(row) if record.len() == 2 => row,
            _ => anyhow::bail!("{source}:{line}: expected `depth,alpha` (two numbers), got `{row_text}`"),
        };
        if !(0.0..=1.0).contains(&row.depth) {
            anyhow::bail!("{source}:{line}: depth {} is outside [0, 1]", row.depth);
        }
        if !(0.0..1.0).contains(&row.alpha) {
            anyhow::bail!("{source}:{line}: alpha {} is outside [0, 1)", row.alpha);
        }
        out.push(Fragment::new(row.depth, row.alpha));
    }
    if out.is_empty() {
        anyhow::bail!("{source}: no fragments (expected `depth,alpha` rows)");
    }
    Ok(out)
}

fn curve(a: &CurveArgs) -> Result<()> {
    let method = registry::find(&a.method).map_err(anyhow::Error::msg)?;
    let mut values = crate::methods::ParamValues::new();
    for p in &a.params {
        let (k, v) = p
            .split_once('=')
            .with_context(|| format!("--param '{p}': expected key=value"))?;
        let v = crate::methods::parse_value(method, k.trim(), v)
            .map_err(|e| anyhow::anyhow!("--param '{p}': {e}"))?;
        values.insert(k.trim().to_string(), v);
    }
    if !(2..=1_000_000).contains(&a.samples) {
        anyhow::bail!("--samples must be in 2..=1000000 (got {})", a.samples);
    }
    if let Some(alpha) = a.hair_alpha
        && !(alpha > 0.0 && alpha <= 1.0)
    {
        anyhow::bail!("--hair-alpha must be in (0, 1] (got {alpha})");
    }
    let frags = read_fragments_csv(&a.fragments)?;
    let alpha = a
        .hair_alpha
        .unwrap_or_else(|| frags.iter().map(|f| f.alpha).sum::<f32>() / frags.len() as f32);
    let zs: Vec<f32> = (0..a.samples)
        .map(|i| i as f32 / (a.samples - 1) as f32)
        .collect();
    use crate::visibility::TexelModel;
    let reference = crate::visibility::Reference.curve(&frags, &zs);
    let model = method.model(&values, alpha).curve(&frags, &zs);
    let mut out = csv::Writer::from_writer(Vec::new());
    out.write_record(["depth", registry::reference().name(), method.name()])?;
    for ((z, r), v) in zs.iter().zip(&reference).zip(&model) {
        out.serialize((z, r, v))?;
    }
    let bytes = out.into_inner().context("fragment curve CSV")?;
    std::io::Write::write_all(&mut std::io::stdout().lock(), &bytes).context("stdout")?;
    Ok(())
}

/// One eye fragment row; with a header its columns are matched by name.
#[derive(Deserialize)]
struct PixelRow {
    depth: f32,
    r: f32,
    g: f32,
    b: f32,
    alpha: f32,
}

/// The columns of a pixel CSV.
const PIXEL_COLUMNS: [&str; 5] = ["depth", "r", "g", "b", "alpha"];

/// Parses one pixel's eye fragments: `depth,r,g,b,alpha` rows, depth and colour finite and >= 0, alpha in
/// [0, 1]. Blank lines and `#` comment lines are skipped wherever they appear; the first other line may be a
/// header naming the five columns (any order, any case). Row `i` (counting rows only) is segment `i`. Errors
/// name `source`, the line and the value; a text without rows is an error too.
pub fn parse_pixel_csv(text: &str, source: &str) -> Result<Vec<crate::transparency::EyeFragment>> {
    let mut header: Option<csv::StringRecord> = None;
    let mut first = true;
    let mut out = Vec::new();
    for (i, text_line) in text.lines().enumerate() {
        let line = i + 1;
        let row_text = text_line.trim();
        if row_text.is_empty() || row_text.starts_with('#') {
            continue;
        }
        let record = csv::ReaderBuilder::new()
            .has_headers(false)
            .trim(csv::Trim::All)
            .from_reader(row_text.as_bytes())
            .records()
            .next();
        let Some(Ok(record)) = record else {
            anyhow::bail!("{source}:{line}: cannot read `{row_text}` as CSV");
        };
        if std::mem::replace(&mut first, false) {
            let names: csv::StringRecord = record.iter().map(str::to_ascii_lowercase).collect();
            let mut sorted: Vec<&str> = names.iter().collect();
            sorted.sort_unstable();
            let mut expected = PIXEL_COLUMNS;
            expected.sort_unstable();
            if sorted == expected {
                header = Some(names);
                continue;
            }
        }
        let row: PixelRow = match record.deserialize(header.as_ref()) {
            Ok(row) if record.len() == PIXEL_COLUMNS.len() => row,
            _ => anyhow::bail!(
                "{source}:{line}: expected `depth,r,g,b,alpha` (five numbers), got `{row_text}`"
            ),
        };
        for (name, v) in [("depth", row.depth), ("r", row.r), ("g", row.g), ("b", row.b)] {
            if !(v.is_finite() && v >= 0.0) {
                anyhow::bail!("{source}:{line}: {name} {v} is not a finite number >= 0");
            }
        }
        if !(0.0..=1.0).contains(&row.alpha) {
            anyhow::bail!("{source}:{line}: alpha {} is outside [0, 1]", row.alpha);
        }
        out.push(crate::transparency::EyeFragment {
            depth: row.depth,
            segment: out.len() as u32,
            color: [row.r, row.g, row.b],
            alpha: row.alpha,
        });
    }
    if out.is_empty() {
        anyhow::bail!("{source}: no fragments (expected `depth,r,g,b,alpha` rows)");
    }
    Ok(out)
}

/// `r,g,b`: three finite numbers >= 0.
fn parse_background(text: &str) -> Result<[f32; 3]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let values: Option<Vec<f32>> = parts
        .iter()
        .map(|p| p.parse::<f32>().ok().filter(|v| v.is_finite() && *v >= 0.0))
        .collect();
    match values.as_deref() {
        Some(&[r, g, b]) => Ok([r, g, b]),
        _ => anyhow::bail!("--background '{text}': expected r,g,b (three finite numbers >= 0)"),
    }
}

fn composite(a: &CompositeArgs) -> Result<()> {
    use crate::render::transparency::registry;
    let technique = registry::find(&a.method).map_err(anyhow::Error::msg)?;
    let mut values = crate::methods::ParamValues::new();
    for p in &a.params {
        let (k, v) = p
            .split_once('=')
            .with_context(|| format!("--param '{p}': expected key=value"))?;
        let v = registry::spec(technique, k.trim())
            .and_then(|spec| spec.parse(v))
            .map_err(|e| anyhow::anyhow!("--param '{p}': {e}"))?;
        values.insert(k.trim().to_string(), v);
    }
    let background = parse_background(&a.background)?;
    if let Some(alpha) = a.hair_alpha
        && !(0.0..=1.0).contains(&alpha)
    {
        anyhow::bail!("--hair-alpha must be in [0, 1] (got {alpha})");
    }
    let path = &a.fragments;
    let text =
        crate::io::read_regular_text(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let frags = parse_pixel_csv(&text, &path.display().to_string())?;
    let hair_alpha = a
        .hair_alpha
        .unwrap_or_else(|| frags.iter().map(|f| f.alpha).sum::<f32>() / frags.len() as f32);
    // One pixel: its own depths are the frame's depth range.
    let depth_range = frags
        .iter()
        .fold([f32::INFINITY, f32::NEG_INFINITY], |[n, f], x| {
            [n.min(x.depth), f.max(x.depth)]
        });
    let ctx = crate::transparency::ModelContext {
        hair_alpha,
        depth_range,
    };
    let [r, g, b] = technique.model(&values, &ctx).composite(&frags, background);
    println!("{r},{g},{b}");
    Ok(())
}

/// A `--config` with `key=auto` pairs, resolved by the method's analysis to `name:key=value,...`; `None` when
/// it has none.
fn auto_config(settings: &Settings, text: &str) -> Result<Option<String>> {
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
    Ok(Some(
        crate::measure::MethodConfig {
            name: base.name,
            params: values,
        }
        .label(),
    ))
}

fn soak(a: &SoakArgs) -> Result<()> {
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

fn measure_transparency(a: &MeasureArgs, settings: &Settings) -> Result<()> {
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

fn measure_fur(a: &MeasureArgs, settings: &Settings) -> Result<()> {
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

fn measure(a: &MeasureArgs) -> Result<()> {
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
        "preset {}: {} strands, {} segments; map {}²: {} fragments in {} texels, depth complexity max {} mean {:.1}",
        a.preset,
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
    println!(
        "{:<width$} {:>9} {:>8} {:>8} {:>8} {:>8} {:>7} {:>7} {:>9} {:>9} {:>7} {:>9} {:>9} {:>10} {:>9} {:>5}  passes",
        "method",
        "map err",
        "p50",
        "p95",
        "p99",
        "worst",
        ">0.05",
        ">0.1",
        "shading",
        "img RMSE",
        "PSNR",
        "flicker",
        "GPU ms",
        "memory MiB",
        "build MiB",
        "geom"
    );
    for m in &rows {
        let passes: Vec<String> = m.pass_ms.iter().map(|(n, ms)| format!("{n} {ms:.2}")).collect();
        let e = &m.texel_errors;
        println!(
            "{:<width$} {:>9.5} {:>8.4} {:>8.4} {:>8.4} {:>8.4} {:>6.1}% {:>6.1}% {:>9.5} {:>9.5} {:>7.2} {:>9.5} {:>9.3} {:>10.2} {:>9.2} {:>5}  {}",
            m.config.label(),
            m.map_error,
            e.p50,
            e.p95,
            e.p99,
            e.worst,
            100.0 * e.share_over[0],
            100.0 * e.share_over[1],
            m.shading_error,
            m.image_rmse,
            m.image_psnr,
            m.flicker,
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
         build: what the method builds its maps from each frame"
    );
    Ok(())
}
