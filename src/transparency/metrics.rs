//! Image-error metrics of a technique's image against the exact transparency reference (spec A.7), over sRGB8
//! images (`image::RgbaImage`, alpha ignored), defined once for `measure`, `bench`, the claim tests and the
//! window.
//!
//! - **RMSE** over the RGB channels in `[0, 1]` (the 8-bit values / 255) and **PSNR** `= −20 log10(RMSE)` (∞
//!   for identical images), over all pixels ([`image_error`]) and over the hair mask only (background pixels
//!   are the same for every technique and dilute the all-pixel figure).
//! - **max_error**: the largest max-channel `|Δ|` of any pixel, in 1/255 steps. **p99**: the 99th percentile
//!   (nearest rank: the `ceil(0.99 n)`-th smallest) of the max-channel `|Δ|` over hair pixels, in 1/255 steps.
//!   **share_over**: the share of hair pixels whose max-channel `|Δ|` exceeds 1, 4 and 8 steps
//!   ([`SHARE_THRESHOLDS`]; 8/255 on at most 1 % of pixels is the project's snapshot tolerance).
//! - **SSIM** ([`ssim`]; Wang, Bovik, Sheikh & Simoncelli, IEEE TIP 13(4), 2004) on the luma
//!   `Y = 0.2126 R + 0.7152 G + 0.0722 B` of the sRGB-encoded values in `[0, 1]`, 11×11 Gaussian window of
//!   σ = 1.5 (normalised), `K1 = 0.01`, `K2 = 0.03`, `L = 1`, population (co)variances. Border: the mean is taken
//!   over the positions whose whole window lies inside the image, as Wang et al.'s reference code (`'valid'`
//!   filtering) and scikit-image (which crops 5 pixels) do; only where a region has no such position (an image
//!   or hair region within 5 pixels of the border) are its positions used with the window clipped to the image
//!   and renormalised. **ssim_hair**: the mean SSIM over the positions inside the hair mask's bounding box, by
//!   the same rule (the windows may reach outside the box, never outside the image).
//! - **contrast_retention** κ: standard deviation of the linear luminance (sRGB decoded, same weights) over the
//!   hair pixels, image over reference — below 1 is "dull" (TC-3); **mean_luminance_ratio**: the mean linear
//!   luminance over the hair pixels, image over reference. Both are 1 where both are 0, ∞ where only the
//!   reference's is 0.
//! - **FLIP** ([`super::flip`]; Andersson et al., HPG 2020): the mean over all pixels and over the hair pixels, and
//!   the 95th and 99th percentiles over the hair pixels.
//!
//! The hair mask is row-major over the image's width and height; an empty mask gives the identity values
//! (RMSE 0, PSNR ∞, SSIM 1, p99, shares and hair FLIP 0, ratios 1). Images of different sizes are compared over their
//! common top-left rectangle, and mask entries beyond the mask's length count as background.

use super::flip::{FlipMap, FlipMetrics};
use image::RgbaImage;

/// Max-channel error thresholds, in 1/255 steps, of [`ImageMetrics::share_over`].
pub const SHARE_THRESHOLDS: [u8; 3] = [1, 4, 8];
/// SSIM window radius: 11×11.
pub const SSIM_RADIUS: usize = 5;
/// SSIM window standard deviation.
pub const SSIM_SIGMA: f64 = 1.5;
/// SSIM stabilising constants `(K1 L)²` and `(K2 L)²` with `L = 1`.
const C1: f64 = 0.01 * 0.01;
const C2: f64 = 0.03 * 0.03;

/// A technique's image against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageMetrics {
    pub rmse: f64,
    pub psnr: f64,
    pub rmse_hair: f64,
    pub psnr_hair: f64,
    pub ssim: f64,
    pub ssim_hair: f64,
    /// Largest max-channel error of any pixel, in 1/255 steps.
    pub max_error: f64,
    /// 99th percentile of the hair pixels' max-channel error, in 1/255 steps.
    pub p99: f64,
    /// Share of hair pixels whose max-channel error exceeds each of [`SHARE_THRESHOLDS`].
    pub share_over: [f64; 3],
    /// σ of linear luminance over the hair pixels, image over reference.
    pub contrast_retention: f64,
    /// Mean linear luminance over the hair pixels, image over reference.
    pub mean_luminance_ratio: f64,
    /// FLIP over all pixels and over the hair pixels.
    pub flip: FlipMetrics,
}

