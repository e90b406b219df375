//! CPU models of every eye transparency technique, and the image metrics they are judged by (spec A.5, A.7).
//!
//! A model is the specification its GPU technique must match pixel for pixel (within about 1e-5 per channel):
//! it composites one pixel's [`EyeFragment`]s over the opaque image's linear colour `B` at that pixel. Models
//! compute in f32, with the GPU's expressions in the GPU's order; sums the GPU forms by unordered blending or
//! atomics are summed here in the order the fragments are given (so a GPU = CPU test feeds them in any order
//! and allows for f32 rounding only). A model whose result depends on order sorts by the total key itself.
//!
//! # Shared conventions
//! - The **total key** of a fragment is `(depth.to_bits(), segment)` ascending = front to back (spec A.4):
//!   depths are `>= 0`, where the bit order of an f32 is its numeric order, and exact depth ties are kept
//!   apart by the segment id, as the GPU's lists sort them. [`front_to_back`] sorts by it, [`ranks`] numbers it.
//! - The **exact composite** (the reference, [`exact`]) is `C = Σ a_j c_j Π_{k before j}(1 - a_k) + B Π(1 - a_k)`.
//! - Inputs are what the GPU produces: finite depths `>= 0`, alphas in `[0, 1]`, finite colours. The models do
//!   not police them (the `composite` command refuses anything else before it reaches a model).
//! - f16 render targets are modelled by [`round_f16`] after every blend (round to nearest, ties to even, the
//!   conversion of IEEE 754 binary16 render targets, by the `half` crate).

pub mod classic_peel;
pub mod exact;
pub mod flip;
pub mod mboit;
pub mod metrics;
pub mod occupancy_order;
pub mod opaque;
pub mod shortcut;
pub mod wboit;
pub mod weighted_average;

pub use classic_peel::ClassicPeelParams;
pub use exact::ExactParams;
pub use flip::{FlipMap, FlipMetrics};
pub use mboit::{Mboit, MboitParams};
pub use metrics::{ImageMetrics, compare, ssim};
pub use occupancy_order::{OccupancyOrder, OccupancyOrderParams};
pub use opaque::OpaqueParams;
pub use shortcut::ShortcutParams;
pub use wboit::WboitParams;
pub use weighted_average::WeightedAverageParams;

use std::cmp::Ordering;

/// One eye fragment of a pixel, as the GPU's per-pixel lists record it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeFragment {
    /// Distance from the eye in units of the camera-to-target distance (>= 0; what `store_hair` receives).
    pub depth: f32,
    /// Segment id (index of the segment's first point); ties in depth are ordered by it.
    pub segment: u32,
    /// Shaded linear radiance, not premultiplied.
    pub color: [f32; 3],
    /// Coverage in [0, 1].
    pub alpha: f32,
}

/// What every model may need beyond the pixel's own fragments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelContext {
    /// The scene's global hair alpha (occupancy ordering assumes one alpha, S&A §3.4).
    pub hair_alpha: f32,
    /// [near, far] of every fragment depth in the frame (the hair's fitted eye range, same units as depth);
    /// for techniques that normalise depth globally (moment-based OIT).
    pub depth_range: [f32; 2],
}

/// A technique's CPU model: the linear colour of one pixel from its fragments (in any order) over `background`.
pub trait Compositor: Send + Sync {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3];
}

/// The total order on fragments: `(depth bits, segment)` ascending, front to back.
pub fn key_order(a: &EyeFragment, b: &EyeFragment) -> Ordering {
    (a.depth.to_bits(), a.segment).cmp(&(b.depth.to_bits(), b.segment))
}

/// The fragments front to back on the total key (depth bits, segment) (ties kept).
pub fn front_to_back(fragments: &[EyeFragment]) -> Vec<EyeFragment> {
    let mut sorted = fragments.to_vec();
    sorted.sort_by(key_order);
    sorted
}

/// The rank `r_j` of every fragment (in input order) in the total key order: 0 for the nearest.
pub fn ranks(fragments: &[EyeFragment]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..fragments.len()).collect();
    order.sort_by(|&i, &j| key_order(&fragments[i], &fragments[j]));
    let mut rank = vec![0; fragments.len()];
    for (r, i) in order.into_iter().enumerate() {
        rank[i] = r;
    }
    rank
}

/// Front to back "under" compositing of already sorted fragments: `C += T a c; T *= 1 - a` from `C = 0`,
/// `T = 1`. Returns `(C, T)` (the caller adds `T B`).
pub(crate) fn under(sorted: impl IntoIterator<Item = EyeFragment>) -> ([f32; 3], f32) {
    let mut c = [0.0f32; 3];
    let mut t = 1.0f32;
    for f in sorted {
        for (ci, fi) in c.iter_mut().zip(f.color) {
            *ci += t * f.alpha * fi;
        }
        t *= 1.0 - f.alpha;
    }
    (c, t)
}

