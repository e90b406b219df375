//! A progressive image's per-pixel sums: each pixel's samples summed in `f64` (an `f32` sum over tens of
//! thousands of samples keeps only the top few bits of each one it adds) and counted. A sample whose radiance is
//! NaN or infinite is left out of its pixel's sum and count and counted apart, so one bad path cannot spoil a
//! pixel for the rest of a progressive render. The mean divides each pixel's sum by its own count of samples
//! kept: a dropped sample is a failed evaluation, not a measured 0, so the mean stays the estimator's over the
//! paths that evaluated (counting it as 0 would darken the pixel by the share dropped). Rows go to rayon's
//! pool a few at a time, so the rows that cross the groom do not all fall to one thread; each pixel's samples
//! are summed in sample order, so the sums do not depend on the thread count.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Rows of pixels one task sums.
const ROWS_PER_TASK: usize = 2;

/// Per pixel (row after row), the sum of the finite samples and their count; and the samples left out.
#[derive(Clone, Debug)]
pub struct Sums {
    width: usize,
    sums: Vec<DVec3>,
    kept: Vec<u32>,
    dropped: u64,
}

impl Sums {
    /// No samples yet in a `width × height` image.
    pub fn new(width: usize, height: usize) -> Sums {
        Sums {
            width,
            sums: vec![DVec3::ZERO; width * height],
            kept: vec![0; width * height],
            dropped: 0,
        }
    }

    /// Adds `radiance(pixel, sample)` of every pixel (`y · width + x`) for each sample in `samples`, in order,
    /// on rayon's pool, [`ROWS_PER_TASK`] rows a task; a non-finite one is counted in [`Sums::dropped`] instead.
    pub fn add(&mut self, samples: std::ops::Range<u32>, radiance: impl Fn(usize, u32) -> Vec3 + Sync) {
        let band = ROWS_PER_TASK * self.width.max(1);
        let dropped: u64 = self
            .sums
            .par_chunks_mut(band)
            .zip(self.kept.par_chunks_mut(band))
            .enumerate()
            .map(|(b, (sums, kept))| {
                let mut left_out = 0;
                for (k, (sum, n)) in sums.iter_mut().zip(kept.iter_mut()).enumerate() {
                    for sample in samples.clone() {
                        let v = radiance(b * band + k, sample);
                        if v.is_finite() {
                            *sum += v.as_dvec3();
                            *n += 1;
                        } else {
                            left_out += 1;
                        }
                    }
                }
                left_out
            })
            .sum();
        self.dropped += dropped;
    }

    /// The mean of each pixel's samples kept (black where none were).
    pub fn mean(&self) -> Vec<Vec3> {
        self.sums
            .iter()
            .zip(&self.kept)
            .map(|(&sum, &n)| (sum / f64::from(n.max(1))).as_vec3())
            .collect()
    }

    /// The samples left out for a NaN or infinite radiance, over every pixel.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }
}

/// The line that says `dropped` samples were left out, or `None` when none were.
pub fn dropped_note(dropped: u64) -> Option<String> {
    (dropped > 0).then(|| {
        format!("warning: {dropped} path samples had a NaN or infinite radiance and were left out of their pixels' means")
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pixel's mean is over its finite samples only, each NaN or ±∞ sample counted once in `dropped`, and the
    /// sums are the same whether the samples come in one call or several.
    #[test]
    fn non_finite_samples_are_left_out_of_the_mean_and_counted() {
        // Pixel p, sample k: p + k, but NaN for k = 1 in pixel 0, +∞ for k = 2 in pixel 3 and −∞ for
        // k = 0 in pixel 5; pixel 6 gets only NaN.
        let radiance = |p: usize, k: u32| match (p, k) {
            (0, 1) => Vec3::new(1.0, f32::NAN, 0.0),
            (3, 2) => Vec3::splat(f32::INFINITY),
            (5, 0) => Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
            (6, _) => Vec3::splat(f32::NAN),
            _ => Vec3::splat((p as u32 + k) as f32),
        };
        let mut whole = Sums::new(4, 3);
        whole.add(0..4, radiance);
        let mut split = Sums::new(4, 3);
        split.add(0..1, radiance);
        split.add(1..4, radiance);
        assert_eq!(whole.mean(), split.mean());
        assert_eq!((whole.dropped(), split.dropped()), (7, 7));
        let mean = whole.mean();
        // Samples kept: pixel 0 → 0, 2, 3 (mean 5/3); pixel 3 → 3, 4, 6 (13/3); pixel 5 → 6, 7, 8 (7); pixel 6
        // none (black); any other pixel p → p, p + 1, p + 2, p + 3 (p + 1.5).
        let want = |p: usize| match p {
            0 => 5.0 / 3.0,
            3 => 13.0 / 3.0,
            5 => 7.0,
            6 => 0.0,
            _ => p as f32 + 1.5,
        };
        for (p, m) in mean.iter().enumerate() {
            assert!(
                (*m - Vec3::splat(want(p))).abs().max_element() <= 1e-6 * want(p),
                "pixel {p}: {m}"
            );
        }
    }

    /// Summed in `f64`: 65,536 samples of 1 + 2⁻¹¹ after one of 2¹⁴ (a firefly) give their mean to within an
    /// `f32` rounding of it, where an `f32` running sum (from 2¹⁴ up its spacing is 2⁻⁹ or more) rounds each 2⁻¹¹
    /// away: a mean 3.9 × 10⁻⁴ low.
    #[test]
    fn long_sums_keep_every_sample() {
        let (n, big, small) = (65_536u32, 16_384.0f32, 1.0 + 1.0 / 2048.0);
        let mut sums = Sums::new(1, 1);
        sums.add(0..n + 1, |_, k| Vec3::splat(if k == 0 { big } else { small }));
        let want = (f64::from(big) + f64::from(n) * f64::from(small)) / f64::from(n + 1);
        let got = f64::from(sums.mean()[0].x);
        assert!(
            (got - want).abs() <= want * f64::from(f32::EPSILON),
            "{got} for {want}"
        );
        let f32_sum = (0..n).fold(big, |s, _| s + small) / (n + 1) as f32;
        assert!(
            (f64::from(f32_sum) - want).abs() > 1e3 * want * f64::from(f32::EPSILON),
            "{f32_sum}"
        );
    }
}
