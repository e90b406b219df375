//! The papers' failure claims, measured on the stress presets (lavapipe in CI). Each test shows the failing
//! method fail and the fixing method fix it, by a ratio of errors measured against the exact reference
//! (`hairlab::measure`; design.md's metrics). Thresholds are set below the ratios measured when the tests were
//! written (stated beside each) so that rasteriser differences do not flip them, while a method that stopped
//! failing (or fixing) would. Reproduce the figures with `hairlab measure --preset <name> --config ...`.

use hairlab::gpu::Gpu;
use hairlab::measure::{Measurement, MethodConfig, measure_on};

fn run(gpu: &Gpu, preset: &str, overrides: &[&str], configs: &[&str]) -> Vec<Measurement> {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let settings = crate::common::measured_preset(preset, &overrides);
    let configs: Vec<MethodConfig> = configs.iter().map(|c| MethodConfig::parse(c).unwrap()).collect();
    let (_, rows) = measure_on(gpu, &settings, &configs, 1, &mut hairlab::progress::Quiet)
        .unwrap()
        .kept();
    for m in &rows {
        eprintln!(
            "{preset} {overrides:?} {}: map error {:.5}, worst texel {:.4}, shading error {:.5}, light-turn flicker {:.5}",
            m.config.label(),
            m.map_error,
            m.texel_errors.worst,
            m.shading_error,
            m.light_turn_flicker
        );
    }
    rows
}

/// Yuksel & Keyser Fig. 1: opacity-map slices are thick against a thin sheet of hair lit at a grazing angle.
#[test]
fn straight_grazing_bands_opacity_maps_but_not_deep_opacity_maps() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let r = run(
        &gpu,
        "straight-grazing",
        &[],
        &["osm:slices=16", "osm:slices=64", "osm:slices=256", "dom:layers=3"],
    );
    let (osm16, osm64, osm256, dom3) = (r[0].map_error, r[1].map_error, r[2].map_error, r[3].map_error);
    // Measured: OSM-16 0.0859 vs DOM-3 0.0462 (1.86x).
    assert!(
        osm16 > 1.5 * dom3,
        "OSM-16 {osm16} should be well above DOM-3 {dom3}"
    );
    // Measured: 0.0859 -> 0.0552 -> 0.0416 (1.56x, 1.33x).
    assert!(
        osm16 > 1.2 * osm64 && osm64 > 1.2 * osm256,
        "OSM error should fall with slices: {osm16} {osm64} {osm256}"
    );
}

/// Sintorn & Assarsson Fig. 4/5a: stray strands in front of a clump start Deep Opacity Maps' layers too early;
/// occupancy maps keep the whole depth range.
#[test]
fn stray_strands_break_deep_opacity_maps_not_occupancy_maps() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let configs = ["dom:layers=3", "dom:layers=4", "occupancy"];
    let strays = run(&gpu, "stray-strand", &["scene.generator.clumps=64"], &configs);
    let (dom3, dom4, occ) = (&strays[0], &strays[1], &strays[2]);
    // Measured shading error: DOM-3 0.0989, DOM-4 0.0951, occupancy 0.0432 (2.29x, 2.20x).
    assert!(
        dom3.shading_error > 1.9 * occ.shading_error,
        "DOM-3 {} vs occupancy {}",
        dom3.shading_error,
        occ.shading_error
    );
    assert!(
        dom4.shading_error > 1.8 * occ.shading_error,
        "DOM-4 {} vs occupancy {}",
        dom4.shading_error,
        occ.shading_error
    );
    // Measured map error: 0.0923 and 0.0830 vs 0.0163 (5.7x, 5.1x).
    assert!(dom3.map_error > 4.0 * occ.map_error && dom4.map_error > 4.0 * occ.map_error);
    // It is the stray strands: with one stray strand DOM-3's shading error is 0.0745 (64 raise it 1.33x) while
    // occupancy's stays at 0.0435 vs 0.0432.
    let one = run(&gpu, "stray-strand", &["scene.generator.clumps=1"], &configs);
    assert!(
        dom3.shading_error > 1.2 * one[0].shading_error,
        "{} vs {}",
        dom3.shading_error,
        one[0].shading_error
    );
    let drift = occ.shading_error / one[2].shading_error;
    assert!(
        (0.95..1.05).contains(&drift),
        "occupancy changed by {drift}x with the stray strands"
    );
}

/// Voicu §4.1/5.5: one fixed layer depth cannot fit a short patch and a tall clump; bounding layers between each
/// texel's start and end depth can.
#[test]
fn mixed_sizes_favour_bounding_over_deep_opacity_maps() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let r = run(
        &gpu,
        "mixed-sizes",
        &[],
        &[
            "dom:layers=3",
            "bom:layers=3",
            "dom:layers=4",
            "bom:layers=4",
            "dom:layers=8",
            "bom:layers=8",
        ],
    );
    // Measured BOM/DOM map error: 0.635 (K=3), 0.613 (K=4), 0.529 (K=8); shading error 0.38, 0.38, 0.44.
    for pair in r.chunks(2) {
        let (dom, bom) = (&pair[0], &pair[1]);
        assert!(
            bom.map_error < 0.75 * dom.map_error,
            "{}: {} vs {}",
            bom.config.label(),
            bom.map_error,
            dom.map_error
        );
        assert!(
            bom.shading_error < 0.6 * dom.shading_error,
            "{}: shading",
            bom.config.label()
        );
    }
}