/// The common size of two images.
fn common_size(a: &RgbaImage, b: &RgbaImage) -> (u32, u32) {
    (a.width().min(b.width()), a.height().min(b.height()))
}

/// `(RMSE, PSNR)` from a sum of squared channel errors over `channels` channels.
fn rmse_psnr(squared: f64, channels: usize) -> (f64, f64) {
    if channels == 0 {
        return (0.0, f64::INFINITY);
    }
    let rmse = (squared / channels as f64).sqrt();
    let psnr = if rmse > 0.0 {
        -20.0 * rmse.log10()
    } else {
        f64::INFINITY
    };
    (rmse, psnr)
}

/// Sum of the squared RGB errors in `[0, 1]` of one pixel.
fn squared_error(p: &image::Rgba<u8>, q: &image::Rgba<u8>) -> f64 {
    (0..3)
        .map(|i| {
            let d = (f64::from(p.0[i]) - f64::from(q.0[i])) / 255.0;
            d * d
        })
        .sum()
}

/// RMSE over RGB in [0,1] and PSNR in dB (infinite for identical images), over all pixels.
pub fn image_error(a: &RgbaImage, b: &RgbaImage) -> (f64, f64) {
    let (w, h) = common_size(a, b);
    let mut squared = 0.0;
    for y in 0..h {
        for x in 0..w {
            squared += squared_error(a.get_pixel(x, y), b.get_pixel(x, y));
        }
    }
    rmse_psnr(squared, (w * h * 3) as usize)
}

