//! Weighted blended OIT (McGuire & Bavoil 2013), exactly what `shaders/transparency/wboit.wgsl` and
//! `wboit_resolve.wgsl` compute today (spec A.5 TR-CPU-4):
//! ```text
//! hair pass, per fragment (in the order given):
//!   w = a · clamp(pow(max(2 − depth, 0), 8), 1e−2, 3e3)
//!   accum += (c · a · w, a · w)        // Rgba16Float, One/One, cleared to 0
//!   R     *= 1 − a                     // R16Float, Zero/OneMinusSrc, cleared to 1
//! resolve:
//!   accum.a <= 1e−6 → discard (C = B)
//!   colour = accum.rgb / max(accum.a, 1e−6),  coverage = 1 − R
//!   C = colour · coverage + B · (1 − coverage)   // SrcAlpha / OneMinusSrcAlpha over the opaque image
//! ```
//! With `half_precision` (the default, today's targets) accum and R are rounded to f16 ([`round_f16`]) after
//! every fragment; without it they are f32 (the sum's order still follows the input).

use super::{Compositor, EyeFragment, round_f16};

/// Parameters of weighted blended OIT.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WboitParams {
    /// 16-bit float accumulation and revealage targets (today's formats) instead of 32-bit.
    pub half_precision: bool,
}

impl Default for WboitParams {
    /// Today's Rgba16Float / R16Float targets.
    fn default() -> Self {
        Self { half_precision: true }
    }
}

/// The depth weight of a fragment: `a · clamp(max(2 − depth, 0)^8, 1e−2, 3e3)`.
pub fn weight(alpha: f32, depth: f32) -> f32 {
    alpha * (2.0 - depth).max(0.0).powf(8.0).clamp(1e-2, 3e3)
}

impl Compositor for WboitParams {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let round = |x: f32| if self.half_precision { round_f16(x) } else { x };
        let mut accum = [0.0f32; 4];
        let mut revealage = 1.0f32;
        for f in fragments {
            let w = weight(f.alpha, f.depth);
            let src = [
                f.color[0] * f.alpha * w,
                f.color[1] * f.alpha * w,
                f.color[2] * f.alpha * w,
                f.alpha * w,
            ];
            for (acc, s) in accum.iter_mut().zip(src) {
                *acc = round(*acc + s);
            }
            revealage = round(revealage * (1.0 - f.alpha));
        }
        if accum[3] <= 1e-6 {
            return background;
        }
        let coverage = 1.0 - revealage;
        let a = accum[3].max(1e-6);
        std::array::from_fn(|i| accum[i] / a * coverage + background[i] * (1.0 - coverage))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::transparency::ExactParams;
    use crate::transparency::test_support::{assert_close, frag, random_pixel};

    const F32: WboitParams = WboitParams {
        half_precision: false,
    };

    #[test]
    fn weight_hand_computed() {
        // depth 1: 1^8 = 1; depth 0: 2^8 = 256; depth 1.5: 0.5^8 = 1/256 → clamped to 1e-2; depth 3: 0 → 1e-2;
        // depth -10: 12^8 = 429981696 → clamped to 3000.
        assert_eq!(weight(0.5, 1.0), 0.5);
        assert_eq!(weight(0.5, 0.0), 128.0);
        assert_eq!(weight(1.0, 1.5), 1e-2);
        assert_eq!(weight(1.0, 3.0), 1e-2);
        assert_eq!(weight(1.0, -10.0), 3e3);
    }

    #[test]
    fn two_fragments_hand_computed() {
        // Red at depth 1 (α 0.5, w = 0.5) and green at depth 0 (α 0.5, w = 128) over blue:
        // accum = (0.25, 64, 0, 0.25 + 64 = 64.25), R = 0.25, coverage 0.75:
        // C = (0.25, 64, 0) / 64.25 · 0.75 + 0.25 · blue = (0.0029183, 0.7470817, 0.25).
        // Every value is exact in f16 too, so both precisions agree.
        let f = [
            frag(1.0, 0, [1.0, 0.0, 0.0], 0.5),
            frag(0.0, 1, [0.0, 1.0, 0.0], 0.5),
        ];
        let expected = [0.25 / 64.25 * 0.75, 64.0 / 64.25 * 0.75, 0.25];
        for params in [F32, WboitParams::default()] {
            assert_close(
                params.composite(&f, [0.0, 0.0, 1.0]),
                expected,
                1e-6,
                &format!("{params:?}"),
            );
        }
    }

    #[test]
    fn half_precision_rounds_the_targets() {
        // One fragment at depth 1 with colour 0.1 and α 0.3: w = 0.3, accum = (0.1 · 0.3 · 0.3, …, 0.09),
        // R = 0.7. In f16: 0.009 → 1180 · 2^-17, 0.09 → 1475 · 2^-14, 0.7 → 1434 · 2^-11 (Python's
        // struct 'e' format agrees). Over black: (1180 · 2^-17) / (1475 · 2^-14) · (1 − 1434 · 2^-11) = 0.0299805.
        let f = [frag(1.0, 0, [0.1; 3], 0.3)];
        let (acc, a, r) = (1180.0 / 131_072.0f64, 1475.0 / 16_384.0f64, 1434.0 / 2048.0f64);
        let expected = (acc / a * (1.0 - r)) as f32;
        let half = WboitParams::default().composite(&f, [0.0; 3]);
        assert_close(half, [expected; 3], 1e-7, "f16");
        // f32: 0.1 · (1 − 0.7) = 0.03 up to f32 rounding; the f16 result differs from it.
        let full = F32.composite(&f, [0.0; 3]);
        assert_close(full, [0.03; 3], 1e-7, "f32");
        assert!((half[0] - full[0]).abs() > 1e-6, "{half:?} vs {full:?}");
    }

    #[test]
    fn single_fragment_is_exact_and_empty_is_background() {
        // TC-8 at f32: the average of one colour is the colour, coverage 1 − (1 − a) = a.
        let mut rng = SplitMix64::new(941);
        for _ in 0..100 {
            let f = [random_pixel(&mut rng, 1)[0]];
            let b = [rng.unit(), rng.unit(), rng.unit()];
            assert_close(F32.composite(&f, b), ExactParams.composite(&f, b), 1e-6, "n = 1");
        }
        assert_eq!(F32.composite(&[], [0.4; 3]), [0.4; 3]);
        // A fragment of zero alpha accumulates nothing: discarded.
        assert_eq!(F32.composite(&[frag(1.0, 0, [1.0; 3], 0.0)], [0.4; 3]), [0.4; 3]);
    }
}