/// `c + t · b` per channel.
pub(crate) fn add_scaled(c: [f32; 3], t: f32, b: [f32; 3]) -> [f32; 3] {
    [c[0] + t * b[0], c[1] + t * b[1], c[2] + t * b[2]]
}

/// `x` rounded to the nearest IEEE 754 binary16 value (ties to even), returned as f32: what an f16 render
/// target stores (the `half` crate's conversion). Magnitudes that round beyond 65504 become infinite; NaN and
/// infinities pass through; subnormals keep their 2^-24 spacing.
pub fn round_f16(x: f32) -> f32 {
    half::f16::from_f32(x).to_f32()
}

#[cfg(test)]
pub(crate) mod test_support {
    use super::EyeFragment;
    use crate::rng::SplitMix64;

    /// A fragment of segment `segment` with colour `color`.
    pub fn frag(depth: f32, segment: u32, color: [f32; 3], alpha: f32) -> EyeFragment {
        EyeFragment {
            depth,
            segment,
            color,
            alpha,
        }
    }

    /// A random pixel: 1..=max_len fragments with depths in a few clumps of `[0.5, 1.5)` (like hair around
    /// the orbit target), distinct segments, colours in `[0, 1)`, alphas in `[0.05, 0.6)`.
    pub fn random_pixel(rng: &mut SplitMix64, max_len: usize) -> Vec<EyeFragment> {
        let n = rng.int(1, max_len);
        let clumps: Vec<(f32, f32)> = (0..rng.int(1, 4))
            .map(|_| (rng.range(0.5, 1.5), rng.range(0.005, 0.2)))
            .collect();
        (0..n)
            .map(|i| {
                let (centre, width) = clumps[rng.int(0, clumps.len() - 1)];
                frag(
                    (centre + width * (rng.unit() - 0.5)).max(0.0),
                    i as u32 * 3,
                    [rng.unit(), rng.unit(), rng.unit()],
                    rng.range(0.05, 0.6),
                )
            })
            .collect()
    }

    /// Asserts `|a - b| <= tol` per channel.
    pub fn assert_close(a: [f32; 3], b: [f32; 3], tol: f32, what: &str) {
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() <= tol,
                "{what}: channel {i}: {a:?} vs {b:?} (tolerance {tol})"
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::frag;
    use super::*;

    #[test]
    fn round_f16_known_values() {
        assert_eq!(round_f16(1.0), 1.0);
        // 1 + 2^-11 lies halfway between 1 and 1 + 2^-10: ties to the even mantissa, 1.
        assert_eq!(round_f16(1.0 + 1.0 / 2048.0), 1.0);
        // 1 + 3·2^-11 lies halfway between 1 + 2^-10 (odd) and 1 + 2^-9 (even).
        assert_eq!(round_f16(1.0 + 3.0 / 2048.0), 1.0 + 1.0 / 512.0);
        // Just above the tie rounds up.
        assert_eq!(round_f16(1.0 + 1.0 / 2048.0 + 1e-6), 1.0 + 1.0 / 1024.0);
        // 0.1 is binary16 0x2E66 = 1638 · 2^-14 = 0.0999755859375.
        assert_eq!(round_f16(0.1), 0.099_975_586);
        assert_eq!(round_f16(-0.1), -0.099_975_586);
        // Largest finite value, the values rounding to it, and overflow (65520 is the tie, to even = 65536).
        assert_eq!(round_f16(65504.0), 65504.0);
        assert_eq!(round_f16(65519.0), 65504.0);
        assert_eq!(round_f16(65520.0), f32::INFINITY);
        assert_eq!(round_f16(-1e9), f32::NEG_INFINITY);
        // Subnormals: spacing 2^-24; 2^-25 is a tie to even (0), 1.5 · 2^-24 a tie to even (2^-23).
        let tiny = 1.0 / 16_777_216.0;
        // Smallest positive normal binary16 value, 2^-14.
        let min_normal = 6.103_515_6e-5;
        assert_eq!(round_f16(tiny), tiny);
        assert_eq!(round_f16(tiny / 2.0), 0.0);
        assert_eq!(round_f16(1.5 * tiny), 2.0 * tiny);
        assert_eq!(round_f16(min_normal), min_normal);
        // 2^-14 + 2^-25 is a tie (the spacing there is 2^-24): to even, 2^-14.
        assert_eq!(round_f16(min_normal + tiny / 2.0), min_normal);
        assert_eq!(round_f16(0.0), 0.0);
        assert!(round_f16(f32::NAN).is_nan());
        assert_eq!(round_f16(f32::INFINITY), f32::INFINITY);
        // 2048 + 1 rounds to even 2048 (spacing 2 there), 2048 + 3 to 2052.
        assert_eq!(round_f16(2049.0), 2048.0);
        assert_eq!(round_f16(2051.0), 2052.0);
    }

    #[test]
    fn front_to_back_orders_by_depth_then_segment() {
        let f = [
            frag(0.7, 1, [0.0; 3], 0.5),
            frag(0.3, 9, [0.0; 3], 0.5),
            frag(0.7, 0, [0.0; 3], 0.5),
            frag(0.3, 2, [0.0; 3], 0.5),
        ];
        let keys: Vec<(f32, u32)> = front_to_back(&f).iter().map(|f| (f.depth, f.segment)).collect();
        assert_eq!(keys, [(0.3, 2), (0.3, 9), (0.7, 0), (0.7, 1)]);
        assert_eq!(ranks(&f), [3, 1, 2, 0]);
        assert!(front_to_back(&[]).is_empty());
    }
}

#[cfg(test)]
mod model_tests {
    use super::test_support::{assert_close, random_pixel};
    use super::*;
    use crate::rng::SplitMix64;
    use crate::visibility::OccupancyVariant;

