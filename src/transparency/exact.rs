//! The exact composite (the reference): fragments sorted front to back on (depth, segment), composited back to
//! front, `C = a c + (1 - a) C` from `C = B`.

use super::{Compositor, EyeFragment, front_to_back};

pub struct Exact;

impl Compositor for Exact {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        front_to_back(fragments).iter().rev().fold(background, |c, f| {
            std::array::from_fn(|i| f.alpha * f.color[i] + (1.0 - f.alpha) * c[i])
        })
    }
}
