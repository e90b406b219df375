//! `hairlab info`: what a strand or mesh file holds.

use crate::scene::hair;
use anyhow::Result;
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// A `.hair`, `.gltf` or `.glb` file.
    pub file: PathBuf,
}

pub(super) fn info(path: &Path) -> Result<()> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    // A .hair file is read once (its warnings print once), for its arrays and its strands.
    let hair_file = match ext.as_deref() {
        Some("hair") => Some(hair::read_hair_file(path)?),
        _ => None,
    };
    let scene = match &hair_file {
        Some(h) => crate::scene::Scene::new(
            h.to_strands()
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
            Vec::new(),
        ),
        None => crate::scene::load::load_scene(path)?,
    };
    println!("file:      {}", path.display());
    if let Some(h) = &hair_file {
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
