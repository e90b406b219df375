//! Occupancy Maps (Sintorn & Assarsson, I3D 2009, §3.1-3.3).
//!
//! Per texel, the depth range `[near, far]` of its fragments (the depth-range map, §3.1, Fig. 7) is cut into
//! 128 slices; the occupancy map holds one bit per slice, set if any fragment falls in it (128 bits = one
//! four-channel u32 texel). The slices are grouped into 4 slabs of 32 (one u32 channel of occupancy each),
//! and the slab map counts the fragments of each slab. With `d = (z - near) / (far - near)`, a fragment is in
//! slice `floor(d * 128)` and slab `floor(d * 4)` (§3.1; both clamped to the last one for `d = 1`).
//!
//! Order estimate `o(z)` (§3.2), the number of fragments in front of depth `z`, under the paper's two
//! assumptions (equal counts in the occupied slices of a slab; fragments spread uniformly over their slice):
//! the counts of the preceding slabs, plus `F_i / B_total * B_before` for the slab `i` of `z`, with `F_i` its
//! fragment count, `B_total` its set bits and `B_before` the set bits before `z`, "linearly interpolated
//! between the results of its occupied slice and the previous slice", i.e.
//! `B_before = (set bits of earlier slices) + (bit of z's slice) * (fraction of the slice in front of z)`.
//!
//! Shadow (§3.3): `opacity = o * w` with `w` the optical depth of one fragment, from the hair alpha the paper
//! assumes uniform: `w = b(alpha)`, [`OccupancyParams::alpha`]; `V = exp(-o * w)`. Each fragment's own alpha
//! is ignored.
//!
//! Occupancy-only variant (§3, before §3.1): a single slab spanning the range, each set bit standing for
//! `F / S` fragments (`F` all the texel's fragments, `S` all its set bits). Stored in the same texel, with
//! the total count in slab 0 and the other slabs 0.
//!
//! The half-texel jitter of §3.3 (offsetting the map lookup coordinate by half a texel against aliasing) is a
//! GPU sampling detail outside this per-texel model.
//!
//! Exact, with uniform alpha equal to the parameter: `V` at every slab boundary (§3.3: the order "will
//! converge towards the correct value on each of the slab boundaries", Fig. 8), `V(z) = 1` for `z <= near`,
//! and a texel whose fragments all lie at one depth. With the occupancy-only variant only the ends are exact.
//! Approximate: inside slabs, and any texel whose alphas differ from the parameter.
//!
//! GPU contract (per texel: `near`, `far` f32; occupancy `vec4<u32>`; slab counts `vec4<u32>`):
//! - `d = select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near)`;
//!   `s = min(u32(max(floor(d * 128.0), 0.0)), 127u)`; word `s >> 5u`, bit `s & 31u`;
//! - build, per fragment: `atomicOr(occupancy[s >> 5u], 1u << (s & 31u))`; `atomicAdd(slabs[s >> 5u], 1u)`
//!   (the slab is `s >> 5`, identical to the paper's `floor(d * 4)` because `d * 128 = (d * 4) * 32` exactly
//!   in f32); occupancy-only: `atomicAdd(slabs[0], 1u)`;
//! - lookup: `o = 0` if `!(d > 0.0)`; else `frac = clamp(d * 128.0 - f32(s), 0.0, 1.0)`,
//!   `own = (occ[w] >> bit) & 1u`, `before = countOneBits(occ[w] & ((1u << bit) - 1u))` with `w = s >> 5u`,
//!   `F = f32(slabs[w])`, `B = f32(countOneBits(occ[w]))`, `base = f32(sum of slabs[0..w])`,
//!   `o = base + select(0.0, min(F * (f32(before) + f32(own) * frac) / B, F), B > 0.0)` (occupancy-only:
//!   `base = 0`, `F = f32(slabs[0])`, `B` all set bits, `before` adds the set bits of the earlier words);
//!   `V = exp(-o * (-log(1.0 - clamp(alpha, 0.0, 1.0 - 1e-6))))`.

use super::{
    Fragment, Model, Stored, TexelModel, depth_range, optical_depth, relative_depth, slice_index,
    transmittance, valid,
};

/// Slices of the occupancy map.
pub const SLICES: usize = 128;
/// Slabs of the slab map.
pub const SLABS: usize = 4;
/// Slices per slab (bits per u32 word).
pub const SLICES_PER_SLAB: usize = SLICES / SLABS;

