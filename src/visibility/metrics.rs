//! Error metrics against the exact reference (design.md, "Error metrics"): texel error and map error.
//!
//! Texel error: mean and max of `|V_m(z) - V_ref(z)|` over `z` in the texel's fragment range `[near, far]`,
//! sampled at
//! - every fragment depth (each fragment once, duplicates included: these are the depths at which the eye
//!   pass shades the hair, and where the reference's "a fragment does not shadow itself" matters most), and
//! - a uniform grid of `M` points from `near` to `far` inclusive, `z_i = near + (far - near) * (i / (M - 1))`
//!   (`M = 1`: `near` only; `M = 0`: no grid).
//!
//! Map error: the mean of the texel mean errors over the texels holding fragments (with the max of their max
//! errors alongside).
//!
//! Error distribution ([`ErrorDistribution`]): a method that fails on a stray strand fails in a band of texels
//! that a whole-map mean dilutes, so the texel mean errors are also reported as the 50th/95th/99th
//! percentiles (nearest rank: the `ceil(p/100 · n)`-th smallest of the `n` occupied texels), the worst texel,
//! and the share of occupied texels whose mean error exceeds 0.05 and 0.1 ([`SHARE_THRESHOLDS`]).

use super::{Fragment, Reference, TexelModel, depth_range, valid};
use rayon::prelude::*;

/// Default number of grid points `M` per texel.
pub const DEFAULT_GRID_POINTS: usize = 64;

/// Error of one texel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelError {
    pub mean: f32,
    pub max: f32,
    /// Number of depths sampled (fragments + grid points).
    pub samples: usize,
}

/// Error of a whole map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapError {
    /// Mean over the texels holding fragments of their mean error.
    pub mean: f32,
    /// Max over those texels of their max error.
    pub max: f32,
    /// Number of texels holding fragments.
    pub texels: usize,
    /// How the texel mean errors spread over those texels.
    pub distribution: ErrorDistribution,
}

/// Texel-error thresholds whose exceeding share [`ErrorDistribution`] reports.
pub const SHARE_THRESHOLDS: [f64; 2] = [0.05, 0.1];

/// How the texel (mean) errors of a map are distributed over its occupied texels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorDistribution {
    pub p50: f64,
    pub p95: f64,
    pub p99: f64,
    /// The largest texel error.
    pub worst: f64,
    /// Share of the texels whose error exceeds each of [`SHARE_THRESHOLDS`], in `[0, 1]`.
    pub share_over: [f64; 2],
}

impl ErrorDistribution {
    /// The distribution of `texel_errors` (one per occupied texel; NaN counts as the worst). All zero when
    /// there are none.
    pub fn of(texel_errors: &[f64]) -> ErrorDistribution {
        if texel_errors.is_empty() {
            return ErrorDistribution::default();
        }
        let mut sorted: Vec<f64> = texel_errors
            .iter()
            .map(|&e| if e.is_nan() { f64::INFINITY } else { e })
            .collect();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let rank = |p: f64| sorted[((p / 100.0 * n as f64).ceil() as usize).clamp(1, n) - 1];
        let share = |t: f64| sorted.iter().filter(|&&e| e > t).count() as f64 / n as f64;
        ErrorDistribution {
            p50: rank(50.0),
            p95: rank(95.0),
            p99: rank(99.0),
            worst: sorted[n - 1],
            share_over: SHARE_THRESHOLDS.map(share),
        }
    }
}

/// The depths the texel error samples: the fragment depths (input order), then the `grid_points` grid over
/// `[near, far]`. Empty when the texel holds no fragment.
pub fn sample_depths(fragments: &[Fragment], grid_points: usize) -> Vec<f32> {
    let mut zs: Vec<f32> = valid(fragments).map(|f| f.depth).collect();
    if zs.is_empty() {
        return zs;
    }
    let (near, far) = depth_range(fragments);
    zs.extend((0..grid_points).map(|i| {
        if grid_points == 1 {
            near
        } else {
            near + (far - near) * (i as f32 / (grid_points - 1) as f32)
        }
    }));
    zs
}

