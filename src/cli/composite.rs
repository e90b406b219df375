//! `hairlab composite`: one pixel's eye fragments through a transparency technique's CPU model.

use anyhow::{Context, Result};
use clap::Args;
use clap::builder::PossibleValuesParser;
use serde::Deserialize;
use std::path::PathBuf;

#[derive(Args, Debug)]
#[command(after_long_help = composite_params_help())]
pub struct CompositeArgs {
    /// CSV of the pixel's fragments: one `depth,r,g,b,alpha` row each (depth >= 0 in units of the
    /// camera-to-target distance, linear colour >= 0, alpha in [0, 1]); an optional header naming those five
    /// columns as the first row, blank lines and `#` comment lines are skipped. Rows are segments 0, 1, ... in
    /// file order (which orders exact-depth ties).
    #[arg(long)]
    pub fragments: PathBuf,
    /// Technique name (see `--help` for every technique's parameters).
    #[arg(long, value_parser = technique_names())]
    pub method: String,
    /// Technique parameter, e.g. `--param k=4` (repeatable).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// Linear background colour `r,g,b` (the opaque image at the pixel).
    #[arg(long, default_value = "0,0,0")]
    pub background: String,
    /// Global hair alpha for techniques that assume one (occupancy order); default: the mean alpha of the
    /// fragments.
    #[arg(long)]
    pub hair_alpha: Option<f32>,
}

/// The registered transparency techniques' names, so clap lists them and rejects any other.
pub(super) fn technique_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        crate::render::transparency::registry::all()
            .iter()
            .map(|t| t.name()),
    )
}

/// Every transparency technique's parameters, for `hairlab composite --help`.
pub(super) fn composite_params_help() -> String {
    let mut out = String::from("Techniques and their parameters:\n");
    for t in crate::render::transparency::registry::all() {
        out.push_str(&format!("  {} — {}\n", t.name(), t.info().paper));
        for p in t.info().params {
            out.push_str(&format!(
                "      {} (default {}): {}\n",
                p.key,
                p.format(p.default),
                p.help
            ));
        }
    }
    out
}

/// One eye fragment row; with a header its columns are matched by name.
#[derive(Deserialize)]
pub(super) struct PixelRow {
    depth: f32,
    r: f32,
    g: f32,
    b: f32,
    alpha: f32,
}

/// The columns of a pixel CSV.
pub(super) const PIXEL_COLUMNS: [&str; 5] = ["depth", "r", "g", "b", "alpha"];

/// Parses one pixel's eye fragments: `depth,r,g,b,alpha` rows, depth and colour finite and >= 0, alpha in
/// [0, 1]. Blank lines and `#` comment lines are skipped wherever they appear; the first other line may be a
/// header naming the five columns (any order, any case). Row `i` (counting rows only) is segment `i`. Errors
/// name `source`, the line and the value; a text without rows is an error too.
pub fn parse_pixel_csv(text: &str, source: &str) -> Result<Vec<crate::transparency::EyeFragment>> {
    let rows: Vec<(usize, PixelRow)> =
        crate::io::read_rows(text, source, &PIXEL_COLUMNS, "`depth,r,g,b,alpha` (five numbers)")?;
    let mut out = Vec::new();
    for (line, row) in rows {
        for (name, v) in [("depth", row.depth), ("r", row.r), ("g", row.g), ("b", row.b)] {
            if !(v.is_finite() && v >= 0.0) {
                anyhow::bail!("{source}:{line}: {name} {v} is not a finite number >= 0");
            }
        }
        if !(0.0..=1.0).contains(&row.alpha) {
            anyhow::bail!("{source}:{line}: alpha {} is outside [0, 1]", row.alpha);
        }
        out.push(crate::transparency::EyeFragment {
            depth: row.depth,
            segment: out.len() as u32,
            color: [row.r, row.g, row.b],
            alpha: row.alpha,
        });
    }
    if out.is_empty() {
        anyhow::bail!("{source}: no fragments (expected `depth,r,g,b,alpha` rows)");
    }
    Ok(out)
}

/// `r,g,b`: three finite numbers >= 0.
pub(super) fn parse_background(text: &str) -> Result<[f32; 3]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let values: Option<Vec<f32>> = parts
        .iter()
        .map(|p| p.parse::<f32>().ok().filter(|v| v.is_finite() && *v >= 0.0))
        .collect();
    match values.as_deref() {
        Some(&[r, g, b]) => Ok([r, g, b]),
        _ => anyhow::bail!("--background '{text}': expected r,g,b (three finite numbers >= 0)"),
    }
}

pub(super) fn composite(a: &CompositeArgs) -> Result<()> {
    use crate::render::transparency::registry;
    let technique = registry::find(&a.method).map_err(anyhow::Error::msg)?;
    let mut values = crate::methods::ParamValues::new();
    for p in &a.params {
        let (k, v) = p
            .split_once('=')
            .with_context(|| format!("--param '{p}': expected key=value"))?;
        let v = registry::spec(technique, k.trim())
            .and_then(|spec| spec.parse(v))
            .map_err(|e| anyhow::anyhow!("--param '{p}': {e}"))?;
        values.insert(k.trim().to_string(), v);
    }
    let background = parse_background(&a.background)?;
    if let Some(alpha) = a.hair_alpha
        && !(0.0..=1.0).contains(&alpha)
    {
        anyhow::bail!("--hair-alpha must be in [0, 1] (got {alpha})");
    }
    let path = &a.fragments;
    let text =
        crate::io::read_regular_text(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let frags = parse_pixel_csv(&text, &path.display().to_string())?;
    let hair_alpha = a
        .hair_alpha
        .unwrap_or_else(|| frags.iter().map(|f| f.alpha).sum::<f32>() / frags.len() as f32);
    // One pixel: its own depths are the frame's depth range.
    let depth_range = frags
        .iter()
        .fold([f32::INFINITY, f32::NEG_INFINITY], |[n, f], x| {
            [n.min(x.depth), f.max(x.depth)]
        });
    let ctx = crate::transparency::ModelContext {
        hair_alpha,
        depth_range,
    };
    let [r, g, b] = technique.model(&values, &ctx).composite(&frags, background);
    println!("{r},{g},{b}");
    Ok(())
}
