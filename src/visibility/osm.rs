//! Opacity Shadow Maps (Kim & Neumann, EGWR 2001), as described by Yuksel & Keyser 2008 §2 and by Voicu's
//! thesis §3 (multi-layer OSM, one map per slice, values accumulated from all previous slices, Appendix §2).
//!
//! `N` planes (1..=256) slice the GLOBAL light range `[0, 1]` uniformly; slice `i` is `[i/N, (i+1)/N)`. The
//! map stores, per slice, the optical depth accumulated up to the slice's FAR plane; the value at the first
//! plane (depth 0) is 0 and not stored. `V(z)` interpolates linearly between the two planes enclosing `z`.
//!
//! Exact: `V` at every plane `k/N` (it sums exactly the fragments in front of the plane, up to f32 rounding
//! of `z * N`) and `V(0) = 1`. Approximate: between planes, where a fragment shadows the points in its own
//! slice in front of it, and itself (by the fraction of its slice it lies behind; this does not vanish as `N`
//! grows, only the width of the affected depth range does). `V = 1` before the first fragment is NOT
//! guaranteed.
//!
//! GPU contract (per texel, `N` f32 values, e.g. `N/4` RGBA32F targets or an array texture):
//! - build, per fragment: `i = min(u32(max(floor(z * f32(N)), 0.0)), N - 1u)`; add `b` to slices `i..N` (a
//!   fragment adds to its slice and all later ones) — by additive blending, or in fixed point with atomics and
//!   a resolve into the chosen storage ([`build_with`], `visibility::opacity_layers`);
//! - lookup: `x = z * f32(N)`, `j = min(u32(max(floor(x), 0.0)), N - 1u)`, `f = clamp(x - f32(j), 0.0, 1.0)`,
//!   `prev = select(0.0, S[max(j, 1u) - 1u], j > 0u)`, `omega = min(prev + (S[j] - prev) * f, S[j])`,
//!   `V = exp(-omega)`.

use super::opacity_layers::{LayerBuild, LayeredModel, accumulate};
use super::{Fragment, Model, Stored, TexelModel, lerp_up, slice_index, transmittance, valid};

/// Largest number of slices.
pub const MAX_SLICES: u32 = 256;

/// Opacity Shadow Map parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OsmParams {
    /// Number of uniform slices over the global range, clamped to `1..=256`.
    pub slices: u32,
}

impl Default for OsmParams {
    /// 16 slices: the real-time setting of the comparisons in Yuksel & Keyser 2008 Fig. 1 (and of the
    /// multi-render target OSM of Nguyen & Donnelly 2005 cited by Sintorn & Assarsson 2009 §2.1).
    fn default() -> Self {
        Self { slices: 16 }
    }
}

impl OsmParams {
    /// The slice count actually used: `slices` clamped to `1..=256`.
    pub fn slice_count(&self) -> usize {
        self.slices.clamp(1, MAX_SLICES) as usize
    }
}

/// One OSM texel: `planes[i]` is the optical depth accumulated in front of plane `(i + 1) / N` (the far plane
/// of slice `i`), `N = planes.len()`.
#[derive(Clone, Debug, PartialEq)]
pub struct OsmTexel {
    pub planes: Vec<f32>,
}

/// Builds an OSM texel: each fragment adds `b` to its slice and all later ones (the colour-target build).
pub fn build(params: &OsmParams, fragments: &[Fragment]) -> OsmTexel {
    build_with(params, LayerBuild::Targets, fragments)
}

/// Builds an OSM texel the way `layers` does (`visibility::opacity_layers`).
pub fn build_with(params: &OsmParams, layers: LayerBuild, fragments: &[Fragment]) -> OsmTexel {
    let n = params.slice_count();
    let entries = valid(fragments).map(|f| (slice_index(f.depth * n as f32, n), f.optical_depth()));
    OsmTexel {
        planes: accumulate(layers, n, entries),
    }
}

/// `V(z)`: linear interpolation of the accumulated optical depth between the planes enclosing `z`. `N` is the
/// texel's plane count (what [`build`] made from the parameters; the GPU gets it as a uniform).
pub fn visibility(_params: &OsmParams, texel: &OsmTexel, z: f32) -> f32 {
    let n = texel.planes.len();
    if n == 0 {
        return 1.0;
    }
    let x = z * n as f32;
    let j = slice_index(x, n);
    let f = (x - j as f32).clamp(0.0, 1.0);
    let prev = if j == 0 { 0.0 } else { texel.planes[j - 1] };
    transmittance(lerp_up(prev, texel.planes[j], f))
}

