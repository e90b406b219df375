//! Occupancy-ordered blending in eye space (Sintorn & Assarsson 2009 §3.4; spec A.5 TR-CPU-2): the order
//! estimate of §3.2 — [`crate::visibility::occupancy::build`] and [`order`](crate::visibility::occupancy::order),
//! unchanged — on the pixel's eye depths gives each fragment an approximate number `o` of fragments in front of
//! it; one additive pass sums `w = (1 − ᾱ)^o ᾱ` times its colour, and the resolve puts the sum over
//! `(1 − ᾱ)^n B`.
//!
//! Per pixel, in f32, the GPU's expressions in this order:
//! ```text
//! near, far = min, max of the pixel's depths            // the depth-range map (Min / Max blending)
//! d_j = relative_depth(z_j, near, far)                  // visibility::relative_depth: far <= near → step at near
//! t   = occupancy::build(variant, d_j's)                // occupancy bits + slab counts, 128 slices, 4 slabs
//! o_j = max(occupancy::order(t, d_j) + order_bias, 0)
//! w_j = exp(−o_j · b̄) · ᾱ,  b̄ = optical_depth(ᾱ)        // (1 − ᾱ)^o ᾱ
//! H = Σ w_j c_j,  A = Σ w_j                             // one Rgba32Float One/One target (rgb, a)
//! n = Σ t.slabs,  T = exp(−n · b̄),  Λ = 1 − T
//! if lambda_correction && A > 1e−12 { H ← H · Λ / A }  // A.3 #1: the total weight becomes Λ
//! C = H + T · B                                         // no fragments: C = B
//! ```
//! - `ᾱ` is [`ModelContext::hair_alpha`] for every α (A.3 #4, paper-literal: S&A assume one alpha); each
//!   fragment's own alpha is not used. With every fragment at that alpha, one fragment is exact (TC-8), and
//!   uniform alpha and colour are exact for any `n` with the correction (only intensity matters).
//! - Depth: the pixel's own depths as given, normalised to their own `[min, max]` (the depth-range map); since
//!   `d` of the nearest is exactly 0 and of the furthest exactly 1, `build`'s own re-normalisation over
//!   `[0, 1]` is the identity. A pixel whose fragments share one depth has `d = 0` for all: every `o = 0`.
//! - `half_precision` models a 16-bit accumulation target (TC-4): every partial sum of `H` and `A` is rounded
//!   to f16 ([`round_f16`]) in the order given.
//! - `order_bias = −0.5` (A.3 #3, [ext]) removes the estimate's mean bias of about +½ (see the TT-U8 test).

use super::{Compositor, EyeFragment, ModelContext, round_f16};
use crate::visibility::occupancy::{self, OccupancyParams, OccupancyVariant};
use crate::visibility::{Fragment, optical_depth, relative_depth};

/// Parameters of occupancy-ordered blending.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OccupancyOrderParams {
    /// Slab map (the paper's method) or the occupancy map alone.
    pub variant: OccupancyVariant,
    /// Rescale the hair colour so the total weight is `Λ = 1 − (1 − ᾱ)^n` (S&A's correction, A.3 #1).
    pub lambda_correction: bool,
    /// Added to every order estimate before clamping at 0 (0, or −0.5 to remove the +½ bias).
    pub order_bias: f32,
    /// Round every partial sum of the accumulation to f16 (a 16-bit target instead of 32-bit).
    pub half_precision: bool,
}

impl Default for OccupancyOrderParams {
    /// The paper's method: slab map, correction on, no bias, 32-bit accumulation.
    fn default() -> Self {
        Self {
            variant: OccupancyVariant::SlabMap,
            lambda_correction: true,
            order_bias: 0.0,
            half_precision: false,
        }
    }
}

impl OccupancyOrderParams {
    /// The model for a frame: these parameters with the frame's hair alpha.
    pub fn model(self, ctx: &ModelContext) -> OccupancyOrder {
        OccupancyOrder {
            params: self,
            hair_alpha: ctx.hair_alpha,
        }
    }
}

