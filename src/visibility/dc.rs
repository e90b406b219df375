//! Density Clustering (Mertens, Kautz, Bekaert & Van Reeth, EGSR 2004, §3.2-3.3).
//!
//! The fragments of a texel are clustered in depth with k-means; each cluster becomes a histogram bin of
//! constant density, so the optical depth `T(z)` is piecewise linear (§3.2, Fig. 2). Per texel, with `K`
//! clusters (the paper implements `K = 4`, one RGBA texel per quantity, §4):
//! 1. Initial centres uniform between the nearest and furthest fragment (§3.3). We take the midpoints of `K`
//!    equal sub-ranges, `c_j = near + (j + 1/2) / K (far - near)`, so that the nearest initial centre of a
//!    fragment is simply its sub-range `j = min(floor(t K), K - 1)`, `t` the relative depth.
//! 2. ONE k-means iteration (§3.3, "We restrict the number of iterations to one"): each fragment goes to its
//!    nearest initial centre and each centre moves to the b-weighted mean of its fragments (Eq. 3,
//!    `mu = sum b z / sum b`). A cluster that received no optical depth keeps its initial centre (the usual
//!    k-means convention; it then holds no density unless fragments are nearest to it).
//! 3. Second pass (§3.2, "rasterize again to compute standard deviations"): each fragment goes to the nearest
//!    mean (the cluster "with the nearest center", as Yuksel & Keyser 2008 §2 summarise it; lowest index on
//!    ties) and accumulates the b-weighted variance about that mean (Eq. 3,
//!    `sigma^2 = sum b (mu - z)^2 / sum b`).
//! 4. Bins `[mu_j - D_j, mu_j + D_j]`, `D_j = gamma sigma_j`, `gamma = sqrt(3)` (a uniform distribution of
//!    width `W` has variance `W^2 / 12`, `W = 2 D`). Overlap rule (§3.2): when the right extent `R1` of a bin
//!    exceeds the left extent `L2` of the next, both become `(R1 + L2) / 2`. (Our addition, active only in
//!    degenerate cases: that shared edge is clamped between the two means, so that a wide bin swallowing a
//!    narrow neighbour cannot invert it.)
//! 5. Histogram pass: each fragment adds `b` to the density of the bin it lies in (`L_j <= z <= R_j`, the
//!    lowest `j` when on a shared edge); a fragment in no bin adds to the nearest cluster (§3.2, "we simply
//!    add their contribution to the nearest cluster").
//! 6. `T(z) = sum_j density_j * ramp_j(z)` with `ramp_j` rising linearly from 0 at `L_j` to 1 at `R_j`
//!    (uniform density inside the bin); a zero-width bin is a step (`z > L_j`, matching the reference's
//!    strict `<`). `V = exp(-T)`.
//!
//! Exact: nothing in general, not even `V = 1` before the first fragment (a bin can start in front of it, as
//! Yuksel & Keyser §2 point out). Exact when each cluster's fragments share one depth (zero-width bins are
//! steps), e.g. one fragment, or all fragments at one depth. Approximate: everything else, and badly when the
//! texel holds more depth clumps than clusters (the paper's Q > K case, Fig. 5).
//!
//! GPU contract (per texel, `K` f32 each: means, half-widths `D_j`, densities; four passes after the
//! light-depth pass, all additive):
//! - pass 1: `t = select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near)`,
//!   `j = min(u32(max(floor(t * f32(K)), 0.0)), K - 1u)`; accumulate `b` and `b * z` per `j`;
//!   `mu_j = select(c_j, sum_bz / sum_b, sum_b > 0.0)`,
//!   `c_j = near + (far - near) * ((f32(j) + 0.5) / f32(K))`;
//! - pass 2: `j` = the lowest index minimising `abs(z - mu_j)`; accumulate `b` and
//!   `b * (mu_j - z) * (mu_j - z)`; `D_j = 1.7320508 * sqrt(select(0.0, sum_bdd / sum_b, sum_b > 0.0))`;
//! - bins, identical in pass 3 and in the lookup ([`bin`]): `L_j = mu_j - D_j`, `R_j = mu_j + D_j`, except
//!   where neighbours overlap: for the pair `(j, j+1)`, if `mu_j + D_j > mu_(j+1) - D_(j+1)` then
//!   `R_j = L_(j+1) = min(max(((mu_j + D_j) + (mu_(j+1) - D_(j+1))) * 0.5, mu_j), mu_(j+1))`;
//! - pass 3: the first `j` with `L_j <= z && z <= R_j`, else the nearest mean as in pass 2; accumulate `b`;
//! - lookup: `T = sum_j density_j * ramp_j`, `V = exp(-T)`, with
//!   `ramp_j = select(select(0.0, 1.0, z > L_j), clamp((z - L_j) / (R_j - L_j), 0.0, 1.0), R_j > L_j)`.

