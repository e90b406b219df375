//! Deep Opacity Maps (Yuksel & Keyser, Eurographics 2008, §3; also Voicu's thesis §4).
//!
//! Per texel, `z0` is the depth of the nearest fragment (the depth map of the first pass). `K` layers
//! (1..=16, the paper uses 3: one RGBA target holding `z0` and three layers) follow it: layer `k` (1-based)
//! lies from `z0 + d_(k-1)` to `z0 + d_k`, `d_0 = 0`, `d_(k-1) < d_k`. The same `d_k` are used for every
//! texel. A fragment adds its optical depth to the layer it falls in and to all the later layers (additive
//! blending), so layer `k` stores the optical depth accumulated up to its far end `z0 + d_k`.
//!
//! Layer sizes ([`LayerSpacing`]): the paper's examples use linearly increasing layer sizes (§5): size of
//! layer `k` proportional to `k`, so `d_k = d * k (k + 1) / (K (K + 1))`; uniform sizes `d_k = d * k / K` are
//! offered too, and Unreal Engine's groom deep shadow layers ([`LayerSpacing::Unreal`]): `K = 4` layers ending
//! at `d × (0.02, 0.1, 0.4, 1)` — `HairStrandsDeepShadowCommon.ush`'s `LAYER_DEPTH0..3` = 0.01, 0.05, 0.2,
//! 0.5 of the light's clip depth, which Unreal fits to the groom's bounds as hairlab fits its light range, so
//! Unreal's own configuration is `d = 0.5` with fragments beyond the last layer ignored (its
//! `ComputeDOMWeights` gives them no layer) and the same interpolated lookup (`ComputeHairCount`). `d` =
//! [`DomParams::depth_span`] is the total depth of the `K` layers in normalised light depth. The paper gives no value (its `d_k` are in scene units per model); the default 0.25 (a quarter of
//! the fitted light range) is this workbench's choice, to be tuned per scene.
//!
//! Fragments beyond the last layer (`z >= z0 + d_K`, §3, [`BeyondLastLayer`]): ignore them (they cast no
//! shadow), add them to the last layer (the paper's choice: "mapping these points onto the last layer usually
//! gave reasonable results"; the default), or stretch the layers to cover the texel's far depth (the paper's
//! third option "ensure that the last layer lies beyond the hair volume ... by increasing the layer sizes",
//! done per texel with the far depth of the light-depth pass: every `d_k` is scaled by
//! `max(1, (far - z0) / d_K)`).
//!
//! Lookup: as in opacity shadow maps (§2, "linear interpolation of the occlusion values at the neighboring
//! slices"), but between the per-texel layer boundaries, i.e. inside the hair volume (§5). The value at `z0`
//! is 0; beyond the last layer it is the last layer's value.
//!
//! Exact: `V(z) = 1` for every `z <= z0` (the paper's guarantee that unshadowed direct illumination is
//! captured correctly), and `V` at each layer boundary when every fragment lies within the layers.
//! Approximate: inside the layers (interpolation), and beyond the last layer (ignored fragments, or fragments
//! lumped into the last layer that shadow points in front of them).
//!
//! GPU contract (per texel: `z0 = near`, `far` (Stretch only), `K` f32 layer values):
//! - `d_k` come from a uniform filled with [`layer_ends`] (not recomputed in the shader), `dK = d_K`;
//! - `scale = 1.0` for Ignore/AddToLast, `scale = max(1.0, (far - near) / dK)` for Stretch;
//! - build, per fragment: `dz = z - near`; its layer is the first `k` (0-based) with `dz < scale * d[k]`;
//!   with none: Ignore drops the fragment, AddToLast and Stretch use `K - 1` (for Stretch this only catches
//!   rounding at `far`); add `b` to layers `k..K` (by additive blending, or in fixed point with atomics and a
//!   resolve into the chosen storage: [`build_with`], `visibility::opacity_layers`);
//! - lookup: `dz = z - near`; if `!(dz > 0.0)`: `V = 1`; else the first `k` with `dz < scale * d[k]`:
//!   `lo = select(0.0, scale * d[max(k, 1u) - 1u], k > 0u)`, `f = (dz - lo) / (scale * d[k] - lo)`,
//!   `prev = select(0.0, L[max(k, 1u) - 1u], k > 0u)`, `omega = min(prev + (L[k] - prev) * f, L[k])`; with no
//!   such `k`, `omega = L[K - 1]`; `V = exp(-omega)`.

