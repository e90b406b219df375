//! `hairlab compare A.png B.png`: every image metric of `B` against the reference `A` (design.md, "Image
//! metrics": RMSE, PSNR, SSIM, the error distribution, contrast and FLIP), for any two PNGs of one size — a
//! technique's render, a user's own screenshots. `--mask` names the hair pixels (white), `--flip-map` writes
//! FLIP's per-pixel error as a magma heat map.

use crate::transparency::{FlipMap, ImageMetrics, compare};
use anyhow::Result;
use clap::Args;
use image::RgbaImage;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The reference image (PNG).
    #[arg(value_name = "A.png")]
    pub reference: PathBuf,
    /// The image compared with it (PNG, the same size).
    #[arg(value_name = "B.png")]
    pub image: PathBuf,
    /// Hair mask (PNG, the same size): white (luma above 127) marks the pixels of the `hair` figures;
    /// default: every pixel.
    #[arg(long, value_name = "M.png")]
    pub mask: Option<PathBuf>,
    /// Write FLIP's per-pixel error of B against A as a heat map (PNG, magma: black is no difference).
    #[arg(long, value_name = "OUT.png")]
    pub flip_map: Option<PathBuf>,
}

/// Why two images cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    #[error("{path}: cannot read: {source}")]
    Read { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a readable image: {source}")]
    Decode {
        path: PathBuf,
        source: image::ImageError,
    },
    #[error("{b}: {bw}x{bh} pixels, but {a} has {aw}x{ah}: images must be the same size")]
    Size {
        a: PathBuf,
        aw: u32,
        ah: u32,
        b: PathBuf,
        bw: u32,
        bh: u32,
    },
}

/// An image file as 8-bit RGBA.
pub fn read_image(path: &Path) -> Result<RgbaImage, CompareError> {
    let bytes = crate::io::read_regular_file(path).map_err(|source| CompareError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    image::load_from_memory(&bytes)
        .map(|i| i.to_rgba8())
        .map_err(|source| CompareError::Decode {
            path: path.to_path_buf(),
            source,
        })
}

/// `b` has `a`'s size, or the error naming both.
fn same_size(a: (&Path, &RgbaImage), b: (&Path, &RgbaImage)) -> Result<(), CompareError> {
    if a.1.dimensions() == b.1.dimensions() {
        return Ok(());
    }
    Err(CompareError::Size {
        a: a.0.to_path_buf(),
        aw: a.1.width(),
        ah: a.1.height(),
        b: b.0.to_path_buf(),
        bw: b.1.width(),
        bh: b.1.height(),
    })
}

/// Every figure `compare` prints, by name, in order.
pub fn named_metrics(m: &ImageMetrics) -> [(&'static str, f64); 17] {
    [
        ("rmse", m.rmse),
        ("psnr", m.psnr),
        ("rmse_hair", m.rmse_hair),
        ("psnr_hair", m.psnr_hair),
        ("ssim", m.ssim),
        ("ssim_hair", m.ssim_hair),
        ("max_error", m.max_error),
        ("p99", m.p99),
        ("share_over_1", m.share_over[0]),
        ("share_over_4", m.share_over[1]),
        ("share_over_8", m.share_over[2]),
        ("contrast_retention", m.contrast_retention),
        ("mean_luminance_ratio", m.mean_luminance_ratio),
        ("flip", m.flip.mean),
        ("flip_hair", m.flip.mean_hair),
        ("flip_p95_hair", m.flip.p95_hair),
        ("flip_p99_hair", m.flip.p99_hair),
    ]
}

pub(super) fn compare_images(a: &CompareArgs) -> Result<()> {
    if let Some(out) = &a.flip_map {
        crate::io::check_output(out, "png")?;
    }
    let reference = read_image(&a.reference)?;
    let image = read_image(&a.image)?;
    same_size((&a.reference, &reference), (&a.image, &image))?;
    let hair: Vec<bool> = match &a.mask {
        Some(path) => {
            let mask = read_image(path)?;
            same_size((&a.reference, &reference), (path, &mask))?;
            let gray = image::DynamicImage::ImageRgba8(mask).to_luma8();
            gray.pixels().map(|p| p.0[0] > 127).collect()
        }
        None => vec![true; (reference.width() * reference.height()) as usize],
    };
    let m = compare(&image, &reference, &hair);
    println!(
        "{} against {}: {}x{}, {} hair pixels ({})",
        a.image.display(),
        a.reference.display(),
        reference.width(),
        reference.height(),
        hair.iter().filter(|&&h| h).count(),
        a.mask
            .as_ref()
            .map_or("no --mask: every pixel".to_string(), |p| p.display().to_string())
    );
    for (name, value) in named_metrics(&m) {
        println!("{name:<22} {value:.6}");
    }
    if let Some(out) = &a.flip_map {
        crate::io::write_png(out, &FlipMap::new(&image, &reference).heat_map())?;
        println!("wrote {}", out.display());
    }
    Ok(())
}
