//! FLIP, the perceptual difference of two images (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström &
//! Fairchild, "FLIP: A Difference Evaluator for Alternating Images", HPG 2020), beside RMSE, PSNR and SSIM
//! ([`super::metrics`]), defined once for `compare`, `measure`, `bench` and the window.
//!
//! The per-pixel error in `[0, 1]` is LDR-FLIP as NVIDIA's reference C++ computes it (through the `nv-flip`
//! crate): both 8-bit sRGB images (alpha ignored) go to the linearised YCxCz opponent space, are filtered by
//! contrast sensitivity functions for [`PIXELS_PER_DEGREE`] (a 0.7 m viewing distance of a 0.7 m wide 3840-pixel
//! monitor), and their colour difference in Hunt-adjusted L*a*b* (HyAB distance, compressed) is raised by the
//! difference of their edge and point features: `ΔE = ΔE_c^(1 - ΔE_f)`.
//!
//! Pooled over a map ([`FlipMetrics`]): **flip** the mean over all pixels, **flip_hair** the mean over the hair
//! pixels, **flip_p95_hair** and **flip_p99_hair** the 95th and 99th percentiles over the hair pixels by nearest
//! rank (the `ceil(p/100 · n)`-th smallest of the `n` values, clamped to `1 … n`). An empty image or hair mask
//! gives 0. Images of different sizes are compared over their common top-left rectangle.

use image::{RgbImage, RgbaImage};

/// Pixels per degree of visual angle the error is computed for (FLIP's default observer).
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// FLIP pooled over a map (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FlipMetrics {
    /// Mean over all pixels.
    pub mean: f64,
    /// Mean over the hair pixels.
    pub mean_hair: f64,
    /// 95th percentile over the hair pixels (nearest rank).
    pub p95_hair: f64,
    /// 99th percentile over the hair pixels (nearest rank).
    pub p99_hair: f64,
}

/// The FLIP error of every pixel of the images' common rectangle, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct FlipMap {
    pub width: u32,
    pub height: u32,
    pub values: Vec<f32>,
}

/// The RGB bytes of an image's `w`×`h` top-left rectangle.
fn rgb_bytes(img: &RgbaImage, w: u32, h: u32) -> Vec<u8> {
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .flat_map(|(x, y)| {
            let p = img.get_pixel(x, y).0;
            [p[0], p[1], p[2]]
        })
        .collect()
}

/// The `ceil(p/100 · n)`-th smallest of sorted values (clamped to `1 … n`); 0 when there are none.
fn nearest_rank(sorted: &[f32], p: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return 0.0;
    }
    f64::from(sorted[((p / 100.0 * n as f64).ceil() as usize).clamp(1, n) - 1])
}

impl FlipMap {
    /// The FLIP error of `test` against `reference`.
    pub fn new(test: &RgbaImage, reference: &RgbaImage) -> FlipMap {
        let (w, h) = (
            test.width().min(reference.width()),
            test.height().min(reference.height()),
        );
        if w == 0 || h == 0 {
            return FlipMap {
                width: w,
                height: h,
                values: Vec::new(),
            };
        }
        let image = |img: &RgbaImage| nv_flip::FlipImageRgb8::with_data(w, h, &rgb_bytes(img, w, h));
        let error = nv_flip::flip(image(reference), image(test), PIXELS_PER_DEGREE);
        FlipMap {
            width: w,
            height: h,
            values: error.to_vec(),
        }
    }

    /// The pooled values; `is_hair(x, y)` says which pixels are hair.
    pub fn metrics(&self, is_hair: impl Fn(u32, u32) -> bool) -> FlipMetrics {
        let w = self.width.max(1) as usize;
        let mut hair: Vec<f32> = self
            .values
            .iter()
            .enumerate()
            .filter(|(i, _)| is_hair((i % w) as u32, (i / w) as u32))
            .map(|(_, v)| *v)
            .collect();
        let mean = |v: &[f32]| {
            if v.is_empty() {
                0.0
            } else {
                v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64
            }
        };
        let mean_hair = mean(&hair);
        hair.sort_by(f32::total_cmp);
        FlipMetrics {
            mean: mean(&self.values),
            mean_hair,
            p95_hair: nearest_rank(&hair, 95.0),
            p99_hair: nearest_rank(&hair, 99.0),
        }
    }

