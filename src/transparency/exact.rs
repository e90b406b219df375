//! The exact composite, the reference every technique is measured against (spec A.5 TR-CPU-1): the fragments
//! sorted on the total key (depth bits, segment), then blended back to front with `C ← a c + (1 − a) C` from
//! `C = B` — what the `sorted` technique's resolve does with a pixel's list.

use super::{Compositor, EyeFragment, front_to_back};

/// The exact technique has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExactParams;

impl Compositor for ExactParams {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let mut c = background;
        for f in front_to_back(fragments).iter().rev() {
            for (ci, fi) in c.iter_mut().zip(f.color) {
                *ci = f.alpha * fi + (1.0 - f.alpha) * *ci;
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::transparency::test_support::{assert_close, frag, random_pixel};
    use crate::transparency::under;

    #[test]
    fn three_fragments_match_the_papers_expansion() {
        // TT-U1: α = 0.5, red nearest, then green, then blue, over black. S&A §3.4 back to front
        // (c0 = blue furthest): f = α c2 + (1 − α)(α c1 + (1 − α)(α c0 + (1 − α) b)) = (0.5, 0.25, 0.125).
        let f = [
            frag(0.9, 2, [0.0, 0.0, 1.0], 0.5),
            frag(0.1, 0, [1.0, 0.0, 0.0], 0.5),
            frag(0.5, 1, [0.0, 1.0, 0.0], 0.5),
        ];
        assert_eq!(ExactParams.composite(&f, [0.0; 3]), [0.5, 0.25, 0.125]);
        // Over a white background the remaining transmittance 1/8 shows in every channel.
        assert_eq!(ExactParams.composite(&f, [1.0; 3]), [0.625, 0.375, 0.25]);
    }

    #[test]
    fn ties_are_ordered_by_segment() {
        // Same depth: segment 3 is in front of segment 7. α = 0.5 each over black:
        // 0.5 · c(3) + 0.25 · c(7).
        let f = [
            frag(0.5, 7, [0.0, 1.0, 0.0], 0.5),
            frag(0.5, 3, [1.0, 0.0, 0.0], 0.5),
        ];
        assert_eq!(ExactParams.composite(&f, [0.0; 3]), [0.5, 0.25, 0.0]);
    }

    #[test]
    fn no_fragments_is_the_background() {
        assert_eq!(ExactParams.composite(&[], [0.2, 0.3, 0.4]), [0.2, 0.3, 0.4]);
    }

    #[test]
    fn order_of_input_does_not_matter_and_front_to_back_agrees() {
        let mut rng = SplitMix64::new(901);
        for _ in 0..200 {
            let mut f = random_pixel(&mut rng, 40);
            let b = [rng.unit(), rng.unit(), rng.unit()];
            let c = ExactParams.composite(&f, b);
            f.reverse();
            assert_eq!(ExactParams.composite(&f, b), c);
            // The front-to-back form of the same sum (S&A §3.4) agrees up to f32 rounding.
            let (u, t) = under(front_to_back(&f));
            let ftb = [u[0] + t * b[0], u[1] + t * b[1], u[2] + t * b[2]];
            assert_close(c, ftb, 1e-5, "back to front vs front to back");
        }
    }
}
