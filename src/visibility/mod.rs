//! CPU models of every self-shadowing method, the exact reference, and the error metrics.
//!
//! These models are the specification the GPU methods must match texel for texel: each model is a pure
//! function pair `build(params, fragments) -> Texel` (the texel holds exactly what the GPU stores, in the
//! same numeric layout) and `visibility(params, &Texel, z) -> f32`. No GPU, no UI here.
//!
//! # Shared conventions (design.md)
//! - A light-space [`Fragment`] has a normalised light depth in `[0, 1]` across the strands' fitted light
//!   range (0 = nearest strand point, 1 = furthest) and an opacity `alpha` in `[0, 1)`.
//! - Every method accumulates optical depth `b = -ln(1 - alpha)` ([`optical_depth`]) and returns
//!   `V = exp(-accumulated b)`.
//! - The exact reference is `V_ref(z) = exp(-sum of b over fragments with depth < z)` (strictly less: a
//!   fragment does not shadow itself), see [`reference`](mod@reference).
//! - Per-texel quantities the GPU gets from the light-depth pass are the min and max fragment depth of the
//!   texel, `near` and `far` ([`depth_range`]); an empty texel keeps the pass's clear values `near = 1`,
//!   `far = 0`.
//! - Fragments whose depth is not finite are ignored by every model (the light-depth pass clamps depth, so
//!   the GPU never produces them).
//! - Fragment order never matters to a model that sums over fragments (GPU additive blending or atomics),
//!   apart from f32 rounding of those sums, which depends on the order on the GPU too. A model whose result
//!   depends on the insertion order orders the fragments itself, by depth or by [`Fragment::segment`] (the
//!   primitive order a rasteriser-ordered implementation would see), never by the input order.
//! - Shared f32 expressions the GPU must use: [`optical_depth`], [`relative_depth`], [`slice_index`],
//!   [`lerp_up`].
//! - Hair count (what Unreal's deep opacity map stores and its dual scattering reads, Zinke et al. 2008): the
//!   number of fragments in front of `z` ([`TexelModel::count_curve`]). A strand that crosses a texel twice
//!   counts twice: light passes through the fibre twice, exactly as `V_ref` multiplies in both fragments'
//!   `1 - alpha`. Exact for the reference; occupancy maps count occupied slots; every other method's count is
//!   [`count_from_visibility`] of its own `V` at the scene's hair alpha (exact for the summed-opacity methods
//!   when every fragment has that alpha).

pub mod adsm;
pub mod avsm;
pub mod bom;
pub mod dc;
pub mod dom;
pub mod dsm;
pub mod fom;
pub mod lookup;
pub mod metrics;
pub mod msm;
pub mod occupancy;
pub mod opacity_layers;
pub mod osm;
pub mod reference;

#[cfg(test)]
mod test_support;

pub use bom::{BomParams, BomTexel, SplitCriterion, SplitScore, SplitSearch};
pub use dc::{DcParams, DcTexel};
pub use dom::{BeyondLastLayer, DomParams, DomTexel, LayerSpacing};
pub use metrics::{ErrorDistribution, MapError, TexelError};
pub use occupancy::{OccupancyParams, OccupancyTexel, OccupancyVariant};
pub use osm::{OsmParams, OsmTexel};
pub use reference::{Reference, ReferenceTexel};

/// One rasterised hair fragment seen from the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    /// Normalised light depth in `[0, 1]` across the strands' fitted light range.
    pub depth: f32,
    /// Opacity in `[0, 1)`.
    pub alpha: f32,
    /// Index of the strand segment (the primitive) that produced the fragment, as the A-buffer records it; 0
    /// where unknown (hand-made texels, CSV files).
    pub segment: u32,
}

impl Fragment {
    /// A fragment of segment 0.
    pub fn new(depth: f32, alpha: f32) -> Self {
        Self {
            depth,
            alpha,
            segment: 0,
        }
    }

    /// The fragment's optical depth `b` ([`optical_depth`] of its alpha).
    pub fn optical_depth(&self) -> f32 {
        optical_depth(self.alpha)
    }
}

