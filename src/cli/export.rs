//! `hairlab export --format mitsuba`: a preset's still scene written for another renderer to check hairlab
//! against (`path_scene/mitsuba.rs` says what maps to what).

use anyhow::Result;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

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
    #[command(flatten)]
    pub scene: super::render::SceneFlags,
    /// The folder to write into (created if missing).
    #[arg(long)]
    pub out: PathBuf,
}

pub(super) fn export(a: &ExportArgs) -> Result<()> {
    let settings = a.scene.settings()?;
    let scene = settings.scene.build()?;
    let files = match a.format {
        ExportFormat::Mitsuba => crate::path_scene::mitsuba::export(&settings, &scene, &a.out)?,
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
