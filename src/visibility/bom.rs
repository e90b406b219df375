//! Bounding Opacity Maps (Voicu, "Real-time volumetric shadows for dynamic rendering", MSc thesis, §5).
//!
//! Like Deep Opacity Maps, but each texel has a start depth (`near`, the first depth map) AND an end depth
//! (`far`, the second depth map, §5 and §5.1), and its `K` layers split `[near, far]` (§5: `d_K = z1`). A
//! fragment adds its optical depth to its layer and all later ones (§4.2 and Appendix §5: "adding the current
//! rendered point ... to all previous rendering targets", `renderTarget <= k`), so layer `k` stores the
//! optical depth accumulated up to its far end.
//!
//! Split schemes (§5.2): with `t = (z - near) / (far - near)` the relative depth, a fragment's layer is
//! `min(floor(s(t) * K), K - 1)` where the split function `s` maps `[0, 1]` onto `[0, 1]`:
//! - linear (§5, the first implementation; Appendix §6): `s(t) = t`;
//! - logarithmic (§5.2.1): `[0, 1]` is mapped to `[1, N]`, the logarithm taken, and `[0, log N]` mapped back
//!   to `[0, 1]`: `L(t) = log2(1 + (N - 1) t) / log2(N)`. The thesis encodes this in a lookup texture
//!   (§5.2.2, Appendix §7) whose input interval is `[1, textureSize - 1]`; we evaluate it directly with
//!   `N = 255` (a 256-texel lookup texture, the 8-bit size of Appendix §7). More layers near the start of the
//!   hair;
//! - hybrid (§5.2.3, Appendix §9): `s(t) = (1 - r) t + r L(t)` with the split ratio `r` in `[0, 1]` (0:
//!   linear, 1: logarithmic). This one formula covers all three schemes, so [`BomParams::split_ratio`]
//!   selects them.
//!
//! Lookup (the thesis shows no lookup code for BOM): `V` interpolates linearly between the layer boundary
//! values in the split coordinate `s` (the coordinate in which the layers are uniform, the one the lookup
//! texture gives directly); the value at `near` is 0. For `r = 0` this is linear in depth; for `r > 0` the
//! inverse of `s` has no closed form, so interpolation in depth would need an iterative inverse per lookup.
//!
//! Automatic split ratio (§5.2.3, §5.2.4, Algorithm 5.2.3.1): for `r = 0.0, 0.1, ..., 1.0` build the `K`
//! layer images of the whole map, score each `r` by the correlation coefficient (Eq. 5.2.3.1) between
//! successive layer images (mean over the `K - 1` pairs) and by the sum of absolute differences (summed over
//! the pairs), and pick the least correlated `r` (the thesis's criterion: "the smallest value ... corresponds
//! to the value for which the layers have the least mutual information") or the largest SAD ("a split ratio
//! that produces a higher sum of absolute differences is chosen"). See [`search_split_ratio`].
//!
//! Exact: `V(z) = 1` for `z <= near`; `V` at every layer boundary `near + s^-1(k/K) (far - near)`; a texel
//! whose fragments all lie at one depth. Approximate: inside the layers.
//!
//! GPU contract (per texel: `near`, `far`, `K` f32 layer values):
//! - `t = select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near)`, then
//!   `t = clamp(t, 0, 1)`;
//! - `s = clamp((1.0 - r) * t + r * (log2(1.0 + 254.0 * t) / log2(255.0)), 0.0, 1.0)`;
//! - build, per fragment: `k = min(u32(max(floor(s * f32(K)), 0.0)), K - 1u)`; add `b` to layers `k..K` (by
//!   additive blending, or in fixed point with atomics and a resolve into the chosen storage: [`build_with`],
//!   `visibility::opacity_layers`);
//! - lookup: if `!(t_unclamped > 0.0)`: `V = 1`; else `x = s * f32(K)`, `j` as above,
//!   `f = clamp(x - f32(j), 0, 1)`, `prev = select(0.0, L[max(j, 1u) - 1u], j > 0u)`,
//!   `omega = min(prev + (L[j] - prev) * f, L[j])`, `V = exp(-omega)`.