/// Occupancy map with or without the slab map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OccupancyVariant {
    /// Occupancy map plus 4-slab fragment counts (the paper's method).
    #[default]
    SlabMap,
    /// Occupancy map plus one total count (the simpler variant the paper improves on).
    OccupancyOnly,
}

/// Occupancy Map parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OccupancyParams {
    /// The uniform hair alpha the shadow weight `w = -ln(1 - alpha)` comes from (clamped like
    /// [`optical_depth`]).
    pub alpha: f32,
    pub variant: OccupancyVariant,
}

impl OccupancyParams {
    /// The paper's method (occupancy + slab map) for hair of opacity `alpha`.
    pub fn new(alpha: f32) -> Self {
        Self {
            alpha,
            variant: OccupancyVariant::SlabMap,
        }
    }
}

/// One occupancy texel: depth range, 128 occupancy bits (slice `i` is bit `i % 32` of word `i / 32`),
/// fragment counts per slab (occupancy-only: the total in slab 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OccupancyTexel {
    pub near: f32,
    pub far: f32,
    pub occupancy: [u32; 4],
    pub slabs: [u32; 4],
}

/// Builds an occupancy texel from the fragments' depths (their alphas are not used).
pub fn build(params: &OccupancyParams, fragments: &[Fragment]) -> OccupancyTexel {
    let (near, far) = depth_range(fragments);
    let mut occupancy = [0u32; 4];
    let mut slabs = [0u32; 4];
    for f in valid(fragments) {
        let s = slice_index(relative_depth(f.depth, near, far) * SLICES as f32, SLICES);
        let word = s / SLICES_PER_SLAB;
        occupancy[word] |= 1 << (s % SLICES_PER_SLAB);
        let slab = match params.variant {
            OccupancyVariant::SlabMap => word,
            OccupancyVariant::OccupancyOnly => 0,
        };
        slabs[slab] = slabs[slab].wrapping_add(1);
    }
    OccupancyTexel {
        near,
        far,
        occupancy,
        slabs,
    }
}

/// The order estimate `o(z)`: approximate number of the texel's fragments in front of depth `z` (§3.2).
pub fn order(params: &OccupancyParams, texel: &OccupancyTexel, z: f32) -> f32 {
    let d = relative_depth(z, texel.near, texel.far);
    if d.is_nan() || d <= 0.0 {
        return 0.0;
    }
    let x = d * SLICES as f32;
    let s = slice_index(x, SLICES);
    let frac = (x - s as f32).clamp(0.0, 1.0);
    let (word, bit) = (s / SLICES_PER_SLAB, s % SLICES_PER_SLAB);
    let occ = texel.occupancy;
    let own = (occ[word] >> bit) & 1;
    let before_in_word = (occ[word] & ((1u32 << bit) - 1)).count_ones();
    let (base, count, bits, before) = match params.variant {
        OccupancyVariant::SlabMap => (
            texel.slabs[..word].iter().map(|&c| u64::from(c)).sum::<u64>(),
            texel.slabs[word],
            occ[word].count_ones(),
            before_in_word,
        ),
        OccupancyVariant::OccupancyOnly => (
            0,
            texel.slabs[0],
            occ.iter().map(|w| w.count_ones()).sum(),
            occ[..word].iter().map(|w| w.count_ones()).sum::<u32>() + before_in_word,
        ),
    };
    let in_slab = if bits > 0 {
        let f = count as f32;
        (f * (before as f32 + own as f32 * frac) / bits as f32).min(f)
    } else {
        0.0
    };
    base as f32 + in_slab
}

/// `V(z) = exp(-o(z) * w)`, `w = -ln(1 - alpha)`.
pub fn visibility(params: &OccupancyParams, texel: &OccupancyTexel, z: f32) -> f32 {
    transmittance(order(params, texel, z) * optical_depth(params.alpha))
}

impl Model for OccupancyParams {
    type Texel = OccupancyTexel;

    fn build(&self, fragments: &[Fragment]) -> OccupancyTexel {
        build(self, fragments)
    }

