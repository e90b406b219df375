//! `hairlab render`: a preset rendered headlessly to a PNG, the same image the window shows.

pub use crate::animation::{animated_gif, render_frame_image, render_frames, render_image};
use crate::animation::{encode_png, frame_file_name};
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
    let encode = encode_png;
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
            render_frames(&mut settings, &frames, &mut |k, image| {
                let path = a.out.join(frame_file_name(k, range.end));
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
