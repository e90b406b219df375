//! `hairlab render`: a preset rendered headlessly to a PNG, the same image the window shows.

use crate::gpu::{self, AdapterPreference, Gpu};
use crate::methods::registry;
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;

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

pub(super) fn render(a: &RenderArgs) -> Result<()> {
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
