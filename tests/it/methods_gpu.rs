//! GPU = CPU: every method's maps, built on the GPU and read through its WGSL lookup, against the CPU model
//! (`hairlab::visibility`) fed each texel's exact fragment list from the reference A-buffer. Samples: every
//! fragment depth and a 16-point grid across each occupied texel's depth range. One test walks the registry
//! (every method at its defaults and at the ends of its sweep, against the tolerance its descriptor states);
//! the per-method files (`gpu_*.rs`) go further into each method's parameter space.

use crate::common::max_gpu_cpu_difference as max_difference;
use crate::common::{Setup, gpu_cpu_differences};
use hairlab::gpu::Gpu;
use hairlab::methods::{ParamValues, registry};

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

/// Every registered method, at its defaults and at the first and last fixed points of its bench sweep: the GPU
/// lookup equals the CPU model within the method's stated `gpu_tolerance`, except for the share of samples its
/// `gpu_outliers` allows (Density Clustering's ill-conditioned texels, see `gpu_dc.rs`; 0 for every other
/// method).
#[test]
fn every_registered_method_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for m in registry::all() {
        let info = m.info();
        let fixed: Vec<ParamValues> = m
            .sweep()
            .into_iter()
            .filter(|p| !p.analysed)
            .map(|p| p.values)
            .collect();
        let mut configs = vec![ParamValues::new()];
        configs.extend(fixed.first().cloned());
        configs.extend(fixed.last().cloned());
        configs.dedup();
        for values in configs {
            let params: Vec<(&str, f32)> = values.iter().map(|(k, v)| (k.as_str(), *v)).collect();
            let d = gpu_cpu_differences(&gpu, info.name, &params, Setup::new(300, 64));
            let worst = d.iter().copied().fold(0.0f32, f32::max);
            let beyond = d.iter().filter(|&&x| x > info.gpu_tolerance).count();
            eprintln!(
                "{} {values:?}: {} samples, max |ΔV| {worst:.3e}, {beyond} beyond {:.0e}",
                info.name,
                d.len(),
                info.gpu_tolerance
            );
            assert!(d.len() > 5000, "{}: only {} samples", info.name, d.len());
            assert!(
                beyond as f64 <= info.gpu_outliers * d.len() as f64,
                "{} {values:?}: {beyond} of {} samples beyond {} (max {worst})",
                info.name,
                d.len(),
                info.gpu_tolerance
            );
        }
    }
}