    /// The map through FLIP's magma colour map (black: no difference, light yellow: the largest).
    pub fn heat_map(&self) -> RgbImage {
        if self.values.is_empty() {
            return RgbImage::new(self.width, self.height);
        }
        let map = nv_flip::FlipImageFloat::with_data(self.width, self.height, &self.values);
        let rgb = map.apply_color_lut(&nv_flip::magma_lut()).to_vec();
        RgbImage::from_raw(self.width, self.height, rgb)
            .unwrap_or_else(|| RgbImage::new(self.width, self.height))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    #[test]
    fn identical_images_have_no_error() {
        let a = RgbaImage::from_fn(20, 12, |x, y| Rgba([(x * 12) as u8, (y * 20) as u8, 90, 255]));
        let map = FlipMap::new(&a, &a);
        assert_eq!((map.width, map.height, map.values.len()), (20, 12, 240));
        assert!(map.values.iter().all(|&v| v == 0.0), "{:?}", map.values);
        assert_eq!(map.metrics(|_, _| true), FlipMetrics::default());
    }

    #[test]
    fn black_against_white_matches_the_reference() {
        // Flat white against flat black: 0.96738833 at every pixel, by flip-evaluator 1.7:
        // python -c "import numpy as np, flip_evaluator as f; m, mean, _ = f.evaluate(np.ones((16, 16, 3)),
        //     np.zeros((16, 16, 3)), 'LDR', applyMagma=False); print(np.min(m), np.max(m), mean)"
        let black = RgbaImage::from_pixel(16, 16, Rgba([0, 0, 0, 255]));
        let white = RgbaImage::from_pixel(16, 16, Rgba([255, 255, 255, 255]));
        let map = FlipMap::new(&black, &white);
        assert!(
            map.values.iter().all(|&v| (v - 0.967_388_33).abs() < 1e-3),
            "{:?}",
            map.values
        );
        let m = map.metrics(|_, _| true);
        assert!((m.mean - 0.967_390_95).abs() < 1e-3, "{m:?}");
    }

    #[test]
    fn hand_pooled_percentiles_and_empty_masks() {
        // A hand-made map: values 0.00, 0.01, …, 0.99 over 10×10; hair = the left half (x < 5).
        let map = FlipMap {
            width: 10,
            height: 10,
            values: (0..100).map(|i| i as f32 / 100.0).collect(),
        };
        let m = map.metrics(|x, _| x < 5);
        // Hair: rows y = 0..10, columns 0..5: i = 10 y + x, mean = (45 + 2) / 100 = 0.47 over 50 values.
        assert!((m.mean - 0.495).abs() < 1e-6, "{m:?}");
        assert!((m.mean_hair - 0.47).abs() < 1e-6, "{m:?}");
        // Sorted hair values: 0.00..0.04, 0.10..0.14, …, 0.90..0.94; the 48th (ceil 47.5) is 0.92, the 50th 0.94.
        assert_eq!((m.p95_hair as f32, m.p99_hair as f32), (0.92, 0.94));
        let none = map.metrics(|_, _| false);
        assert_eq!((none.mean_hair, none.p95_hair, none.p99_hair), (0.0, 0.0, 0.0));
        let empty = FlipMap::new(&RgbaImage::new(0, 4), &RgbaImage::new(3, 4));
        assert_eq!(empty.metrics(|_, _| true), FlipMetrics::default());
        assert_eq!(empty.heat_map().dimensions(), (0, 4));
    }

    #[test]
    fn heat_map_is_magma() {
        let a = RgbaImage::from_pixel(8, 8, Rgba([40, 80, 120, 255]));
        let magma = nv_flip::magma_lut().to_vec();
        // No difference: magma's first entry everywhere.
        let same = FlipMap::new(&a, &a).heat_map();
        assert!(
            same.pixels().all(|p| p.0 == magma[0..3]),
            "{:?}",
            same.get_pixel(0, 0)
        );
        // One changed pixel: it is the largest error and the brightest pixel.
        let mut b = a.clone();
        b.put_pixel(4, 4, Rgba([255, 255, 255, 255]));
        let map = FlipMap::new(&b, &a);
        let heat = map.heat_map();
        assert_eq!(heat.dimensions(), (8, 8));
        let largest = map.values.iter().copied().fold(0.0f32, f32::max);
        assert_eq!(map.values[4 * 8 + 4], largest);
        let sum = |p: &image::Rgb<u8>| p.0.iter().map(|&c| u32::from(c)).sum::<u32>();
        let brightest = heat.pixels().map(sum).max().unwrap_or(0);
        assert_eq!(sum(heat.get_pixel(4, 4)), brightest);
    }

    /// A fixture pair `tests/fixtures/flip/<name>_a.png` (reference) and `<name>_b.png` (test).
    fn fixture(name: &str) -> (RgbaImage, RgbaImage) {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/flip");
        let load = |s: &str| image::open(dir.join(format!("{name}_{s}.png"))).map(|i| i.to_rgba8());
        match (load("a"), load("b")) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => panic!("fixture {name}: {:?} {:?}", a.err(), b.err()),
        }
    }

