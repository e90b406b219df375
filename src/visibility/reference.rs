//! Exact reference visibility: what the papers call the depth-peeled ground truth (Sintorn & Assarsson 2009,
//! Fig. 2 and Fig. 5; "opacity mapping with an infinite number of slices"), and Mertens et al. 2004 §3.1, Eq.
//! 1-2 with the density field taken as the exact sum of fragment optical depths.
//!
//! `V_ref(z) = exp(-sum of b_f over fragments f with depth_f < z)`: strictly less, so a fragment does not
//! shadow itself. Nothing here is approximate; sums are taken in f64. On the GPU side the reference is not a
//! lookup but the per-texel fragment list (depth peel / A-buffer) read back and fed to this model.

use super::{Fragment, Model, TexelModel, optical_depth, valid};

/// Exact visibility at depth `z`: `exp(-sum of b over fragments with depth < z)`, summed in f64.
pub fn visibility(fragments: &[Fragment], z: f32) -> f32 {
    let omega: f64 = valid(fragments)
        .filter(|f| f.depth < z)
        .map(|f| f64::from(f.optical_depth()))
        .sum();
    (-omega).exp() as f32
}

/// Exact hair count at depth `z`: the number of fragments with depth `< z` (the fragments `V_ref(z)` sums).
pub fn count(fragments: &[Fragment], z: f32) -> usize {
    valid(fragments).filter(|f| f.depth < z).count()
}

/// `(depth, b)` of every fragment (finite depths only), sorted by depth; fragments at equal depths keep their
/// input order.
pub fn sorted_optical_depths(fragments: &[Fragment]) -> Vec<(f32, f32)> {
    let mut v: Vec<(f32, f32)> = valid(fragments)
        .map(|f| (f.depth, optical_depth(f.alpha)))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

/// Depth complexity of a texel: its number of fragments.
pub fn depth_complexity(fragments: &[Fragment]) -> usize {
    fragments.len()
}

/// The reference as a [`Model`] (no parameters).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Reference;

/// The reference "texel": fragment depths sorted ascending with the running optical depth after each
/// (`cumulative[i] = sum of b over fragments 0..=i`), for O(log n) queries.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceTexel {
    pub depths: Vec<f32>,
    pub cumulative: Vec<f64>,
}

impl Model for Reference {
    type Texel = ReferenceTexel;

    fn build(&self, fragments: &[Fragment]) -> ReferenceTexel {
        let sorted = sorted_optical_depths(fragments);
        let mut sum = 0.0f64;
        let cumulative = sorted
            .iter()
            .map(|&(_, b)| {
                sum += f64::from(b);
                sum
            })
            .collect();
        ReferenceTexel {
            depths: sorted.into_iter().map(|(d, _)| d).collect(),
            cumulative,
        }
    }

    fn visibility(&self, texel: &ReferenceTexel, z: f32) -> f32 {
        // Number of fragments strictly in front of z.
        let n = texel.depths.partition_point(|&d| d < z);
        let omega = if n == 0 { 0.0 } else { texel.cumulative[n - 1] };
        (-omega).exp() as f32
    }
}