    fn visibility(&self, texel: &OccupancyTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

impl TexelModel for OccupancyParams {
    fn label(&self) -> String {
        match self.variant {
            OccupancyVariant::SlabMap => "occupancy".into(),
            OccupancyVariant::OccupancyOnly => "occupancy-only".into(),
        }
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    /// The order estimate `o(z)` itself (§3.2): the count the map stores, whatever the alphas.
    fn count_curve(&self, fragments: &[Fragment], zs: &[f32], _hair_alpha: f32) -> Vec<f32> {
        let texel = build(self, fragments);
        zs.iter().map(|&z| order(self, &texel, z)).collect()
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        build(self, fragments).slabs.iter().map(|&c| c as f32).collect()
    }

    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        let t = build(self, fragments);
        let at = |x: f32| t.near + (t.far - t.near) * x;
        let mut s = Stored::new(self.label());
        s.occupied = (0..SLICES)
            .filter(|&i| t.occupancy[i / SLICES_PER_SLAB] >> (i % SLICES_PER_SLAB) & 1 == 1)
            .map(|i| [at(i as f32 / SLICES as f32), at((i + 1) as f32 / SLICES as f32)])
            .collect();
        let w = optical_depth(self.alpha);
        match self.variant {
            OccupancyVariant::SlabMap => {
                let mut before = 0u32;
                for i in 0..=SLABS {
                    let z = at(i as f32 / SLABS as f32);
                    s.boundaries.push(z);
                    s.knots.push([z, transmittance(before as f32 * w)]);
                    if i < SLABS {
                        before += t.slabs[i];
                    }
                }
                s.summary.push(format!("slab counts {:?}", t.slabs));
            }
            OccupancyVariant::OccupancyOnly => {
                s.boundaries = vec![t.near, t.far];
                s.summary.push(format!("fragment count {}", t.slabs[0]));
            }
        }
        s.summary.push(format!(
            "range [{:.4}, {:.4}], {} of {SLICES} slices occupied; w = b(α {:.2}) = {w:.4}",
            t.near,
            t.far,
            s.occupied.len(),
            self.alpha
        ));
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::reference;
    use crate::visibility::test_support::{Rng, assert_valid_curve, extreme_texels, random_texel};

    fn only(alpha: f32) -> OccupancyParams {
        OccupancyParams {
            alpha,
            variant: OccupancyVariant::OccupancyOnly,
        }
    }

    // near 0, far 1 (so d = z); alpha 0.5 everywhere. Fragments at 0.0, 0.1, 0.1, 0.2, 0.6, 1.0:
    // slices floor(128 d) = 0, 12, 12, 25, 76, 127 (1.0 -> 128 -> clamped); slabs 0, 0, 0, 0, 2, 3.
    fn texel_fragments() -> Vec<Fragment> {
        [0.6, 0.1, 0.0, 1.0, 0.2, 0.1]
            .iter()
            .map(|&z| Fragment::new(z, 0.5))
            .collect()
    }

    /// The GPU's eye pass reads the count as `−ln V / b(α)` of the lookup's `V` (`count_from_visibility`); for
    /// occupancy maps that returns the order estimate the map stores, to f32 rounding of `exp` and `ln`: relative
    /// tolerance 1e-5 (measured at most 1.3e-7 here, printed), both variants, alphas 0.2 / 0.5 / 0.8.
    #[test]
    fn count_from_its_visibility_is_its_order() {
        let mut worst = 0.0f32;
        for alpha in [0.2, 0.5, 0.8] {
            for params in [OccupancyParams::new(alpha), only(alpha)] {
                let frags: Vec<Fragment> = [0.6, 0.1, 0.0, 1.0, 0.2, 0.1]
                    .iter()
                    .map(|&z| Fragment::new(z, alpha))
                    .collect();
                let t = build(&params, &frags);
                for k in 0..=40 {
                    let z = k as f32 / 40.0;
                    let o = order(&params, &t, z);
                    let n = crate::visibility::count_from_visibility(visibility(&params, &t, z), alpha);
                    let err = (n - o).abs() / o.max(1.0);
                    assert!(err <= 1e-5, "alpha {alpha}, z {z}: count {n} vs order {o}");
                    worst = worst.max(err);
                }
            }
        }
        println!("occupancy: count from V against the order, max relative difference {worst:e}");
    }

    #[test]
    fn hand_computed_maps() {
        let t = build(&OccupancyParams::new(0.5), &texel_fragments());
        assert_eq!((t.near, t.far), (0.0, 1.0));
        // Word 0: bits 0, 12, 25. Word 2: slice 76 = bit 12. Word 3: slice 127 = bit 31.
        assert_eq!(t.occupancy, [1 | 1 << 12 | 1 << 25, 0, 1 << 12, 1 << 31]);
        assert_eq!(t.slabs, [4, 0, 1, 1]);
        let t = build(&only(0.5), &texel_fragments());
        assert_eq!(t.occupancy, [1 | 1 << 12 | 1 << 25, 0, 1 << 12, 1 << 31]);
        assert_eq!(t.slabs, [6, 0, 0, 0]);
    }

    #[test]
    fn hand_computed_order_and_visibility() {
        let params = OccupancyParams::new(0.5);
        let t = build(&params, &texel_fragments());
        let o = |z| order(&params, &t, z);
        // Slab 0 has F = 4 fragments on B = 3 set bits: 4/3 per bit.
        // z = 0.05: slice 6 (x = 6.4, unset); set bits before it: {0} -> o = 4/3.
        assert!((o(0.05) - 4.0 / 3.0).abs() < 1e-6);
        // z = 0.1: slice 12 (x = 12.8, set), 0.8 of it in front; bits before {0}: o = 4/3 * 1.8 = 2.4.
        assert!((o(0.1) - 2.4).abs() < 1e-5);
        // Slab boundaries are exact: 0.25 -> 4 (fragments 0, 0.1, 0.1, 0.2), 0.5 -> 4, 0.75 -> 5.
        assert_eq!(o(0.25), 4.0);
        assert_eq!(o(0.5), 4.0);
        assert_eq!(o(0.75), 5.0);
        // z = 0.7: slab 2 (F = 1, B = 1), slice 89 after the set bit 76: 4 + 1 = 5.
        assert_eq!(o(0.7), 5.0);
        // z = 1: end of slice 127 (frac 1): 5 + 1 = 6, while the reference counts 5 (the fragment at 1 does
        // not shadow itself). Beyond: 6.
        assert_eq!(o(1.0), 6.0);
        assert_eq!(o(3.0), 6.0);
        assert_eq!(o(0.0), 0.0);
        assert_eq!(o(-1.0), 0.0);
        // V = exp(-o ln 2) = 2^-o.
        let v = |z| visibility(&params, &t, z);
        assert!((v(0.05) - 2f32.powf(-4.0 / 3.0)).abs() < 1e-6);
        assert!((v(0.1) - 2f32.powf(-2.4)).abs() < 1e-6);
        assert!((v(0.25) - 1.0 / 16.0).abs() < 1e-7);
        assert_eq!(v(0.0), 1.0);
    }

    /// The count is the order estimate, not `-ln V / b`: with alpha 0.9 fragments and a model built for
    /// alpha 0.5, the hand values of `hand_computed_order_and_visibility` (4/3 at 0.05, 2.4 at 0.1, 4 at 0.25)
    /// whatever hair alpha the caller passes.
    #[test]
    fn count_is_the_order_estimate() {
        let f: Vec<Fragment> = texel_fragments()
            .iter()
            .map(|f| Fragment::new(f.depth, 0.9))
            .collect();
        let counts = OccupancyParams::new(0.5).count_curve(&f, &[0.05, 0.1, 0.25], 0.9);
        for (got, want) in counts.iter().zip([4.0 / 3.0, 2.4, 4.0]) {
            assert!((got - want).abs() < 1e-5, "{counts:?}");
        }
    }

    #[test]
    fn hand_computed_occupancy_only() {
        // One slab: F = 6 fragments on S = 5 set bits: 6/5 per bit.
        let params = only(0.5);
        let t = build(&params, &texel_fragments());
        let o = |z| order(&params, &t, z);
        // z = 0.25: bits before slice 32: {0, 12, 25} -> 3.6 (the reference counts 4: not exact here).
        assert!((o(0.25) - 3.6).abs() < 1e-5);
        // z = 0.7: bits before slice 89: {0, 12, 25, 76} -> 4.8.
        assert!((o(0.7) - 4.8).abs() < 1e-5);
        // Both ends exact: 0 and 6.
        assert_eq!(o(0.0), 0.0);
        assert_eq!(o(1.0), 6.0);
    }

    #[test]
    fn near_far_range_is_per_texel() {
        // near 0.2, far 0.6; fragments at 0.2, 0.3, 0.6 (alpha 0.5). d = 0, 0.25, 1 -> slices 0, 32, 127
        // (0.25 in f32: (0.3 - 0.2) / 0.4 = 0.25000003 -> x = 32.000004, slice 32, slab 1).
        let params = OccupancyParams::new(0.5);
        let f = [
            Fragment::new(0.3, 0.5),
            Fragment::new(0.6, 0.5),
            Fragment::new(0.2, 0.5),
        ];
        let t = build(&params, &f);
        assert_eq!((t.near, t.far), (0.2, 0.6));
        assert_eq!(t.occupancy, [1, 1, 0, 1 << 31]);
        assert_eq!(t.slabs, [1, 1, 0, 1]);
        // z = 0.4: d = 0.5, slab 2 starts: 1 + 1 = 2 fragments in front -> V = 1/4 = reference.
        assert!((visibility(&params, &t, 0.4) - 0.25).abs() < 1e-6);
        assert!((reference::visibility(&f, 0.4) - 0.25).abs() < 1e-6);
    }

    #[test]
    fn exact_at_slab_boundaries_with_uniform_alpha() {
        let mut rng = Rng::new(50);
        for _ in 0..200 {
            let alpha = rng.range(0.05, 0.6);
            let params = OccupancyParams::new(alpha);
            let f: Vec<Fragment> = random_texel(&mut rng, 100)
                .into_iter()
                .map(|f| Fragment::new(f.depth, alpha))
                .collect();
            let t = build(&params, &f);
            // The boundaries near + k/4 (far - near), k = 0..=3 (skipping those with a fragment within f32
            // noise of them), and just past far, where the order reaches the total count. (At far itself the
            // fragments there shadow themselves: o counts them, the reference does not.)
            let mut zs: Vec<f32> = (1..4)
                .map(|k| t.near + (t.far - t.near) * (k as f32 / 4.0))
                .filter(|&z| f.iter().all(|f| (f.depth - z).abs() >= 1e-5))
                .collect();
            zs.extend([t.near, t.far.next_up()]);
            for z in zs {
                let (m, r) = (visibility(&params, &t, z), reference::visibility(&f, z));
                assert!((m - r).abs() < 1e-5, "z={z}: {m} vs {r}, fragments {f:?}");
            }
        }
    }

    #[test]
    fn exact_at_slice_boundaries_with_one_fragment_per_slice() {
        // When no slice holds two fragments, each set bit is exactly one fragment: o is exact at every slice
        // boundary. Fragments at slice centres (i + 1/2) / 128 of distinct slices, plus 0 and 1 to fix the
        // range.
        let mut rng = Rng::new(51);
        for _ in 0..50 {
            let slices: Vec<usize> = (1..127).filter(|_| rng.unit() < 0.3).collect();
            let mut f: Vec<Fragment> = slices
                .iter()
                .map(|&i| Fragment::new((i as f32 + 0.5) / 128.0, 0.3))
                .collect();
            f.extend([Fragment::new(0.0, 0.3), Fragment::new(1.0, 0.3)]);
            let params = OccupancyParams::new(0.3);
            let t = build(&params, &f);
            for i in 0..=127 {
                let z = i as f32 / 128.0;
                let exact = f.iter().filter(|f| f.depth < z).count() as f32;
                assert_eq!(order(&params, &t, z), exact, "slice boundary {i}");
            }
        }
    }

    #[test]
    fn all_at_one_depth_is_exact() {
        let f = vec![Fragment::new(0.42, 0.5); 3];
        for params in [OccupancyParams::new(0.5), only(0.5)] {
            let t = build(&params, &f);
            assert_eq!(visibility(&params, &t, 0.42), 1.0);
            assert!((visibility(&params, &t, 0.420_001) - 0.125).abs() < 1e-6);
        }
    }

    #[test]
    fn properties_and_extremes() {
        let mut rng = Rng::new(52);
        let random: Vec<_> = (0..100).map(|_| random_texel(&mut rng, 120)).collect();
        for variant in [OccupancyVariant::SlabMap, OccupancyVariant::OccupancyOnly] {
            for alpha in [0.0, 0.35, 0.9, 1.0, -1.0, f32::NAN] {
                let params = OccupancyParams { alpha, variant };
                for f in extreme_texels().iter().chain(&random) {
                    assert_valid_curve(&params, f, &format!("occupancy {params:?}"));
                    let t = build(&params, f);
                    assert_eq!(visibility(&params, &t, t.near), 1.0);
                    let n = f.iter().filter(|f| f.depth.is_finite()).count() as u32;
                    assert_eq!(t.slabs.iter().sum::<u32>(), n);
                }
            }
        }
    }

    #[test]
    fn order_does_not_matter() {
        let mut rng = Rng::new(53);
        let mut f = random_texel(&mut rng, 60);
        let params = OccupancyParams::new(0.3);
        let a = build(&params, &f);
        f.reverse();
        assert_eq!(a, build(&params, &f));
    }
}
