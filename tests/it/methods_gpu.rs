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
            assert_within_stated_tolerance(info, &format!("{values:?}"), &d);
        }
    }
}

/// `d`, a method's |V_gpu - V_cpu| samples (`what`: the configuration), holds more than 5000 samples and at
/// most the method's `gpu_outliers` share of them beyond its `gpu_tolerance`; prints the maximum.
pub fn assert_within_stated_tolerance(info: &hairlab::methods::MethodInfo, what: &str, d: &[f32]) {
    let worst = d.iter().copied().fold(0.0f32, f32::max);
    let beyond = d.iter().filter(|&&x| x > info.gpu_tolerance).count();
    eprintln!(
        "{} {what}: {} samples, max |ΔV| {worst:.3e}, {beyond} beyond {:.0e}",
        info.name,
        d.len(),
        info.gpu_tolerance
    );
    assert!(d.len() > 5000, "{}: only {} samples", info.name, d.len());
    assert!(
        beyond as f64 <= info.gpu_outliers * d.len() as f64,
        "{} {what}: {beyond} of {} samples beyond {} (max {worst})",
        info.name,
        d.len(),
        info.gpu_tolerance
    );
}

/// A method's maps beyond hairlab's map budget are refused before anything is allocated, with one error naming
/// the map, its resolution and the budget (OSM-256 at 4096²: 256 slices of 4 bytes × 16.8 M texels = 16 GiB).
#[test]
fn maps_beyond_the_budget_are_refused_naming_the_map_and_resolution() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (r, result) = crate::common::render_method_light(&gpu, "osm", &[("slices", 256.0)], 20, 4096);
    match result {
        Err(hairlab::gpu::GpuError::OverBudget { what, bytes, budget }) => {
            assert!(what.contains("64 RGBA32F layers at 4096²"), "{what}");
            assert_eq!(bytes, 4096 * 4096 * 16 * 64);
            assert_eq!(budget, hairlab::render::maps::MAP_BUDGET_BYTES);
        }
        other => panic!("expected OverBudget, got {other:?}"),
    }
    assert!(
        r.method_gpu(registry::find("osm").unwrap()).is_none(),
        "no maps held"
    );
}