impl From<(f32, f32)> for Fragment {
    /// From `(depth, alpha)`, segment 0.
    fn from((depth, alpha): (f32, f32)) -> Self {
        Self::new(depth, alpha)
    }
}

/// Largest alpha used in [`optical_depth`]: `1 - 1e-6`, so that `b` stays finite (at most about 13.8).
pub const MAX_ALPHA: f32 = 1.0 - 1e-6;

/// Optical depth `b = -ln(1 - alpha)` with alpha clamped to `[0, MAX_ALPHA]` (a NaN alpha counts as 0).
///
/// GPU: `-log(1.0 - clamp(alpha, 0.0, 1.0 - 1e-6))`.
pub fn optical_depth(alpha: f32) -> f32 {
    let a = if alpha > 0.0 { alpha.min(MAX_ALPHA) } else { 0.0 };
    -(1.0 - a).ln()
}

/// The fragments with a finite depth (the only ones any model sees).
pub(crate) fn valid(fragments: &[Fragment]) -> impl Iterator<Item = &Fragment> {
    fragments.iter().filter(|f| f.depth.is_finite())
}

/// `(near, far)`: min and max depth of the texel's fragments, as the light-depth pass stores them (Min and
/// Max blending). With no fragments, the pass's clear values `(1.0, 0.0)`.
pub fn depth_range(fragments: &[Fragment]) -> (f32, f32) {
    valid(fragments).fold((1.0, 0.0), |(near, far), f| (near.min(f.depth), far.max(f.depth)))
}

/// Relative depth `t` of `z` inside the texel range `[near, far]` (0 at near, 1 at far), unclamped.
///
/// When the range is empty or a single point (`far <= near`: one fragment, all fragments at one depth, or an
/// empty texel) the result is the step `t = 0` for `z <= near`, `t = 1` beyond, which keeps every range-based
/// method exact there. GPU, exactly this expression:
/// `select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near)`.
pub fn relative_depth(z: f32, near: f32, far: f32) -> f32 {
    if far > near {
        (z - near) / (far - near)
    } else if z > near {
        1.0
    } else {
        0.0
    }
}

/// Index of the slice a coordinate `x = t * n` falls in, for `n` uniform slices: `min(floor(x), n - 1)`, and
/// 0 for negative (or NaN) `x`.
///
/// GPU: `min(u32(max(floor(x), 0.0)), n - 1u)` with `x` computed as `t * f32(n)`.
pub fn slice_index(x: f32, n: usize) -> usize {
    // `as usize` saturates: negative and NaN give 0.
    (x.floor() as usize).min(n.saturating_sub(1))
}

/// Linear interpolation between two accumulated optical depths `a <= b`, capped at `b`:
/// `min(a + (b - a) * f, b)`. The cap keeps the reconstructed optical depth non-decreasing across slice
/// boundaries under f32 rounding (so `V` never increases with depth). GPU: the same expression.
pub fn lerp_up(a: f32, b: f32, f: f32) -> f32 {
    (a + (b - a) * f).min(b)
}

/// Visibility from accumulated optical depth: `V = exp(-omega)`. GPU: `exp(-omega)`.
pub fn transmittance(omega: f32) -> f32 {
    (-omega).exp()
}

/// The hair count a visibility `v` stands for when every strand has opacity `hair_alpha`:
/// `-ln V / b(alpha)` ([`optical_depth`]), with `V` floored at the smallest normal f32 (so an opaque `V = 0`
/// gives a finite count) and 0 for a transparent hair (`b = 0`). GPU: `count_from_visibility` in
/// `shaders/common/visibility.wgsl`, the same expression.
pub fn count_from_visibility(v: f32, hair_alpha: f32) -> f32 {
    let b = optical_depth(hair_alpha);
    if b > 0.0 {
        (-v.max(f32::MIN_POSITIVE).ln()).max(0.0) / b
    } else {
        0.0
    }
}

/// A method model: its parameters build one texel from the texel's fragments and answer visibility queries.
pub trait Model {
    /// Exactly what the GPU stores per texel.
    type Texel;
    /// Builds the texel from its fragments (any order).
    fn build(&self, fragments: &[Fragment]) -> Self::Texel;
    /// Visibility at normalised light depth `z`.
    fn visibility(&self, texel: &Self::Texel, z: f32) -> f32;
}