/// The sRGB decoding of an 8-bit value to linear `[0, 1]` (IEC 61966-2-1).
pub fn srgb_to_linear(v: u8) -> f64 {
    let c = f64::from(v) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Rec. 709 luminance weights.
fn luminance(r: f64, g: f64, b: f64) -> f64 {
    0.2126 * r + 0.7152 * g + 0.0722 * b
}

/// Luma of the sRGB-encoded values in `[0, 1]` (what SSIM compares).
fn luma(p: &image::Rgba<u8>) -> f64 {
    luminance(f64::from(p.0[0]), f64::from(p.0[1]), f64::from(p.0[2])) / 255.0
}

/// Linear luminance of a pixel.
fn linear_luminance(p: &image::Rgba<u8>) -> f64 {
    luminance(
        srgb_to_linear(p.0[0]),
        srgb_to_linear(p.0[1]),
        srgb_to_linear(p.0[2]),
    )
}

/// `a / b`, 1 where both are 0, ∞ where only `b` is.
fn ratio(a: f64, b: f64) -> f64 {
    if b != 0.0 {
        a / b
    } else if a == 0.0 {
        1.0
    } else {
        f64::INFINITY
    }
}

/// Mean and population standard deviation.
fn mean_sigma(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// Every metric of `image` against `reference` (see the module docs); `hair` is the row-major hair mask.
pub fn compare(image: &RgbaImage, reference: &RgbaImage, hair: &[bool]) -> ImageMetrics {
    let (w, h) = common_size(image, reference);
    let is_hair = |x: u32, y: u32| {
        hair.get(y as usize * image.width() as usize + x as usize)
            .copied()
            .unwrap_or(false)
    };
    let (mut squared, mut squared_hair) = (0.0, 0.0);
    let mut max_error = 0u8;
    let mut hair_errors: Vec<u8> = Vec::new();
    let (mut lum_image, mut lum_reference) = (Vec::new(), Vec::new());
    let mut bbox: Option<[u32; 4]> = None;
    for y in 0..h {
        for x in 0..w {
            let (p, q) = (image.get_pixel(x, y), reference.get_pixel(x, y));
            let se = squared_error(p, q);
            let e = (0..3).map(|i| p.0[i].abs_diff(q.0[i])).max().unwrap_or(0);
            squared += se;
            max_error = max_error.max(e);
            if is_hair(x, y) {
                squared_hair += se;
                hair_errors.push(e);
                lum_image.push(linear_luminance(p));
                lum_reference.push(linear_luminance(q));
                bbox = Some(bbox.map_or([x, y, x, y], |[x0, y0, x1, y1]| {
                    [x0.min(x), y0.min(y), x1.max(x), y1.max(y)]
                }));
            }
        }
    }
    let (rmse, psnr) = rmse_psnr(squared, (w * h * 3) as usize);
    let (rmse_hair, psnr_hair) = rmse_psnr(squared_hair, hair_errors.len() * 3);
    let map = SsimMap::new(image, reference);
    let ssim = map.mean([0, 0, w.saturating_sub(1), h.saturating_sub(1)]);
    let ssim_hair = bbox.map_or(1.0, |b| map.mean(b));
    let n = hair_errors.len();
    hair_errors.sort_unstable();
    let p99 = if n == 0 {
        0.0
    } else {
        f64::from(hair_errors[((0.99 * n as f64).ceil() as usize).clamp(1, n) - 1])
    };
    let share_over = SHARE_THRESHOLDS.map(|t| {
        if n == 0 {
            0.0
        } else {
            hair_errors.iter().filter(|&&e| e > t).count() as f64 / n as f64
        }
    });
    let (contrast_retention, mean_luminance_ratio) = if n == 0 {
        (1.0, 1.0)
    } else {
        let (mi, si) = mean_sigma(&lum_image);
        let (mr, sr) = mean_sigma(&lum_reference);
        (ratio(si, sr), ratio(mi, mr))
    };
    ImageMetrics {
        rmse,
        psnr,
        rmse_hair,
        psnr_hair,
        ssim,
        ssim_hair,
        max_error: f64::from(max_error),
        p99,
        share_over,
        contrast_retention,
        mean_luminance_ratio,
        flip: FlipMap::new(image, reference).metrics(is_hair),
    }
}

/// Mean SSIM of two images over all positions whose window fits in the image (see the module docs).
pub fn ssim(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let (w, h) = common_size(a, b);
    SsimMap::new(a, b).mean([0, 0, w.saturating_sub(1), h.saturating_sub(1)])
}

/// The normalised 1-D Gaussian of the SSIM window, offsets `−SSIM_RADIUS..=SSIM_RADIUS`.
fn gaussian() -> [f64; 2 * SSIM_RADIUS + 1] {
    let g: [f64; 2 * SSIM_RADIUS + 1] = std::array::from_fn(|i| {
        let d = i as f64 - SSIM_RADIUS as f64;
        (-d * d / (2.0 * SSIM_SIGMA * SSIM_SIGMA)).exp()
    });
    let sum: f64 = g.iter().sum();
    g.map(|v| v / sum)
}

/// Filters `n` values along one axis with the Gaussian clipped to `0..n` and renormalised (separable: the
/// product of two clipped 1-D windows is the clipped 2-D window, renormalised).
fn filter_line(line: &[f64], g: &[f64; 2 * SSIM_RADIUS + 1]) -> Vec<f64> {
    let n = line.len() as isize;
    let r = SSIM_RADIUS as isize;
    (0..n)
        .map(|i| {
            let (mut sum, mut weight) = (0.0, 0.0);
            for k in -r..=r {
                let j = i + k;
                if (0..n).contains(&j) {
                    let gk = g[(k + r) as usize];
                    sum += gk * line[j as usize];
                    weight += gk;
                }
            }
            sum / weight
        })
        .collect()
}

/// The Gaussian-windowed mean of a `w`×`h` field at every position.
fn filter(field: &[f64], w: usize, h: usize) -> Vec<f64> {
    let g = gaussian();
    let mut rows = Vec::with_capacity(w * h);
    for y in 0..h {
        rows.extend(filter_line(&field[y * w..(y + 1) * w], &g));
    }
    let mut out = vec![0.0; w * h];
    for x in 0..w {
        let column: Vec<f64> = (0..h).map(|y| rows[y * w + x]).collect();
        for (y, v) in filter_line(&column, &g).into_iter().enumerate() {
            out[y * w + x] = v;
        }
    }
    out
}

/// The SSIM value at every position of the images' common rectangle.
struct SsimMap {
    w: usize,
    h: usize,
    values: Vec<f64>,
}

impl SsimMap {
    fn new(a: &RgbaImage, b: &RgbaImage) -> SsimMap {
        let (w, h) = common_size(a, b);
        let (w, h) = (w as usize, h as usize);
        let field = |img: &RgbaImage| -> Vec<f64> {
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| luma(img.get_pixel(x as u32, y as u32)))
                .collect()
        };
        let (x, y) = (field(a), field(b));
        let product = |p: &[f64], q: &[f64]| -> Vec<f64> { p.iter().zip(q).map(|(p, q)| p * q).collect() };
        let (mx, my) = (filter(&x, w, h), filter(&y, w, h));
        let (mxx, myy, mxy) = (
            filter(&product(&x, &x), w, h),
            filter(&product(&y, &y), w, h),
            filter(&product(&x, &y), w, h),
        );
        let values = (0..w * h)
            .map(|i| {
                let (ux, uy) = (mx[i], my[i]);
                let vx = mxx[i] - ux * ux;
                let vy = myy[i] - uy * uy;
                let vxy = mxy[i] - ux * uy;
                ((2.0 * ux * uy + C1) * (2.0 * vxy + C2)) / ((ux * ux + uy * uy + C1) * (vx + vy + C2))
            })
            .collect();
        SsimMap { w, h, values }
    }

    /// The mean over the positions of the inclusive box `[x0, y0, x1, y1]` whose window fits in the image, or
    /// over all its positions when none does. 1 for an empty image.
    fn mean(&self, [x0, y0, x1, y1]: [u32; 4]) -> f64 {
        if self.w == 0 || self.h == 0 {
            return 1.0;
        }
        let (x0, y0) = (x0 as usize, y0 as usize);
        let (x1, y1) = ((x1 as usize).min(self.w - 1), (y1 as usize).min(self.h - 1));
        let r = SSIM_RADIUS;
        let fits = |x: usize, y: usize| x >= r && y >= r && x + r < self.w && y + r < self.h;
        let positions = || (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| (x, y)));
        let inner: Vec<f64> = positions()
            .filter(|&(x, y)| fits(x, y))
            .map(|(x, y)| self.values[y * self.w + x])
            .collect();
        let chosen = if inner.is_empty() {
            positions().map(|(x, y)| self.values[y * self.w + x]).collect()
        } else {
            inner
        };
        chosen.iter().sum::<f64>() / chosen.len() as f64
    }
}

