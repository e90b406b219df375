//! `hairlab info`: what a strand or mesh file holds.

use crate::scene::hair;
use anyhow::Result;
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// A `.hair`, `.gltf`, `.glb`, TressFX `.tfx`, USC-HairSalon `.data` or USD (`.usda`, `.usdc`, `.usdz`) file.
    pub file: PathBuf,
    /// Fail (exit 1) when reading the file gave a warning (a USD layer missing or unreadable, an arc dropped), for
    /// scripts.
    #[arg(long)]
    pub strict: bool,
}

pub(super) fn run(a: &InfoArgs) -> Result<()> {
    crate::scene::load::set_strict(a.strict);
    info(&a.file)
}

fn info(path: &Path) -> Result<()> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    // A .hair file is read once (its warnings print once), for its arrays and its strands.
    let hair_file = match ext.as_deref() {
        Some("hair") => Some(hair::read_hair_file(path)?),
        _ => None,
    };
    // For the strand-only formats: the arrays the file holds and what hairlab drops of it.
    let mut arrays_dropped: Option<(Vec<&str>, Vec<String>)> = None;
    let scene = match (&hair_file, ext.as_deref()) {
        (Some(h), _) => crate::scene::Scene::new(
            h.to_strands()
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
            Vec::new(),
        ),
        (None, Some("tfx")) => {
            let f = crate::scene::tfx::read_tfx_file(path)?;
            let mut arrays = vec!["positions"];
            let mut dropped = vec!["position w (TressFX's simulation flag)".to_owned()];
            for (present, name, drop) in [
                (f.strand_uvs, "strand UVs", true),
                (f.vertex_uvs, "vertex UVs", true),
                (f.strand_thickness.is_some(), "strand thickness", false),
                (f.vertex_color.is_some(), "vertex colours", false),
            ] {
                if present {
                    arrays.push(name);
                    if drop {
                        dropped.push(format!("{name} (hairlab has no texture coordinates)"));
                    }
                }
            }
            arrays_dropped = Some((arrays, dropped));
            crate::scene::Scene::new(f.to_strands(), Vec::new())
        }
        (None, Some("data")) => {
            let f = crate::scene::usc_data::read_data_file(path)?;
            let dropped = (f.empty_strands > 0).then(|| format!("{} strands of 0 vertices", f.empty_strands));
            arrays_dropped = Some((vec!["positions"], dropped.into_iter().collect()));
            if !f.bare_roots.is_empty() {
                println!("{}", bare_roots_line(f.bare_roots.len()));
            }
            crate::scene::Scene::new(f.strands, Vec::new())
        }
        #[cfg(feature = "usd")]
        (None, Some("usda" | "usdc" | "usdz")) => {
            let f = crate::scene::usd::read_usd_file(path)?;
            let s = &f.strands;
            let arrays: Vec<&str> = [
                ("points", true),
                ("widths", s.thickness.is_some()),
                ("displayColor", s.color.is_some()),
                ("displayOpacity", s.alpha.is_some()),
            ]
            .iter()
            .filter(|(_, p)| *p)
            .map(|(n, _)| *n)
            .collect();
            println!(
                "stage:     upAxis {}, metersPerUnit {} (read as Y-up metres), {} time samples at {} time codes \
                 per second",
                f.up_axis,
                f.meters_per_unit,
                f.time_codes.len(),
                f.time_codes_per_second
            );
            arrays_dropped = Some((arrays, Vec::new()));
            for n in &f.notes {
                println!("converted: {n}");
            }
            for w in &f.warnings {
                println!("warning:   {w}");
            }
            crate::scene::load::refuse_if_strict(path, &f.warnings)?;
            let tris: usize = f.meshes.iter().map(|m| m.indices.len() / 3).sum();
            println!("meshes:    {} ({tris} triangles)", f.meshes.len());
            crate::scene::Scene::new(f.strands, f.meshes)
        }
        (None, _) => crate::scene::load::load_scene(path)?,
    };
    println!("file:      {}", path.display());
    if let Some((arrays, dropped)) = &arrays_dropped {
        println!("arrays:    {}", arrays.join(", "));
        for d in dropped {
            println!("dropped:   {d}");
        }
    } else if let Some(h) = &hair_file {
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

/// The one line `info` prints for a `.data` file's strands of one vertex.
fn bare_roots_line(n: usize) -> String {
    format!(
        "roots:     {n} bare roots (strands of one vertex: scalp with no hair), counted apart from the strands drawn"
    )
}