/// Occupancy-ordered blending bound to the frame's hair alpha.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OccupancyOrder {
    pub params: OccupancyOrderParams,
    /// `ᾱ`, the one alpha the method assumes.
    pub hair_alpha: f32,
}

/// The fragments' depths (input order) normalised to the pixel's own `[min, max]` with
/// [`relative_depth`](crate::visibility::relative_depth).
pub fn normalised_depths(fragments: &[EyeFragment]) -> Vec<f32> {
    let (near, far) = fragments
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(n, f), x| {
            (n.min(x.depth), f.max(x.depth))
        });
    fragments
        .iter()
        .map(|f| relative_depth(f.depth, near, far))
        .collect()
}

/// The occupancy texel of the pixel and every fragment's order estimate `o_j` (input order, no bias).
fn texel_and_orders(
    variant: OccupancyVariant,
    fragments: &[EyeFragment],
) -> (occupancy::OccupancyTexel, Vec<f32>) {
    // `build` and `order` do not use the alpha.
    let params = OccupancyParams { alpha: 0.0, variant };
    let d = normalised_depths(fragments);
    let as_fragments: Vec<Fragment> = d.iter().map(|&d| Fragment::new(d, 0.0)).collect();
    let texel = occupancy::build(&params, &as_fragments);
    let orders = d.iter().map(|&d| occupancy::order(&params, &texel, d)).collect();
    (texel, orders)
}

/// Every fragment's order estimate `o_j` (input order, before the bias): the inspector's "estimated order"
/// beside [`ranks`](super::ranks).
pub fn estimated_orders(variant: OccupancyVariant, fragments: &[EyeFragment]) -> Vec<f32> {
    texel_and_orders(variant, fragments).1
}

/// The order error of a pixel (spec A.7, diagnostic): mean and max over its fragments of `|o_j − r_j|`, the
/// estimate (no bias) against the true rank; `(0, 0)` without fragments.
pub fn order_error(variant: OccupancyVariant, fragments: &[EyeFragment]) -> (f32, f32) {
    if fragments.is_empty() {
        return (0.0, 0.0);
    }
    let errors: Vec<f32> = estimated_orders(variant, fragments)
        .iter()
        .zip(super::ranks(fragments))
        .map(|(o, r)| (o - r as f32).abs())
        .collect();
    let max = errors.iter().copied().fold(0.0, f32::max);
    (errors.iter().sum::<f32>() / errors.len() as f32, max)
}

impl Compositor for OccupancyOrder {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let p = &self.params;
        let alpha = self.hair_alpha;
        let b = optical_depth(alpha);
        let (texel, orders) = texel_and_orders(p.variant, fragments);
        let round = |x: f32| if p.half_precision { round_f16(x) } else { x };
        let mut h = [0.0f32; 3];
        let mut a_sum = 0.0f32;
        for (f, o) in fragments.iter().zip(orders) {
            let o = (o + p.order_bias).max(0.0);
            let w = (-o * b).exp() * alpha;
            for (hi, ci) in h.iter_mut().zip(f.color) {
                *hi = round(*hi + w * ci);
            }
            a_sum = round(a_sum + w);
        }
        let n = texel.slabs.iter().sum::<u32>() as f32;
        let t = (-n * b).exp();
        let lambda = 1.0 - t;
        if p.lambda_correction && a_sum > 1e-12 {
            for hi in &mut h {
                *hi = *hi * lambda / a_sum;
            }
        }
        super::add_scaled(h, t, background)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::transparency::test_support::{assert_close, frag, random_pixel};
    use crate::transparency::{ExactParams, ranks};

    fn model(params: OccupancyOrderParams, hair_alpha: f32) -> OccupancyOrder {
        params.model(&ModelContext {
            hair_alpha,
            depth_range: [0.0, 2.0],
        })
    }

    fn uncorrected() -> OccupancyOrderParams {
        OccupancyOrderParams {
            lambda_correction: false,
            ..OccupancyOrderParams::default()
        }
    }

