//! No transparency (spec A.5 TR-CPU-5, S&A Fig. 2's "no transparency"): one hair pass with depth writes keeps
//! the nearest fragment, drawn opaque. The model takes the fragment with the smallest total key (depth bits,
//! segment); the GPU's `Less` test keeps the first rasterised of exact-depth ties, so a GPU = CPU comparison
//! skips pixels whose nearest depth is tied. No fragments: `B`.

use super::{Compositor, EyeFragment, key_order};

/// No transparency has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OpaqueParams;

impl Compositor for OpaqueParams {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        fragments
            .iter()
            .min_by(|a, b| key_order(a, b))
            .map_or(background, |f| f.color)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transparency::test_support::frag;

    #[test]
    fn nearest_colour_or_background() {
        let f = [
            frag(0.5, 4, [0.0, 1.0, 0.0], 0.1),
            frag(0.3, 9, [0.0, 0.0, 1.0], 0.1),
            frag(0.3, 2, [1.0, 0.0, 0.0], 0.1),
        ];
        // Nearest depth 0.3, tie broken by the lower segment 2; its alpha does not matter.
        assert_eq!(OpaqueParams.composite(&f, [0.5; 3]), [1.0, 0.0, 0.0]);
        assert_eq!(OpaqueParams.composite(&[], [0.5; 3]), [0.5; 3]);
    }
}
