//! Model of weighted blended OIT (McGuire & Bavoil 2013) exactly as `shaders/transparency/wboit*.wgsl` compute it.

use super::{Compositor, EyeFragment};

pub struct Wboit {
    /// Round the accumulation and revealage to f16 after every fragment (the Rgba16Float/R16Float targets).
    pub half_precision: bool,
}

impl Compositor for Wboit {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3] {
        let round = |x: f32| {
            if self.half_precision {
                half::f16::from_f32(x).to_f32()
            } else {
                x
            }
        };
        let mut acc = [0.0f32; 4];
        let mut reveal = 1.0f32;
        for f in fragments {
            let w = f.alpha * (2.0 - f.depth).max(0.0).powf(8.0).clamp(1e-2, 3e3);
            for (a, c) in acc.iter_mut().zip(f.color) {
                *a = round(*a + c * f.alpha * w);
            }
            acc[3] = round(acc[3] + f.alpha * w);
            reveal = round(reveal * (1.0 - f.alpha));
        }
        if acc[3] <= 1e-6 {
            return background;
        }
        let a = 1.0 - reveal;
        std::array::from_fn(|c| acc[c] / acc[3].max(1e-6) * a + background[c] * (1.0 - a))
    }
}