    /// Every transparency model with `ctx` (`opaque` draws without transparency, so it is not here), labelled
    /// by its parameter type, with how far its output may move when its input is reversed: 4.8e-7 measured for
    /// the summing models; MBOIT's reconstruction amplifies the f32 rounding of its moment sums, 2.1e-3
    /// measured with 4 moments and 5.6e-4 with 6.
    fn models(ctx: &ModelContext) -> Vec<(&'static str, Box<dyn Compositor>, f32)> {
        let only = OccupancyOrderParams {
            variant: OccupancyVariant::OccupancyOnly,
            ..OccupancyOrderParams::default()
        };
        let wboit = WboitParams {
            half_precision: false,
        };
        vec![
            ("ExactParams", Box::new(ExactParams), 1e-5),
            ("ClassicPeelParams", Box::new(ClassicPeelParams), 1e-5),
            (
                "OccupancyOrderParams",
                Box::new(OccupancyOrderParams::default().model(ctx)),
                1e-5,
            ),
            (
                "OccupancyOrderParams (occupancy only)",
                Box::new(only.model(ctx)),
                1e-5,
            ),
            ("WeightedAverageParams", Box::new(WeightedAverageParams), 1e-5),
            ("WboitParams (f32)", Box::new(wboit), 1e-5),
            ("ShortcutParams", Box::new(ShortcutParams::default()), 1e-5),
            (
                "MboitParams (4 moments)",
                Box::new(MboitParams::with_moments(4).model(ctx)),
                5e-3,
            ),
            (
                "MboitParams (6 moments)",
                Box::new(MboitParams::with_moments(6).model(ctx)),
                5e-3,
            ),
        ]
    }

    #[test]
    fn single_fragment_pixels_are_exact_for_every_technique() {
        // TC-8, with the hair alpha equal to the fragment's (occupancy's assumption).
        let mut rng = SplitMix64::new(971);
        for _ in 0..200 {
            let f = [random_pixel(&mut rng, 1)[0]];
            let ctx = ModelContext {
                hair_alpha: f[0].alpha,
                depth_range: [0.4, 1.6],
            };
            let b = [rng.unit(), rng.unit(), rng.unit()];
            let exact = ExactParams.composite(&f, b);
            for (name, m, _) in models(&ctx) {
                assert_close(m.composite(&f, b), exact, 1e-5, name);
            }
            // 16-bit WBOIT: within f16 rounding of the targets.
            assert_close(WboitParams::default().composite(&f, b), exact, 2e-3, "wboit-f16");
        }
    }

    /// The GPU sums in an unknown order: reversing the input changes a model's output by f32 rounding only.
    #[test]
    fn input_order_changes_only_rounding() {
        let mut rng = SplitMix64::new(972);
        let ctx = ModelContext {
            hair_alpha: 0.3,
            depth_range: [0.4, 1.6],
        };
        for _ in 0..100 {
            let mut f = random_pixel(&mut rng, 120);
            let b = [rng.unit(), rng.unit(), rng.unit()];
            let before: Vec<[f32; 3]> = models(&ctx).iter().map(|(_, m, _)| m.composite(&f, b)).collect();
            f.reverse();
            for ((name, m, tol), c) in models(&ctx).iter().zip(before) {
                assert_close(m.composite(&f, b), c, *tol, name);
            }
        }
    }
}
