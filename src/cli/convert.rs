//! `hairlab convert`: strands from any readable format to `.hair`, `.tfx` or `.data`, written whole.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input: `.hair`, `.gltf`, `.glb`, `.tfx` or `.data`.
    pub input: PathBuf,
    /// Output: `.hair`, `.tfx` or `.data`.
    pub output: PathBuf,
}

pub(super) fn convert(a: &ConvertArgs) -> Result<()> {
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
