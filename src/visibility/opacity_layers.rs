//! How the opacity-layer family — Opacity Shadow Maps (`osm`), Deep Opacity Maps (`dom`) and Bounding Opacity
//! Maps (`bom`) — turns the fragments of a texel into its `N` stored entries, once for the three models. Each
//! model assigns every fragment an entry `k` (its slice or layer) and its optical depth `b`; entry `i` then
//! stores the optical depth accumulated up to its far end, `sum of b over the fragments with k <= i`, built one
//! of two ways ([`LayerBuild`]):
//!
//! - **targets**: the GPU adds `b` to entry `k` and every later one with additive f32 blending, 4 entries per
//!   RGBA32F colour target and at most 8 targets (32 entries) per geometry pass. The model adds in f32 in the
//!   fragments' order (the GPU's order differs: f32 rounding, within the stated tolerance).
//! - **atomic**: one geometry pass (per band of entries whose counters fit four storage bindings) in which each fragment
//!   adds its quantised optical depth `q = floor(b · 2^16 + 0.5)` ([`quantise`]) to the u32 counter of its
//!   `(texel, k)` with a storage atomic, saturating at [`SATURATION`] (optical depth 256, where
//!   `V = e^-256` is 0 in f32 already beyond 104); then a resolve pass sums the counters front to back
//!   (saturating again) and writes each entry in the chosen [`LayerStorage`]. Integer sums do not depend on
//!   the order, so the model's entries are the GPU's bit for bit up to the rounding of `b` itself (`ln` in
//!   WGSL against Rust's, which moves `q` by one quantum in rare cases).
//!
//! Saturation on the GPU: `old = atomicAdd(c, q); if old + q > SATURATION { atomicMin(c, SATURATION) }`.
//! Every add that ends above the cap is followed by its own min, and a counter never falls below the cap once
//! above it, so the final value is exactly `min(sum, SATURATION)` provided the counter never wraps: with
//! `q <= 13.81 · 2^16 < 905 000`, that needs more than `(2^32 - 2^24) / 905 000 = 4727` adds to one counter
//! between their add and their min at once.
//!
//! Storage of an entry (`cum` the saturated fixed-point sum, `cum · 2^-16` its optical depth, exact in f32 as
//! `cum <= 2^24`): `f32` that value (4 bytes per entry); `f16` that value rounded to 11 significant bits (to
//! nearest, ties to even; exact in half precision, so the GPU's f16 conversion cannot round it again; 2
//! bytes); `u8` the optical depth in steps of 1/32, `q8 = min((cum + 2^10) >> 11, 255)` stored as the unorm
//! `q8 / 255` and read back times [`U8_UNIT`] = 255/32 (saturates at optical depth 7.97, `V = 3.5e-4`; 1 byte).
//! Voicu's thesis keeps four layers per texture at 32 bits per channel (f32 here); Yuksel & Keyser 2008 found
//! an 8-bit depth map enough for the deep opacity map's `z0` but do not vary the layers' precision, which is
//! what f16 and u8 measure.

use super::{Fragment, Model, Stored, TexelModel};

/// Fixed-point scale of the atomic build: one unit of a counter is `2^-16` of optical depth.
pub const FIXED_POINT_SCALE: f32 = 65536.0;
/// Largest counter and accumulated value of the atomic build: `2^24`, optical depth 256.
pub const SATURATION: u32 = 1 << 24;
/// Fixed-point units per step of the 8-bit storage: `2^11`, so a step is `1/32` of optical depth.
pub const U8_STEP_SHIFT: u32 = 11;
/// What the 8-bit storage's unorm value is multiplied by to give optical depth: `255 / 32`.
pub const U8_UNIT: f32 = 255.0 / 32.0;
/// Significant bits of a half-precision value (10 stored + the implicit one).
const F16_SIGNIFICANT_BITS: u32 = 11;

/// How one entry is stored by the atomic build.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LayerStorage {
    /// RGBA32F: 4 bytes per entry.
    #[default]
    F32,
    /// RGBA16F: 2 bytes per entry.
    F16,
    /// RGBA8 unorm, optical depth in steps of 1/32: 1 byte per entry.
    U8,
}

impl LayerStorage {
    /// Every storage, in the order of the `storage` parameter's options.
    pub const ALL: [LayerStorage; 3] = [LayerStorage::F32, LayerStorage::F16, LayerStorage::U8];