    #[test]
    fn one_fragment_is_exact() {
        // TT-U2 / TC-8: o = 0, w = α, Λ = α = A: C = α c + (1 − α) B.
        let f = [frag(0.8, 4, [0.9, 0.5, 0.1], 0.3)];
        let b = [0.2, 0.4, 0.6];
        let exact = ExactParams.composite(&f, b);
        for params in [OccupancyOrderParams::default(), uncorrected()] {
            assert_close(model(params, 0.3).composite(&f, b), exact, 1e-6, "n = 1");
        }
    }

    #[test]
    fn two_fragments_at_near_and_far_hand_computed() {
        // TT-U2: the near fragment has o = 0; the far one d = 1, slice 127 with frac 1, slab 3 after the near
        // fragment's slab 0: o = 1 + 1 · (0 + 1) / 1 = 2 (A.3 #3, the +½ bias at its worst).
        let f = [
            frag(1.3, 1, [0.0, 1.0, 0.0], 0.5),
            frag(0.7, 0, [1.0, 0.0, 0.0], 0.5),
        ];
        assert_eq!(estimated_orders(OccupancyVariant::SlabMap, &f), [2.0, 0.0]);
        // Ranks 1 and 0: order errors 1 and 0.
        assert_eq!(order_error(OccupancyVariant::SlabMap, &f), (0.5, 1.0));
        assert_eq!(order_error(OccupancyVariant::SlabMap, &[]), (0.0, 0.0));
        let blue = [0.0, 0.0, 1.0];
        // α = 0.5: weights 0.5 and 0.25 · 0.5 = 0.125, A = 0.625, Λ = 1 − 0.25 = 0.75, T = 0.25.
        // Uncorrected: (0.5, 0.125, 0) + 0.25 blue.
        assert_close(
            model(uncorrected(), 0.5).composite(&f, blue),
            [0.5, 0.125, 0.25],
            1e-6,
            "uncorrected",
        );
        // Corrected: (0.5, 0.125, 0) · 0.75 / 0.625 = (0.6, 0.15, 0), + 0.25 blue.
        let corrected = OccupancyOrderParams::default();
        assert_close(
            model(corrected, 0.5).composite(&f, blue),
            [0.6, 0.15, 0.25],
            1e-6,
            "corrected",
        );
        // The exact composite for comparison: 0.5 red + 0.25 green + 0.25 blue.
        assert_close(ExactParams.composite(&f, blue), [0.5, 0.25, 0.25], 0.0, "exact");
        // Bias −0.5: o = 0 (clamped) and 1.5, weights 0.5 and 0.5^1.5 · 0.5 = 0.1767767.
        let biased = OccupancyOrderParams {
            order_bias: -0.5,
            ..uncorrected()
        };
        assert_close(
            model(biased, 0.5).composite(&f, blue),
            [0.5, 0.176_776_7, 0.25],
            1e-6,
            "order bias",
        );
    }

    #[test]
    fn occupancy_only_uses_one_count() {
        // Fragments at d = 0, 0.1, 0.5, 1 (depths 1 + d): occupancy-only has F = 4 on S = 4 set bits, so the
        // far fragment gets o = 4 · (3 + 1) / 4 = 4, and the one at 0.5 (slice 64, frac 0, bits before 2):
        // 4 · 2 / 4 = 2. The 0.1 one: slice 12 (x = 12.8, own bit), bits before 1: 1 + 0.8 = 1.8.
        let f: Vec<EyeFragment> = [1.0, 1.1, 1.5, 2.0]
            .iter()
            .enumerate()
            .map(|(i, &z)| frag(z, i as u32, [1.0; 3], 0.5))
            .collect();
        let o = estimated_orders(OccupancyVariant::OccupancyOnly, &f);
        assert_eq!(o[0], 0.0);
        assert!((o[1] - 1.8).abs() < 1e-4, "{o:?}");
        assert!((o[2] - 2.0).abs() < 1e-5, "{o:?}");
        assert_eq!(o[3], 4.0);
    }

