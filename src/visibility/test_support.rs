//! Test helpers shared by the model tests: the seeded RNG, random texels, curve property checks.

use super::{Fragment, Model, depth_range};

/// The crate's seeded generator, under the name the model tests use.
pub use crate::rng::SplitMix64 as Rng;

/// A random texel: 1..=max_len fragments, depths in `[0, 1)` bunched in a few clumps (like hair), alphas in
/// `[0.05, 0.6)`.
pub fn random_texel(rng: &mut Rng, max_len: usize) -> Vec<Fragment> {
    let n = rng.int(1, max_len);
    let clumps: Vec<(f32, f32)> = (0..rng.int(1, 4))
        .map(|_| (rng.unit(), rng.range(0.005, 0.2)))
        .collect();
    (0..n)
        .map(|_| {
            let (centre, width) = clumps[rng.int(0, clumps.len() - 1)];
            let depth = (centre + width * (rng.unit() - 0.5)).clamp(0.0, 1.0);
            Fragment::new(depth, rng.range(0.05, 0.6))
        })
        .collect()
}

/// Depths to probe a texel's curve at: a fine grid over `[-0.1, 1.1]`, every fragment depth, and the depths a
/// hair above and below each.
pub fn probe_depths(fragments: &[Fragment]) -> Vec<f32> {
    let mut zs: Vec<f32> = (0..=600).map(|i| -0.1 + 1.2 * i as f32 / 600.0).collect();
    for f in fragments.iter().filter(|f| f.depth.is_finite()) {
        zs.extend([
            f.depth,
            f.depth - 1e-4,
            f.depth + 1e-4,
            f.depth.next_up(),
            f.depth.next_down(),
        ]);
    }
    let (near, far) = depth_range(fragments);
    zs.extend([near, far]);
    zs.sort_by(f32::total_cmp);
    zs
}

/// Asserts that the model's curve over [`probe_depths`] is finite, in `[0, 1]` and non-increasing.
pub fn assert_valid_curve<M: Model>(model: &M, fragments: &[Fragment], what: &str) {
    let zs = probe_depths(fragments);
    let v = super::model_curve(model, fragments, &zs);
    for (i, (&z, &vi)) in zs.iter().zip(&v).enumerate() {
        assert!(
            (0.0..=1.0).contains(&vi),
            "{what}: V({z}) = {vi} not in [0, 1]; fragments {fragments:?}"
        );
        if i > 0 {
            assert!(
                vi <= v[i - 1],
                "{what}: V increases from V({}) = {} to V({z}) = {vi}; fragments {fragments:?}",
                zs[i - 1],
                v[i - 1]
            );
        }
    }
}

/// The texels of the parameter-extreme checks: empty, one fragment, all at one depth, near == far at the
/// range ends, an opaque fragment, zero alphas, and a long list.
pub fn extreme_texels() -> Vec<Vec<Fragment>> {
    let mut rng = Rng::new(99);
    vec![
        vec![],
        vec![Fragment::new(0.5, 0.3)],
        vec![Fragment::new(0.0, 0.3)],
        vec![Fragment::new(1.0, 0.3)],
        vec![Fragment::new(0.42, 0.5); 7],
        vec![Fragment::new(0.0, 0.2), Fragment::new(0.0, 0.9)],
        vec![Fragment::new(1.0, 0.2); 3],
        vec![Fragment::new(0.3, 1.0), Fragment::new(0.6, 0.99999)],
        vec![Fragment::new(0.3, 0.0), Fragment::new(0.6, 0.0)],
        vec![
            Fragment::new(0.3, 0.5),
            Fragment::new(f32::NAN, 0.5),
            Fragment::new(f32::INFINITY, 0.5),
        ],
        vec![Fragment::new(0.5, 0.5), Fragment::new(0.5f32.next_up(), 0.5)],
        (0..500)
            .map(|_| Fragment::new(rng.unit(), rng.range(0.0, 0.9)))
            .collect(),
    ]
}
