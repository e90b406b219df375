//! Adaptive volumetric shadow maps (Salvi et al. 2010) on the stress presets, measured against the exact reference
//! with the helpers of `stability.rs` (`hairlab::measure`). Two claims: the insertion order changes the lossy
//! compression's result (the paper's "insertion order changes the result"; submission = primitive order, as a
//! rasteriser-ordered implementation inserts, against the deterministic depth order) by a few percent of the
//! error, not by its size; and the error falls as the node count grows from 4 to 16. Thresholds sit below the
//! ratios measured when the test was written (stated beside each). Reproduce with
//! `hairlab measure --preset <name> --config avsm:nodes=4 --config avsm:nodes=4,order=submission ...`.

use hairlab::gpu::Gpu;
use hairlab::measure::{Measurement, MethodConfig, measure_on};

const CONFIGS: [&str; 4] = [
    "avsm:nodes=4",
    "avsm:nodes=4,order=submission",
    "avsm:nodes=16",
    "avsm:nodes=16,order=submission",
];

fn run(gpu: &Gpu, preset: &str, overrides: &[&str]) -> Vec<Measurement> {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let settings = crate::common::measured_preset(preset, &overrides);
    let configs: Vec<MethodConfig> = CONFIGS.iter().map(|c| MethodConfig::parse(c).unwrap()).collect();
    let (_, rows) = measure_on(gpu, &settings, &configs, 1, &mut hairlab::progress::Quiet)
        .unwrap()
        .kept();
    for m in &rows {
        eprintln!(
            "{preset} {overrides:?} {}: map error {:.5}, worst texel {:.4}, shading error {:.5}",
            m.config.label(),
            m.map_error,
            m.texel_errors.worst,
            m.shading_error
        );
    }
    rows
}

/// Relative change `submission / depth - 1` of the map error and of the worst texel.
fn order_change(depth: &Measurement, submission: &Measurement) -> (f64, f64) {
    (
        submission.map_error / depth.map_error - 1.0,
        submission.texel_errors.worst / depth.texel_errors.worst - 1.0,
    )
}

/// The order changes the map error by more than 2 % and less than 20 %, the worst texel by more than 5 % and less
/// than 50 %; 16 nodes bring the map error down more than 8x and the worst texel more than 4x from 4 nodes.
fn check(preset: &str, r: &[Measurement]) {
    let (n4, n4s, n16, n16s) = (&r[0], &r[1], &r[2], &r[3]);
    for (depth, submission) in [(n4, n4s), (n16, n16s)] {
        let (map, worst) = order_change(depth, submission);
        eprintln!(
            "{preset} {}: submission vs depth order: map error {:+.1} %, worst texel {:+.1} %",
            depth.config.label(),
            100.0 * map,
            100.0 * worst
        );
        assert!(
            map.abs() > 0.02 && map.abs() < 0.2,
            "{preset} {}: map error changed by {map} with the order",
            depth.config.label()
        );
        assert!(
            worst.abs() > 0.05 && worst.abs() < 0.5,
            "{preset} {}: worst texel changed by {worst} with the order",
            depth.config.label()
        );
    }
    for (few, many) in [(n4, n16), (n4s, n16s)] {
        assert!(
            few.map_error > 8.0 * many.map_error && few.texel_errors.worst > 4.0 * many.texel_errors.worst,
            "{preset}: error should fall from 4 to 16 nodes: {} {} -> {} {}",
            few.map_error,
            few.texel_errors.worst,
            many.map_error,
            many.texel_errors.worst
        );
    }
}

/// Stray strands in front of a clump: 325,423 fragments in 44,631 texels at 256², depth complexity up to 24.
#[test]
fn insertion_order_and_node_count_on_stray_strands() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let r = run(&gpu, "stray-strand", &[]);
    // Measured: map error N=4 0.04465 depth, 0.04156 submission (-6.9 %), worst texel 0.2251, 0.1785 (-21 %);
    // N=16 0.00184, 0.00193 (+4.9 %), worst 0.0176, 0.0197 (+12 %). Map error N=4 / N=16: 24x (depth), 22x
    // (submission); worst texel 12.8x, 9.1x.
    check("stray-strand", &r);
}

/// The default head, shrunk to a test-sized scene (2000 strands, 256²).
#[test]
fn insertion_order_and_node_count_on_the_default_head() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let r = run(
        &gpu,
        "default",
        &["scene.generator.strands=2000", "render.map_resolution=256"],
    );
    // Measured: map error N=4 0.03478 depth, 0.03288 submission (-5.5 %), worst texel 0.3000, 0.2038 (-32 %);
    // N=16 0.00162, 0.00179 (+10.5 %), worst 0.0168, 0.0205 (+22 %). Map error N=4 / N=16: 21x (depth), 18x
    // (submission); worst texel 17.9x, 9.9x. On both scenes submission order is the better one at 4 nodes and the
    // worse one at 16 (not asserted).
    check("default", &r);
}