    /// The parameter word: `f32`, `f16`, `u8`.
    pub fn name(self) -> &'static str {
        match self {
            LayerStorage::F32 => "f32",
            LayerStorage::F16 => "f16",
            LayerStorage::U8 => "u8",
        }
    }

    /// Bytes one entry takes in the map.
    pub fn bytes_per_entry(self) -> u64 {
        match self {
            LayerStorage::F32 => 4,
            LayerStorage::F16 => 2,
            LayerStorage::U8 => 1,
        }
    }

    /// What the lookup multiplies a stored value by to get optical depth.
    pub fn unit(self) -> f32 {
        match self {
            LayerStorage::U8 => U8_UNIT,
            _ => 1.0,
        }
    }

    /// The value the map holds for the fixed-point sum `cum` (`<= SATURATION`), as the resolve pass writes it.
    pub fn raw(self, cum: u32) -> f32 {
        match self {
            LayerStorage::F32 => cum as f32 / FIXED_POINT_SCALE,
            LayerStorage::F16 => round_significand(cum, F16_SIGNIFICANT_BITS) as f32 / FIXED_POINT_SCALE,
            LayerStorage::U8 => ((cum + (1 << (U8_STEP_SHIFT - 1))) >> U8_STEP_SHIFT).min(255) as f32 / 255.0,
        }
    }

    /// The optical depth the lookup reads for `cum`: [`LayerStorage::raw`] times [`LayerStorage::unit`], in
    /// the lookup's f32 expression.
    pub fn value(self, cum: u32) -> f32 {
        self.raw(cum) * self.unit()
    }
}

/// How the entries are built on the GPU (and so what the model computes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayerBuild {
    /// Additive f32 blending into colour targets, 32 entries per geometry pass.
    Targets,
    /// Fixed-point storage atomics in one geometry pass, resolved into `storage`.
    Atomic(LayerStorage),
}

/// `b` in fixed point: `floor(b · 2^16 + 0.5)` in f32 (exact: `b · 2^16 < 2^20`). GPU:
/// `u32(optical_depth(alpha) * 65536.0 + 0.5)`.
pub fn quantise(b: f32) -> u32 {
    (b * FIXED_POINT_SCALE + 0.5) as u32
}

/// `c` rounded to `bits` significant bits, to nearest with ties to even (unchanged below `2^bits`). GPU: the
/// same integer steps (`round_significand` in `shaders/layer_resolve.wgsl`).
pub fn round_significand(c: u32, bits: u32) -> u32 {
    if c < 1 << bits {
        return c;
    }
    let shift = (31 - c.leading_zeros()) + 1 - bits;
    let low = c & ((1 << shift) - 1);
    let half = 1 << (shift - 1);
    let mut m = c >> shift;
    if low > half || (low == half && m & 1 == 1) {
        m += 1;
    }
    m << shift
}

/// The `n` accumulated entries of a texel from its fragments' `(entry, optical depth)` pairs (`entry < n`).
pub fn accumulate(build: LayerBuild, n: usize, entries: impl IntoIterator<Item = (usize, f32)>) -> Vec<f32> {
    match build {
        LayerBuild::Targets => {
            let mut values = vec![0.0f32; n];
            for (k, b) in entries {
                for v in &mut values[k..] {
                    *v += b;
                }
            }
            values
        }
        LayerBuild::Atomic(storage) => {
            let mut sums = vec![0u32; n];
            for (k, b) in entries {
                sums[k] = sums[k].saturating_add(quantise(b)).min(SATURATION);
            }
            let mut cum = 0u32;
            sums.iter()
                .map(|&s| {
                    cum = (cum + s).min(SATURATION);
                    storage.value(cum)
                })
                .collect()
        }
    }
}

/// A model of the family: it builds its texel either way and describes a built texel to the inspector.
pub trait LayeredModel: Model + TexelModel + Clone {
    /// The texel as `build` makes it.
    fn build_with(&self, build: LayerBuild, fragments: &[Fragment]) -> Self::Texel;
    /// The texel's accumulated entries, in the GPU's order.
    fn entries(texel: &Self::Texel) -> &[f32];
    /// What the inspector draws for a built texel, labelled `label`.
    fn describe(&self, texel: &Self::Texel, label: String) -> Stored;
}

/// A model of the family with its build: what the methods hand to every generic caller.
#[derive(Clone, Debug, PartialEq)]
pub struct Layered<P> {
    pub params: P,
    pub build: LayerBuild,
}

impl<P: LayeredModel> Model for Layered<P> {
    type Texel = P::Texel;

    fn build(&self, fragments: &[Fragment]) -> P::Texel {
        self.params.build_with(self.build, fragments)
    }

    fn visibility(&self, texel: &P::Texel, z: f32) -> f32 {
        self.params.visibility(texel, z)
    }
}