    #[test]
    fn corrected_weight_sum_is_lambda() {
        // TT-U3: white fragments over black show the rescaled weight sum, which must be 1 − (1 − ᾱ)^n.
        let mut rng = SplitMix64::new(921);
        for _ in 0..300 {
            let f: Vec<EyeFragment> = random_pixel(&mut rng, 200)
                .into_iter()
                .map(|f| EyeFragment { color: [1.0; 3], ..f })
                .collect();
            let alpha = rng.range(0.02, 0.7);
            let c = model(OccupancyOrderParams::default(), alpha).composite(&f, [0.0; 3]);
            let lambda = 1.0 - (1.0 - f64::from(alpha)).powi(f.len() as i32);
            for ch in c {
                assert!(
                    (f64::from(ch) - lambda).abs() < 1e-6,
                    "n = {}, α = {alpha}: {ch} vs Λ = {lambda}",
                    f.len()
                );
            }
        }
    }

    #[test]
    fn uniform_alpha_and_colour_is_exact_with_the_correction() {
        // TT-U4: only the intensity matters then, and the correction makes it exact.
        let mut rng = SplitMix64::new(922);
        for variant in [OccupancyVariant::SlabMap, OccupancyVariant::OccupancyOnly] {
            for _ in 0..200 {
                let alpha = rng.range(0.02, 0.7);
                let colour = [rng.unit(), rng.unit(), rng.unit()];
                let f: Vec<EyeFragment> = random_pixel(&mut rng, 300)
                    .into_iter()
                    .map(|f| EyeFragment {
                        color: colour,
                        alpha,
                        ..f
                    })
                    .collect();
                let b = [rng.unit(), rng.unit(), rng.unit()];
                let params = OccupancyOrderParams {
                    variant,
                    ..OccupancyOrderParams::default()
                };
                assert_close(
                    model(params, alpha).composite(&f, b),
                    ExactParams.composite(&f, b),
                    1e-5,
                    &format!("{variant:?}, n = {}", f.len()),
                );
            }
        }
    }

    #[test]
    fn lambda_correction_lowers_error_on_deep_pixels() {
        // TC-5 on the models: 200 pixels of 64..=300 fragments in clumps, uniform α = 0.35, colours darkening with
        // depth (as self-shadowed hair does), over grey; mean max-channel error against the exact composite.
        // Measured: 6.6e-4 corrected, 0.23 uncorrected (the spec's simulation: 0.23 uncorrected at n = 300).
        let mut rng = SplitMix64::new(926);
        let alpha = 0.35;
        let (mut on, mut off, mut count) = (0.0f64, 0.0f64, 0);
        while count < 200 {
            let f: Vec<EyeFragment> = random_pixel(&mut rng, 300)
                .into_iter()
                .map(|f| {
                    let shade = (1.5 - f.depth).clamp(0.0, 1.0);
                    EyeFragment {
                        color: [shade, shade * 0.8, shade * 0.5],
                        alpha,
                        ..f
                    }
                })
                .collect();
            if f.len() < 64 {
                continue;
            }
            let b = [0.5; 3];
            let exact = ExactParams.composite(&f, b);
            let err = |c: [f32; 3]| (0..3).map(|i| (c[i] - exact[i]).abs()).fold(0.0, f32::max);
            on += f64::from(err(model(OccupancyOrderParams::default(), alpha).composite(&f, b)));
            off += f64::from(err(model(uncorrected(), alpha).composite(&f, b)));
            count += 1;
        }
        let (on, off) = (on / count as f64, off / count as f64);
        assert!(on < 0.1 * off, "corrected {on} vs uncorrected {off}");
    }

    #[test]
    fn order_estimate_is_biased_by_a_half() {
        // TT-U8 (A.3 #3): mean (o − r) over random pixels lies in [0.4, 0.6] for 2 <= n <= 32. Measured
        // (uniform depths, 400 pixels each): 0.500, 0.502, 0.511, 0.498, 0.499, 0.512 for n = 2, 3, 4, 8, 16, 32.
        let mut rng = SplitMix64::new(923);
        for n in [2, 3, 4, 8, 16, 32] {
            let mut sum = 0.0f64;
            let mut count = 0usize;
            for _ in 0..400 {
                let f: Vec<EyeFragment> = (0..n)
                    .map(|i| frag(rng.range(0.5, 1.5), i, [0.5; 3], 0.3))
                    .collect();
                let o = estimated_orders(OccupancyVariant::SlabMap, &f);
                for (o, r) in o.iter().zip(ranks(&f)) {
                    sum += f64::from(*o) - r as f64;
                    count += 1;
                }
            }
            let mean = sum / count as f64;
            assert!((0.4..=0.6).contains(&mean), "n = {n}: mean bias {mean}");
        }
    }