use super::{
    Fragment, Model, Stored, TexelModel, depth_range, relative_depth, slice_index, transmittance, valid,
};

/// Largest number of clusters.
pub const MAX_CLUSTERS: u32 = 16;
/// `gamma = sqrt(3)`: bin half-width over standard deviation (§3.2).
pub const GAMMA: f32 = 1.732_050_8;

/// Density Clustering parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DcParams {
    /// Number of clusters `K`, clamped to `1..=16`.
    pub clusters: u32,
}

impl Default for DcParams {
    /// `K = 4` (§4: "We implemented the clustering for K = 4, since it fits best in the 4-vector format").
    fn default() -> Self {
        Self { clusters: 4 }
    }
}

impl DcParams {
    /// The cluster count actually used: `clusters` clamped to `1..=16`.
    pub fn cluster_count(&self) -> usize {
        self.clusters.clamp(1, MAX_CLUSTERS) as usize
    }
}

/// One DC texel, per cluster: mean depth `mu_j` (pass 1), bin half-width `D_j = sqrt(3) sigma_j` (pass 2,
/// before the overlap rule), and density `sum of b` (pass 3).
#[derive(Clone, Debug, PartialEq)]
pub struct DcTexel {
    pub means: Vec<f32>,
    pub half_widths: Vec<f32>,
    pub densities: Vec<f32>,
}

/// Index of the mean nearest to `z` (the lowest on ties); 0 when there are no means.
fn nearest(means: &[f32], z: f32) -> usize {
    let mut best = 0;
    for (j, &m) in means.iter().enumerate() {
        if (z - m).abs() < (z - means[best]).abs() {
            best = j;
        }
    }
    best
}

/// The edge shared by bins `j` and `j + 1` after the overlap rule, when their raw extents overlap.
fn shared_edge(means: &[f32], half_widths: &[f32], j: usize) -> Option<f32> {
    let right = means[j] + half_widths[j];
    let left = means[j + 1] - half_widths[j + 1];
    (right > left).then(|| ((right + left) * 0.5).max(means[j]).min(means[j + 1]))
}

/// Bin `j` as `(L_j, R_j)`: `mu_j -+ D_j`, with each edge replaced by the shared edge where the bin overlaps
/// its neighbour. Each neighbour pair is resolved from the raw extents, so this equals applying the paper's
/// rule to the pairs in order. `j` must be below the length of both slices.
pub fn bin(means: &[f32], half_widths: &[f32], j: usize) -> (f32, f32) {
    let k = means.len().min(half_widths.len());
    let lo = (j > 0).then(|| shared_edge(means, half_widths, j - 1)).flatten();
    let hi = (j + 1 < k).then(|| shared_edge(means, half_widths, j)).flatten();
    let (m, d) = (means[j], half_widths[j]);
    (lo.unwrap_or(m - d), hi.unwrap_or(m + d))
}

/// All the histogram bins ([`bin`]).
pub fn bins(means: &[f32], half_widths: &[f32]) -> Vec<(f32, f32)> {
    (0..means.len().min(half_widths.len()))
        .map(|j| bin(means, half_widths, j))
        .collect()
}

