//! `hairlab export --format mitsuba`: a preset's still scene written for another renderer to check hairlab
//! against (`pathtrace/mitsuba.rs` says what maps to what).

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

use crate::settings::Settings;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ExportFormat {
    /// Mitsuba 3: `scene.xml`, `hair.txt` (linearcurve) and one OBJ per mesh.
    Mitsuba,
}

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// What to write.
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Preset: built-in name (default, patch), `presets/<name>.toml`, or a path to a TOML file.
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value by dotted key (`render.spp` sets the samples per pixel of the exported sensor).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Image width in pixels (overrides render.width).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides render.height).
    #[arg(long)]
    pub height: Option<u32>,
    /// The folder to write into (created if missing).
    #[arg(long)]
    pub out: PathBuf,
}

pub(super) fn export(a: &ExportArgs) -> Result<()> {
    let mut settings = Settings::load_preset(&a.preset, &a.set)?;
    settings.render.width = a.width.unwrap_or(settings.render.width);
    settings.render.height = a.height.unwrap_or(settings.render.height);
    settings.validate().context("--width/--height")?;
    let scene = settings.scene.build()?;
    let files = match a.format {
        ExportFormat::Mitsuba => crate::pathtrace::mitsuba::export(&settings, &scene, &a.out)?,
    };
    for f in &files {
        println!("wrote {}", f.display());
    }
    println!(
        "render it with Mitsuba 3: `mitsuba -m scalar_rgb {}` ({}×{}, {} spp)",
        a.out.join("scene.xml").display(),
        settings.render.width,
        settings.render.height,
        settings.render.spp
    );
    Ok(())
}
