//! GPU = CPU: every method's maps, built on the GPU and read through its WGSL lookup, against the CPU model
//! (`hairlab::visibility`) fed each texel's exact fragment list from the reference A-buffer. Samples: every
//! fragment depth and a 16-point grid across each occupied texel's depth range.

mod common;

use common::max_gpu_cpu_difference as max_difference;
use hairlab::gpu::Gpu;

/// Additive blending sums the same f32 values as the CPU in another order: only rounding differs.
const TOLERANCE: f32 = 1e-4;

#[test]
fn osm_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for slices in [1.0, 7.0, 16.0, 64.0, 256.0] {
        let (worst, n) = max_difference(&gpu, "osm", &[("slices", slices)], 64);
        assert!(n > 5000, "only {n} samples");
        assert!(worst <= TOLERANCE, "OSM-{slices}: max |ΔV| = {worst}");
    }
}
