//! `hairlab curve`: one texel's fragments through a shadow method's CPU model, and the fragment CSV reader.

use crate::methods::registry;
use crate::visibility::Fragment;
use anyhow::{Context, Result};
use clap::Args;
use clap::builder::PossibleValuesParser;
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
#[command(after_long_help = curve_params_help())]
pub struct CurveArgs {
    /// CSV of the texel's fragments: one `depth,alpha` row each (depth in [0, 1], alpha in [0, 1)); an optional
    /// `depth,alpha` header, blank lines and `#` comment lines are skipped.
    #[arg(long)]
    pub fragments: PathBuf,
    /// Method name (see `--help` for every method's parameters).
    #[arg(long, value_parser = method_names())]
    pub method: String,
    /// Method parameter, e.g. `--param slices=64` (repeatable).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// Number of depths, uniform over [0, 1].
    #[arg(long, default_value_t = 256)]
    pub samples: usize,
    /// Global hair alpha for methods that assume one (occupancy); default: the mean alpha of the fragments.
    #[arg(long)]
    pub hair_alpha: Option<f32>,
}

/// The registered methods' names, so clap lists them and rejects any other.
pub(super) fn method_names() -> PossibleValuesParser {
    PossibleValuesParser::new(registry::all().iter().map(|m| m.name()))
}

/// Every method's parameters, for `hairlab curve --help`.
pub(super) fn curve_params_help() -> String {
    let mut out = String::from("Methods and their parameters:\n");
    for m in crate::methods::registry::all() {
        out.push_str(&format!("  {} — {}\n", m.name(), m.info().paper));
        for p in m.params() {
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

/// Reads a fragment CSV ([`parse_fragments_csv`]); errors name the file.
pub fn read_fragments_csv(path: &Path) -> Result<Vec<Fragment>> {
    let text =
        crate::io::read_regular_text(path).with_context(|| format!("{}: cannot read", path.display()))?;
    parse_fragments_csv(&text, &path.display().to_string())
}

/// One fragment row; with a header its columns are matched by name.
#[derive(Deserialize)]
pub(super) struct FragmentRow {
    depth: f32,
    alpha: f32,
}

/// Parses one texel's fragments: `depth,alpha` rows, depth in [0, 1] and alpha in [0, 1). Blank lines and `#`
/// comment lines are skipped wherever they appear; the first other line may be the header `depth,alpha`
/// (either order, any case). Every other line must be a row: errors name `source`, the line and the value,
/// and a text without rows is an error too.
pub fn parse_fragments_csv(text: &str, source: &str) -> Result<Vec<Fragment>> {
    let rows: Vec<(usize, FragmentRow)> =
        crate::io::read_rows(text, source, &["depth", "alpha"], "`depth,alpha` (two numbers)")?;
    let mut out = Vec::new();
    for (line, row) in rows {
        if !(0.0..=1.0).contains(&row.depth) {
            anyhow::bail!("{source}:{line}: depth {} is outside [0, 1]", row.depth);
        }
        if !(0.0..1.0).contains(&row.alpha) {
            anyhow::bail!("{source}:{line}: alpha {} is outside [0, 1)", row.alpha);
        }
        out.push(Fragment::new(row.depth, row.alpha));
    }
    if out.is_empty() {
        anyhow::bail!("{source}: no fragments (expected `depth,alpha` rows)");
    }
    Ok(out)
}

pub(super) fn curve(a: &CurveArgs) -> Result<()> {
    let method = registry::find(&a.method).map_err(anyhow::Error::msg)?;
    let mut values = crate::methods::ParamValues::new();
    for p in &a.params {
        let (k, v) = p
            .split_once('=')
            .with_context(|| format!("--param '{p}': expected key=value"))?;
        let v = crate::methods::parse_value(method, k.trim(), v)
            .map_err(|e| anyhow::anyhow!("--param '{p}': {e}"))?;
        values.insert(k.trim().to_string(), v);
    }
    if !(2..=1_000_000).contains(&a.samples) {
        anyhow::bail!("--samples must be in 2..=1000000 (got {})", a.samples);
    }
    if let Some(alpha) = a.hair_alpha
        && !(alpha > 0.0 && alpha <= 1.0)
    {
        anyhow::bail!("--hair-alpha must be in (0, 1] (got {alpha})");
    }
    let frags = read_fragments_csv(&a.fragments)?;
    let alpha = a
        .hair_alpha
        .unwrap_or_else(|| frags.iter().map(|f| f.alpha).sum::<f32>() / frags.len() as f32);
    let zs: Vec<f32> = (0..a.samples)
        .map(|i| i as f32 / (a.samples - 1) as f32)
        .collect();
    use crate::visibility::TexelModel;
    let reference = crate::visibility::Reference.curve(&frags, &zs);
    let model = method.model(&values, alpha).curve(&frags, &zs);
    let header = ["depth", registry::reference().name(), method.name()].map(String::from);
    let rows = zs.iter().zip(&reference).zip(&model).map(|((z, r), v)| (z, r, v));
    let text = crate::io::csv_table("the fragment curve", &header, rows)?;
    std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes()).context("stdout")?;
    Ok(())
}
