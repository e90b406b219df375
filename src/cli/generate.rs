//! `hairlab gen`: procedural hair written as a `.hair` file.

use crate::scene::generate::{GenKind, GenParams, HairStyle};
use crate::scene::hair;
use crate::settings::apply_override;
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use serde::Deserialize;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct GenArgs {
    /// What to grow: a head, a patch, or a stress scene (see the presets of the same names).
    pub kind: GenKind,
    /// Shape of each strand (default: the generator's, wavy).
    #[arg(long)]
    pub style: Option<HairStyle>,
    /// Number of strands.
    #[arg(long)]
    pub strands: Option<u32>,
    /// Segments per strand (1..=65535).
    #[arg(long)]
    pub segments: Option<u32>,
    /// Strand length in world units.
    #[arg(long)]
    pub length: Option<f32>,
    /// Number of clumps (0: none).
    #[arg(long)]
    pub clumps: Option<u32>,
    /// Random seed (same seed, same hair).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Grow the hair on this glTF mesh's triangles instead of the built-in ellipsoid (`head` kind).
    #[arg(long)]
    pub scalp: Option<PathBuf>,
    /// Any other generator parameter, e.g. `--set curl_radius=0.01` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output `.hair` path.
    #[arg(long)]
    pub out: PathBuf,
}

pub(super) fn gen_hair(a: &GenArgs) -> Result<()> {
    crate::io::check_output(&a.out, "hair")?;
    let mut p = GenParams {
        kind: a.kind,
        ..GenParams::default()
    };
    p.style = a.style.unwrap_or(p.style);
    p.strands = a.strands.unwrap_or(p.strands);
    p.segments = a.segments.unwrap_or(p.segments);
    p.length = a.length.unwrap_or(p.length);
    p.clumps = a.clumps.unwrap_or(p.clumps);
    p.seed = a.seed.unwrap_or(p.seed);
    if !a.set.is_empty() {
        let mut tree = toml::Table::try_from(&p).context("generator parameters")?;
        for o in &a.set {
            apply_override(&mut tree, o)?;
        }
        p = GenParams::deserialize(toml::Value::Table(tree)).context("generator parameters")?;
    }
    let scene = crate::settings::SceneSettings {
        file: None,
        scalp: a.scalp.clone(),
        generator: p.clone(),
    }
    .build()?;
    let kind = a.kind.to_possible_value().map(|v| v.get_name().to_owned());
    let info = format!("hairlab gen {} seed {}", kind.unwrap_or_default(), p.seed);
    let file = hair::HairFile::from_strands(&scene.strands, &info)?;
    hair::write_hair_file(&a.out, &file)?;
    println!(
        "wrote {}: {} strands, {} points, {} segments",
        a.out.display(),
        scene.strands.strand_count(),
        scene.strands.point_count(),
        scene.strands.segment_count()
    );
    Ok(())
}
