//! TressFX ShortCut-style blending (spec A.12: the K nearest exact, the rest approximate): the `K` nearest
//! fragments of the total key are blended exactly front to back; the remaining ones ("the tail") are one layer
//! behind them with their alpha-weighted average colour and coverage `1 − Π(1 − a)` of the tail; the background
//! is covered by `Π(1 − a)` of all fragments:
//! ```text
//! front = the K nearest (key order),  (C, T) = under(front)            // C += T a c; T *= 1 − a
//! tail (the others, in the order given): S = Σ a c, A = Σ a, P = Π (1 − a)
//! if A > 0 { C += T · (1 − P) · S / A }
//! C += Π_all (1 − a) · B                                              // all fragments, in the order given
//! ```
//! With `average_front` the K nearest are averaged instead, TressFX 4.x's ShortCut as it ships:
//! `C = (Σ_front a c / Σ_front a) · (1 − Π_all) + B Π_all`.
//!
//! What TressFX 4.x does (AMD's `TressFXShortCut.hlsl`, four passes): (1) a depth-only geometry pass keeps the
//! three nearest depths per pixel with an `InterlockedMin` insertion chain (each step passes the larger of the
//! old and new value on) and multiplies `1 − alpha` of every fragment into a target; (2) a full-screen pass
//! writes the third-nearest depth into the depth buffer; (3) a shading pass with a `LessEqual` test shades only
//! the fragments up to that depth, adding `(c a, a)`; (4) the resolve divides the colour sum by the alpha sum
//! and blends it with coverage `1 − Π(1 − alpha)` over the background. So the shipping ShortCut averages the
//! K = 3 nearest without ordering them, and the fragments behind them add only coverage — `average_front`
//! matches that, except that ties at the K-th depth are kept apart here by the segment (all pass the `LessEqual`
//! test there) and TressFX's `SHORTCUT_MIN_ALPHA` cut and its early exit for near-opaque fragments are not
//! modelled. The default (the K nearest in order, the tail as a weighted layer behind them) is the k-buffer idea
//! of TressFX's per-pixel-linked-list path and of hybrid transparency (Maule et al. 2013), with an
//! order-independent tail, so that a GPU version needs only the `atomicMin` chain for the K keys and additive
//! targets.

use super::{Compositor, EyeFragment, add_scaled, front_to_back, ranks, under};

/// Smallest and largest `k`.
pub const K_RANGE: [u32; 2] = [1, 8];

/// Parameters of ShortCut blending.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShortcutParams {
    /// Fragments blended exactly (clamped to [`K_RANGE`]).
    pub k: u32,
    /// Average the K nearest too (TressFX 4.x's ShortCut as shipped) instead of blending them in order.
    pub average_front: bool,
}

impl Default for ShortcutParams {
    /// TressFX's K = 3, nearest fragments in order.
    fn default() -> Self {
        Self {
            k: 3,
            average_front: false,
        }
    }
}

impl ShortcutParams {
    /// `k` clamped to [`K_RANGE`].
    pub fn k(&self) -> usize {
        self.k.clamp(K_RANGE[0], K_RANGE[1]) as usize
    }
}

/// `(Σ a c, Σ a, Π (1 − a))` of `fragments`, in their order.
fn sums<'a>(fragments: impl Iterator<Item = &'a EyeFragment>) -> ([f32; 3], f32, f32) {
    fragments.fold(([0.0f32; 3], 0.0f32, 1.0f32), |(mut s, a, p), f| {
        for (si, ci) in s.iter_mut().zip(f.color) {
            *si += f.alpha * ci;
        }
        (s, a + f.alpha, p * (1.0 - f.alpha))
    })
}