impl TexelModel for Reference {
    fn label(&self) -> String {
        "reference".into()
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    /// Exact: [`count`], whatever the alphas.
    fn count_curve(&self, fragments: &[Fragment], zs: &[f32], _hair_alpha: f32) -> Vec<f32> {
        let texel = self.build(fragments);
        zs.iter()
            .map(|&z| texel.depths.partition_point(|&d| d < z) as f32)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::test_support::{Rng, assert_valid_curve, extreme_texels, random_texel};

    // Fragments: depth 0.3 alpha 0.5 (b = ln 2), depth 0.1 alpha 0.5 (b = ln 2), depth 0.3 alpha 0.75 (b = 2
    // ln 2).
    fn texel() -> Vec<Fragment> {
        vec![
            Fragment::new(0.3, 0.5),
            Fragment::new(0.1, 0.5),
            Fragment::new(0.3, 0.75),
        ]
    }

    /// Three strands at depths 0.2, 0.5 and 0.8 (alphas 0.3, 0.6, 0.9, the count ignores them): 0 strands in
    /// front at 0.1 and at 0.2 itself (a fragment does not count itself), 1 at 0.3, 2 at 0.6, 3 at 0.9.
    #[test]
    fn count_by_hand() {
        let f = [
            Fragment::new(0.5, 0.6),
            Fragment::new(0.2, 0.3),
            Fragment::new(0.8, 0.9),
        ];
        let zs = [0.1, 0.2, 0.3, 0.6, 0.9];
        assert_eq!(Reference.count_curve(&f, &zs, 0.5), [0.0, 0.0, 1.0, 2.0, 3.0]);
        let direct: Vec<usize> = zs.iter().map(|&z| count(&f, z)).collect();
        assert_eq!(direct, [0, 0, 1, 2, 3]);
    }

    #[test]
    fn hand_computed() {
        let f = texel();
        // Nothing strictly before 0.1: V = 1 (the first fragment does not shadow itself).
        assert_eq!(visibility(&f, 0.1), 1.0);
        assert_eq!(visibility(&f, 0.0), 1.0);
        // Between 0.1 and 0.3: only the ln 2 fragment: V = 1/2.
        assert!((visibility(&f, 0.2) - 0.5).abs() < 1e-7);
        assert!((visibility(&f, 0.3) - 0.5).abs() < 1e-7);
        // Beyond 0.3: ln 2 + ln 2 + 2 ln 2 = 4 ln 2: V = 1/16.
        assert!((visibility(&f, 0.31) - 0.0625).abs() < 1e-7);
        assert!((visibility(&f, 5.0) - 0.0625).abs() < 1e-7);
    }

    #[test]
    fn model_matches_direct_sum() {
        let f = texel();
        let t = Reference.build(&f);
        assert_eq!(t.depths, [0.1, 0.3, 0.3]);
        for z in [0.0, 0.1, 0.2, 0.3, 0.31, 5.0] {
            assert!((Reference.visibility(&t, z) - visibility(&f, z)).abs() < 1e-7);
        }
        let mut rng = Rng::new(1);
        for _ in 0..50 {
            let f = random_texel(&mut rng, 60);
            let t = Reference.build(&f);
            for i in 0..=100 {
                let z = i as f32 / 100.0;
                assert!((Reference.visibility(&t, z) - visibility(&f, z)).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn sorted_and_complexity() {
        let s = sorted_optical_depths(&texel());
        assert_eq!(s.len(), 3);
        assert_eq!(s[0].0, 0.1);
        assert!((s[0].1 - std::f32::consts::LN_2).abs() < 1e-7);
        // Equal depths keep input order: ln 2 then 2 ln 2.
        assert!((s[2].1 - 2.0 * std::f32::consts::LN_2).abs() < 1e-6);
        assert_eq!(depth_complexity(&texel()), 3);
        assert_eq!(depth_complexity(&[]), 0);
    }

    #[test]
    fn order_does_not_matter() {
        let mut f = texel();
        f.reverse();
        let a = Reference.build(&f);
        let b = Reference.build(&texel());
        assert_eq!(a.depths, b.depths);
        assert!((a.cumulative[2] - b.cumulative[2]).abs() < 1e-12);
    }

    #[test]
    fn properties() {
        for f in extreme_texels() {
            assert_valid_curve(&Reference, &f, "reference");
        }
        let mut rng = Rng::new(2);
        for _ in 0..100 {
            let f = random_texel(&mut rng, 80);
            assert_valid_curve(&Reference, &f, "reference");
            let first = f.iter().map(|f| f.depth).fold(f32::INFINITY, f32::min);
            assert_eq!(visibility(&f, first), 1.0);
        }
    }
}