impl Model for OsmParams {
    type Texel = OsmTexel;

    fn build(&self, fragments: &[Fragment]) -> OsmTexel {
        build(self, fragments)
    }

    fn visibility(&self, texel: &OsmTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

impl TexelModel for OsmParams {
    fn label(&self) -> String {
        format!("osm-{}", self.slice_count())
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        build(self, fragments).planes
    }

    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        Some(self.describe(&build(self, fragments), self.label()))
    }
}

impl LayeredModel for OsmParams {
    fn build_with(&self, build: LayerBuild, fragments: &[Fragment]) -> OsmTexel {
        build_with(self, build, fragments)
    }

    fn entries(texel: &OsmTexel) -> &[f32] {
        &texel.planes
    }

    fn describe(&self, t: &OsmTexel, label: String) -> Stored {
        let n = t.planes.len();
        let mut s = Stored::new(label);
        s.boundaries = (0..=n).map(|k| k as f32 / n as f32).collect();
        s.knots.push([0.0, 1.0]);
        s.knots.extend(
            t.planes
                .iter()
                .enumerate()
                .map(|(i, &b)| [(i + 1) as f32 / n as f32, transmittance(b)]),
        );
        s.summary.push(format!(
            "{n} slice planes over the whole light range; each stores the optical depth in front of it"
        ));
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::reference;
    use crate::visibility::test_support::{Rng, assert_valid_curve, extreme_texels, random_texel};
    use std::f32::consts::LN_2;

    fn p(slices: u32) -> OsmParams {
        OsmParams { slices }
    }

    #[test]
    fn hand_computed() {
        // N = 4 slices of width 0.25. Three fragments, alpha 0.5 (b = ln 2) at 0.1 (slice 0), 0.3 and 0.35
        // (slice 1). Planes: 0.25 -> ln 2, 0.5 -> 3 ln 2, 0.75 -> 3 ln 2, 1.0 -> 3 ln 2.
        let f = [
            Fragment::new(0.3, 0.5),
            Fragment::new(0.1, 0.5),
            Fragment::new(0.35, 0.5),
        ];
        let t = build(&p(4), &f);
        let want = [LN_2, 3.0 * LN_2, 3.0 * LN_2, 3.0 * LN_2];
        for (got, want) in t.planes.iter().zip(want) {
            assert!((got - want).abs() < 1e-6);
        }
        let v = |z| visibility(&p(4), &t, z);
        // Plane 0 has value 0.
        assert_eq!(v(0.0), 1.0);
        // Middle of slice 0: half of ln 2 -> 2^-0.5. (The reference is 1 here: OSM shadows before the
        // fragment.)
        assert!((v(0.125) - 0.5f32.sqrt()).abs() < 1e-6);
        // Plane 0.25: ln 2 -> 1/2, exact.
        assert!((v(0.25) - 0.5).abs() < 1e-6);
        // Middle of slice 1: ln 2 + (3 ln 2 - ln 2) / 2 = 2 ln 2 -> 1/4 (the reference is 1/8 at 0.375).
        assert!((v(0.375) - 0.25).abs() < 1e-6);
        // Plane 0.5 and beyond: 3 ln 2 -> 1/8.
        assert!((v(0.5) - 0.125).abs() < 1e-6);
        assert!((v(1.0) - 0.125).abs() < 1e-6);
        assert!((v(3.0) - 0.125).abs() < 1e-6);
        assert_eq!(v(-1.0), 1.0);
    }

    #[test]
    fn fragment_on_a_plane_belongs_to_the_later_slice() {
        // z = 0.5 with N = 2: floor(0.5 * 2) = 1 -> slice 1; it does not shadow plane 0.5 (reference: strict
        // <).
        let t = build(&p(2), &[Fragment::new(0.5, 0.5)]);
        assert_eq!(t.planes, [0.0, LN_2]);
        assert_eq!(visibility(&p(2), &t, 0.5), 1.0);
    }

    #[test]
    fn exact_at_planes() {
        let mut rng = Rng::new(10);
        for n in [1u32, 3, 16, 100, 256] {
            for _ in 0..20 {
                let f = random_texel(&mut rng, 60);
                let t = build(&p(n), &f);
                for k in 1..=n {
                    let z = k as f32 / n as f32;
                    // Skip planes with a fragment within f32 noise of them (slice assignment there is a coin
                    // flip).
                    if f.iter().any(|f| (f.depth - z).abs() < 1e-6) {
                        continue;
                    }
                    // The stored plane value is the exact optical depth in front of the plane.
                    let r = reference::visibility(&f, z);
                    assert!(
                        (transmittance(t.planes[k as usize - 1]) - r).abs() < 2e-6,
                        "N={n} z={z}"
                    );
                    // For N a power of two, z * N is exactly k: the lookup returns the plane value.
                    if n.is_power_of_two() {
                        assert!((visibility(&p(n), &t, z) - r).abs() < 2e-6, "N={n} z={z}");
                    }
                }
            }
        }
    }

    /// Mean |V_osm - V_ref| over the grid z_i = (i + 0.5) / 4096, i < 4096.
    fn grid_error(n: u32, f: &[Fragment]) -> f64 {
        let t = build(&p(n), f);
        let m = 4096;
        let sum: f64 = (0..m)
            .map(|i| {
                let z = (i as f32 + 0.5) / m as f32;
                f64::from((visibility(&p(n), &t, z) - reference::visibility(f, z)).abs())
            })
            .sum();
        sum / m as f64
    }

    #[test]
    fn converges_to_reference() {
        // Bound worked out by hand: for z in slice j both the reference and OSM optical depths lie in
        // [S_(j-1), S_j], so |dV| <= |d omega| <= B_j (the optical depth held by slice j). The grid puts
        // exactly 4096/N points in each slice (N a power of two), so the grid mean is <= sum_j B_j / N =
        // total b / N.
        let mut rng = Rng::new(11);
        let texels: Vec<Vec<Fragment>> = (0..200).map(|_| random_texel(&mut rng, 80)).collect();
        let (mut first, mut previous) = (f64::INFINITY, f64::INFINITY);
        for n in [1u32, 4, 16, 64, 256] {
            let mut mean = 0.0;
            for f in &texels {
                let e = grid_error(n, f);
                let total: f64 = f.iter().map(|f| f64::from(f.optical_depth())).sum();
                assert!(
                    e <= total / f64::from(n) + 1e-6,
                    "N={n}: error {e} above bound {}",
                    total / f64::from(n)
                );
                mean += e / texels.len() as f64;
            }
            assert!(
                mean < previous,
                "N={n}: mean grid error {mean} did not decrease from {previous}"
            );
            if n == 1 {
                first = mean;
            }
            previous = mean;
        }
        // Small at N = 256: measured with this seed 0.254 (N = 1), 0.078, 0.018, 0.0042, 0.0011 (N = 256),
        // about a quarter per 4x slices as the bound predicts.
        assert!(
            previous < 0.002 && previous < first / 100.0,
            "mean grid error at N=256: {previous}"
        );
    }

    #[test]
    fn order_does_not_matter() {
        let mut rng = Rng::new(12);
        let mut f = random_texel(&mut rng, 50);
        let a = build(&p(32), &f);
        f.reverse();
        let b = build(&p(32), &f);
        for (x, y) in a.planes.iter().zip(&b.planes) {
            assert!((x - y).abs() < 1e-5);
        }
    }

    #[test]
    fn properties_and_extremes() {
        for n in [0u32, 1, 2, 7, 16, 256, 257, u32::MAX] {
            for f in extreme_texels() {
                assert_valid_curve(&p(n), &f, &format!("osm N={n}"));
                assert_eq!(visibility(&p(n), &build(&p(n), &f), 0.0), 1.0);
            }
        }
        let mut rng = Rng::new(13);
        for _ in 0..100 {
            let f = random_texel(&mut rng, 80);
            assert_valid_curve(&p(rng.int(1, 256) as u32), &f, "osm");
        }
        assert_eq!(build(&p(0), &[]).planes.len(), 1);
        assert_eq!(build(&p(1000), &[]).planes.len(), 256);
    }
}
