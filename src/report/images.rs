//! Each configuration's image beside the reference's: a fresh study renders the scene with every measured
//! configuration and with the exact reference shadows, and writes into the bench's folder `images/reference.png`
//! and per result row `k` (in `results.csv` order) `images/k.png`, `images/k_difference.png` (the max-channel
//! difference ×[`DIFFERENCE_GAIN`] as a heat map, the Compare window's) and `images/k_flip.png` (FLIP's heat
//! map). The section shows the rows whose files are there.

use super::data::{IMAGES, Shadows, Transparency, WORST_TEXELS, vz_file};
use super::page::{escape, section};
use crate::gpu::Gpu;
use crate::io::write_png;
use crate::measure::MethodConfig;
use crate::measure::transparency::TechniqueConfig;
use crate::progress::{Progress, share};
use crate::settings::Settings;
use crate::transparency::FlipMap;
use crate::transparency::metrics::difference_image;
use anyhow::{Context, Result};
use image::RgbaImage;
use std::fmt::Write as _;
use std::path::Path;

/// The gain of the difference maps.
pub const DIFFERENCE_GAIN: f32 = 8.0;

/// `settings` with the shadow method `method`.
pub fn with_method(settings: &Settings, method: &MethodConfig) -> Settings {
    let mut s = settings.clone();
    s.method.name = method.name.clone();
    s.method.params = method.params.clone();
    s
}

/// `settings` with the eye transparency technique `technique`.
pub fn with_technique(settings: &Settings, technique: &TechniqueConfig) -> Settings {
    let mut s = settings.clone();
    s.transparency.name = technique.name.clone();
    s.transparency.params = technique.params.clone();
    s
}

/// Frame 0 of `settings`' scene.
pub(super) fn render(gpu: &Gpu, mut s: Settings) -> Result<RgbaImage> {
    let mut out = None;
    crate::animation::render_frames_on(
        gpu,
        &mut s,
        &[0],
        &mut |_| {},
        &mut crate::progress::Quiet,
        &mut |_, image| {
            out = Some(image);
            Ok(())
        },
    )?;
    out.context("no frame rendered")
}

/// Renders `reference` and each of `variants` (label, settings; a table's rows in order) into `dir`
/// (`reference.png`, and per row `k.png`, `k_difference.png`, `k_flip.png`); stops after the image in progress
/// when `progress` asks. Whether every image was rendered.
pub fn render_set(
    gpu: &Gpu,
    reference: Settings,
    variants: Vec<(String, Settings)>,
    dir: &Path,
    progress: &mut dyn Progress,
) -> Result<bool> {
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    if !progress.step("rendering the reference image", 0.0) {
        return Ok(false);
    }
    let reference = render(gpu, reference)?;
    write_png(&dir.join("reference.png"), &reference)?;
    let total = variants.len() + 1;
    for (k, (label, s)) in variants.into_iter().enumerate() {
        if !progress.step(&format!("rendering {label}"), share(k + 1, total)) {
            return Ok(false);
        }
        let image = render(gpu, s)?;
        let difference = difference_image(&image, &reference, DIFFERENCE_GAIN);
        let flip = FlipMap::new(&image, &reference).heat_map();
        write_png(&dir.join(format!("{k}_difference.png")), &difference)?;
        write_png(&dir.join(format!("{k}_flip.png")), &flip)?;
        write_png(&dir.join(format!("{k}.png")), &image)?;
    }
    Ok(true)
}

/// Renders the reference shadows and each of `configs` (the bench's rows, in order) into `bench_dir/images`;
/// whether every image was rendered.
pub fn render_configs(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MethodConfig],
    bench_dir: &Path,
    progress: &mut dyn Progress,
) -> Result<bool> {
    let reference = MethodConfig::new(crate::methods::registry::reference().name(), Default::default());
    let variants = configs
        .iter()
        .map(|c| (c.label(), with_method(settings, c)))
        .collect();
    let dir = bench_dir.join(IMAGES);
    render_set(gpu, with_method(settings, &reference), variants, &dir, progress)
}

/// Renders the exact composite and each of `techniques` (the transparency bench's rows, in order) into
/// `bench_dir/images`: Sintorn & Assarsson's Fig. 2 grid; whether every image was rendered.
pub fn render_techniques(
    gpu: &Gpu,
    settings: &Settings,
    techniques: &[TechniqueConfig],
    bench_dir: &Path,
    progress: &mut dyn Progress,
) -> Result<bool> {
    let reference = TechniqueConfig::new(
        crate::render::transparency::registry::reference().name(),
        Default::default(),
    );
    let variants = techniques
        .iter()
        .map(|t| (t.label(), with_technique(settings, t)))
        .collect();
    let dir = bench_dir.join(IMAGES);
    render_set(
        gpu,
        with_technique(settings, &reference),
        variants,
        &dir,
        progress,
    )
}

/// The images of `rows` rows in `dir` whose three files are there, after `reference.png` (none without it).
fn files_in(dir: &Path, rows: usize) -> Vec<String> {
    if !dir.join("reference.png").is_file() {
        return Vec::new();
    }
    let mut out = vec!["reference.png".to_string()];
    for k in 0..rows {
        let names = row_files(k);
        if names.iter().all(|n| dir.join(n).is_file()) {
            out.extend(names);
        }
    }
    out
}

/// The transparency folder's images the report copies.
pub fn technique_files(t: &Transparency) -> Vec<String> {
    files_in(&t.dir.join(IMAGES), t.table.rows.len())
}