/// Builds `model`'s texel once and evaluates `V` at every depth of `zs` (what every [`TexelModel::curve`] does).
pub fn model_curve<M: Model>(model: &M, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
    let texel = model.build(fragments);
    zs.iter().map(|&z| model.visibility(&texel, z)).collect()
}

/// What a method stores for one texel, in absolute light depth, as the texel inspector draws it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stored {
    /// The model's short label (e.g. `osm-16`).
    pub label: String,
    /// A description of the stored values, one line each.
    pub summary: Vec<String>,
    /// Slice planes, layer boundaries or slab boundaries.
    pub boundaries: Vec<f32>,
    /// `(depth, V)` where the method stores a value (`V = exp(-stored optical depth)`).
    pub knots: Vec<[f32; 2]>,
    /// Cluster means and bins `[L, R]` (Density Clustering).
    pub means: Vec<f32>,
    pub bins: Vec<[f32; 2]>,
    /// Occupied depth intervals `[from, to]` (occupancy maps).
    pub occupied: Vec<[f32; 2]>,
}

impl Stored {
    /// An empty description labelled `label`.
    pub fn new(label: String) -> Stored {
        Stored {
            label,
            ..Stored::default()
        }
    }

    /// Depths where the method's curve has a kink or a step.
    pub fn events(&self) -> impl Iterator<Item = f32> + '_ {
        self.boundaries
            .iter()
            .copied()
            .chain(self.means.iter().copied())
            .chain(self.bins.iter().flatten().copied())
            .chain(self.occupied.iter().flatten().copied())
    }
}

/// A method's CPU model with its parameters bound: the object-safe face every generic caller (inspector,
/// light-map view, metrics, `measure`, the CLI's `curve`, the GPU = CPU harness) uses. Each method's model
/// implements it in the method's own file.
pub trait TexelModel: Send + Sync + std::fmt::Debug {
    /// Short label with the parameter that matters, e.g. `osm-16`, `dc-4`.
    fn label(&self) -> String;
    /// Builds the texel from `fragments` once and evaluates `V` at every depth of `zs`.
    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32>;
    /// The hair count at every depth of `zs`: how many strands lie in front (see the module's conventions). By
    /// default [`count_from_visibility`] of [`TexelModel::curve`] with the scene's uniform `hair_alpha` (where
    /// fragments' alphas differ, the count of strands of that alpha that give the same `V`); a method that
    /// stores a count answers from it.
    fn count_curve(&self, fragments: &[Fragment], zs: &[f32], hair_alpha: f32) -> Vec<f32> {
        self.curve(fragments, zs)
            .into_iter()
            .map(|v| count_from_visibility(v, hair_alpha))
            .collect()
    }
    /// The per-texel values the method stores besides near/far, in the GPU's order (for the light-map view).
    fn stored_values(&self, _fragments: &[Fragment]) -> Vec<f32> {
        Vec::new()
    }
    /// What the method stores for a texel of `fragments`, for the inspector's plot (`None`: nothing beyond
    /// the fragments).
    fn stored(&self, _fragments: &[Fragment]) -> Option<Stored> {
        None
    }
}

