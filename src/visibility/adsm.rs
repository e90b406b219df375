//! Approximated deep shadow maps (ADSM): the hair shadow most shipped engines use — Lacroix, "A Survivor Reborn:
//! Tomb Raider on DX11" (GDC 2013), AMD TressFX (`ComputeShadow` / `ComputeHairShadowAttenuation`), vkhr
//! (Jansson, Chajdas, Lacroix, Ragnemalm, "Real-Time Hybrid Hair Rendering", EGSR 2019). Only the nearest strand depth `z0` of the texel is stored (the shared light-depth
//! pass); the number of fibres in front of a point is estimated from a constant fibre spacing `s`:
//!
//! `n(z) = min(n_max, (z - z0) / s)`, raised to at least one fibre when `z - z0 > 1e-5` (TressFX: "if occluded
//! by hair, there is at least one fiber"), and `V(z) = (1 - alpha_s)^n = exp(-n * b(alpha_s))`.
//!
//! `n_max` caps the count as TressFX 4.x's `MaxShadowFibers` does. Units: TressFX divides a world-space depth
//! by `fiber spacing × fiber radius`; hairlab's depths are normalised
//! over the strands' fitted light range, so `s` here is that product divided by the range (a fraction of the
//! range). An empty texel (`near > far`, the light-depth pass's clear values) is lit.
//!
//! GPU: `shaders/methods/adsm.wgsl`, exactly these f32 expressions: `max(z - near, 0)`, `min(d / s, n_max)`,
//! `select(n, max(n, 1), d > 1e-5)`, `transmittance(n * optical_depth(alpha))`.

use super::{Fragment, Model, Stored, TexelModel, depth_range, optical_depth, transmittance};

/// Depth behind `z0` beyond which a point has at least one fibre in front of it (TressFX's `1e-5`).
pub const OCCLUDED_EPSILON: f32 = 1e-5;

/// ADSM parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdsmParams {
    /// Fibre spacing `s` in normalised light depth (> 0).
    pub spacing: f32,
    /// Shadow alpha `alpha_s` of one fibre, in `[0, 1)`.
    pub shadow_alpha: f32,
    /// Most fibres counted, `n_max >= 1`.
    pub max_fibres: f32,
}

impl Default for AdsmParams {
    /// TressFX 4.1's shadow alpha 0.35 and max shadow fibres 50 (`ShadowAlpha`, `MaxShadowFibers` in
    /// `TressFXConstantBuffers.h`, as O3DE's AtomTressFX gem ships them). Its fibre spacing, 0.4 × the fibre
    /// radius (0.4 × 0.0021 scene units), is in the units of TressFX's assets, which hairlab's scenes do not
    /// share: the workbench default is 64 fibres across the whole light range (`s = 1/64`).
    fn default() -> Self {
        Self {
            spacing: 1.0 / 64.0,
            shadow_alpha: 0.35,
            max_fibres: 50.0,
        }
    }
}

/// An ADSM texel: what the GPU reads of the shared light-depth maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdsmTexel {
    pub near: f32,
    pub far: f32,
}

/// The estimated number of fibres in front of depth `z`.
pub fn fibres(params: &AdsmParams, texel: &AdsmTexel, z: f32) -> f32 {
    let d = (z - texel.near).max(0.0);
    let n = (d / params.spacing).min(params.max_fibres);
    if d > OCCLUDED_EPSILON { n.max(1.0) } else { n }
}

/// `V(z)`; 1 in an empty texel.
pub fn visibility(params: &AdsmParams, texel: &AdsmTexel, z: f32) -> f32 {
    if texel.near > texel.far {
        return 1.0;
    }
    transmittance(fibres(params, texel, z) * optical_depth(params.shadow_alpha))
}

impl Model for AdsmParams {
    type Texel = AdsmTexel;

    fn build(&self, fragments: &[Fragment]) -> AdsmTexel {
        let (near, far) = depth_range(fragments);
        AdsmTexel { near, far }
    }

    fn visibility(&self, texel: &AdsmTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

impl TexelModel for AdsmParams {
    fn label(&self) -> String {
        format!("adsm s{:.4}", self.spacing)
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        vec![self.build(fragments).near]
    }

    /// The fibre ramp: a knot at `z0` and at each whole fibre up to `n_max` (or the texel's far depth).
    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        let t = self.build(fragments);
        let mut s = Stored::new(self.label());
        if t.near > t.far {
            return Some(s);
        }
        s.boundaries.push(t.near);
        s.knots.push([t.near, 1.0]);
        let last = self
            .max_fibres
            .min(((t.far - t.near) / self.spacing).ceil())
            .max(1.0) as u32;
        for k in 1..=last.min(256) {
            let z = t.near + k as f32 * self.spacing;
            s.knots.push([z, visibility(self, &t, z)]);
        }
        s.summary.push(format!(
            "z0 = {:.4}; fibre spacing {:.4}, shadow alpha {:.2}, at most {} fibres (V floor {:.4})",
            t.near,
            self.spacing,
            self.shadow_alpha,
            self.max_fibres,
            transmittance(self.max_fibres * optical_depth(self.shadow_alpha))
        ));
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> AdsmParams {
        AdsmParams {
            spacing: 0.1,
            shadow_alpha: 0.5,
            max_fibres: 3.0,
        }
    }

    #[test]
    fn hand_computed_fibre_counts_and_visibility() {
        let t = AdsmTexel { near: 0.2, far: 0.9 };
        // In front of and at z0: no fibre, lit.
        assert_eq!(visibility(&p(), &t, 0.1), 1.0);
        assert_eq!(visibility(&p(), &t, 0.2), 1.0);
        // Just behind z0: at least one fibre, V = 1/2.
        assert!((visibility(&p(), &t, 0.201) - 0.5).abs() < 1e-6);
        // 2.5 fibres at z0 + 0.25: V = 2^-2.5.
        assert!((fibres(&p(), &t, 0.45) - 2.5).abs() < 1e-5);
        assert!((visibility(&p(), &t, 0.45) - 2f32.powf(-2.5)).abs() < 1e-6);
        // Capped at n_max = 3: V = 1/8 however deep.
        assert!((visibility(&p(), &t, 0.9) - 0.125).abs() < 1e-6);
        assert!((visibility(&p(), &t, 5.0) - 0.125).abs() < 1e-6);
    }

    #[test]
    fn empty_texel_is_lit_and_the_model_reads_only_the_nearest_depth() {
        assert_eq!(p().curve(&[], &[0.0, 0.5, 1.0]), [1.0, 1.0, 1.0]);
        let a = [Fragment::new(0.3, 0.9), Fragment::new(0.8, 0.1)];
        let b = [
            Fragment::new(0.3, 0.1),
            Fragment::new(0.5, 0.7),
            Fragment::new(0.8, 0.2),
        ];
        let zs = [0.35, 0.5, 0.7, 0.8];
        assert_eq!(
            p().curve(&a, &zs),
            p().curve(&b, &zs),
            "same near and far, same curve"
        );
    }

    #[test]
    fn curves_are_valid() {
        use crate::visibility::test_support::{Rng, assert_valid_curve, random_texel};
        let mut rng = Rng::new(41);
        for _ in 0..200 {
            let f = random_texel(&mut rng, 40);
            assert_valid_curve(&AdsmParams::default(), &f, "adsm");
        }
    }
}