/// Texel error of `method` on one texel (`None` when it holds no fragment).
pub fn texel_error(
    method: &dyn TexelModel,
    fragments: &[Fragment],
    grid_points: usize,
) -> Option<TexelError> {
    let zs = sample_depths(fragments, grid_points);
    if zs.is_empty() {
        return None;
    }
    let model = method.curve(fragments, &zs);
    let exact = Reference.curve(fragments, &zs);
    let (sum, max) = model
        .iter()
        .zip(&exact)
        .fold((0.0f64, 0.0f32), |(sum, max), (&m, &r)| {
            let e = (m - r).abs();
            (sum + f64::from(e), max.max(e))
        });
    Some(TexelError {
        mean: (sum / zs.len() as f64) as f32,
        max,
        samples: zs.len(),
    })
}

/// The texel mean errors of `method` over the texels of `map` holding fragments, in map order, computed on
/// rayon's pool in blocks of texels (the result does not depend on the threads).
pub fn texel_errors<T: AsRef<[Fragment]> + Sync>(
    method: &dyn TexelModel,
    map: &[T],
    grid_points: usize,
) -> Vec<TexelError> {
    const BLOCK: usize = 256;
    map.par_chunks(BLOCK)
        .flat_map_iter(|block| {
            block
                .iter()
                .filter_map(|t| texel_error(method, t.as_ref(), grid_points))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Map error of `method` over a map given as one fragment list per texel (`None` when no texel holds
/// fragments).
pub fn map_error<T: AsRef<[Fragment]> + Sync>(
    method: &dyn TexelModel,
    map: &[T],
    grid_points: usize,
) -> Option<MapError> {
    let errors = texel_errors(method, map, grid_points);
    let means: Vec<f64> = errors.iter().map(|e| f64::from(e.mean)).collect();
    (!errors.is_empty()).then(|| MapError {
        mean: (means.iter().sum::<f64>() / means.len() as f64) as f32,
        max: errors.iter().map(|e| e.max).fold(0.0, f32::max),
        texels: errors.len(),
        distribution: ErrorDistribution::of(&means),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::test_support::{Rng, random_texel};
    use crate::visibility::{BomParams, DcParams, DomParams, OccupancyParams, OsmParams};

    #[test]
    fn sample_depths_hand_computed() {
        let f = [
            Fragment::new(0.2, 0.5),
            Fragment::new(0.6, 0.5),
            Fragment::new(0.2, 0.1),
        ];
        // Fragments, then 3 grid points over [0.2, 0.6]: 0.2, 0.4, 0.6.
        let zs = sample_depths(&f, 3);
        assert_eq!(zs.len(), 6);
        assert_eq!(zs[..3], [0.2, 0.6, 0.2]);
        assert_eq!(zs[3], 0.2);
        assert!((zs[4] - 0.4).abs() < 1e-7);
        assert_eq!(zs[5], 0.6);
        assert_eq!(sample_depths(&f, 1), [0.2, 0.6, 0.2, 0.2]);
        assert_eq!(sample_depths(&f, 0), [0.2, 0.6, 0.2]);
        assert!(sample_depths(&[], 64).is_empty());
        assert!(sample_depths(&[Fragment::new(f32::NAN, 0.5)], 64).is_empty());
    }

    #[test]
    fn texel_error_hand_computed() {
        // OSM with one slice: the only plane (z = 1) holds everything, V_osm(z) = exp(-z * total b).
        let osm = OsmParams { slices: 1 };
        // Fragments 0 and 1, alpha 0.5: V_osm = 4^-z; V_ref = 1 at z = 0, 1/2 on (0, 1].
        // Samples (M = 3): 0, 1 | 0, 0.5, 1. Errors 0, 1/4 | 0, 0, 1/4: mean 0.1, max 0.25.
        let two = [Fragment::new(0.0, 0.5), Fragment::new(1.0, 0.5)];
        let e = texel_error(&osm, &two, 3).unwrap();
        assert_eq!(e.samples, 5);
        assert!((e.mean - 0.1).abs() < 1e-6);
        assert!((e.max - 0.25).abs() < 1e-6);
        // One fragment at 0.5: all 4 samples at 0.5, V_osm = 2^-0.5, V_ref = 1: error 1 - 1/sqrt 2.
        let one = [Fragment::new(0.5, 0.5)];
        let e1 = texel_error(&osm, &one, 3).unwrap();
        let want = 1.0 - 0.5f32.sqrt();
        assert!((e1.mean - want).abs() < 1e-6 && (e1.max - want).abs() < 1e-6);
        assert!(texel_error(&osm, &[], 3).is_none());

        // Map error: texels holding fragments only; the mean of (0.1, 1 - 1/sqrt 2), the max of the maxes.
        let map: Vec<&[Fragment]> = vec![&two[..], &[], &one[..]];
        let m = map_error(&osm, &map, 3).unwrap();
        assert_eq!(m.texels, 2);
        assert!((m.mean - (0.1 + want) / 2.0).abs() < 1e-6);
        assert!((m.max - want).abs() < 1e-6);
        assert!((m.distribution.worst - f64::from(want)).abs() < 1e-6);
        assert!((m.distribution.p50 - 0.1).abs() < 1e-6, "nearest rank: 1st of 2");
        assert_eq!(m.distribution.share_over[0], 1.0, "both texels above 0.05");
        let empty: Vec<Vec<Fragment>> = vec![vec![], vec![]];
        assert!(map_error(&osm, &empty, 3).is_none());
    }

    #[test]
    fn error_distribution_hand_computed() {
        // 20 texels: errors 0.00, 0.01, ..., 0.19. Nearest rank: p50 = 10th smallest = 0.09, p95 = 19th = 0.18,
        // p99 = 20th = 0.19; above 0.05: 0.06..0.19 = 14 of 20; above 0.1: 0.11..0.19 = 9 of 20.
        let e: Vec<f64> = (0..20).rev().map(|i| i as f64 / 100.0).collect();
        let d = ErrorDistribution::of(&e);
        assert!((d.p50 - 0.09).abs() < 1e-12, "{d:?}");
        assert!((d.p95 - 0.18).abs() < 1e-12, "{d:?}");
        assert!((d.p99 - 0.19).abs() < 1e-12 && d.worst == d.p99, "{d:?}");
        assert_eq!(d.share_over, [14.0 / 20.0, 9.0 / 20.0]);
        // One bad texel among 1000: invisible in p50..p99, the worst and a 0.1 % share say it.
        let mut band = vec![0.001; 999];
        band.push(0.4);
        let d = ErrorDistribution::of(&band);
        assert_eq!((d.p50, d.p95, d.p99, d.worst), (0.001, 0.001, 0.001, 0.4));
        assert_eq!(d.share_over, [0.001, 0.001]);
        // NaN is the worst; nothing is all zero.
        assert_eq!(ErrorDistribution::of(&[0.2, f64::NAN]).worst, f64::INFINITY);
        assert_eq!(ErrorDistribution::of(&[]), ErrorDistribution::default());
        assert_eq!(ErrorDistribution::of(&[0.3]).p50, 0.3);
    }

    #[test]
    fn reference_has_no_error_and_methods_stay_in_range() {
        let mut rng = Rng::new(60);
        let map: Vec<Vec<Fragment>> = (0..50).map(|_| random_texel(&mut rng, 60)).collect();
        let r = map_error(&Reference, &map, DEFAULT_GRID_POINTS).unwrap();
        assert_eq!((r.mean, r.max, r.texels), (0.0, 0.0, 50));
        assert_eq!(r.distribution, ErrorDistribution::default());
        let methods: [&dyn TexelModel; 5] = [
            &OsmParams::default(),
            &DomParams::default(),
            &BomParams::default(),
            &DcParams::default(),
            &OccupancyParams::new(0.3),
        ];
        for m in methods {
            let e = map_error(m, &map, DEFAULT_GRID_POINTS).unwrap();
            assert!(
                e.mean > 0.0 && e.mean <= e.max && e.max <= 1.0,
                "{}: {e:?}",
                m.label()
            );
        }
    }

    /// The texel errors are the same on any number of threads: in map order, empty texels left out, each the
    /// one-thread value bit for bit.
    #[test]
    fn texel_errors_do_not_depend_on_the_threads() {
        let mut rng = Rng::new(35);
        let map: Vec<Vec<Fragment>> = (0..3000)
            .map(|i| {
                if i % 7 == 0 {
                    Vec::new()
                } else {
                    random_texel(&mut rng, 40)
                }
            })
            .collect();
        let dom = DomParams::default();
        let on = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| texel_errors(&dom, &map, 8))
        };
        let one = on(1);
        assert_eq!(one.len(), map.iter().filter(|t| !t.is_empty()).count());
        for threads in [2, 3, 8] {
            assert_eq!(on(threads), one, "{threads} threads");
        }
    }
}
