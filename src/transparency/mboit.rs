//! Moment-based OIT (Münstermann, Krumpen, Klein & Peters, I3D 2018): pass 1 sums the zeroth and 4 or 6 power
//! moments of the absorbance `b = −ln(1 − a)` over depth; pass 2 reconstructs, for each fragment, the
//! transmittance `T(z)` of everything in front of it from those moments and sums `(a c T(z), a T(z))`; the
//! resolve normalises the colour and covers it with the exact total `1 − exp(−b_0)`:
//! ```text
//! z'  = clamp(relative_depth(depth, near_f, far_f), 0, 1)     // ModelContext::depth_range, global per frame
//! pass 1: the moment texel of msm::build over (z', a)         // b_0 = Σ b, b_j = Σ b · (2z' − 1)^j
//! pass 2: T_j = msm::visibility(moments, z'_j);  S = Σ a c T_j,  A = Σ a T_j   (in the order given)
//! C = S / A · (1 − exp(−b_0)) + B · exp(−b_0)                 // A = 0 (or no fragments): C = B · exp(−b_0)
//! ```
//! Everything about the moments — the warp to `[−1, 1]`, the bias toward MBOIT's bias vector, the Hankel
//! solve, the bound with its overestimation weight, the f32 fall-backs — is
//! [`crate::visibility::msm`], reused unchanged (the moment shadow map is the same reconstruction from the
//! light). The depth is normalised over the frame's whole eye range (MBOIT's per-frame `[near, far]`), not per
//! pixel, so the pass needs no depth-range map.
//!
//! GPU = CPU tolerance: the reconstruction is ill-conditioned in f32 and amplifies the rounding of the moment
//! sums, whose order the GPU's additive blending does not fix. Reversing the input order of random pixels of up
//! to 120 fragments changes this model's output by up to 2.1e-3 (4 moments) and 5.6e-4 (6 moments) per channel
//! (`transparency::model_tests`), against 5e-7 for the other summing models: compare MBOIT within 5e-3.

use super::{Compositor, EyeFragment, ModelContext, add_scaled};
use crate::visibility::msm::{self, DEFAULT_BIAS_4, DEFAULT_BIAS_6, MsmParams};
use crate::visibility::{Fragment, relative_depth};

/// Parameters of moment-based OIT: the moment count, bias and overestimation of [`MsmParams`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MboitParams {
    pub moments: MsmParams,
}

impl MboitParams {
    /// `moments` power moments (4 or 6; any other value counts as 4) with MBOIT's single-precision bias for
    /// that count and its default overestimation.
    pub fn with_moments(moments: u32) -> Self {
        let bias = if moments == 6 {
            DEFAULT_BIAS_6
        } else {
            DEFAULT_BIAS_4
        };
        Self {
            moments: MsmParams {
                moments,
                bias,
                ..MsmParams::default()
            },
        }
    }

    /// The model for a frame: these parameters with the frame's eye depth range.
    pub fn model(self, ctx: &ModelContext) -> Mboit {
        Mboit {
            params: self,
            depth_range: ctx.depth_range,
        }
    }
}

/// Moment-based OIT bound to the frame's depth range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mboit {
    pub params: MboitParams,
    /// `[near, far]` the depths are normalised over.
    pub depth_range: [f32; 2],
}

impl Mboit {
    /// A fragment's depth in `[0, 1]` over the frame's range.
    pub fn normalised(&self, depth: f32) -> f32 {
        let [near, far] = self.depth_range;
        relative_depth(depth, near, far).clamp(0.0, 1.0)
    }
}

impl Compositor for Mboit {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let p = &self.params.moments;
        let light: Vec<Fragment> = fragments
            .iter()
            .map(|f| Fragment::new(self.normalised(f.depth), f.alpha))
            .collect();
        let texel = msm::build(p, &light);
        let mut s = [0.0f32; 3];
        let mut a_sum = 0.0f32;
        for (f, l) in fragments.iter().zip(&light) {
            let w = f.alpha * msm::visibility(p, &texel, l.depth);
            for (si, ci) in s.iter_mut().zip(f.color) {
                *si += w * ci;
            }
            a_sum += w;
        }
        let t = (-texel.b[0]).exp();
        let c = if a_sum > 0.0 {
            std::array::from_fn(|i| s[i] / a_sum * (1.0 - t))
        } else {
            [0.0; 3]
        };
        add_scaled(c, t, background)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::transparency::ExactParams;
    use crate::transparency::test_support::{assert_close, frag, random_pixel};

    fn model(moments: u32) -> Mboit {
        MboitParams::with_moments(moments).model(&ModelContext {
            hair_alpha: 0.3,
            depth_range: [0.5, 1.5],
        })
    }

    #[test]
    fn one_fragment_is_exact() {
        // TC-8: S / A = c and 1 − exp(−b_0) = a.
        let mut rng = SplitMix64::new(961);
        for moments in [4, 6] {
            for _ in 0..100 {
                let f = [random_pixel(&mut rng, 1)[0]];
                let b = [rng.unit(), rng.unit(), rng.unit()];
                assert_close(
                    model(moments).composite(&f, b),
                    ExactParams.composite(&f, b),
                    1e-5,
                    "n = 1",
                );
            }
        }
    }

    #[test]
    fn uniform_colour_is_exact_whatever_the_alphas() {
        // The coverage 1 − exp(−Σ b) = 1 − Π(1 − a) is exact, and one colour makes S / A that colour.
        let mut rng = SplitMix64::new(962);
        for moments in [4, 6] {
            for _ in 0..100 {
                let colour = [rng.unit(), rng.unit(), rng.unit()];
                let f: Vec<EyeFragment> = random_pixel(&mut rng, 100)
                    .into_iter()
                    .map(|f| EyeFragment { color: colour, ..f })
                    .collect();
                let b = [rng.unit(), rng.unit(), rng.unit()];
                assert_close(
                    model(moments).composite(&f, b),
                    ExactParams.composite(&f, b),
                    1e-5,
                    "uniform colour",
                );
            }
        }
    }

    #[test]
    fn two_fragments_keep_their_order() {
        // Red in front of green, α 0.5, over black: exact (0.5, 0.25, 0). Four moments determine two points,
        // so the reconstruction is nearly exact (measured: within 1.8e-7 with 4 and 6 moments); the colour sum
        // is normalised to the exact coverage 0.75.
        let f = [
            frag(1.2, 1, [0.0, 1.0, 0.0], 0.5),
            frag(0.8, 0, [1.0, 0.0, 0.0], 0.5),
        ];
        for moments in [4, 6] {
            let c = model(moments).composite(&f, [0.0; 3]);
            assert!((c[0] + c[1] - 0.75).abs() < 1e-6, "{moments}: {c:?}");
            assert!(
                (c[0] - 0.5).abs() < 1e-4 && (c[1] - 0.25).abs() < 1e-4,
                "{moments}: {c:?}"
            );
        }
    }

    #[test]
    fn empty_is_background() {
        assert_eq!(model(4).composite(&[], [0.3; 3]), [0.3; 3]);
    }
}
