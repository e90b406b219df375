//! A motion's frames rendered offscreen with one renderer (the first frame's points uploaded with the scene, the
//! later ones through `Renderer::update_points`), as `hairlab render --frame/--frames` and the window's
//! animation export do, and written as a numbered PNG sequence or one looping animated GIF.

use crate::gpu::{self, AdapterPreference, Gpu};
use crate::methods::registry;
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use anyhow::{Context, Result};
use std::path::Path;

/// The file name of frame `k` in a PNG sequence whose frames end before `end`: `frame_0007.png` (at least four
/// digits, more when `end` needs them).
pub fn frame_file_name(k: u32, end: u32) -> String {
    let digits = (end.saturating_sub(1).max(1).ilog10() as usize + 1).max(4);
    format!("frame_{k:0digits$}.png")
}

/// `image` encoded as PNG.
pub fn encode_png(image: &image::RgbaImage) -> Result<Vec<u8>> {
    let mut png = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    Ok(png)
}

/// Writes `frames` (frame number, image) into the folder `dir` (created) as [`frame_file_name`]s, each file
/// whole; `end` is the range's end (for the digits).
pub fn write_png_sequence(dir: &Path, frames: &[(u32, image::RgbaImage)], end: u32) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    for (k, image) in frames {
        crate::io::write_atomic(&dir.join(frame_file_name(*k, end)), &encode_png(image)?)?;
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
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    render_frames_on(&gpu, settings, frames, &mut |line| eprintln!("{line}"), sink)
}

/// [`render_frames`] on `gpu`, the scene, adapter, GPU times and fur figures told to `log` line by line.
pub fn render_frames_on(
    gpu: &Gpu,
    settings: &mut Settings,
    frames: &[u32],
    log: &mut dyn FnMut(&str),
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
    // Under `light.fit = bound` (`stable`) every frame's hair maps are fitted to the whole motion's box (its
    // bounding sphere), whichever frames are rendered.
    let fit_bound = match settings.light.fit {
        crate::scene::LightFit::Bound | crate::scene::LightFit::Stable if !motion.is_still() => {
            Some(motion.bound(&settings.motion)?)
        }
        _ => None,
    };
    let scene_ms = start.elapsed().as_secs_f64() * 1e3;
    let fur = crate::fur::settings::FurScene::build(&scene, &settings.fur).map_err(anyhow::Error::msg)?;
    for w in fur.iter().flat_map(|f| &f.warnings) {
        log(&format!("warning: {w}"));
    }
    let mut renderer = Renderer::new(gpu, &scene, settings.render.map_resolution)?;
    renderer.set_fit_bound(fit_bound);
    if let Some((meshes, pose)) = motion.mesh_pose(first) {
        renderer.pose_meshes(meshes, pose)?;
    }
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
    log(&format!(
        "{} strands, {} segments, {} triangles on {}",
        scene.strands.strand_count(),
        scene.strands.segment_count(),
        scene.triangle_count(),
        gpu::describe(&gpu.info)
    ));
    for t in &times {
        log(&format!("  {:>16}: {:.3} ms", t.name, t.ms));
    }
    if let Some(f) = &fur {
        let table = crate::measure::fur::table1(&renderer, f, scene_ms, &times)?;
        let march = match renderer.fur_state() {
            Some(state) => state.shell.read_stats(gpu)?,
            None => Default::default(),
        };
        log(&format!(
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
        ));
    }
    for &k in rest {
        motion.show(&mut renderer, k)?;
        renderer.render(&input)?;
        sink(k, renderer.read_output()?)?;
    }
    Ok(())
}
