//! Classic depth peeling (Everitt 2001; S&A's ground truth and cost baseline, spec A.5 TR-CPU-6): layer `k` is
//! the nearest fragment strictly behind layer `k − 1`'s depth, found by one geometry pass with a fresh depth
//! buffer (`Less`) that discards `z ≤ prev_z`; the layers are blended front to back `C += T a c; T *= 1 − a`,
//! then `C += T B`.
//!
//! Exact-depth ties: of the fragments sharing a depth, a layer keeps one and the strict test discards the rest
//! in every later layer. The GPU's `Less` test keeps the first one rasterised; this model keeps the one with the
//! lowest segment id (the first in the total key). Which tied fragment survives is therefore not modelled for
//! the GPU — a GPU = CPU comparison must skip pixels with exact-depth ties — but that the others are lost is:
//! the ties are the technique's measurable loss against the exact composite, which it equals otherwise.

use super::{Compositor, EyeFragment, add_scaled, front_to_back, under};

/// Classic depth peeling has no parameters (it peels until a layer is empty).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClassicPeelParams;

/// The peeled layers front to back: the nearest fragment, then each time the nearest one strictly deeper
/// than the previous layer (ties: the lowest segment). Their count is the number of geometry passes that
/// find a fragment at this pixel.
pub fn layers(fragments: &[EyeFragment]) -> Vec<EyeFragment> {
    let mut out: Vec<EyeFragment> = Vec::new();
    for f in front_to_back(fragments) {
        if out.last().is_none_or(|prev| f.depth > prev.depth) {
            out.push(f);
        }
    }
    out
}

impl Compositor for ClassicPeelParams {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let (c, t) = under(layers(fragments));
        add_scaled(c, t, background)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::transparency::ExactParams;
    use crate::transparency::test_support::{assert_close, frag, random_pixel};

    #[test]
    fn hand_computed_front_to_back() {
        // Red at 0.2 (α 0.5), green at 0.4 (α 0.5), over white: C = 0.5 R + 0.25 G + 0.25 · white.
        let f = [
            frag(0.4, 1, [0.0, 1.0, 0.0], 0.5),
            frag(0.2, 0, [1.0, 0.0, 0.0], 0.5),
        ];
        assert_eq!(ClassicPeelParams.composite(&f, [1.0; 3]), [0.75, 0.5, 0.25]);
    }

    #[test]
    fn equals_exact_when_depths_are_distinct() {
        // TT-U6, first half.
        let mut rng = SplitMix64::new(911);
        for _ in 0..300 {
            let f = random_pixel(&mut rng, 60);
            let mut depths: Vec<u32> = f.iter().map(|f| f.depth.to_bits()).collect();
            depths.sort();
            depths.dedup();
            assert_eq!(depths.len(), f.len(), "test pixels have distinct depths");
            assert_eq!(layers(&f).len(), f.len());
            let b = [rng.unit(), rng.unit(), rng.unit()];
            assert_close(
                ClassicPeelParams.composite(&f, b),
                ExactParams.composite(&f, b),
                1e-5,
                "peel vs exact",
            );
        }
    }

    #[test]
    fn loses_exactly_the_tied_duplicates() {
        // TT-U6, second half. Fragments at 0.3 (segments 5 and 2) and 0.6 (segments 4, 1, 8): the layers are
        // segment 2 at 0.3 and segment 1 at 0.6; the others are lost. α 0.5 each, over black:
        // 0.5 · c(2) + 0.25 · c(1).
        let f = [
            frag(0.6, 4, [9.0, 9.0, 9.0], 0.5),
            frag(0.3, 5, [9.0, 9.0, 9.0], 0.5),
            frag(0.6, 1, [0.0, 1.0, 0.0], 0.5),
            frag(0.3, 2, [1.0, 0.0, 0.0], 0.5),
            frag(0.6, 8, [9.0, 9.0, 9.0], 0.5),
        ];
        let kept: Vec<u32> = layers(&f).iter().map(|f| f.segment).collect();
        assert_eq!(kept, [2, 1]);
        assert_eq!(ClassicPeelParams.composite(&f, [0.0; 3]), [0.5, 0.25, 0.0]);
        // It equals the exact composite of the surviving fragments alone.
        let survivors = [f[2], f[3]];
        assert_close(
            ClassicPeelParams.composite(&f, [0.2; 3]),
            ExactParams.composite(&survivors, [0.2; 3]),
            1e-6,
            "peel vs exact of the survivors",
        );
        assert!(layers(&[]).is_empty());
    }
}