/// Fraction of a bin's density in front of `z`: linear from `lo` to `hi`; a step at `lo` for an empty bin.
fn ramp(z: f32, lo: f32, hi: f32) -> f32 {
    if hi > lo {
        ((z - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else if z > lo {
        1.0
    } else {
        0.0
    }
}

/// Builds a DC texel: one k-means iteration, weighted variance, overlap rule, histogram.
pub fn build(params: &DcParams, fragments: &[Fragment]) -> DcTexel {
    let k = params.cluster_count();
    let (near, far) = depth_range(fragments);

    // Pass 1: nearest initial centre = sub-range j; weighted mean.
    let mut sum_b = vec![0.0f32; k];
    let mut sum_bz = vec![0.0f32; k];
    for f in valid(fragments) {
        let j = slice_index(relative_depth(f.depth, near, far) * k as f32, k);
        let b = f.optical_depth();
        sum_b[j] += b;
        sum_bz[j] += b * f.depth;
    }
    let means: Vec<f32> = (0..k)
        .map(|j| {
            if sum_b[j] > 0.0 {
                sum_bz[j] / sum_b[j]
            } else {
                near + (far - near) * ((j as f32 + 0.5) / k as f32)
            }
        })
        .collect();

    // Pass 2: nearest mean; weighted variance about it.
    let mut sum_b = vec![0.0f32; k];
    let mut sum_bdd = vec![0.0f32; k];
    for f in valid(fragments) {
        let j = nearest(&means, f.depth);
        let b = f.optical_depth();
        let d = means[j] - f.depth;
        sum_b[j] += b;
        sum_bdd[j] += b * d * d;
    }
    let half_widths: Vec<f32> = (0..k)
        .map(|j| {
            let variance = if sum_b[j] > 0.0 {
                sum_bdd[j] / sum_b[j]
            } else {
                0.0
            };
            GAMMA * variance.sqrt()
        })
        .collect();

    // Pass 3: histogram over the bins; off-bin fragments to the nearest cluster.
    let bins = bins(&means, &half_widths);
    let mut densities = vec![0.0f32; k];
    for f in valid(fragments) {
        let j = bins
            .iter()
            .position(|&(lo, hi)| lo <= f.depth && f.depth <= hi)
            .unwrap_or_else(|| nearest(&means, f.depth));
        densities[j] += f.optical_depth();
    }
    DcTexel {
        means,
        half_widths,
        densities,
    }
}

/// `V(z) = exp(-T(z))`, `T` piecewise linear across each bin.
pub fn visibility(_params: &DcParams, texel: &DcTexel, z: f32) -> f32 {
    let k = texel
        .means
        .len()
        .min(texel.half_widths.len())
        .min(texel.densities.len());
    let t: f32 = (0..k)
        .map(|j| {
            let (lo, hi) = bin(&texel.means, &texel.half_widths, j);
            texel.densities[j] * ramp(z, lo, hi)
        })
        .sum();
    transmittance(t)
}

impl Model for DcParams {
    type Texel = DcTexel;

    fn build(&self, fragments: &[Fragment]) -> DcTexel {
        build(self, fragments)
    }

    fn visibility(&self, texel: &DcTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

impl TexelModel for DcParams {
    fn label(&self) -> String {
        format!("dc-{}", self.cluster_count())
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        build(self, fragments).densities
    }

    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        let t = build(self, fragments);
        let mut s = Stored::new(self.label());
        s.means = t.means.clone();
        s.bins = bins(&t.means, &t.half_widths)
            .into_iter()
            .map(|(l, r)| [l, r])
            .collect();
        for (j, ((m, [l, r]), d)) in t.means.iter().zip(&s.bins).zip(&t.densities).enumerate() {
            s.summary.push(format!(
                "cluster {j}: mean {m:.4}, bin [{l:.4}, {r:.4}], density {d:.3}"
            ));
        }
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::test_support::{Rng, assert_valid_curve, extreme_texels, random_texel};
    use std::f32::consts::LN_2;

    const SQRT3: f64 = 1.732_050_807_568_877_2;

    fn p(clusters: u32) -> DcParams {
        DcParams { clusters }
    }

    fn close(a: &[f32], b: &[f64], tol: f64) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(&x, &y)| (f64::from(x) - y).abs() <= tol)
    }

    fn frags(list: &[(f32, f32)]) -> Vec<Fragment> {
        list.iter().map(|&p| p.into()).collect()
    }

    #[test]
    fn gamma_is_sqrt3() {
        assert!((f64::from(GAMMA) - SQRT3).abs() < 1e-7);
    }

    #[test]
    fn hand_computed_separate_bins() {
        // K = 2, near 0, far 1: sub-ranges [0, 0.5) and [0.5, 1]. Fragments alpha 0.5 (b = ln 2) at 0.0, 0.2,
        // 1.0. Pass 1: mu0 = (0 + 0.2) / 2 = 0.1, mu1 = 1. Pass 2: 0.0 and 0.2 nearest mu0, variance (0.1^2 +
        // 0.1^2) / 2 = 0.01, sigma0 = 0.1, D0 = 0.1 sqrt 3; sigma1 = 0. Bins [0.1 -+ 0.1732], [1, 1], no
        // overlap. Densities 2 ln 2, ln 2.
        let t = build(&p(2), &frags(&[(1.0, 0.5), (0.0, 0.5), (0.2, 0.5)]));
        assert!(close(&t.means, &[0.1, 1.0], 1e-6));
        assert!(close(&t.half_widths, &[0.1 * SQRT3, 0.0], 1e-6));
        assert!(close(
            &t.densities,
            &[2.0 * f64::from(LN_2), f64::from(LN_2)],
            1e-6
        ));
        let v = |z| f64::from(visibility(&p(2), &t, z));
        let l0 = 0.1 - 0.1 * SQRT3;
        // Before the bin: 1. At 0: (0 - L0) / (2 D0) = 0.5 - 1/(2 sqrt 3) of 2 ln 2.
        assert_eq!(v(-0.1), 1.0);
        assert!((v(0.0) - 4f64.powf(-(0.0 - l0) / (0.2 * SQRT3))).abs() < 1e-6);
        assert!((v(0.0) - 4f64.powf(-(0.5 - 1.0 / (2.0 * SQRT3)))).abs() < 1e-6);
        // At the mean, half the cluster: ln 2 -> 1/2.
        assert!((v(0.1) - 0.5).abs() < 1e-6);
        // After the bin: 1/4; the zero-width bin at 1 is a step just after 1.
        assert!((v(0.5) - 0.25).abs() < 1e-6);
        assert!((v(1.0) - 0.25).abs() < 1e-6);
        assert!((v(1.000_001) - 0.125).abs() < 1e-6);
    }

    #[test]
    fn hand_computed_overlap() {
        // K = 2: fragments alpha 0.5 at 0.0, 0.4 | 0.6, 1.0. mu = 0.2, 0.8; sigma = 0.2 each; D = 0.2 sqrt 3
        // = 0.3464. Bins [-0.1464, 0.5464] and [0.4536, 1.1464] overlap: R0 = L1 = (0.5464 + 0.4536) / 2 =
        // 0.5.
        let t = build(&p(2), &frags(&[(0.6, 0.5), (0.0, 0.5), (1.0, 0.5), (0.4, 0.5)]));
        assert!(close(&t.means, &[0.2, 0.8], 1e-6));
        assert!(close(&t.half_widths, &[0.2 * SQRT3, 0.2 * SQRT3], 1e-6));
        let b = bins(&t.means, &t.half_widths);
        assert!((b[0].1 - 0.5).abs() < 1e-6 && (b[1].0 - 0.5).abs() < 1e-6);
        assert!((f64::from(b[0].0) - (0.2 - 0.2 * SQRT3)).abs() < 1e-6);
        // Histogram: 0.0, 0.4 in bin 0; 0.6, 1.0 in bin 1: 2 ln 2 each.
        assert!(close(
            &t.densities,
            &[2.0 * f64::from(LN_2), 2.0 * f64::from(LN_2)],
            1e-6
        ));
        let v = |z| f64::from(visibility(&p(2), &t, z));
        let (l0, r1) = (0.2 - 0.2 * SQRT3, 0.8 + 0.2 * SQRT3);
        assert!((v(0.0) - 4f64.powf(-(0.0 - l0) / (0.5 - l0))).abs() < 1e-6);
        assert!((v(0.5) - 0.25).abs() < 1e-6);
        assert!((v(0.8) - 0.25 * 4f64.powf(-(0.8 - 0.5) / (r1 - 0.5))).abs() < 1e-6);
        assert!((v(1.2) - 1.0 / 16.0).abs() < 1e-6);
    }

    #[test]
    fn hand_computed_off_bin_fragment() {
        // K = 2: P at 0.0 alpha 0.9375 (1 - alpha = 1/16, b = 4 ln 2), Q at 0.4 alpha 0.5 (ln 2), R at 1.0
        // alpha 0.5 (ln 2). Cluster 0 = {P, Q}: mu0 = 0.4 * 1/5 = 0.08; variance (4 * 0.08^2 + 0.32^2) / 5 =
        // 0.0256, sigma0 = 0.16, D0 = 0.16 sqrt 3 = 0.2771: bin [-0.1971, 0.3571] misses Q (0.4), whose
        // nearest mean is mu0 (0.32 away, against 0.6): density0 = 5 ln 2. Cluster 1 = {R}: zero width at 1,
        // ln 2.
        let t = build(&p(2), &frags(&[(0.4, 0.5), (1.0, 0.5), (0.0, 0.9375)]));
        assert!(close(&t.means, &[0.08, 1.0], 1e-6));
        assert!(close(&t.half_widths, &[0.16 * SQRT3, 0.0], 1e-6));
        assert!(close(
            &t.densities,
            &[5.0 * f64::from(LN_2), f64::from(LN_2)],
            1e-5
        ));
        let v = |z| f64::from(visibility(&p(2), &t, z));
        // At 0: (0 - L0) / (2 D0) = (0.16 sqrt 3 - 0.08) / (0.32 sqrt 3) = 1/2 - 1/(4 sqrt 3) of 5 ln 2.
        assert!((v(0.0) - 2f64.powf(-5.0 * (0.5 - 1.0 / (4.0 * SQRT3)))).abs() < 1e-6);
        // Past the bin (0.3571): 2^-5, though the reference at 0.4 is 2^-4: Q shadows from inside the bin.
        assert!((v(0.4) - 1.0 / 32.0).abs() < 1e-6);
        assert!((v(1.5) - 1.0 / 64.0).abs() < 1e-6);
    }

    #[test]
    fn variance_pass_uses_the_nearest_mean() {
        // K = 2, fragments alpha 0.5 at 0.0, 0.45 | 0.55, 1.0, 1.0, 1.0. Pass 1: mu0 = 0.225,
        // mu1 = (0.55 + 3) / 4 = 0.8875. Pass 2: 0.55 is nearer mu0 (0.325 < 0.3375), so cluster 0 =
        // {0, 0.45, 0.55}: variance (0.225^2 + 0.225^2 + 0.325^2) / 3 = 0.206875 / 3; cluster 1 = {1, 1, 1}:
        // variance 0.1125^2. (Keeping the pass-1 groups would give D0 = 0.225 sqrt 3, D1 = 0.3375.)
        let t = build(
            &p(2),
            &frags(&[
                (0.0, 0.5),
                (0.45, 0.5),
                (0.55, 0.5),
                (1.0, 0.5),
                (1.0, 0.5),
                (1.0, 0.5),
            ]),
        );
        assert!(close(&t.means, &[0.225, 0.8875], 1e-6));
        assert!(close(
            &t.half_widths,
            &[SQRT3 * (0.206875f64 / 3.0).sqrt(), SQRT3 * 0.1125],
            1e-6
        ));
        // Bins [-0.2298, 0.6798] and [0.6926, 1.0824] do not overlap: 3 ln 2 each.
        assert!(close(
            &t.densities,
            &[3.0 * f64::from(LN_2), 3.0 * f64::from(LN_2)],
            1e-5
        ));
    }

    #[test]
    fn empty_clusters_keep_their_initial_centres() {
        // K = 4 over [0, 1]: centres 0.125, 0.375, 0.625, 0.875. Fragments alpha 0.5 at 0 and 1 fill clusters
        // 0 and 3 (means 0 and 1); 1 and 2 stay at 0.375 and 0.625 with no width and no density. Exact here.
        let f = frags(&[(0.0, 0.5), (1.0, 0.5)]);
        let t = build(&p(4), &f);
        assert_eq!(t.means, [0.0, 0.375, 0.625, 1.0]);
        assert_eq!(t.half_widths, [0.0; 4]);
        assert!(close(
            &t.densities,
            &[f64::from(LN_2), 0.0, 0.0, f64::from(LN_2)],
            1e-7
        ));
        let v = |z| visibility(&p(4), &t, z);
        assert_eq!(v(0.0), 1.0);
        assert!((v(0.5) - 0.5).abs() < 1e-7);
        assert!((v(1.0) - 0.5).abs() < 1e-7);
        assert!((v(1.5) - 0.25).abs() < 1e-7);
    }

    #[test]
    fn overlap_rule_never_inverts_bins() {
        // A wide bin [0, 10] around 5 and a narrow one [5.5, 6.5] around 6: the midpoint (10 + 5.5) / 2 =
        // 7.75 would invert the second bin; clamped to its mean 6.
        assert_eq!(bins(&[5.0, 6.0], &[5.0, 0.5]), [(0.0, 6.0), (6.0, 6.5)]);
        // Inverted means (cannot come from build) give a finite result, no panic.
        assert_eq!(bins(&[0.6, 0.4], &[0.0, 0.0]), [(0.6, 0.4), (0.4, 0.4)]);
    }

    #[test]
    fn all_at_one_depth_is_exact() {
        // near == far: every fragment in cluster 0 with zero width: a step just after the depth.
        let f = vec![Fragment::new(0.42, 0.5); 3];
        for k in [1, 4, 16] {
            let t = build(&p(k), &f);
            assert_eq!(visibility(&p(k), &t, 0.42), 1.0);
            assert!((visibility(&p(k), &t, 0.420_001) - 0.125).abs() < 1e-6);
        }
    }

    #[test]
    fn properties_and_extremes() {
        let mut rng = Rng::new(40);
        let random: Vec<_> = (0..200).map(|_| random_texel(&mut rng, 80)).collect();
        for k in [0, 1, 2, 4, 8, 16, 17] {
            for f in extreme_texels().iter().chain(&random) {
                assert_valid_curve(&p(k), f, &format!("dc K={k}"));
                let t = build(&p(k), f);
                let total: f32 = f
                    .iter()
                    .filter(|f| f.depth.is_finite())
                    .map(|f| f.optical_depth())
                    .sum();
                let held: f32 = t.densities.iter().sum();
                // Every fragment's b lands in exactly one cluster.
                assert!(
                    (held - total).abs() <= 1e-4 * total.max(1.0),
                    "K={k}: {held} vs {total}"
                );
            }
        }
    }

    #[test]
    fn order_does_not_matter() {
        let mut rng = Rng::new(41);
        let mut f = random_texel(&mut rng, 50);
        let a = build(&p(4), &f);
        f.reverse();
        let b = build(&p(4), &f);
        for (x, y) in a
            .means
            .iter()
            .zip(&b.means)
            .chain(a.half_widths.iter().zip(&b.half_widths))
        {
            assert!((x - y).abs() < 1e-5);
        }
        for (x, y) in a.densities.iter().zip(&b.densities) {
            assert!((x - y).abs() < 1e-4);
        }
    }
}