/// Mertens et al. Fig. 5: with more clumps along the light than clusters, Density Clustering merges them.
#[test]
fn more_clumps_than_clusters_break_density_clustering() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let dc = |q: u32| {
        run(
            &gpu,
            "many-clumps",
            &[&format!("scene.generator.clumps={q}")],
            &["dc:clusters=4"],
        )
        .remove(0)
    };
    let (q2, q4, q8) = (dc(2), dc(4), dc(8));
    let few = q2.map_error.max(q4.map_error);
    let few_worst = q2.texel_errors.worst.max(q4.texel_errors.worst);
    // Measured map error: Q=2 0.0279, Q=4 0.0223, Q=8 0.0352 (1.26x the larger); worst texel 0.071, 0.057, 0.134
    // (1.89x).
    assert!(q8.map_error > 1.15 * few, "Q=8 {} vs Q<=4 {few}", q8.map_error);
    assert!(
        q8.texel_errors.worst > 1.6 * few_worst,
        "Q=8 worst {} vs Q<=4 {few_worst}",
        q8.texel_errors.worst
    );
}

/// Sintorn & Assarsson Fig. 4/5a through the texel-error distribution, on the preset with ONE stray strand:
/// Deep Opacity Maps fail in a band of texels (the stray strand's shadow across the clump), which the map mean
/// dilutes and the tail shows; occupancy maps have no such band.
#[test]
fn one_stray_strand_fails_dom_in_a_band_of_texels() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let r = run(&gpu, "stray-strand", &[], &["dom:layers=3", "occupancy"]);
    let (dom, occ) = (&r[0].texel_errors, &r[1].texel_errors);
    let mean_ratio = r[0].map_error / r[1].map_error;
    let p99_ratio = dom.p99 / occ.p99;
    eprintln!("DOM-3 {dom:?}\noccupancy {occ:?}\nmap error ratio {mean_ratio:.2}, p99 ratio {p99_ratio:.2}");
    // Measured: p99 0.195 vs 0.031 (6.3x); map error 0.0579 vs 0.0166 (3.5x): the tail is 1.8x the mean's ratio.
    assert!(p99_ratio > 4.0, "p99 ratio {p99_ratio}");
    assert!(
        p99_ratio > 1.3 * mean_ratio,
        "p99 ratio {p99_ratio} vs map error ratio {mean_ratio}"
    );
    // Measured: 9.2 % of DOM-3's occupied texels above 0.1, none of occupancy's.
    assert!(
        dom.share_over[1] > 0.05 && occ.share_over[1] < 0.005,
        "{dom:?} {occ:?}"
    );
}

/// ADSM (TressFX's approximated deep shadow maps) assumes a constant fibre spacing behind the nearest strand.
/// Against the reference that fails wherever density varies: on `stray-strand` and `mixed-sizes` its error is
/// many times occupancy's. With a spacing that fits the scene it still beats OSM-16 on the typical texel at a
/// fraction of the memory and with no geometry pass of its own, while losing in the tail.
#[test]
fn adsm_constant_spacing_against_the_reference() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let strays = run(&gpu, "stray-strand", &[], &["adsm", "occupancy"]);
    // Measured map error: 0.187 vs 0.0166 (11x).
    assert!(
        strays[0].map_error > 5.0 * strays[1].map_error,
        "ADSM {} vs occupancy {}",
        strays[0].map_error,
        strays[1].map_error
    );
    let mixed = run(
        &gpu,
        "mixed-sizes",
        &[],
        &["adsm", "occupancy", "adsm:fiber_spacing=0.03125", "osm:slices=16"],
    );
    let (adsm, occ, fitted, osm) = (&mixed[0], &mixed[1], &mixed[2], &mixed[3]);
    // Measured: 0.139 vs 0.0107 (13x).
    assert!(
        adsm.map_error > 5.0 * occ.map_error,
        "{} vs {}",
        adsm.map_error,
        occ.map_error
    );
    // Measured at twice the default spacing: median texel error 0.0477 vs OSM-16's 0.0652 (0.73x) with 1/8 of
    // its memory (0.5 vs 4 MiB) and no geometry pass; 95th percentile 0.354 vs 0.270.
    assert!(
        fitted.texel_errors.p50 < 0.85 * osm.texel_errors.p50,
        "median: ADSM {} vs OSM-16 {}",
        fitted.texel_errors.p50,
        osm.texel_errors.p50
    );
    assert!(fitted.memory_bytes * 4 < osm.memory_bytes && fitted.geometry_passes == 0);
    assert!(
        fitted.texel_errors.p95 > osm.texel_errors.p95,
        "tail: ADSM {} vs OSM-16 {}",
        fitted.texel_errors.p95,
        osm.texel_errors.p95
    );
}