impl<P: LayeredModel> TexelModel for Layered<P> {
    /// The parameters' label, with the storage when it is not f32 (both builds store f32 sums of the same
    /// optical depths, equal within the quantisation of 2^-17 per fragment).
    fn label(&self) -> String {
        match self.build {
            LayerBuild::Atomic(s) if s != LayerStorage::F32 => {
                format!("{} {}", self.params.label(), s.name())
            }
            _ => self.params.label(),
        }
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        P::entries(&Model::build(self, fragments)).to_vec()
    }

    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        Some(self.params.describe(&Model::build(self, fragments), self.label()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantise_rounds_to_the_nearest_unit() {
        assert_eq!(quantise(0.0), 0);
        assert_eq!(quantise(1.0), 65536);
        // 0.5 units round up, just below rounds down.
        assert_eq!(quantise(0.5 / 65536.0), 1);
        assert_eq!(quantise(0.49 / 65536.0), 0);
        // The largest optical depth (alpha clamped to 1 - 1e-6): 13.8023 -> 904 543, below 905 000.
        let most = quantise(super::super::optical_depth(1.0));
        assert!((904_000..905_000).contains(&most), "{most}");
    }

    #[test]
    fn significand_rounding_is_to_nearest_even() {
        assert_eq!(round_significand(2047, 11), 2047);
        assert_eq!(round_significand(2048, 11), 2048);
        // 4097 = 2048 * 2 + 1: halfway between 4096 and 4098, ties to the even significand 2048 -> 4096.
        assert_eq!(round_significand(4097, 11), 4096);
        // 4099: halfway between 4098 (significand 2049, odd) and 4100 (2050, even) -> 4100.
        assert_eq!(round_significand(4099, 11), 4100);
        assert_eq!(round_significand(4103, 11), 4104);
        // 2^24 - 1 rounds up to 2^24.
        assert_eq!(round_significand((1 << 24) - 1, 11), 1 << 24);
        // Every result has at most 11 significant bits, so it is exact in half precision.
        for c in (0..(1u32 << 24)).step_by(9973) {
            let r = round_significand(c, 11);
            assert!(r >> r.trailing_zeros().min(31) < 1 << 11, "{c} -> {r}");
            assert!(r.abs_diff(c) <= (c >> 11).max(1), "{c} -> {r}");
        }
    }

    #[test]
    fn storages_decode_to_the_accumulated_optical_depth() {
        // 1.5 in fixed point.
        let c = 3 << 15;
        assert_eq!(LayerStorage::F32.value(c), 1.5);
        assert_eq!(LayerStorage::F16.value(c), 1.5);
        assert!((LayerStorage::U8.value(c) - 1.5).abs() < 1e-6);
        // f16: 11 significant bits, relative error at most half an ulp, 2^-11.
        let c = 123_457_u32;
        let exact = c as f32 / FIXED_POINT_SCALE;
        assert!((LayerStorage::F16.value(c) - exact).abs() <= exact / 2048.0);
        // u8: steps of 1/32, saturating at 255/32.
        assert!((LayerStorage::U8.value(c) - exact).abs() <= 1.0 / 64.0 + 1e-6);
        assert!((LayerStorage::U8.value(SATURATION) - U8_UNIT).abs() < 1e-6);
        assert_eq!(LayerStorage::F32.value(SATURATION), 256.0);
    }

    #[test]
    fn both_builds_accumulate_front_to_back() {
        let pairs = [(1usize, 0.5f32), (0, 0.25), (2, 1.0), (1, 0.125)];
        let targets = accumulate(LayerBuild::Targets, 4, pairs);
        assert_eq!(targets, [0.25, 0.875, 1.875, 1.875]);
        // These b are exact in fixed point: the atomic build gives the same values in every storage but u8,
        // which rounds to 1/32 (0.875 = 28/32 and 1.875 = 60/32 are on the grid; 0.25 too).
        for s in LayerStorage::ALL {
            let atomic = accumulate(LayerBuild::Atomic(s), 4, pairs);
            for (a, t) in atomic.iter().zip(&targets) {
                assert!((a - t).abs() < 1e-6, "{s:?}: {atomic:?}");
            }
        }
    }

    /// The atomic build's error against the float (colour-target) build, `max |V_atomic - V_targets|` over 400
    /// hair-like texels of up to 80 fragments at every probe depth, for OSM-64, DOM-3 and BOM-4. Bounds, as
    /// `|e^-a - e^-b| <= |a - b|` and the lookup interpolates between entries: f32 at most 2^-17 per fragment
    /// (80 · 7.6e-6 = 6.1e-4); f16 adds half an ulp of 11 significant bits, `omega · 2^-11 · e^-omega <= 2^-11 / e
    /// = 1.8e-4`; u8 adds half a step, 1/64, on the texels whose total optical depth stays below its saturation
    /// (255/32). Where an entry saturates, V interpolated towards it is too bright: that error has no small
    /// bound and is only reported. Measured with this seed (OSM-64, DOM-3, BOM-4, max over all texels): f32
    /// 9.4e-6; f16 1.8e-4; u8 1.4e-2 below saturation and 0.49 above it.
    #[test]
    fn storage_error_against_the_float_build_is_within_its_bound() {
        use crate::visibility::test_support::{Rng, probe_depths, random_texel};
        use crate::visibility::{BomParams, DomParams, OsmParams};
        let mut rng = Rng::new(21);
        let texels: Vec<Vec<Fragment>> = (0..400).map(|_| random_texel(&mut rng, 80)).collect();
        let fragment_bound = 80.0 * 0.5 / FIXED_POINT_SCALE;
        let bounds = [
            fragment_bound,
            fragment_bound + 1.8e-4,
            fragment_bound + 1.0 / 64.0,
        ];
        fn worst<P: LayeredModel>(params: &P, storage: LayerStorage, texels: &[Vec<Fragment>]) -> f32 {
            let exact = Layered {
                params: params.clone(),
                build: LayerBuild::Targets,
            };
            let atomic = Layered {
                params: params.clone(),
                build: LayerBuild::Atomic(storage),
            };
            texels
                .iter()
                .map(|f| {
                    let zs = probe_depths(f);
                    let (a, b) = (exact.curve(f, &zs), atomic.curve(f, &zs));
                    a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max)
                })
                .fold(0.0, f32::max)
        }
        let (light, deep): (Vec<Vec<Fragment>>, Vec<Vec<Fragment>>) = texels
            .into_iter()
            .partition(|f| f.iter().map(Fragment::optical_depth).sum::<f32>() < U8_UNIT);
        assert!(
            light.len() > 100 && deep.len() > 50,
            "{} {}",
            light.len(),
            deep.len()
        );
        for (storage, bound) in LayerStorage::ALL.into_iter().zip(bounds) {
            let measure = |texels: &[Vec<Fragment>]| {
                [
                    worst(&OsmParams { slices: 64 }, storage, texels),
                    worst(&DomParams::default(), storage, texels),
                    worst(&BomParams::default(), storage, texels),
                ]
            };
            let (within, beyond) = (measure(&light), measure(&deep));
            eprintln!(
                "{}: max |V_atomic - V_targets| (OSM-64, DOM-3, BOM-4) {within:?} below u8 saturation, \
                 {beyond:?} above (bound {bound:.1e})",
                storage.name()
            );
            assert!(
                within.iter().all(|&m| m <= bound),
                "{storage:?}: {within:?} above {bound}"
            );
            if storage != LayerStorage::U8 {
                assert!(
                    beyond.iter().all(|&m| m <= bound),
                    "{storage:?}: {beyond:?} above {bound}"
                );
            }
        }
    }

    #[test]
    fn labels_name_the_storage_when_not_f32() {
        let params = super::super::OsmParams { slices: 16 };
        let label = |build| Layered { params, build }.label();
        assert_eq!(label(LayerBuild::Targets), params.label());
        assert_eq!(label(LayerBuild::Atomic(LayerStorage::F32)), params.label());
        assert_eq!(
            label(LayerBuild::Atomic(LayerStorage::F16)),
            format!("{} f16", params.label())
        );
        assert_eq!(
            label(LayerBuild::Atomic(LayerStorage::U8)),
            format!("{} u8", params.label())
        );
    }

    #[test]
    fn the_atomic_build_saturates_at_the_cap() {
        // 40 fragments of b = 13.8 in one entry: 552 > 256.
        let b = super::super::optical_depth(1.0);
        let pairs = std::iter::repeat_n((0usize, b), 40);
        let v = accumulate(LayerBuild::Atomic(LayerStorage::F32), 2, pairs);
        assert_eq!(v, [256.0, 256.0]);
        // Two entries each below the cap whose sum is above it: the running sum saturates too.
        let pairs = std::iter::repeat_n((0usize, b), 15).chain(std::iter::repeat_n((1usize, b), 15));
        let v = accumulate(LayerBuild::Atomic(LayerStorage::F32), 2, pairs);
        assert_eq!(v[0], (15 * quantise(b)) as f32 / FIXED_POINT_SCALE);
        assert_eq!(v[1], 256.0);
    }
}