/// A colour ramp for `t` in [0, 1]: black, purple, red, yellow, white.
pub fn heat(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [0.35, 0.0, 0.55],
        [0.9, 0.1, 0.1],
        [1.0, 0.85, 0.0],
        [1.0, 1.0, 1.0],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    std::array::from_fn(|c| ((STOPS[i][c] + f * (STOPS[i + 1][c] - STOPS[i][c])) * 255.0).round() as u8)
}

/// The heat map of the max-channel `|a − b|` (1/255 steps) times `gain`, over 255.
pub fn difference_image(a: &RgbaImage, b: &RgbaImage, gain: f32) -> RgbaImage {
    let (w, h) = (a.width().min(b.width()), a.height().min(b.height()));
    RgbaImage::from_fn(w, h, |x, y| {
        let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
        let e = (0..3).map(|i| p.0[i].abs_diff(q.0[i])).max().unwrap_or(0);
        let [r, g, b] = heat(f32::from(e) * gain / 255.0);
        image::Rgba([r, g, b, 255])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    fn solid(w: u32, h: u32, v: [u8; 3]) -> RgbaImage {
        RgbaImage::from_pixel(w, h, Rgba([v[0], v[1], v[2], 255]))
    }

    /// The frozen pattern pair (reproduced in the test docs' Python).
    fn pattern_pair() -> (RgbaImage, RgbaImage) {
        let (w, h) = (24u32, 20u32);
        let a = RgbaImage::from_fn(w, h, |x, y| {
            Rgba([
                ((x * 37 + y * 11) % 256) as u8,
                ((x * x + 3 * y) % 256) as u8,
                ((200 + 7 * y + 256 - 5 * x) % 256) as u8,
                255,
            ])
        });
        let b = RgbaImage::from_fn(w, h, |x, y| {
            let p = a.get_pixel(x, y).0;
            let c = |i: u32| {
                let offset = ((x * 13 + y * 29 + i * 5) % 41) as i32 - 20;
                (i32::from(p[i as usize]) + offset).clamp(0, 255) as u8
            };
            Rgba([c(0), c(1), c(2), 255])
        });
        (a, b)
    }

    #[test]
    fn identical_images() {
        let (a, _) = pattern_pair();
        let hair: Vec<bool> = (0..a.width() * a.height()).map(|i| i % 3 == 0).collect();
        let m = compare(&a, &a, &hair);
        assert_eq!((m.rmse, m.rmse_hair), (0.0, 0.0));
        assert_eq!((m.psnr, m.psnr_hair), (f64::INFINITY, f64::INFINITY));
        assert!(
            (m.ssim - 1.0).abs() < 1e-12 && (m.ssim_hair - 1.0).abs() < 1e-12,
            "{m:?}"
        );
        assert_eq!((m.max_error, m.p99, m.share_over), (0.0, 0.0, [0.0; 3]));
        assert_eq!((m.contrast_retention, m.mean_luminance_ratio), (1.0, 1.0));
        assert_eq!(m.flip, FlipMetrics::default());
    }

    #[test]
    fn hand_computed_errors() {
        // 2×2, reference black; image (10,0,0), (0,0,0), (0,2,0), (255,255,255); hair = the first three.
        let reference = solid(2, 2, [0, 0, 0]);
        let mut image = reference.clone();
        image.put_pixel(0, 0, Rgba([10, 0, 0, 255]));
        image.put_pixel(0, 1, Rgba([0, 2, 0, 255]));
        image.put_pixel(1, 1, Rgba([255, 255, 255, 255]));
        let hair = [true, true, true, false];
        let m = compare(&image, &reference, &hair);
        // All: (10² + 2² + 3 · 255²) / 255² over 12 channels.
        let rmse = ((100.0 + 4.0 + 3.0 * 65025.0) / 12.0f64).sqrt() / 255.0;
        assert!((m.rmse - rmse).abs() < 1e-12);
        assert!((m.psnr + 20.0 * rmse.log10()).abs() < 1e-9);
        // Hair: (10² + 2²) / 255² over 9 channels.
        let rmse_hair = (104.0 / 9.0f64).sqrt() / 255.0;
        assert!((m.rmse_hair - rmse_hair).abs() < 1e-12);
        assert_eq!(m.max_error, 255.0);
        // Hair max-channel errors 10, 0, 2: p99 = the 3rd of 3; above 1: 2 of 3, above 4 and 8: 1 of 3.
        assert_eq!(m.p99, 10.0);
        assert_eq!(m.share_over, [2.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0]);
        assert_eq!(image_error(&image, &reference), (m.rmse, m.psnr));
    }

    #[test]
    fn hand_computed_contrast() {
        // Reference hair: black and white (linear luminance 0 and 1: σ 0.5, mean 0.5). Image hair: black and
        // sRGB 188, linear ((188/255 + 0.055) / 1.055)^2.4 = 0.502886: σ = 0.251443, mean = 0.251443.
        let mut reference = solid(2, 1, [0, 0, 0]);
        reference.put_pixel(1, 0, Rgba([255, 255, 255, 255]));
        let mut image = solid(2, 1, [0, 0, 0]);
        image.put_pixel(1, 0, Rgba([188, 188, 188, 255]));
        let grey = ((188.0 / 255.0 + 0.055) / 1.055f64).powf(2.4);
        assert!((grey - 0.502_886).abs() < 1e-6);
        let m = compare(&image, &reference, &[true, true]);
        assert!((m.contrast_retention - grey).abs() < 1e-12, "{m:?}");
        assert!((m.mean_luminance_ratio - grey).abs() < 1e-12, "{m:?}");
        // Against a flat reference: ∞ contrast ratio; flat against flat: 1.
        let flat = solid(2, 1, [0, 0, 0]);
        assert_eq!(
            compare(&image, &flat, &[true, true]).contrast_retention,
            f64::INFINITY
        );
        assert_eq!(compare(&flat, &flat, &[true, true]).contrast_retention, 1.0);
        // No hair: identity values.
        let none = compare(&image, &reference, &[false, false]);
        assert_eq!((none.rmse_hair, none.p99, none.ssim_hair), (0.0, 0.0, 1.0));
        assert_eq!(none.contrast_retention, 1.0);
    }

    #[test]
    fn constant_images_ssim_by_hand() {
        // Constant grey 100 against 110 (the luma weights sum to 1): σ = 0, so SSIM = (2pq + C1)/(p² + q² + C1)
        // with p = 100/255, q = 110/255, everywhere.
        let (a, b) = (solid(16, 16, [100; 3]), solid(16, 16, [110; 3]));
        let (p, q) = (100.0 / 255.0, 110.0 / 255.0);
        let expected = (2.0 * p * q + 1e-4) / (p * p + q * q + 1e-4);
        assert!((ssim(&a, &b) - expected).abs() < 1e-12);
        assert!((expected - 0.995_476).abs() < 1e-6, "{expected}");
        // Small images (no window fits) use clipped windows: still the constant value.
        let (a, b) = (solid(4, 3, [100; 3]), solid(4, 3, [110; 3]));
        assert!((ssim(&a, &b) - expected).abs() < 1e-12);
    }

    #[test]
    fn ssim_matches_scikit_image_on_a_pattern_pair() {
        // Frozen with scikit-image 0.26.0 (`pip install scikit-image`), on the luma of `pattern_pair` rebuilt
        // in numpy with the same integer formulas and computed in float64 as
        // (0.2126 R + 0.7152 G + 0.0722 B) / 255:
        // skimage.metrics.structural_similarity(ya, yb, gaussian_weights=True, sigma=1.5,
        //     use_sample_covariance=False, data_range=1) = 0.946361529130138
        let (a, b) = pattern_pair();
        let value = ssim(&a, &b);
        assert!((value - SKIMAGE_PATTERN_SSIM).abs() < 1e-9, "{value}");
    }

    const SKIMAGE_PATTERN_SSIM: f64 = 0.946_361_529_130_138;

    #[test]
    fn ssim_matches_scikit_image_on_the_fixture_pairs() {
        // `python tests/fixtures/flip/reference.py` (scikit-image 0.26.0): structural_similarity(luma(a), luma(b),
        // gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=1.0) on the float64 luma of
        // `tests/fixtures/flip/<name>_a.png` and `<name>_b.png`.
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/flip");
        for (name, expected) in [
            ("pattern", 0.958_947_998_834_157),
            ("strands", -0.221_951_821_230_348_35),
            ("noise", 0.447_599_741_073_244_35),
        ] {
            let load = |s: &str| {
                let path = dir.join(format!("{name}_{s}.png"));
                image::open(&path)
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
                    .to_rgba8()
            };
            let value = ssim(&load("a"), &load("b"));
            assert!((value - expected).abs() < 1e-9, "{name}: {value}");
        }
    }

    #[test]
    fn hair_ssim_ignores_differences_far_from_the_hair() {
        // Hair in a 6×6 box at (20..26, 20..26) of a 48×48 pattern; the images differ only at x < 8, more than
        // a window radius away from the box.
        let (a, _) = pattern_pair();
        let big = RgbaImage::from_fn(48, 48, |x, y| *a.get_pixel(x % 24, y % 20));
        let mut other = big.clone();
        for y in 0..48 {
            for x in 0..8 {
                other.put_pixel(x, y, Rgba([0, 0, 0, 255]));
            }
        }
        let hair: Vec<bool> = (0..48 * 48)
            .map(|i| (20..26).contains(&(i % 48)) && (20..26).contains(&(i / 48)))
            .collect();
        let m = compare(&other, &big, &hair);
        assert!((m.ssim_hair - 1.0).abs() < 1e-12, "{m:?}");
        assert!(m.ssim < 0.95, "{m:?}");
        assert_eq!(m.rmse_hair, 0.0);
        assert!(m.rmse > 0.0);
    }
}
