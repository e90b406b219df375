//! `hairlab convert`: strands from any readable format to `.hair`, `.tfx`, `.data` or `.usda`, written whole. A
//! time-sampled USD stage converted to `.usda` keeps every frame (time-sampled points); to any other format, its
//! first time code.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input: `.hair`, `.gltf`, `.glb`, `.tfx`, `.data`, `.usda`, `.usdc` or `.usdz`.
    pub input: PathBuf,
    /// Output: `.hair`, `.tfx`, `.data` or `.usda`.
    pub output: PathBuf,
    /// Fail (exit 1, nothing written) when reading the input gave a warning (a USD layer missing or unreadable, an
    /// arc dropped), for scripts.
    #[arg(long)]
    pub strict: bool,
}

pub(super) fn convert(a: &ConvertArgs) -> Result<()> {
    use crate::scene::load::{STRAND_EXTENSIONS, load_scene, save_strands};
    crate::scene::load::set_strict(a.strict);
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
    let in_ext = a
        .input
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    // A `.data` file's bare roots (strands of one vertex) are not part of the scene drawn: read apart, kept where the
    // output holds one-point strands.
    let (scene, data) = if in_ext.as_deref() == Some("data") {
        let f = crate::scene::usc_data::read_data_file(&a.input)?;
        (crate::scene::Scene::new(f.strands.clone(), Vec::new()), Some(f))
    } else {
        (load_scene(&a.input)?, None)
    };
    let roots = data.as_ref().map_or(0, |f| f.bare_roots.len());
    let keeps_roots = matches!(ext.as_str(), "data" | "hair");
    let strands = match &data {
        Some(f) if roots > 0 && keeps_roots => f.strands_with_roots(),
        _ => scene.strands.clone(),
    };
    let name = a.input.file_name().unwrap_or_default().to_string_lossy();
    #[cfg(feature = "usd")]
    let frames = write_usd_frames(a, &ext)?;
    #[cfg(not(feature = "usd"))]
    let frames: Option<usize> = None;
    match frames {
        Some(n) => println!("frames:    {n} (time-sampled points)"),
        None => save_strands(&a.output, &strands, &format!("hairlab convert {name}"))?,
    }
    let s = &strands;
    println!(
        "wrote {}: {} strands, {} points, {} segments",
        a.output.display(),
        s.strand_count(),
        s.point_count(),
        s.segment_count()
    );
    if roots > 0 {
        if keeps_roots {
            println!("kept:      {roots} bare roots (strands of one vertex, after the strands drawn)");
        } else {
            println!(
                "dropped:   {roots} bare roots (strands of one vertex: a .{ext} curve needs two points)"
            );
        }
    }
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

/// A time-sampled USD stage to `.usda`: writes every frame and returns how many; `None` (nothing written) for any
/// other input or output, or a stage of one frame.
#[cfg(feature = "usd")]
fn write_usd_frames(a: &ConvertArgs, ext: &str) -> Result<Option<usize>> {
    let in_ext = a
        .input
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if ext != "usda" || !matches!(in_ext.as_deref(), Some("usda" | "usdc" | "usdz")) {
        return Ok(None);
    }
    let f = crate::scene::usd::read_usd_frames(&a.input)?;
    if f.frames.len() < 2 {
        return Ok(None);
    }
    crate::scene::usda_write::write_usda_file(&a.output, &f.frames, f.time_codes_per_second)?;
    Ok(Some(f.frames.len()))
}