impl Compositor for ShortcutParams {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let k = self.k();
        let (_, _, transmittance_all) = sums(fragments.iter());
        let rank = ranks(fragments);
        let (front, tail): (Vec<_>, Vec<_>) = fragments.iter().zip(&rank).partition(|(_, r)| **r < k);
        let (front, tail) = (
            front.into_iter().map(|(f, _)| f),
            tail.into_iter().map(|(f, _)| f),
        );
        let c = if self.average_front {
            let (s, a, _) = sums(front);
            if a > 0.0 {
                let coverage = 1.0 - transmittance_all;
                std::array::from_fn(|i| s[i] / a * coverage)
            } else {
                [0.0; 3]
            }
        } else {
            let (mut c, t) = under(front_to_back(fragments).into_iter().take(k));
            let (s, a, p) = sums(tail);
            if a > 0.0 {
                let cover = t * (1.0 - p);
                for (ci, si) in c.iter_mut().zip(s) {
                    *ci += cover * si / a;
                }
            }
            c
        };
        add_scaled(c, transmittance_all, background)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::transparency::ExactParams;
    use crate::transparency::test_support::{assert_close, frag, random_pixel};

    fn four() -> [EyeFragment; 4] {
        // Front to back: red, green, blue, white, α 0.5 each (input order shuffled).
        [
            frag(0.8, 3, [1.0, 1.0, 1.0], 0.5),
            frag(0.2, 0, [1.0, 0.0, 0.0], 0.5),
            frag(0.6, 2, [0.0, 0.0, 1.0], 0.5),
            frag(0.4, 1, [0.0, 1.0, 0.0], 0.5),
        ]
    }

    #[test]
    fn hand_computed_k2() {
        // Front (red, green): C = 0.5 R + 0.25 G, T = 0.25. Tail (blue, white): S = (0.5, 0.5, 1), A = 1,
        // P = 0.25: C += 0.25 · 0.75 · (0.5, 0.5, 1) = (0.09375, 0.09375, 0.1875). Over black:
        // (0.59375, 0.34375, 0.1875); exact would be (0.5625, 0.3125, 0.1875).
        let p = ShortcutParams {
            k: 2,
            average_front: false,
        };
        assert_close(
            p.composite(&four(), [0.0; 3]),
            [0.59375, 0.34375, 0.1875],
            1e-7,
            "k = 2",
        );
        // Over white, + Π(1 − a) = 1/16.
        assert_close(
            p.composite(&four(), [1.0; 3]),
            [0.65625, 0.40625, 0.25],
            1e-7,
            "k = 2 over white",
        );
    }

    #[test]
    fn hand_computed_tressfx_average() {
        // The two nearest averaged: (0.5 R + 0.5 G) / 1 = (0.5, 0.5, 0), coverage 1 − 1/16 = 0.9375.
        let p = ShortcutParams {
            k: 2,
            average_front: true,
        };
        assert_close(
            p.composite(&four(), [0.0; 3]),
            [0.46875, 0.46875, 0.0],
            1e-7,
            "average front",
        );
    }

    #[test]
    fn k_at_least_n_is_exact_and_k_is_clamped() {
        let mut rng = SplitMix64::new(951);
        for _ in 0..200 {
            let f = random_pixel(&mut rng, 8);
            let b = [rng.unit(), rng.unit(), rng.unit()];
            let p = ShortcutParams {
                k: 8,
                average_front: false,
            };
            assert_close(p.composite(&f, b), ExactParams.composite(&f, b), 1e-5, "k >= n");
        }
        assert_eq!(
            ShortcutParams {
                k: 0,
                average_front: false
            }
            .k(),
            1
        );
        assert_eq!(
            ShortcutParams {
                k: 99,
                average_front: false
            }
            .k(),
            8
        );
        // k = 1 on the four: red exact in front (C = 0.5 R, T = 0.5); the tail green, blue, white has
        // S = (0.5, 1, 1), A = 1.5, P = 1/8: C += 0.5 · 0.875 · (1/3, 2/3, 2/3).
        let p = ShortcutParams {
            k: 0,
            average_front: false,
        };
        assert_close(
            p.composite(&four(), [0.0; 3]),
            [0.645_833_3, 0.291_666_7, 0.291_666_7],
            1e-6,
            "k clamped to 1",
        );
    }

    #[test]
    fn empty_is_background() {
        assert_eq!(ShortcutParams::default().composite(&[], [0.3; 3]), [0.3; 3]);
    }
}