/// Sintorn & Assarsson's Fig. 2 layout: the exact composite, then each technique's image with its metrics from
/// `transparency.csv`, and its difference and FLIP maps; nothing when no images were rendered.
pub fn fig2(t: &Transparency, images_dir: &str) -> String {
    let present = technique_files(t);
    if !present.iter().any(|f| f.ends_with("_flip.png")) {
        return String::new();
    }
    let tab = &t.table;
    // Three rows as in Fig. 2: the images (the reference first), the differences, the FLIP maps.
    let mut rows = [
        super::page::figure(
            &format!("{images_dir}/reference.png"),
            "The scene's hair composited exactly (every fragment sorted), the reference",
            "exact composite (reference)",
        ),
        String::new(),
        String::new(),
    ];
    for k in 0..tab.rows.len() {
        let files = row_files(k);
        if !present.contains(&files[0]) {
            continue;
        }
        let label = tab.text(k, "configuration").unwrap_or("?");
        let cell = |name: &str| super::page::shown(name, tab.text(k, name).unwrap_or(""));
        let captions = [
            (
                format!("The hair composited by {label}"),
                format!(
                    "{label}: hair RMSE {}, SSIM {}, FLIP {}, {} ms",
                    cell("rmse_hair"),
                    cell("ssim_hair"),
                    cell("flip_hair"),
                    cell("gpu_ms")
                ),
            ),
            (
                format!("Heat map of the difference between {label} and the exact composite"),
                format!("{label}: difference ×{DIFFERENCE_GAIN}"),
            ),
            (
                format!("FLIP heat map of {label} against the exact composite"),
                format!("{label}: FLIP"),
            ),
        ];
        for ((row, file), (alt, caption)) in rows.iter_mut().zip(&files).zip(captions) {
            *row += &super::page::figure(&format!("{images_dir}/{file}"), &alt, &caption);
        }
    }
    let mut out =
        String::from("<h3>The techniques' images (Sintorn &amp; Assarsson 2009, Fig. 2 layout)</h3>\n");
    for row in rows {
        out += &format!("<div class=\"grid\">\n{row}</div>\n");
    }
    out
}

/// The names of row `k`'s files, in the order shown.
fn row_files(k: usize) -> [String; 3] {
    [
        format!("{k}.png"),
        format!("{k}_difference.png"),
        format!("{k}_flip.png"),
    ]
}

/// The bench folder's images the report copies: the reference, every row's three, and its `V(z)` charts.
pub fn files(s: &Shadows) -> Vec<String> {
    let dir = s.dir.join(IMAGES);
    let mut out = files_in(&dir, s.results.rows.len());
    if out.is_empty() {
        return out;
    }
    for k in 0..s.results.rows.len() {
        for rank in 0..WORST_TEXELS {
            let vz = vz_file(k, rank);
            if dir.join(&vz).is_file() {
                out.push(vz);
            }
        }
    }
    out
}

/// Per configuration: its image beside the reference, the difference and the FLIP map, with its memory,
/// geometry passes and image metrics from `results.csv`; `None` when no images were rendered.
pub fn configurations(s: &Shadows, images_dir: &str) -> Option<String> {
    let present = files(s);
    if !present.iter().any(|f| f.ends_with("_flip.png")) {
        return None;
    }
    let t = &s.results;
    let mut content = format!(
        "<p>Each configuration's image (frame 0) beside the exact reference's, the difference (max channel \
         ×{DIFFERENCE_GAIN}, black: none) and FLIP's per-pixel map (magma, black: none). The figures are the \
         bench's, from results.csv.</p>\n"
    );
    let reference = format!("{images_dir}/reference.png");
    for k in 0..t.rows.len() {
        let [image, difference, flip] = row_files(k);
        if !present.contains(&image) {
            continue;
        }
        let label = t.text(k, "label").unwrap_or("?");
        let cell = |name: &str| super::page::shown(name, t.text(k, name).unwrap_or(""));
        let _ = write!(
            content,
            "<article class=\"config\">\n<h3>{l}</h3>\n<p>map error {me}, FLIP {fl}, image RMSE {rm}; memory {mb} \
             bytes; {gp} geometry passes; GPU {ms} ms</p>\n<div class=\"grid\">\n",
            l = escape(label),
            me = escape(&cell("map_error")),
            fl = escape(&cell("flip")),
            rm = escape(&cell("image_rmse")),
            mb = escape(&cell("memory_bytes")),
            gp = escape(&cell("geometry_passes")),
            ms = escape(&cell("gpu_ms_median")),
        );
        for (src, alt, caption) in [
            (
                format!("{images_dir}/{image}"),
                format!("The scene rendered with {label} shadows"),
                label.to_string(),
            ),
            (
                reference.clone(),
                "The scene rendered with the exact reference shadows".to_string(),
                crate::methods::registry::reference().name().to_string(),
            ),
            (
                format!("{images_dir}/{difference}"),
                format!("Heat map of the difference between the {label} image and the reference"),
                format!("difference ×{DIFFERENCE_GAIN}"),
            ),
            (
                format!("{images_dir}/{flip}"),
                format!("FLIP heat map of the {label} image against the reference"),
                "FLIP".to_string(),
            ),
        ] {
            content += &super::page::figure(&src, &alt, &caption);
        }
        content += "</div>\n<div class=\"grid3\">\n";
        for rank in 0..WORST_TEXELS {
            let vz = vz_file(k, rank);
            if present.contains(&vz) {
                content += &super::page::figure(
                    &format!("{images_dir}/{vz}"),
                    &format!(
                        "Line chart of V(z) at the texel where {label} errs most (number {} of {}), against the \
                         exact reference's",
                        rank + 1,
                        WORST_TEXELS
                    ),
                    &format!("V(z) at worst texel {}", rank + 1),
                );
            }
        }
        content += "</div>\n</article>\n";
    }
    Some(section(
        "configurations",
        "Each configuration against the reference",
        &content,
    ))
}
