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
    /// Render frame K of the preset's motion (`[motion]`; frame 0 is the still scene of a simulation).
    #[arg(long, value_name = "K", conflicts_with = "frames")]
    pub frame: Option<u32>,
    /// Render frames A up to B (exclusive) of the motion: as a numbered PNG sequence `frame_0000.png` … in the
    /// folder `--out`, or, when `--out` ends in `.gif`, as one animated GIF at the motion's frame rate (looping).
    #[arg(long, value_name = "A..B")]
    pub frames: Option<String>,
    /// Output PNG path (with `--frames`: a folder, or an animated `.gif`).
    #[arg(long)]
    pub out: PathBuf,
}

/// Parses `A..B` (B exclusive, A < B).
pub fn parse_frame_range(text: &str) -> Result<std::ops::Range<u32>> {
    let bad = || anyhow::anyhow!("--frames '{text}': expected A..B with whole numbers A < B, e.g. 0..30");
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a >= b {
        return Err(bad());
    }
    Ok(a..b)
}

pub(super) fn render(a: &RenderArgs) -> Result<()> {
    let range = a.frames.as_deref().map(parse_frame_range).transpose()?;
    let gif = range.is_some() && a.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("gif"));
    if range.is_none() {
        crate::io::check_output(&a.out, "png")?;
    } else if gif {
        crate::io::check_output(&a.out, "gif")?;
    }
    let mut settings = Settings::load_preset(&a.preset, &a.set)?;
    // The image size flags apply after the preset and its overrides, and are checked as themselves.
    settings.render.width = a.width.unwrap_or(settings.render.width);
    settings.render.height = a.height.unwrap_or(settings.render.height);
    settings.validate().context("--width/--height")?;
    let encode = |image: &image::RgbaImage| -> Result<Vec<u8>> {
        let mut png = Vec::new();
        image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
        Ok(png)
    };
    match range {
        None => {
            let image = render_frame_image(&mut settings, a.frame.unwrap_or(0))?;
            crate::io::write_atomic(&a.out, &encode(&image)?)?;
            println!("wrote {} ({}×{})", a.out.display(), image.width(), image.height());
        }
        Some(range) if gif => {
            let frames: Vec<u32> = range.clone().collect();
            let mut images = Vec::new();
            render_frames(&mut settings, &frames, &mut |_, image| {
                images.push(image);
                Ok(())
            })?;
            crate::io::write_atomic(&a.out, &animated_gif(&images, settings.motion.fps)?)?;
            println!(
                "wrote frames {}..{} to {} as an animated GIF ({}×{}, {} fps)",
                range.start,
                range.end,
                a.out.display(),
                settings.render.width,
                settings.render.height,
                settings.motion.fps
            );
        }
        Some(range) => {
            std::fs::create_dir_all(&a.out)
                .with_context(|| format!("--out {}: cannot create", a.out.display()))?;
            let frames: Vec<u32> = range.clone().collect();
            let digits = (range.end.saturating_sub(1).max(1).ilog10() as usize + 1).max(4);
            render_frames(&mut settings, &frames, &mut |k, image| {
                let path = a.out.join(format!("frame_{k:0digits$}.png"));
                crate::io::write_atomic(&path, &encode(&image)?)
            })?;
            println!(
                "wrote frames {}..{} to {} ({}×{})",
                range.start,
                range.end,
                a.out.display(),
                settings.render.width,
                settings.render.height
            );
        }
    }
    Ok(())
}

/// `images` as an animated GIF at `fps` frames per second, looping (each frame quantised to 256 colours).
pub fn animated_gif(images: &[image::RgbaImage], fps: f32) -> Result<Vec<u8>> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let mut bytes = Vec::new();
    {
        let mut encoder = GifEncoder::new_with_speed(&mut bytes, 10);
        encoder.set_repeat(Repeat::Infinite)?;
        let delay = image::Delay::from_numer_denom_ms(1000, fps.max(1e-3).round().max(1.0) as u32);
        encoder.encode_frames(
            images
                .iter()
                .map(|i| image::Frame::from_parts(i.clone(), 0, 0, delay)),
        )?;
    }
    Ok(bytes)
}

/// Renders frame `k` of `settings`' motion (a still preset has only its one scene, whatever `k`).
pub fn render_frame_image(settings: &mut Settings, k: u32) -> Result<image::RgbaImage> {
    let mut out = None;
    render_frames(settings, &[k], &mut |_, image| {
        out = Some(image);
        Ok(())
    })?;
    out.context("no frame rendered")
}

/// Renders `settings` headlessly (framing the camera when its distance is 0) and returns the image. Prints the
/// scene, the adapter and per-pass GPU times on stderr.
pub fn render_image(settings: &mut Settings) -> Result<image::RgbaImage> {
    render_frame_image(settings, 0)
}

/// Renders `frames` of `settings`' motion in order with one renderer (the first frame's points uploaded with
/// the scene, the later ones through `Renderer::update_points`), passing each image to `sink`. The camera is
/// framed on the first frame when its distance is 0. Prints the scene, the adapter and the first frame's
/// per-pass GPU times on stderr.
pub fn render_frames(
    settings: &mut Settings,
    frames: &[u32],
    sink: &mut dyn FnMut(u32, image::RgbaImage) -> Result<()>,
) -> Result<()> {
    let Some((&first, rest)) = frames.split_first() else {
        return Ok(());
    };
    let start = std::time::Instant::now();
    let (mut scene, mut motion) = settings.open_motion()?;
    // Framed on the motion's frame 0 (the scene as built), so every frame of a motion gets the same camera.
    if settings.camera.distance <= 0.0 {
        settings.camera.frame(&scene.framing_bounds());
    }
    if !motion.is_still() {
        let count = motion.frame_count(&settings.motion);
        if let Some(&k) = frames.iter().find(|&&k| k >= count) {
            anyhow::bail!(
                "frame {k} is beyond the motion's {count} frames (0..={})",
                count - 1
            );
        }
        scene.set_strand_points(motion.frame(first)?)?;
    }
    // Under `light.fit = bound` every frame's hair maps are fitted to the whole motion's box, whichever frames
    // are rendered.
    let fit_bound = match settings.light.fit {
        crate::scene::LightFit::Bound if !motion.is_still() => Some(motion.bound(&settings.motion)?),
        _ => None,
    };
    let scene_ms = start.elapsed().as_secs_f64() * 1e3;
    let fur = crate::fur::settings::FurScene::build(&scene, &settings.fur).map_err(anyhow::Error::msg)?;
    for w in fur.iter().flat_map(|f| &f.warnings) {
        eprintln!("warning: {w}");
    }
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut renderer = Renderer::new(&gpu, &scene, settings.render.map_resolution)?;
    renderer.set_fit_bound(fit_bound);
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
    sink(first, renderer.read_output()?)?;
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
    for &k in rest {
        renderer.update_points(motion.frame(k)?)?;
        renderer.render(&input)?;
        sink(k, renderer.read_output()?)?;
    }
    Ok(())
}