    /// `tests/fixtures/flip/strands_mask.png`: white = hair.
    fn strands_mask() -> image::GrayImage {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/flip/strands_mask.png");
        image::open(&path)
            .map(|i| i.to_luma8())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    // NVIDIA's FLIP on the fixture pairs: `python tests/fixtures/flip/reference.py` (flip-evaluator 1.7), which
    // prints the evaluator's mean and the nearest-rank p95 / p99 of its map; (mean, p95, p99) over all pixels.
    const REFERENCE_FLIP: [(&str, [f64; 3]); 3] = [
        ("pattern", [0.083_347_350, 0.143_800_51, 0.195_917_17]),
        ("strands", [0.187_431_14, 0.274_549_48, 0.505_492_99]),
        ("noise", [0.488_858_49, 0.841_985_11, 0.962_512_31]),
    ];

    #[test]
    fn flip_matches_nvidia_flip_on_the_fixture_pairs() {
        for (name, [mean, p95, p99]) in REFERENCE_FLIP {
            let (reference, test) = fixture(name);
            let m = FlipMap::new(&test, &reference).metrics(|_, _| true);
            assert!((m.mean - mean).abs() < 1e-3, "{name}: {m:?}");
            assert!((m.mean_hair - mean).abs() < 1e-3, "{name}: {m:?}");
            assert!((m.p95_hair - p95).abs() < 1e-3, "{name}: {m:?}");
            assert!((m.p99_hair - p99).abs() < 1e-3, "{name}: {m:?}");
        }
    }

    #[test]
    fn hair_pooling_matches_nvidia_flip_on_the_strand_mask() {
        // `reference.py`'s "strands hair (303 pixels)" line: mean, p95, p99 over the mask's white pixels.
        let (reference, test) = fixture("strands");
        let mask = strands_mask();
        let m = FlipMap::new(&test, &reference).metrics(|x, y| mask.get_pixel(x, y).0[0] > 127);
        assert_eq!(mask.pixels().filter(|p| p.0[0] > 127).count(), 303);
        assert!((m.mean_hair - 0.203_148_66).abs() < 1e-3, "{m:?}");
        assert!((m.p95_hair - 0.274_549_48).abs() < 1e-3, "{m:?}");
        assert!((m.p99_hair - 0.597_611_90).abs() < 1e-3, "{m:?}");
    }
}