use super::opacity_layers::{LayerBuild, LayeredModel, accumulate};
use super::{Fragment, Model, Stored, TexelModel, depth_range, lerp_up, list, transmittance, valid};

/// Largest number of layers.
pub const MAX_LAYERS: u32 = 16;
/// Smallest and largest depth span `d` (normalised light depth).
pub const DEPTH_SPAN_RANGE: (f32, f32) = (1e-4, 1.0);

/// How layer sizes grow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LayerSpacing {
    /// Layer `k` has size proportional to `k` (Yuksel & Keyser §5, used for all their examples).
    #[default]
    LinearlyIncreasing,
    /// All layers have size `d / K`.
    Uniform,
    /// Unreal Engine's four groom deep shadow layers, ending at `d ×` [`UNREAL_LAYER_FRACTIONS`] (the layer
    /// count is 4 whatever [`DomParams::layers`] says).
    Unreal,
}

/// Unreal Engine's deep shadow layer ends as fractions of the last: `LAYER_DEPTH0..3` = 0.01, 0.05, 0.2, 0.5
/// (`Engine/Shaders/Private/HairStrands/HairStrandsDeepShadowCommon.ush`) divided by 0.5.
pub const UNREAL_LAYER_FRACTIONS: [f32; 4] = [0.02, 0.1, 0.4, 1.0];

/// What happens to fragments beyond the last layer (Yuksel & Keyser §3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BeyondLastLayer {
    /// They cast no shadow.
    Ignore,
    /// They are added to the last layer (and so shadow themselves); the paper's choice.
    #[default]
    AddToLast,
    /// The layers of each texel are scaled to reach the texel's far depth when they would end before it.
    Stretch,
}

/// Deep Opacity Map parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DomParams {
    /// Number of layers `K`, clamped to `1..=16`.
    pub layers: u32,
    /// Total depth `d = d_K` of the layers in normalised light depth, clamped to `[1e-4, 1]` (NaN: default).
    pub depth_span: f32,
    pub spacing: LayerSpacing,
    pub beyond: BeyondLastLayer,
}

impl Default for DomParams {
    /// 3 layers (Yuksel & Keyser §3: three layers in one RGBA target with the depth; used in all their
    /// figures), linearly increasing sizes, fragments beyond the last layer added to it, `d = 0.25`
    /// (workbench choice).
    fn default() -> Self {
        Self {
            layers: 3,
            depth_span: 0.25,
            spacing: LayerSpacing::LinearlyIncreasing,
            beyond: BeyondLastLayer::AddToLast,
        }
    }
}

impl DomParams {
    /// The layer count actually used: `layers` clamped to `1..=16`; 4 with [`LayerSpacing::Unreal`].
    pub fn layer_count(&self) -> usize {
        match self.spacing {
            LayerSpacing::Unreal => UNREAL_LAYER_FRACTIONS.len(),
            _ => self.layers.clamp(1, MAX_LAYERS) as usize,
        }
    }

    /// The depth span actually used: `depth_span` clamped to `[1e-4, 1]`, the default 0.25 when NaN.
    pub fn span(&self) -> f32 {
        if self.depth_span.is_nan() {
            Self::default().depth_span
        } else {
            self.depth_span.clamp(DEPTH_SPAN_RANGE.0, DEPTH_SPAN_RANGE.1)
        }
    }
}

/// Layer far ends `[d_1, ..., d_K]` relative to `z0` (`d_0 = 0` is implicit), in f32 exactly as the GPU must
/// use them: linearly increasing `d * (k (k + 1)) as f32 / (K (K + 1)) as f32`, uniform
/// `d * k as f32 / K as f32`, Unreal `d * UNREAL_LAYER_FRACTIONS[k - 1]`. `d_K = d` exactly in all three.
pub fn layer_ends(params: &DomParams) -> Vec<f32> {
    let (ends, k_count) = ends_array(params);
    ends[..k_count].to_vec()
}