use super::opacity_layers::{LayerBuild, LayeredModel, accumulate};
use super::{
    Fragment, Model, Stored, TexelModel, depth_range, lerp_up, list, relative_depth, slice_index,
    transmittance, valid,
};

/// Largest number of layers (8 render targets of 4 channels, thesis §3.4).
pub const MAX_LAYERS: u32 = 32;
/// `N` of the logarithmic split: the relative depth is mapped to `[1, N]` before the logarithm.
pub const LOG_SPLIT_RANGE: f32 = 255.0;
/// Number of split ratios the automatic search tries: 0.0, 0.1, ..., 1.0 (Algorithm 5.2.3.1, lines 15-17).
pub const SPLIT_RATIO_STEPS: usize = 11;

/// Bounding Opacity Map parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BomParams {
    /// Number of layers `K`, clamped to `1..=32`.
    pub layers: u32,
    /// Hybrid split ratio `r`: 0 linear, 1 logarithmic, between hybrid. Clamped to `[0, 1]` (NaN: 0).
    pub split_ratio: f32,
}

impl Default for BomParams {
    /// 4 layers (one RGBA target; the smallest count of the thesis's tables 5.2.3.1 and 6.3.1) and the linear
    /// split of the thesis's first implementation (Algorithm 5.2.3.1 also starts its search at ratio 0).
    fn default() -> Self {
        Self {
            layers: 4,
            split_ratio: 0.0,
        }
    }
}

impl BomParams {
    /// The layer count actually used: `layers` clamped to `1..=32`.
    pub fn layer_count(&self) -> usize {
        self.layers.clamp(1, MAX_LAYERS) as usize
    }

    /// The split ratio actually used: clamped to `[0, 1]`, 0 when NaN.
    pub fn ratio(&self) -> f32 {
        if self.split_ratio.is_nan() {
            0.0
        } else {
            self.split_ratio.clamp(0.0, 1.0)
        }
    }
}

/// Logarithmic split `L(t) = log2(1 + (N - 1) t) / log2(N)`, `N = 255`, for `t` in `[0, 1]`.
pub fn log_split(t: f32) -> f32 {
    (1.0 + (LOG_SPLIT_RANGE - 1.0) * t).log2() / LOG_SPLIT_RANGE.log2()
}

/// Hybrid split `s(t) = (1 - r) t + r L(t)`, with `t` clamped to `[0, 1]` and the result clamped to `[0, 1]`.
pub fn split(t: f32, ratio: f32) -> f32 {
    let t = t.clamp(0.0, 1.0);
    ((1.0 - ratio) * t + ratio * log_split(t)).clamp(0.0, 1.0)
}

/// One BOM texel: start and end depth, and `layers[k]`, the optical depth accumulated up to the far end of
/// layer `k`.
#[derive(Clone, Debug, PartialEq)]
pub struct BomTexel {
    pub near: f32,
    pub far: f32,
    pub layers: Vec<f32>,
}

/// Builds a BOM texel: each fragment adds `b` to its layer and all later ones (the colour-target build).
pub fn build(params: &BomParams, fragments: &[Fragment]) -> BomTexel {
    build_with(params, LayerBuild::Targets, fragments)
}

/// Builds a BOM texel the way `layers` does (`visibility::opacity_layers`).
pub fn build_with(params: &BomParams, layers: LayerBuild, fragments: &[Fragment]) -> BomTexel {
    let (near, far) = depth_range(fragments);
    let k_count = params.layer_count();
    let r = params.ratio();
    let entries = valid(fragments).map(|f| {
        let s = split(relative_depth(f.depth, near, far), r);
        (slice_index(s * k_count as f32, k_count), f.optical_depth())
    });
    BomTexel {
        near,
        far,
        layers: accumulate(layers, k_count, entries),
    }
}