    #[test]
    fn nearest_fragment_gets_order_zero_and_ties_share_one_depth() {
        let mut rng = SplitMix64::new(924);
        for _ in 0..100 {
            let f = random_pixel(&mut rng, 80);
            let o = estimated_orders(OccupancyVariant::SlabMap, &f);
            let nearest = ranks(&f).iter().position(|&r| r == 0).unwrap();
            assert_eq!(o[nearest], 0.0);
        }
        // All at one depth: the degenerate range puts every fragment at d = 0, o = 0.
        let same = vec![frag(0.9, 0, [1.0; 3], 0.5); 4];
        assert_eq!(estimated_orders(OccupancyVariant::SlabMap, &same), [0.0; 4]);
        // Corrected: colour · Λ, Λ = 1 − 0.5^4 = 0.9375, over black.
        assert_close(
            model(OccupancyOrderParams::default(), 0.5).composite(&same, [0.0; 3]),
            [0.9375; 3],
            1e-6,
            "ties",
        );
    }

    #[test]
    fn no_fragments_is_the_background() {
        let m = model(OccupancyOrderParams::default(), 0.4);
        assert_eq!(m.composite(&[], [0.1, 0.2, 0.3]), [0.1, 0.2, 0.3]);
    }

    /// The spec's formula in f64 from the model's own order estimates (checked by the tests above).
    fn composite_f64(f: &[EyeFragment], alpha: f32, b: [f32; 3]) -> [f64; 3] {
        let a = f64::from(alpha);
        let o = estimated_orders(OccupancyVariant::SlabMap, f);
        let (mut h, mut w_sum) = ([0.0f64; 3], 0.0f64);
        for (f, o) in f.iter().zip(o) {
            let w = (1.0 - a).powf(f64::from(o)) * a;
            for (hi, ci) in h.iter_mut().zip(f.color) {
                *hi += w * f64::from(ci);
            }
            w_sum += w;
        }
        let t = (1.0 - a).powi(f.len() as i32);
        std::array::from_fn(|i| h[i] * (1.0 - t) / w_sum + t * f64::from(b[i]))
    }

    #[test]
    fn half_precision_accumulation_is_measurably_worse() {
        // TC-4: f32 accumulation stays within 1e-5 of f64; f16 partial sums deviate far more, most with many
        // fragments of small alpha. Measured on these 40 pixels of 400 fragments at α = 0.02: f32 4.7e-7,
        // f16 5.3e-3 (the spec's simulation expects up to ~6e-3 there).
        let mut rng = SplitMix64::new(925);
        let (mut worst32, mut worst16) = (0.0f64, 0.0f64);
        for _ in 0..40 {
            let alpha = 0.02;
            let f: Vec<EyeFragment> = (0..400)
                .map(|i| {
                    frag(
                        rng.range(0.5, 1.5),
                        i,
                        [rng.unit(), rng.unit(), rng.unit()],
                        alpha,
                    )
                })
                .collect();
            let reference = composite_f64(&f, alpha, [0.0; 3]);
            let full = model(OccupancyOrderParams::default(), alpha).composite(&f, [0.0; 3]);
            let half = OccupancyOrderParams {
                half_precision: true,
                ..OccupancyOrderParams::default()
            };
            let half = model(half, alpha).composite(&f, [0.0; 3]);
            for i in 0..3 {
                worst32 = worst32.max((f64::from(full[i]) - reference[i]).abs());
                worst16 = worst16.max((f64::from(half[i]) - reference[i]).abs());
            }
        }
        assert!(worst32 < 1e-5, "f32: {worst32}");
        assert!(
            worst16 > 1e-4 && worst16 > 20.0 * worst32,
            "f16 {worst16} vs f32 {worst32}"
        );
    }
}