/// [`layer_ends`] in a fixed array (no allocation per lookup), with the layer count.
fn ends_array(params: &DomParams) -> ([f32; MAX_LAYERS as usize], usize) {
    let k_count = params.layer_count();
    let d = params.span();
    let mut ends = [0.0; MAX_LAYERS as usize];
    for (i, e) in ends[..k_count].iter_mut().enumerate() {
        let k = i + 1;
        *e = match params.spacing {
            LayerSpacing::LinearlyIncreasing => d * ((k * (k + 1)) as f32 / (k_count * (k_count + 1)) as f32),
            LayerSpacing::Uniform => d * (k as f32 / k_count as f32),
            LayerSpacing::Unreal => d * UNREAL_LAYER_FRACTIONS[i],
        };
    }
    (ends, k_count)
}

/// One DOM texel: `z0 = near`, `far` (only read by [`BeyondLastLayer::Stretch`]), and `layers[k]`, the
/// optical depth accumulated up to the far end of layer `k`.
#[derive(Clone, Debug, PartialEq)]
pub struct DomTexel {
    pub near: f32,
    pub far: f32,
    pub layers: Vec<f32>,
}

/// Scale applied to every `d_k` of a texel: `max(1, (far - near) / d_K)` for Stretch, else 1.
fn scale(params: &DomParams, ends: &[f32], near: f32, far: f32) -> f32 {
    match (params.beyond, ends.last()) {
        (BeyondLastLayer::Stretch, Some(&d_last)) => ((far - near) / d_last).max(1.0),
        _ => 1.0,
    }
}

/// Index of the first layer whose (scaled) far end lies beyond `dz`.
fn layer_of(dz: f32, ends: &[f32], scale: f32) -> Option<usize> {
    ends.iter().position(|&e| dz < scale * e)
}

/// Builds a DOM texel: each fragment adds `b` to its layer and all later ones (the colour-target build).
pub fn build(params: &DomParams, fragments: &[Fragment]) -> DomTexel {
    build_with(params, LayerBuild::Targets, fragments)
}

/// Builds a DOM texel the way `layers` does (`visibility::opacity_layers`).
pub fn build_with(params: &DomParams, layers: LayerBuild, fragments: &[Fragment]) -> DomTexel {
    let (near, far) = depth_range(fragments);
    let (ends, k_count) = ends_array(params);
    let ends = &ends[..k_count];
    let s = scale(params, ends, near, far);
    let entries = valid(fragments).filter_map(|f| {
        let k = match (layer_of(f.depth - near, ends, s), params.beyond) {
            (Some(k), _) => k,
            (None, BeyondLastLayer::Ignore) => return None,
            (None, _) => ends.len() - 1,
        };
        Some((k, f.optical_depth()))
    });
    DomTexel {
        near,
        far,
        layers: accumulate(layers, ends.len(), entries),
    }
}

/// `V(z)`: 1 up to `z0`, then linear interpolation between the layer boundaries. A texel whose layer count is
/// not the parameters' casts no shadow.
pub fn visibility(params: &DomParams, texel: &DomTexel, z: f32) -> f32 {
    let (ends, k_count) = ends_array(params);
    let ends = &ends[..k_count];
    let dz = z - texel.near;
    if dz.is_nan() || dz <= 0.0 || texel.layers.len() != ends.len() {
        return 1.0;
    }
    let s = scale(params, ends, texel.near, texel.far);
    let omega = match layer_of(dz, ends, s) {
        Some(k) => {
            let lo = if k == 0 { 0.0 } else { s * ends[k - 1] };
            let f = (dz - lo) / (s * ends[k] - lo);
            let prev = if k == 0 { 0.0 } else { texel.layers[k - 1] };
            lerp_up(prev, texel.layers[k], f)
        }
        None => texel.layers[ends.len() - 1],
    };
    transmittance(omega)
}

impl Model for DomParams {
    type Texel = DomTexel;

    fn build(&self, fragments: &[Fragment]) -> DomTexel {
        build(self, fragments)
    }

    fn visibility(&self, texel: &DomTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

impl TexelModel for DomParams {
    fn label(&self) -> String {
        format!("dom-{}", self.layer_count())
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        build(self, fragments).layers
    }

    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        Some(self.describe(&build(self, fragments), self.label()))
    }
}

impl LayeredModel for DomParams {
    fn build_with(&self, build: LayerBuild, fragments: &[Fragment]) -> DomTexel {
        build_with(self, build, fragments)
    }