/// `V(z)`: 1 up to `near`, then linear interpolation between layer boundaries in the split coordinate. `K` is
/// the texel's layer count.
pub fn visibility(params: &BomParams, texel: &BomTexel, z: f32) -> f32 {
    let k_count = texel.layers.len();
    let t = relative_depth(z, texel.near, texel.far);
    if t.is_nan() || t <= 0.0 || k_count == 0 {
        return 1.0;
    }
    let x = split(t, params.ratio()) * k_count as f32;
    let j = slice_index(x, k_count);
    let f = (x - j as f32).clamp(0.0, 1.0);
    let prev = if j == 0 { 0.0 } else { texel.layers[j - 1] };
    transmittance(lerp_up(prev, texel.layers[j], f))
}

impl Model for BomParams {
    type Texel = BomTexel;

    fn build(&self, fragments: &[Fragment]) -> BomTexel {
        build(self, fragments)
    }

    fn visibility(&self, texel: &BomTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

/// The relative depth `t` with `split(t, ratio) = s` (the split is increasing; bisection to f32 precision).
pub fn split_inverse(s: f32, ratio: f32) -> f32 {
    let (mut lo, mut hi) = (0.0f32, 1.0f32);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if split(mid, ratio) < s {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

impl TexelModel for BomParams {
    fn label(&self) -> String {
        if self.ratio() > 0.0 {
            format!("bom-{} r{:.2}", self.layer_count(), self.ratio())
        } else {
            format!("bom-{}", self.layer_count())
        }
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

impl LayeredModel for BomParams {
    fn build_with(&self, build: LayerBuild, fragments: &[Fragment]) -> BomTexel {
        build_with(self, build, fragments)
    }

    fn entries(texel: &BomTexel) -> &[f32] {
        &texel.layers
    }

    fn describe(&self, t: &BomTexel, label: String) -> Stored {
        let k = t.layers.len();
        let mut s = Stored::new(label);
        s.boundaries.push(t.near);
        s.knots.push([t.near, 1.0]);
        if t.far > t.near {
            for (i, b) in t.layers.iter().enumerate() {
                let z = t.near + split_inverse((i + 1) as f32 / k as f32, self.ratio()) * (t.far - t.near);
                s.boundaries.push(z);
                s.knots.push([z, transmittance(*b)]);
            }
        }
        s.summary.push(format!(
            "start {:.4}, end {:.4}; {k} layers, split ratio {:.2}",
            t.near,
            t.far,
            self.ratio()
        ));
        s.summary
            .push(format!("layer optical depths {}", list(&t.layers)));
        s
    }
}

/// How the automatic search ranks split ratios.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SplitCriterion {
    /// Least mean correlation coefficient between successive layers (the thesis's preferred measure, §5.2.3).
    #[default]
    CrossCorrelation,
    /// Largest sum of absolute differences between successive layers.
    SumOfAbsoluteDifferences,
}

/// Scores of one split ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitScore {
    pub ratio: f32,
    /// Mean over successive layer pairs of the correlation coefficient (Eq. 5.2.3.1), in `[-1, 1]`. A pair
    /// where either image is constant counts as 1 (a constant layer image adds no information); with one
    /// layer (no pairs) the score is 0.
    pub correlation: f32,
    /// Sum over successive layer pairs and texels of `|I_(k+1) - I_k|` (accumulated optical depth); 0 with
    /// one layer.
    pub sad: f32,
}

/// Result of the automatic split-ratio search: the scores of every ratio tried, in increasing ratio.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitSearch {
    pub scores: Vec<SplitScore>,
}

impl SplitSearch {
    /// The chosen ratio: least correlation or largest SAD; on ties the smallest ratio.
    pub fn best(&self, criterion: SplitCriterion) -> f32 {
        let mut best: Option<&SplitScore> = None;
        for s in &self.scores {
            let better = match (best, criterion) {
                (None, _) => true,
                (Some(b), SplitCriterion::CrossCorrelation) => s.correlation < b.correlation,
                (Some(b), SplitCriterion::SumOfAbsoluteDifferences) => s.sad > b.sad,
            };
            if better {
                best = Some(s);
            }
        }
        best.map_or(0.0, |s| s.ratio)
    }
}

/// The split ratios the search tries: `i / 10` for `i` in `0..=10`.
pub fn split_ratios() -> [f32; SPLIT_RATIO_STEPS] {
    std::array::from_fn(|i| i as f32 / 10.0)
}

/// Automatic split-ratio search (thesis §5.2.3-5.2.4) over a whole map given as one fragment list per texel
/// (every texel is a pixel of the layer images, empty ones included, as in the thesis's read-back images;
/// pass only non-empty texels to leave them out). The layer images hold the stored f32 accumulated optical
/// depth (the thesis read back 8-bit channels).
pub fn search_split_ratio<T: AsRef<[Fragment]>>(layers: u32, map: &[T]) -> SplitSearch {
    let scores = split_ratios()
        .into_iter()
        .map(|ratio| {
            let params = BomParams {
                layers,
                split_ratio: ratio,
            };
            let k_count = params.layer_count();
            // images[k][texel]
            let mut images = vec![Vec::with_capacity(map.len()); k_count];
            for texel in map {
                for (image, value) in images.iter_mut().zip(build(&params, texel.as_ref()).layers) {
                    image.push(value);
                }
            }
            let pairs = images.windows(2);
            let n_pairs = pairs.len();
            let (corr_sum, sad) = pairs.fold((0.0f64, 0.0f64), |(c, s), w| {
                (c + correlation(&w[0], &w[1]), s + sum_abs_diff(&w[0], &w[1]))
            });
            let correlation = if n_pairs == 0 {
                0.0
            } else {
                corr_sum / n_pairs as f64
            };
            SplitScore {
                ratio,
                correlation: correlation as f32,
                sad: sad as f32,
            }
        })
        .collect();
    SplitSearch { scores }
}

/// Correlation coefficient of two images (Eq. 5.2.3.1): covariance over the product of standard deviations,
/// computed in f64 with the means taken first (two passes; the thesis's one-pass form of §5.2.4 is the same
/// value up to rounding). 1 when either image is constant.
fn correlation(a: &[f32], b: &[f32]) -> f64 {
    let constant = |x: &[f32]| x.windows(2).all(|w| w[0] == w[1]);
    if constant(a) || constant(b) {
        return 1.0;
    }
    let n = a.len() as f64;
    let mean = |x: &[f32]| x.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
    let (ma, mb) = (mean(a), mean(b));
    let (mut e1, mut e2, mut e3) = (0.0, 0.0, 0.0);
    for (&x, &y) in a.iter().zip(b) {
        let (dx, dy) = (f64::from(x) - ma, f64::from(y) - mb);
        e1 += dx * dy;
        e2 += dx * dx;
        e3 += dy * dy;
    }
    (e1 / (e2 * e3).sqrt()).clamp(-1.0, 1.0)
}

/// Sum of absolute differences of two images, in f64.
fn sum_abs_diff(a: &[f32], b: &[f32]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).abs())
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_inverse_inverts_the_split() {
        for r in [0.0, 0.4, 1.0] {
            for s in [0.25, 0.5, 0.75] {
                let t = split_inverse(s, r);
                assert!((split(t, r) - s).abs() < 1e-5, "r {r} s {s}");
            }
        }
    }
    use crate::visibility::reference;
    use crate::visibility::test_support::{Rng, assert_valid_curve, extreme_texels, random_texel};
    use std::f32::consts::LN_2;

    fn p(layers: u32, split_ratio: f32) -> BomParams {
        BomParams { layers, split_ratio }
    }

    fn close(a: &[f32], b: &[f32], tol: f32) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn split_function() {
        for r in [0.0, 0.3, 1.0] {
            assert_eq!(split(0.0, r), 0.0);
            assert_eq!(split(1.0, r), 1.0);
            assert_eq!(split(-3.0, r), 0.0);
            assert_eq!(split(7.0, r), 1.0);
        }
        assert_eq!(split(0.37, 0.0), 0.37);
        // L(0.1) = log(1 + 25.4) / log(255) = 0.590725.
        assert!((log_split(0.1) - (26.4f64.ln() / 255f64.ln()) as f32).abs() < 1e-6);
        // Hybrid r = 0.5 at t = 0.1: (0.1 + 0.590725) / 2.
        assert!((split(0.1, 0.5) - 0.345_362_6).abs() < 1e-6);
        assert_eq!(split_ratios()[3], 0.3);
        assert_eq!(split_ratios()[10], 1.0);
    }

    // near = 0, far = 1; fragments alpha 0.5 (b = ln 2) at 0.0, 0.1, 0.6, 1.0.
    fn texel() -> Vec<Fragment> {
        [0.6, 0.0, 1.0, 0.1]
            .iter()
            .map(|&z| Fragment::new(z, 0.5))
            .collect()
    }

    #[test]
    fn hand_computed_linear() {
        // K = 2, s = t: 0.0, 0.1 -> layer 0; 0.6, 1.0 -> layer 1. Layers 2 ln 2, 4 ln 2.
        let params = p(2, 0.0);
        let t = build(&params, &texel());
        assert_eq!((t.near, t.far), (0.0, 1.0));
        assert!(close(&t.layers, &[2.0 * LN_2, 4.0 * LN_2], 1e-6));
        let v = |z| visibility(&params, &t, z);
        assert_eq!(v(0.0), 1.0);
        assert_eq!(v(-0.5), 1.0);
        // z = 0.25: half of layer 0 -> ln 2 -> 1/2. z = 0.75: 2 ln 2 + (4 - 2) ln 2 / 2 = 3 ln 2 -> 1/8.
        assert!((v(0.25) - 0.5).abs() < 1e-6);
        assert!((v(0.5) - 0.25).abs() < 1e-6);
        assert!((v(0.75) - 0.125).abs() < 1e-6);
        assert!((v(1.0) - 0.0625).abs() < 1e-6);
        assert!((v(4.0) - 0.0625).abs() < 1e-6);
    }

    #[test]
    fn hand_computed_logarithmic() {
        // K = 2, r = 1: s(0.1) = 0.5907 >= 0.5 -> layer 1, so layer 0 = {0.0} (ln 2), layer 1 = all (4 ln 2).
        let params = p(2, 1.0);
        let t = build(&params, &texel());
        assert!(close(&t.layers, &[LN_2, 4.0 * LN_2], 1e-6));
        // z = 0.05: s = log(13.7) / log(255) = 0.472346, x = 2 s = 0.944693 in layer 0:
        // omega = 0.944693 ln 2.
        let want = 2f64.powf(-2.0 * 13.7f64.ln() / 255f64.ln()) as f32;
        assert!((visibility(&params, &t, 0.05) - want).abs() < 1e-6);
        // The layer boundary s = 1/2 is at t = (sqrt(255) - 1) / 254 = 0.058931; there omega = ln 2.
        let boundary = ((255f64.sqrt() - 1.0) / 254.0) as f32;
        assert!((visibility(&params, &t, boundary) - 0.5).abs() < 1e-5);
    }

    #[test]
    fn hand_computed_hybrid() {
        // r = 0.5: s(0.1) = 0.345363 < 0.5 -> layer 0 (as linear); s(0.6) > 0.5 -> layer 1.
        let t = build(&p(2, 0.5), &texel());
        assert!(close(&t.layers, &[2.0 * LN_2, 4.0 * LN_2], 1e-6));
    }

    #[test]
    fn all_at_one_depth_is_exact() {
        // near == far = 0.5: every fragment has t = 0 -> layer 0; V = 1 up to 0.5, exp(-3 ln 2) = 1/8 beyond.
        let f = vec![Fragment::new(0.5, 0.5); 3];
        for params in [p(1, 0.0), p(4, 0.5), p(32, 1.0)] {
            let t = build(&params, &f);
            assert_eq!(visibility(&params, &t, 0.5), 1.0);
            assert!((visibility(&params, &t, 0.500_001) - 0.125).abs() < 1e-6);
        }
    }

    #[test]
    fn exact_up_to_near_and_at_layer_boundaries() {
        // Layer boundary k sits at relative depth t_k = k/K (linear) or t_k = (255^(k/K) - 1) / 254
        // (logarithmic, the inverse of L). The stored layer value is the exact optical depth in front of it.
        // (The lookup at t_k is only as exact as f32 lets s(t_k) * K land on k, and the log split amplifies
        // depth rounding about 18 times near the start, so for r = 1 the stored values are what is compared.)
        let mut rng = Rng::new(30);
        let k_count = 6u32;
        for (ratio, inverse) in [
            (0.0, (|s: f64| s) as fn(f64) -> f64),
            (1.0, |s: f64| (255f64.powf(s) - 1.0) / 254.0),
        ] {
            let params = p(k_count, ratio);
            for _ in 0..50 {
                let f = random_texel(&mut rng, 60);
                let t = build(&params, &f);
                assert_eq!(visibility(&params, &t, t.near), 1.0);
                for k in 1..=k_count {
                    let tk = inverse(f64::from(k) / f64::from(k_count));
                    let z = (f64::from(t.near) + tk * f64::from(t.far - t.near)) as f32;
                    if f.iter().any(|f| (f.depth - z).abs() < 1e-5) {
                        continue;
                    }
                    let (m, r) = (
                        transmittance(t.layers[k as usize - 1]),
                        reference::visibility(&f, z),
                    );
                    assert!((m - r).abs() < 2e-6, "r={ratio} k={k}: {m} vs {r}");
                    if ratio == 0.0 {
                        // Linear: the lookup at the boundary gives the stored value up to f32 rounding of t.
                        assert!((visibility(&params, &t, z) - r).abs() < 1e-5, "k={k}");
                    }
                }
            }
        }
    }

    #[test]
    fn properties_and_extremes() {
        let mut rng = Rng::new(31);
        let random: Vec<_> = (0..30).map(|_| random_texel(&mut rng, 80)).collect();
        for layers in [0, 1, 4, 32, 33] {
            for ratio in [0.0, 0.1, 0.5, 1.0, -1.0, 2.0, f32::NAN] {
                let params = p(layers, ratio);
                for f in extreme_texels().iter().chain(&random) {
                    assert_valid_curve(&params, f, &format!("bom {params:?}"));
                    let t = build(&params, f);
                    assert_eq!(visibility(&params, &t, t.near), 1.0);
                }
            }
        }
    }

    // Four texels, K = 2, depths 0 and 1 in each (near = 0, far = 1), b in units of ln 2:
    //   A: 0.0 (1), 1.0 (1)            -> I0 = 1, I1 = 2 for every ratio;
    //   B: 0.0 (1), 0.3 (1), 1.0 (1)   -> 0.3 is in layer 0 while s(0.3) < 0.5, i.e. for r <= 0.4
    //                                     (r = 0.4: 0.6 * 0.3 + 0.4 * 0.78437 = 0.4937), layer 1 for r >= 0.5
    //                                     (0.5 * 0.3 + 0.5 * 0.78437 = 0.5422): I0 = 2 or 1, I1 = 3;
    //   C: 0.0 (1), 1.0 (2)            -> I0 = 1, I1 = 3;
    //   D: 0.0 (2), 1.0 (1)            -> I0 = 2, I1 = 3.
    fn map() -> Vec<Vec<Fragment>> {
        let f = Fragment::new;
        vec![
            vec![f(0.0, 0.5), f(1.0, 0.5)],
            vec![f(0.0, 0.5), f(0.3, 0.5), f(1.0, 0.5)],
            vec![f(0.0, 0.5), f(1.0, 0.75)],
            vec![f(0.0, 0.75), f(1.0, 0.5)],
        ]
    }

    #[test]
    fn split_search_hand_computed() {
        // r <= 0.4: I0 = [1, 2, 1, 2] (mean 1.5), I1 = [2, 3, 3, 3] (mean 2.75);
        //   deviations [-.5, .5, -.5, .5] and [-.75, .25, .25, .25]: E1 = .375 + .125 - .125 + .125 = .5,
        //   E2 = 1, E3 = .5625 + 3 * .0625 = .75: C = .5 / sqrt(.75) = 1/sqrt(3). SAD = (1 + 1 + 2 + 1) ln 2.
        // r >= 0.5: I0 = [1, 1, 1, 2] (mean 1.25): deviations [-.25, -.25, -.25, .75];
        //   E1 = .1875 - .0625 - .0625 + .1875 = .25, E2 = .75, E3 = .75: C = 1/3.
        //   SAD = (1 + 2 + 2 + 1) ln 2.
        let search = search_split_ratio(2, &map());
        assert_eq!(search.scores.len(), 11);
        for (i, s) in search.scores.iter().enumerate() {
            assert_eq!(s.ratio, i as f32 / 10.0);
            let (c, sad) = if i <= 4 {
                (1.0 / 3f32.sqrt(), 5.0 * LN_2)
            } else {
                (1.0 / 3.0, 6.0 * LN_2)
            };
            assert!(
                (s.correlation - c).abs() < 1e-6,
                "r={}: {}",
                s.ratio,
                s.correlation
            );
            assert!((s.sad - sad).abs() < 1e-5, "r={}: {}", s.ratio, s.sad);
        }
        // Least correlated: first of r >= 0.5. Largest SAD: the same.
        assert_eq!(search.best(SplitCriterion::CrossCorrelation), 0.5);
        assert_eq!(search.best(SplitCriterion::SumOfAbsoluteDifferences), 0.5);
    }

    #[test]
    fn split_search_constant_layer_counts_as_correlated() {
        // Texels A, B and C' = 0.0 (1), 1.0 (2) only:
        // r <= 0.4: I0 = [1, 2, 1], I1 = [2, 3, 3]; means 4/3, 8/3; deviations [-1/3, 2/3, -1/3] and
        //   [-2/3, 1/3, 1/3]: E1 = 2/9 + 2/9 - 1/9 = 1/3, E2 = E3 = 6/9: C = (1/3) / (2/3) = 1/2.
        // r >= 0.5: I0 = [1, 1, 1] is constant: C = 1 by the rule. SAD 4 ln 2 then 5 ln 2.
        let m = &map()[..3];
        let search = search_split_ratio(2, m);
        assert!((search.scores[0].correlation - 0.5).abs() < 1e-6);
        assert_eq!(search.scores[10].correlation, 1.0);
        assert_eq!(search.best(SplitCriterion::CrossCorrelation), 0.0);
        assert_eq!(search.best(SplitCriterion::SumOfAbsoluteDifferences), 0.5);
    }

    #[test]
    fn split_search_degenerate_inputs() {
        // One layer: no pairs, every ratio scores 0 and the first (linear) is chosen.
        let s = search_split_ratio(1, &map());
        assert!(s.scores.iter().all(|s| s.correlation == 0.0 && s.sad == 0.0));
        assert_eq!(s.best(SplitCriterion::CrossCorrelation), 0.0);
        // Empty map and map of empty texels: constant images, correlation 1, SAD 0.
        let empty: Vec<Vec<Fragment>> = vec![];
        let s = search_split_ratio(4, &empty);
        assert!(s.scores.iter().all(|s| s.correlation == 1.0 && s.sad == 0.0));
        let s = search_split_ratio(4, &[vec![], vec![]]);
        assert!(s.scores.iter().all(|s| s.correlation == 1.0 && s.sad == 0.0));
        assert_eq!(
            SplitSearch { scores: vec![] }.best(SplitCriterion::CrossCorrelation),
            0.0
        );
        // Slices of slices work too, and scores stay finite on random maps.
        let mut rng = Rng::new(32);
        let texels: Vec<Vec<Fragment>> = (0..40).map(|_| random_texel(&mut rng, 40)).collect();
        let slices: Vec<&[Fragment]> = texels.iter().map(|t| t.as_slice()).collect();
        for s in search_split_ratio(8, &slices).scores {
            assert!((-1.0..=1.0).contains(&s.correlation) && s.sad.is_finite() && s.sad >= 0.0);
        }
    }
}