/// A list of values for [`Stored::summary`], three decimals each.
pub(crate) fn list(values: &[f32]) -> String {
    let v: Vec<String> = values.iter().map(|x| format!("{x:.3}")).collect();
    v.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::LN_2;

    #[test]
    fn optical_depth_of_half_is_ln2() {
        assert!((optical_depth(0.5) - LN_2).abs() < 1e-7);
        // 1 - 0.75 = 1/4 -> b = ln 4 = 2 ln 2.
        assert!((optical_depth(0.75) - 2.0 * LN_2).abs() < 1e-6);
        assert_eq!(optical_depth(0.0), 0.0);
    }

    #[test]
    fn optical_depth_clamps() {
        assert_eq!(optical_depth(-0.5), 0.0);
        assert_eq!(optical_depth(f32::NAN), 0.0);
        assert_eq!(optical_depth(1.0), optical_depth(MAX_ALPHA));
        assert_eq!(optical_depth(7.0), optical_depth(MAX_ALPHA));
        // -ln(1e-6) = 13.8155; in f32, MAX_ALPHA = 0.99999899 and 1 - MAX_ALPHA = 1.01328e-6, so b = 13.8023.
        assert!((optical_depth(1.0) - 13.8023).abs() < 1e-3);
    }

    #[test]
    fn depth_range_is_min_max_or_clear_values() {
        let f = [
            Fragment::new(0.4, 0.1),
            Fragment::new(0.2, 0.1),
            Fragment::new(f32::NAN, 0.1),
        ];
        assert_eq!(depth_range(&f), (0.2, 0.4));
        assert_eq!(depth_range(&[]), (1.0, 0.0));
    }

    #[test]
    fn relative_depth_cases() {
        assert_eq!(relative_depth(0.3, 0.2, 0.6), (0.3f32 - 0.2) / (0.6f32 - 0.2));
        assert_eq!(relative_depth(0.6, 0.2, 0.6), 1.0);
        // Degenerate range: step at near.
        assert_eq!(relative_depth(0.5, 0.5, 0.5), 0.0);
        assert_eq!(relative_depth(0.4, 0.5, 0.5), 0.0);
        assert_eq!(relative_depth(0.50001, 0.5, 0.5), 1.0);
        // Empty texel clear values.
        assert_eq!(relative_depth(0.9, 1.0, 0.0), 0.0);
    }

    #[test]
    fn slice_index_cases() {
        assert_eq!(slice_index(0.0, 4), 0);
        assert_eq!(slice_index(3.999, 4), 3);
        assert_eq!(slice_index(4.0, 4), 3);
        assert_eq!(slice_index(-2.5, 4), 0);
        assert_eq!(slice_index(f32::NAN, 4), 0);
        assert_eq!(slice_index(1e30, 4), 3);
        assert_eq!(slice_index(5.0, 0), 0);
    }

    /// `-ln V / b` by hand: alpha 0.5 (b = ln 2): V = 1/8 is 3 strands, V = 1 none; alpha 0.75 (b = 2 ln 2):
    /// V = 1/16 is 2; V = 0 is floored at 2^-126, i.e. 126 strands of alpha 0.5; a transparent hair counts 0.
    #[test]
    fn count_from_visibility_by_hand() {
        assert!((count_from_visibility(0.125, 0.5) - 3.0).abs() < 1e-5);
        assert_eq!(count_from_visibility(1.0, 0.5), 0.0);
        assert!((count_from_visibility(0.0625, 0.75) - 2.0).abs() < 1e-5);
        assert!((count_from_visibility(0.0, 0.5) - 126.0).abs() < 1e-3);
        assert_eq!(count_from_visibility(0.3, 0.0), 0.0);
    }

    /// The default count of a model is `-ln V / b` of its own curve: a method whose `V` is 1/4 after one
    /// fragment of alpha 0.75 counts 2 strands of alpha 0.5 (and 1 of alpha 0.75).
    #[test]
    fn default_count_reads_the_models_visibility() {
        let osm = osm::OsmParams { slices: 4 };
        let f = [Fragment::new(0.0, 0.75), Fragment::new(1.0, 0.75)];
        // OSM's first plane at z = 0.25 holds the fragment at 0 (b = 2 ln 2): V = 1/4 there.
        assert!((osm.curve(&f, &[0.25])[0] - 0.25).abs() < 1e-6);
        let counts = osm.count_curve(&f, &[0.25, 0.25], 0.5);
        assert!((counts[0] - 2.0).abs() < 1e-5, "{counts:?}");
        assert!((osm.count_curve(&f, &[0.25], 0.75)[0] - 1.0).abs() < 1e-5);
    }

    #[test]
    fn lerp_up_is_capped() {
        assert_eq!(lerp_up(1.0, 3.0, 0.5), 2.0);
        assert_eq!(lerp_up(1.0, 3.0, 1.0), 3.0);
        assert_eq!(lerp_up(1.0, 3.0, 2.0), 3.0);
        assert_eq!(lerp_up(1.0, 3.0, 0.0), 1.0);
    }
}