    fn entries(texel: &DomTexel) -> &[f32] {
        &texel.layers
    }

    fn describe(&self, t: &DomTexel, label: String) -> Stored {
        let ends = layer_ends(self);
        let scale = match (self.beyond, ends.last()) {
            (BeyondLastLayer::Stretch, Some(&d)) => ((t.far - t.near) / d).max(1.0),
            _ => 1.0,
        };
        let mut s = Stored::new(label);
        s.boundaries.push(t.near);
        s.knots.push([t.near, 1.0]);
        for (e, b) in ends.iter().zip(&t.layers) {
            s.boundaries.push(t.near + scale * e);
            s.knots.push([t.near + scale * e, transmittance(*b)]);
        }
        s.summary.push(format!(
            "start depth z0 = {:.4}; {} layers to z0 + {:.4}",
            t.near,
            ends.len(),
            scale * ends.last().copied().unwrap_or(0.0)
        ));
        s.summary
            .push(format!("layer optical depths {}", list(&t.layers)));
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::reference;
    use crate::visibility::test_support::{Rng, assert_valid_curve, extreme_texels, random_texel};
    use std::f32::consts::LN_2;

    fn p(layers: u32, depth_span: f32, spacing: LayerSpacing, beyond: BeyondLastLayer) -> DomParams {
        DomParams {
            layers,
            depth_span,
            spacing,
            beyond,
        }
    }

    fn close(a: &[f32], b: &[f32], tol: f32) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn layer_ends_hand_computed() {
        // Linearly increasing, K = 3, d = 0.3: sizes 1:2:3 of 0.3/6 = 0.05 -> ends 0.05, 0.15, 0.3.
        let e = layer_ends(&p(
            3,
            0.3,
            LayerSpacing::LinearlyIncreasing,
            BeyondLastLayer::AddToLast,
        ));
        assert!(close(&e, &[0.05, 0.15, 0.3], 1e-7));
        assert_eq!(e[2], 0.3);
        // Uniform, K = 4, d = 1: 0.25, 0.5, 0.75, 1.
        let e = layer_ends(&p(4, 1.0, LayerSpacing::Uniform, BeyondLastLayer::AddToLast));
        assert_eq!(e, [0.25, 0.5, 0.75, 1.0]);
        // Unreal: four layers at 0.01, 0.05, 0.2 and 0.5 of the range with d = 0.5, whatever the layer count.
        let e = layer_ends(&p(9, 0.5, LayerSpacing::Unreal, BeyondLastLayer::Ignore));
        assert_eq!(e, [0.01, 0.05, 0.2, 0.5]);
        // K = 1: one layer of size d in both spacings.
        assert_eq!(
            layer_ends(&p(
                1,
                0.2,
                LayerSpacing::LinearlyIncreasing,
                BeyondLastLayer::Ignore
            )),
            [0.2]
        );
        // Clamping: K 0 -> 1, 99 -> 16; d 0 -> 1e-4, 7 -> 1, NaN -> 0.25.
        assert_eq!(
            layer_ends(&p(0, 7.0, LayerSpacing::Uniform, BeyondLastLayer::Ignore)),
            [1.0]
        );
        assert_eq!(
            layer_ends(&p(99, 0.0, LayerSpacing::Uniform, BeyondLastLayer::Ignore)).len(),
            16
        );
        assert_eq!(
            p(3, 0.0, LayerSpacing::Uniform, BeyondLastLayer::Ignore).span(),
            1e-4
        );
        assert_eq!(
            p(3, f32::NAN, LayerSpacing::Uniform, BeyondLastLayer::Ignore).span(),
            0.25
        );
    }

    // Five fragments, alpha 0.5 (b = ln 2), at 0.2 (= z0), 0.22, 0.3, 0.45, 0.9: offsets dz = 0, 0.02, 0.1,
    // 0.25, 0.7 from z0. With K = 3, d = 0.3, linearly increasing (ends 0.05, 0.15, 0.3): layers 0, 0, 1, 2
    // and the last one beyond.
    fn texel() -> Vec<Fragment> {
        [0.45, 0.2, 0.9, 0.22, 0.3]
            .iter()
            .map(|&z| Fragment::new(z, 0.5))
            .collect()
    }

    #[test]
    fn hand_computed_add_to_last() {
        let params = p(
            3,
            0.3,
            LayerSpacing::LinearlyIncreasing,
            BeyondLastLayer::AddToLast,
        );
        let t = build(&params, &texel());
        assert_eq!((t.near, t.far), (0.2, 0.9));
        // Layers: {0, 0.02} -> 2 ln 2; + {0.1} -> 3 ln 2; + {0.25} + beyond {0.7} -> 5 ln 2.
        assert!(close(&t.layers, &[2.0 * LN_2, 3.0 * LN_2, 5.0 * LN_2], 1e-6));
        let v = |z| visibility(&params, &t, z);
        assert_eq!(v(0.1), 1.0);
        assert_eq!(v(0.2), 1.0);
        // dz = 0.025: layer 0, half way: omega = ln 2 -> 1/2.
        assert!((v(0.225) - 0.5).abs() < 1e-6);
        // dz = 0.1: layer 1 [0.05, 0.15], half way: 2 ln 2 + (3 - 2) ln 2 / 2 = 2.5 ln 2 -> 2^-2.5.
        assert!((v(0.3) - 2f32.powf(-2.5)).abs() < 1e-6);
        // dz = 0.25: layer 2 [0.15, 0.3], 2/3 of the way: 3 ln 2 + 2/3 * 2 ln 2 -> 2^-(13/3).
        assert!((v(0.45) - 2f32.powf(-13.0 / 3.0)).abs() < 1e-6);
        // Beyond the last layer (dz >= 0.3): 5 ln 2 -> 1/32.
        assert!((v(0.5) - 1.0 / 32.0).abs() < 1e-6);
        assert!((v(0.95) - 1.0 / 32.0).abs() < 1e-6);
    }

    #[test]
    fn hand_computed_ignore() {
        let params = p(3, 0.3, LayerSpacing::LinearlyIncreasing, BeyondLastLayer::Ignore);
        let t = build(&params, &texel());
        // The fragment at dz = 0.7 is dropped: 2, 3, 4 ln 2.
        assert!(close(&t.layers, &[2.0 * LN_2, 3.0 * LN_2, 4.0 * LN_2], 1e-6));
        assert!((visibility(&params, &t, 0.95) - 1.0 / 16.0).abs() < 1e-6);
    }

    #[test]
    fn hand_computed_stretch() {
        let params = p(3, 0.3, LayerSpacing::LinearlyIncreasing, BeyondLastLayer::Stretch);
        let t = build(&params, &texel());
        // scale = (0.9 - 0.2) / 0.3 = 7/3: ends 0.1167, 0.35, 0.7. dz 0, 0.02, 0.1 -> layer 0; 0.25 -> layer
        // 1; 0.7 -> layer 2 (at the far end). Layers 3, 4, 5 ln 2.
        assert!(close(&t.layers, &[3.0 * LN_2, 4.0 * LN_2, 5.0 * LN_2], 1e-6));
        let v = |z| visibility(&params, &t, z);
        // dz = 0.1 in layer 0 [0, 0.7/6]: f = 0.1 / (0.7/6) = 6/7; omega = 3 ln 2 * 6/7 -> 2^-(18/7).
        assert!((v(0.3) - 2f32.powf(-18.0 / 7.0)).abs() < 1e-6);
        // dz = 0.35 is the end of layer 1: 4 ln 2 -> 1/16.
        assert!((v(0.55) - 1.0 / 16.0).abs() < 1e-6);
        // At far and beyond: 5 ln 2.
        assert!((v(0.9) - 1.0 / 32.0).abs() < 1e-6);
        assert!((v(2.0) - 1.0 / 32.0).abs() < 1e-6);
    }

    #[test]
    fn stretch_does_not_shrink() {
        // far - z0 = 0.1 < d = 0.3: scale stays 1, same layers as AddToLast.
        let f = [Fragment::new(0.5, 0.5), Fragment::new(0.6, 0.5)];
        let a = build(
            &p(3, 0.3, LayerSpacing::LinearlyIncreasing, BeyondLastLayer::Stretch),
            &f,
        );
        let b = build(
            &p(
                3,
                0.3,
                LayerSpacing::LinearlyIncreasing,
                BeyondLastLayer::AddToLast,
            ),
            &f,
        );
        assert_eq!(a.layers, b.layers);
    }

    #[test]
    fn hand_computed_uniform() {
        // K = 2, d = 0.4, uniform: ends 0.2, 0.4. Fragments (alpha 0.5) at 0.1 (= z0), 0.35 (dz 0.25, layer
        // 1), 0.6 (dz 0.5, beyond -> last). Layers ln 2, 3 ln 2.
        let params = p(2, 0.4, LayerSpacing::Uniform, BeyondLastLayer::AddToLast);
        let f = [
            Fragment::new(0.6, 0.5),
            Fragment::new(0.1, 0.5),
            Fragment::new(0.35, 0.5),
        ];
        let t = build(&params, &f);
        assert!(close(&t.layers, &[LN_2, 3.0 * LN_2], 1e-6));
        // dz = 0.1: half of layer 0 -> 0.5 ln 2.
        assert!((visibility(&params, &t, 0.2) - 0.5f32.sqrt()).abs() < 1e-6);
        // dz = 0.3: half of layer 1 -> ln 2 + ln 2 = 2 ln 2.
        assert!((visibility(&params, &t, 0.4) - 0.25).abs() < 1e-6);
    }

    #[test]
    fn exact_up_to_z0() {
        let mut rng = Rng::new(20);
        for _ in 0..100 {
            let f = random_texel(&mut rng, 60);
            let params = DomParams::default();
            let t = build(&params, &f);
            for z in [t.near, t.near - 1e-3, t.near.next_down(), -1.0] {
                assert_eq!(visibility(&params, &t, z), 1.0);
                assert_eq!(reference::visibility(&f, z), 1.0);
            }
        }
    }

    #[test]
    fn exact_at_layer_boundaries_when_layers_cover_the_texel() {
        // With d = 1 every fragment is inside the layers, so at each boundary z0 + d_k the layer value is the
        // exact sum of the fragments in front of it.
        let mut rng = Rng::new(21);
        for spacing in [LayerSpacing::LinearlyIncreasing, LayerSpacing::Uniform] {
            let params = p(8, 1.0, spacing, BeyondLastLayer::Ignore);
            for _ in 0..50 {
                let f = random_texel(&mut rng, 60);
                let t = build(&params, &f);
                for e in layer_ends(&params) {
                    let z = t.near + e;
                    if f.iter().any(|f| (f.depth - z).abs() < 1e-5) {
                        continue;
                    }
                    let (m, r) = (visibility(&params, &t, z), reference::visibility(&f, z));
                    assert!((m - r).abs() < 2e-6, "{m} vs {r}");
                }
            }
        }
    }

    #[test]
    fn properties_and_extremes() {
        let mut rng = Rng::new(22);
        let random: Vec<_> = (0..30).map(|_| random_texel(&mut rng, 80)).collect();
        for layers in [0, 1, 3, 16, 17] {
            for d in [
                0.0,
                1e-9,
                1e-4,
                0.05,
                0.25,
                1.0,
                5.0,
                f32::NAN,
                f32::INFINITY,
                -1.0,
            ] {
                for spacing in [LayerSpacing::LinearlyIncreasing, LayerSpacing::Uniform] {
                    for beyond in [
                        BeyondLastLayer::Ignore,
                        BeyondLastLayer::AddToLast,
                        BeyondLastLayer::Stretch,
                    ] {
                        let params = p(layers, d, spacing, beyond);
                        for f in extreme_texels().iter().chain(&random) {
                            assert_valid_curve(&params, f, &format!("dom {params:?}"));
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn order_does_not_matter() {
        let mut rng = Rng::new(23);
        let mut f = random_texel(&mut rng, 50);
        let params = DomParams {
            layers: 8,
            ..DomParams::default()
        };
        let a = build(&params, &f);
        f.reverse();
        let b = build(&params, &f);
        assert!(close(&a.layers, &b.layers, 1e-5));
    }
}
