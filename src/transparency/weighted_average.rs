//! Weighted average blending, Bavoil & Myers 2008 as published (S&A's "dull" comparison, spec A.3 #6 and A.5
//! TR-CPU-3): one additive pass sums `(a c, a)` and counts the fragments; the resolve takes the alpha-weighted
//! mean colour and the mean alpha, and covers the background with `n` layers of that mean alpha:
//! ```text
//! S = Σ a_j c_j,  A = Σ a_j  (in the order given),  n = fragment count
//! C_avg = S / A,  α_avg = A / n,  T = (1 − α_avg)^n,  C = C_avg (1 − T) + B T
//! ```
//! No fragments, or fragments that cover nothing (`A = 0`), leave `C = B`. S&A's wording ("the sum of colors
//! divided by the averaged alpha") is not a weighted average; the published formula is implemented.

use super::{Compositor, EyeFragment};

/// Weighted average blending has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WeightedAverageParams;

impl Compositor for WeightedAverageParams {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let mut s = [0.0f32; 3];
        let mut a_sum = 0.0f32;
        for f in fragments {
            for (si, ci) in s.iter_mut().zip(f.color) {
                *si += f.alpha * ci;
            }
            a_sum += f.alpha;
        }
        if a_sum <= 0.0 {
            return background;
        }
        let n = fragments.len() as f32;
        let t = (1.0 - a_sum / n).powf(n);
        std::array::from_fn(|i| s[i] / a_sum * (1.0 - t) + background[i] * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::transparency::ExactParams;
    use crate::transparency::test_support::{assert_close, frag, random_pixel};

    #[test]
    fn uniform_alpha_is_mean_colour_over_the_background() {
        // TT-U5: α = 0.5, red, green, blue over white: mean colour 1/3 each, T = 0.5³ = 0.125:
        // C = 1/3 · 0.875 + 0.125 = 0.4166667 in every channel.
        let f = [
            frag(0.2, 0, [1.0, 0.0, 0.0], 0.5),
            frag(0.4, 1, [0.0, 1.0, 0.0], 0.5),
            frag(0.6, 2, [0.0, 0.0, 1.0], 0.5),
        ];
        assert_close(
            WeightedAverageParams.composite(&f, [1.0; 3]),
            [0.416_666_7; 3],
            1e-6,
            "uniform α",
        );
        // The exact composite is (0.625, 0.375, 0.25): the average loses the order.
        assert_eq!(ExactParams.composite(&f, [1.0; 3]), [0.625, 0.375, 0.25]);
    }

    #[test]
    fn mixed_alphas_hand_computed() {
        // α 0.2 (red) and 0.6 (green) over black: S = (0.2, 0.6, 0), A = 0.8, α_avg = 0.4, T = 0.36:
        // C = (0.25, 0.75, 0) · 0.64 = (0.16, 0.48, 0).
        let f = [
            frag(0.2, 0, [1.0, 0.0, 0.0], 0.2),
            frag(0.4, 1, [0.0, 1.0, 0.0], 0.6),
        ];
        assert_close(
            WeightedAverageParams.composite(&f, [0.0; 3]),
            [0.16, 0.48, 0.0],
            1e-6,
            "mixed α",
        );
    }

    #[test]
    fn empty_or_transparent_is_the_background() {
        let b = [0.3, 0.2, 0.1];
        assert_eq!(WeightedAverageParams.composite(&[], b), b);
        let clear = [frag(0.5, 0, [1.0; 3], 0.0), frag(0.6, 1, [1.0; 3], 0.0)];
        assert_eq!(WeightedAverageParams.composite(&clear, b), b);
    }

    #[test]
    fn uniform_colour_and_alpha_is_exact() {
        let mut rng = SplitMix64::new(931);
        for _ in 0..100 {
            let colour = [rng.unit(), rng.unit(), rng.unit()];
            let alpha = rng.range(0.05, 0.6);
            let f: Vec<EyeFragment> = random_pixel(&mut rng, 100)
                .into_iter()
                .map(|f| EyeFragment {
                    color: colour,
                    alpha,
                    ..f
                })
                .collect();
            let b = [rng.unit(), rng.unit(), rng.unit()];
            assert_close(
                WeightedAverageParams.composite(&f, b),
                ExactParams.composite(&f, b),
                1e-5,
                "uniform",
            );
        }
    }
}
