//! The CPU visibility models through their public API only, as the inspector, the bench and the GPU
//! comparison tests use them: generic evaluation through `TexelModel`, the error metrics, and the BOM
//! split-ratio search.

use hairlab::visibility::{
    BomParams, DcParams, DomParams, Fragment, OccupancyParams, OsmParams, Reference, SplitCriterion,
    TexelModel, bom, metrics, reference,
};

use hairlab::rng::SplitMix64 as Rng;

/// A hair-like texel of uniform `alpha`: a stray strand in front, then a clump of 20..40 fragments further
/// in.
fn stray_then_clump(rng: &mut Rng, alpha: f32) -> Vec<Fragment> {
    let stray = 0.3 * rng.unit();
    let centre = stray + 0.3 + 0.3 * rng.unit();
    let n = 20 + (20.0 * rng.unit()) as usize;
    let mut f: Vec<Fragment> = (0..n)
        .map(|_| (centre + 0.1 * (rng.unit() - 0.5), alpha).into())
        .collect();
    f.push(Fragment::new(stray, alpha));
    f
}

/// Every model, and whether it leaves everything up to the first fragment unshadowed (the reference, DOM, BOM
/// and occupancy maps do).
fn all_methods(alpha: f32) -> Vec<(Box<dyn TexelModel>, bool)> {
    vec![
        (Box::new(Reference), true),
        (Box::new(OsmParams { slices: 16 }), false),
        (Box::new(OsmParams { slices: 256 }), false),
        (Box::new(DomParams::default()), true),
        (Box::new(BomParams::default()), true),
        (Box::new(DcParams::default()), false),
        (Box::new(OccupancyParams::new(alpha)), true),
    ]
}

#[test]
fn every_method_gives_a_valid_curve() {
    let mut rng = Rng::new(7);
    let zs: Vec<f32> = (0..=200).map(|i| -0.1 + 1.2 * i as f32 / 200.0).collect();
    for _ in 0..50 {
        let texel = stray_then_clump(&mut rng, 0.3);
        let first = texel.iter().map(|f| f.depth).fold(f32::INFINITY, f32::min);
        for (m, starts_lit) in all_methods(0.3) {
            let v = m.curve(&texel, &zs);
            assert!(v.iter().all(|v| (0.0..=1.0).contains(v)), "{}", m.label());
            assert!(
                v.windows(2).all(|w| w[1] <= w[0]),
                "{} not non-increasing",
                m.label()
            );
            if starts_lit {
                assert_eq!(m.curve(&texel, &[first])[0], 1.0, "{}", m.label());
            }
        }
        assert_eq!(reference::visibility(&texel, first), 1.0);
    }
}

#[test]
fn map_errors_follow_the_papers_claims() {
    let mut rng = Rng::new(8);
    let map: Vec<Vec<Fragment>> = (0..100).map(|_| stray_then_clump(&mut rng, 0.3)).collect();
    let error = |m: &dyn TexelModel| {
        metrics::map_error(m, &map, metrics::DEFAULT_GRID_POINTS)
            .unwrap()
            .mean
    };
    assert_eq!(error(&Reference), 0.0);
    // More OSM slices, less error (Kim & Neumann; Yuksel & Keyser Fig. 1).
    assert!(error(&OsmParams { slices: 256 }) < error(&OsmParams { slices: 16 }));
    // A stray strand in front of the clump: 3 DOM layers starting at the stray strand miss the clump, the
    // occupancy map follows it (Sintorn & Assarsson §2.1, Fig. 4-5).
    assert!(error(&OccupancyParams::new(0.3)) < error(&DomParams::default()));
}

#[test]
fn bom_split_search_scores_every_ratio() {
    let mut rng = Rng::new(9);
    let map: Vec<Vec<Fragment>> = (0..64).map(|_| stray_then_clump(&mut rng, 0.5)).collect();
    let search = bom::search_split_ratio(8, &map);
    let ratios: Vec<f32> = search.scores.iter().map(|s| s.ratio).collect();
    assert_eq!(ratios, bom::split_ratios());
    for criterion in [
        SplitCriterion::CrossCorrelation,
        SplitCriterion::SumOfAbsoluteDifferences,
    ] {
        let best = search.best(criterion);
        assert!(ratios.contains(&best));
        let chosen = BomParams {
            layers: 8,
            split_ratio: best,
        };
        assert!(metrics::map_error(&chosen, &map, 16).is_some());
    }
}

#[test]
fn method_labels_and_curves() {
    let frags = [Fragment::new(0.2, 0.5), Fragment::new(0.6, 0.5)];
    let methods: [&dyn TexelModel; 6] = [
        &Reference,
        &OsmParams::default(),
        &DomParams::default(),
        &BomParams::default(),
        &DcParams::default(),
        &OccupancyParams::new(0.5),
    ];
    let labels: Vec<_> = methods.iter().map(|m| m.label()).collect();
    assert_eq!(
        labels,
        ["reference", "osm-16", "dom-3", "bom-4", "dc-4", "occupancy"]
    );
    for m in methods {
        // Every method is exactly 1 at depth 0 here (nothing precedes it, and 0 is the first OSM plane)
        // and exp(-2 ln 2) = 1/4 beyond the last fragment.
        let v = m.curve(&frags, &[0.0, 2.0]);
        assert_eq!(v[0], 1.0, "{}", m.label());
        assert!((v[1] - 0.25).abs() < 1e-6, "{}: {}", m.label(), v[1]);
    }
}
