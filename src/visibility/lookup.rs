//! CPU model of the eye lookup `hair_visibility` (`shaders/common/method_lookup.wgsl`): which light-map
//! texels a shaded point's visibility averages, under light-map supersampling (Yuksel & Keyser 2008, §5:
//! multisampling the shadow computation against the flicker of aliased strands) and 3×3 PCF.
//!
//! The light maps are built at `side = base × s` texels a side. A point at light-map coordinate `uv` in
//! `[0, 1)²` falls in the base texel `b = clamp(floor(uv · base), 0, base − 1)`; its visibility is
//!
//! ```text
//! V_s(b, z) = (1 / s²) · Σ_{i, j < s} V(s·b + (i, j), z)
//! ```
//!
//! the method's `V` averaged over the `s × s` texels of the maps as built that make up `b` (the point
//! integrates `s²` light rays over its own texel's footprint), and with PCF the mean of `V_s` over the 3×3 base
//! texels around `b`, each clamped to the map. A point outside `[0, 1)²` is lit (`V = 1`). Half-texel jitter
//! moves `uv` before this step, by a hash of the point's bits; the model takes `uv` after it.

use glam::Vec2;

/// The eye lookup's texel choice: the base resolution, the supersampling factor and the PCF filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lookup {
    /// Texels a side of the base grid (`render.map_resolution`).
    pub base: u32,
    /// Sub-texels a side of each base texel (`render.light_supersample`, at least 1).
    pub supersample: u32,
    /// 3×3 percentage-closer filtering over base texels (`render.pcf`).
    pub pcf: bool,
}

impl Lookup {
    /// Texels a side of the maps as built, `base × supersample`.
    pub fn side(&self) -> u32 {
        self.base * self.supersample.max(1)
    }

    /// The base texel of `uv`, `None` outside `[0, 1)²` (the point is lit).
    pub fn base_texel(&self, uv: Vec2) -> Option<[u32; 2]> {
        if uv.x < 0.0 || uv.y < 0.0 || uv.x >= 1.0 || uv.y >= 1.0 || self.base == 0 {
            return None;
        }
        let last = (self.base - 1) as f32;
        let b = (uv * self.base as f32)
            .floor()
            .clamp(Vec2::ZERO, Vec2::splat(last));
        Some([b.x as u32, b.y as u32])
    }

    /// Texels (`[x, y]` of the maps as built) whose visibility the lookup averages for a point in base texel
    /// `b`, each with equal weight. A texel appears more than once when the PCF neighbourhood is clamped at the
    /// border, as on the GPU.
    pub fn around(&self, b: [u32; 2]) -> Vec<[u32; 2]> {
        let s = self.supersample.max(1);
        let last = self.base as i32 - 1;
        let reach = i32::from(self.pcf);
        let mut out = Vec::with_capacity(((2 * reach + 1) as usize).pow(2) * (s * s) as usize);
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let x = (b[0] as i32 + dx).clamp(0, last) as u32;
                let y = (b[1] as i32 + dy).clamp(0, last) as u32;
                for j in 0..s {
                    for i in 0..s {
                        out.push([x * s + i, y * s + j]);
                    }
                }
            }
        }
        out
    }

    /// [`Lookup::around`] the base texel of `uv`; empty outside the map.
    pub fn texels(&self, uv: Vec2) -> Vec<[u32; 2]> {
        self.base_texel(uv).map_or_else(Vec::new, |b| self.around(b))
    }

    /// The lookup's visibility at `uv` and light depth `z`, from `at(texel, z)`: the method's visibility at a
    /// texel of the maps as built (its CPU model on that texel's fragments).
    pub fn visibility(&self, uv: Vec2, z: f32, mut at: impl FnMut([u32; 2], f32) -> f32) -> f32 {
        let texels = self.texels(uv);
        if texels.is_empty() {
            return 1.0;
        }
        texels.iter().map(|&t| at(t, z)).sum::<f32>() / texels.len() as f32
    }
}

#[cfg(test)]
mod tests {
    use super::{Lookup, Vec2};

    /// The base texel (1, 2) of a 4² grid at s = 2 is the sub-texels x 2..=3, y 4..=5 of the 8² maps; a point
    /// outside the map is lit.
    #[test]
    fn supersampled_texels_cover_the_base_texel() {
        let l = Lookup {
            base: 4,
            supersample: 2,
            pcf: false,
        };
        assert_eq!(l.side(), 8);
        assert_eq!(
            l.texels(Vec2::new(0.3, 0.6)),
            vec![[2, 4], [3, 4], [2, 5], [3, 5]]
        );
        assert!(l.texels(Vec2::new(1.0, 0.5)).is_empty());
        assert_eq!(l.visibility(Vec2::new(-0.1, 0.5), 0.5, |_, _| 0.0), 1.0);
        // V = x / 8 over the four sub-texels: (2 + 3 + 2 + 3) / 32.
        let v = l.visibility(Vec2::new(0.3, 0.6), 0.5, |t, _| t[0] as f32 / 8.0);
        assert_eq!(v, 10.0 / 32.0);
    }

    /// At s = 1 the lookup reads the point's texel alone; with PCF at a corner the clamped 3×3 neighbourhood
    /// repeats the border texels (texel (0, 0) four times, (1, 0) and (0, 1) twice, (1, 1) once).
    #[test]
    fn plain_and_pcf_lookups() {
        let plain = Lookup {
            base: 4,
            supersample: 1,
            pcf: false,
        };
        assert_eq!(plain.texels(Vec2::new(0.3, 0.6)), vec![[1, 2]]);
        let pcf = Lookup { pcf: true, ..plain };
        let t = pcf.texels(Vec2::new(0.01, 0.01));
        assert_eq!(t.len(), 9);
        let count = |x: [u32; 2]| t.iter().filter(|&&u| u == x).count();
        assert_eq!(
            [count([0, 0]), count([1, 0]), count([0, 1]), count([1, 1])],
            [4, 2, 2, 1]
        );
        let s2 = Lookup {
            supersample: 2,
            ..pcf
        };
        assert_eq!(s2.texels(Vec2::new(0.01, 0.01)).len(), 36);
    }
}
