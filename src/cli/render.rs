//! `hairlab render`: a preset rendered headlessly to a PNG, the same image the window shows; under
//! `render.mode = path`, the CPU path-traced reference of its still scene instead.

use super::interrupt::InterruptedAt;
use crate::animation::AnimationOut;
pub use crate::animation::{animated_gif, render_frame_image, render_frames, render_image};
use crate::io::encode_png;
use crate::path_scene::PathScene;
use crate::render::render_settings::RenderMode;
use crate::settings::Settings;
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;

/// The scene flags `render` and `export` share: the preset, its overrides and the image size.
#[derive(Args, Debug)]
pub struct SceneFlags {
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
}

impl SceneFlags {
    /// The preset with its overrides; the image size flags apply after them and are checked as themselves.
    pub fn settings(&self) -> Result<Settings> {
        let mut settings = Settings::load_preset(&self.preset, &self.set)?;
        self.size(&mut settings)?;
        Ok(settings)
    }

    /// Applies `--width`/`--height` to `settings` and checks them.
    fn size(&self, settings: &mut Settings) -> Result<()> {
        settings.render.width = self.width.unwrap_or(settings.render.width);
        settings.render.height = self.height.unwrap_or(settings.render.height);
        settings.validate().context("--width/--height")
    }
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneFlags,
    /// Render frame K of the preset's motion (`[motion]`; frame 0 is the still scene of a simulation).
    #[arg(long, value_name = "K", conflicts_with = "frames")]
    pub frame: Option<u32>,
    /// Render frames A up to B (exclusive) of the motion: as a numbered PNG sequence `frame_0000.png` … in the
    /// folder `--out`, or, when `--out` ends in `.gif`, as one animated GIF at the motion's frame rate (looping).
    #[arg(long, value_name = "A..B")]
    pub frames: Option<String>,
    /// Output PNG path (with `--frames`: a folder, or an animated `.gif`; under `render.mode = path`, a `.png` or
    /// a `.exr` of the linear float image).
    #[arg(long)]
    pub out: PathBuf,
    /// Fail (exit 1, nothing written) when reading the scene file gave a warning (a USD layer missing or
    /// unreadable, an arc dropped), for scripts.
    #[arg(long)]
    pub strict: bool,
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
    crate::scene::load::set_strict(a.strict);
    let mut settings = Settings::load_preset(&a.scene.preset, &a.scene.set)?;
    if settings.render.mode == RenderMode::Path {
        return path_render(a, settings);
    }
    let range = a.frames.as_deref().map(parse_frame_range).transpose()?;
    let gif = range.is_some() && a.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("gif"));
    let out = range.clone().map(|r| {
        if gif {
            AnimationOut::Gif {
                file: a.out.clone(),
                fps: settings.motion.fps,
            }
        } else {
            AnimationOut::Pngs {
                dir: a.out.clone(),
                end: r.end,
            }
        }
    });
    match &out {
        None => crate::io::check_output(&a.out, "png")?,
        Some(out) => out.check()?,
    }
    a.scene.size(&mut settings)?;
    let (Some(range), Some(out)) = (range, out) else {
        let image = render_frame_image(&mut settings, a.frame.unwrap_or(0))?;
        crate::io::write_png(&a.out, &image)?;
        println!("wrote {} ({}×{})", a.out.display(), image.width(), image.height());
        return Ok(());
    };
    // Each frame is written as it renders (into a temporary beside `--out`, renamed into place at the end).
    let frames: Vec<u32> = range.clone().collect();
    out.write(|sink| render_frames(&mut settings, &frames, sink))?;
    let (w, h) = (settings.render.width, settings.render.height);
    let what = if gif {
        format!(" as an animated GIF ({w}×{h}, {} fps)", settings.motion.fps)
    } else {
        format!(" ({w}×{h})")
    };
    println!(
        "wrote frames {}..{} to {}{what}",
        range.start,
        range.end,
        a.out.display()
    );
    Ok(())
}

/// `render.mode = path`: the still scene's fibres (widths from `render.strand_width`) and meshes path-traced on
/// the CPU under the preset's camera and directional light, `render.spp` samples per pixel in passes, progress on
/// stderr. `--out` is a `.png` (over black, sRGB) or a `.exr` (the linear float image). Ctrl-C stops after the
/// pass in progress, writes the image of the samples taken so far and fails with [`InterruptedAt`] (exit 130).
/// Samples whose radiance was NaN or infinite are left out of their pixels' means and said once.
fn path_render(a: &RenderArgs, mut settings: Settings) -> Result<()> {
    if a.frame.is_some() || a.frames.is_some() {
        anyhow::bail!(
            "render.mode=path renders the still scene: --frame and --frames are for render.mode=raster"
        );
    }
    let exr = a.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    crate::io::check_output(&a.out, if exr { "exr" } else { "png" })?;
    a.scene.size(&mut settings)?;
    let scene = settings.scene.build()?;
    let start = std::time::Instant::now();
    let path = PathScene::new(&settings, &scene)?;
    let s = &path.settings;
    eprintln!(
        "path: {} segments, {} triangles, BVH in {:.0} ms; {}×{} at {} spp",
        path.bvh.segments().len(),
        path.bvh.triangle_count(),
        start.elapsed().as_secs_f64() * 1e3,
        s.width,
        s.height,
        s.samples
    );
    // Ctrl-C answers the bar's next step with a stop: the image holds the samples taken.
    let mut bar = super::progress::TerminalProgress::new();
    let acc = path.render(s.samples.div_ceil(20), &mut bar);
    drop(bar);
    let (image, done) = (acc.mean(), acc.samples());
    let (w, h) = (settings.render.width, settings.render.height);
    let bytes = if exr {
        crate::io::encode_exr(&image, w, h)?
    } else {
        let rgba: Vec<[f32; 4]> = image.iter().map(|v| [v.x, v.y, v.z, 1.0]).collect();
        encode_png(&crate::io::over_black(&rgba, w, h))?
    };
    crate::io::write_atomic(&a.out, &bytes)?;
    if let Some(note) = crate::pathtrace::accumulation::dropped_note(acc.dropped()) {
        eprintln!("{note}");
    }
    println!(
        "wrote {} ({w}×{h}, path-traced, {done} spp, {:.1} s)",
        a.out.display(),
        start.elapsed().as_secs_f64()
    );
    if done < s.samples {
        return Err(InterruptedAt {
            done: done.into(),
            unit: format!("of {} samples per pixel", s.samples),
            wrote: Some(a.out.clone()),
        }
        .into());
    }
    Ok(())
}
