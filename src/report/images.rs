//! Each configuration's image beside the reference's: a fresh study renders the scene with every measured
//! configuration and with the exact reference shadows, and writes into the bench's folder `images/reference.png`
//! and per result row `k` (in `results.csv` order) `images/k.png`, `images/k_difference.png` (the max-channel
//! difference ×[`DIFFERENCE_GAIN`] as a heat map, the Compare window's) and `images/k_flip.png` (FLIP's heat
//! map). The section shows the rows whose files are there.

use super::data::{IMAGES, Shadows, WORST_TEXELS, vz_file};
use super::page::{escape, section};
use crate::gpu::Gpu;
use crate::measure::MethodConfig;
use crate::settings::Settings;
use crate::transparency::FlipMap;
use crate::transparency::metrics::difference_image;
use anyhow::{Context, Result};
use image::RgbaImage;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// The gain of the difference maps.
pub const DIFFERENCE_GAIN: f32 = 8.0;

/// `settings`' scene rendered with `method` (frame 0).
fn render(gpu: &Gpu, settings: &Settings, method: &MethodConfig) -> Result<RgbaImage> {
    let mut s = settings.clone();
    s.method.name = method.name.clone();
    s.method.params = method.params.clone();
    let mut out = None;
    crate::animation::render_frames_on(gpu, &mut s, &[0], &mut |_| {}, &mut |_, image| {
        out = Some(image);
        Ok(())
    })?;
    out.context("no frame rendered")
}

fn save(image: &image::DynamicImage, path: &Path) -> Result<()> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .with_context(|| format!("{}: cannot encode", path.display()))?;
    crate::io::write_atomic(path, bytes.get_ref())
}

/// Renders the reference and each of `configs` (the bench's rows, in order) into `bench_dir/images`; stops
/// after the image in progress when `cancel` is set.
pub fn render_configs(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MethodConfig],
    bench_dir: &Path,
    cancel: &AtomicBool,
    log: &mut dyn FnMut(&str),
) -> Result<()> {
    let dir = bench_dir.join(IMAGES);
    std::fs::create_dir_all(&dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let reference_method =
        MethodConfig::new(crate::methods::registry::reference().name(), Default::default());
    log("  rendering the reference image");
    let reference = render(gpu, settings, &reference_method)?;
    save(&reference.clone().into(), &dir.join("reference.png"))?;
    for (k, c) in configs.iter().enumerate() {
        if cancel.load(Ordering::SeqCst) {
            break;
        }
        log(&format!("  rendering {}", c.label()));
        let image = render(gpu, settings, c)?;
        let difference = difference_image(&image, &reference, DIFFERENCE_GAIN);
        let flip = FlipMap::new(&image, &reference).heat_map();
        save(&difference.into(), &dir.join(format!("{k}_difference.png")))?;
        save(&flip.into(), &dir.join(format!("{k}_flip.png")))?;
        save(&image.into(), &dir.join(format!("{k}.png")))?;
    }
    Ok(())
}

/// The names of row `k`'s files, in the order shown.
fn row_files(k: usize) -> [String; 3] {
    [
        format!("{k}.png"),
        format!("{k}_difference.png"),
        format!("{k}_flip.png"),
    ]
}

/// The files of the images folder the report copies: the reference and every row's whose three are there.
pub fn files(s: &Shadows) -> Vec<String> {
    let dir = s.dir.join(IMAGES);
    if !dir.join("reference.png").is_file() {
        return Vec::new();
    }
    let mut out = vec!["reference.png".to_string()];
    for k in 0..s.results.rows.len() {
        let names = row_files(k);
        if names.iter().all(|n| dir.join(n).is_file()) {
            out.extend(names);
        }
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
        let cell = |name: &str| t.text(k, name).unwrap_or("");
        let _ = write!(
            content,
            "<article class=\"config\">\n<h3>{l}</h3>\n<p>map error {me}, FLIP {fl}, image RMSE {rm}; memory {mb} \
             bytes; {gp} geometry passes; GPU {ms} ms</p>\n<div class=\"grid\">\n",
            l = escape(label),
            me = escape(cell("map_error")),
            fl = escape(cell("flip")),
            rm = escape(cell("image_rmse")),
            mb = escape(cell("memory_bytes")),
            gp = escape(cell("geometry_passes")),
            ms = escape(cell("gpu_ms_median")),
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
                "reference".to_string(),
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
