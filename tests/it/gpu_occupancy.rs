//! Occupancy Maps on the GPU (`hairlab::methods::occupancy`) against the CPU model `visibility::occupancy`, fed
//! each texel's exact fragment list from the reference A-buffer: both variants, map resolutions 1 to 2048,
//! hair alphas from nearly clear to opaque; memory and the storage-size limit.

use crate::common;

use crate::common::{Setup, gpu_cpu_difference, max_gpu_cpu_difference};
use hairlab::gpu::{Gpu, GpuError};
use hairlab::methods::{ParamValues, registry};
use hairlab::render::Renderer;

/// The bitmap and the counts are integers built by the same f32 expressions as the CPU's (no sum of floats):
/// only `exp`/`log` and the final division round differently, far below this.
const TOLERANCE: f32 = 1e-4;

const VARIANTS: [f32; 2] = [0.0, 1.0];

#[test]
fn occupancy_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for variant in VARIANTS {
        for resolution in [1, 64, 256] {
            let (worst, n) = max_gpu_cpu_difference(&gpu, "occupancy", &[("variant", variant)], resolution);
            eprintln!("occupancy variant {variant} at {resolution}²: max |ΔV| = {worst:e} over {n} samples");
            assert!(n > 100, "only {n} samples");
            assert!(
                worst <= TOLERANCE,
                "variant {variant} at {resolution}²: max |ΔV| = {worst}"
            );
        }
    }
}

#[test]
fn extreme_resolutions_and_alphas() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (strands, resolution) in common::EXTREME_SETUPS {
        for variant in VARIANTS {
            for hair_alpha in [0.01, 0.35, 1.0] {
                let (worst, n) = gpu_cpu_difference(
                    &gpu,
                    "occupancy",
                    &[("variant", variant)],
                    Setup {
                        hair_alpha: Some(hair_alpha),
                        ..Setup::new(strands, resolution)
                    },
                );
                eprintln!(
                    "occupancy variant {variant}, {strands} strands at {resolution}², alpha {hair_alpha}: \
                     max |ΔV| = {worst:e} over {n} samples"
                );
                assert!(n > 10, "only {n} samples");
                assert!(
                    worst <= TOLERANCE,
                    "variant {variant} at {resolution}², alpha {hair_alpha}: max |ΔV| = {worst}"
                );
            }
        }
    }
}

fn render_light_at(gpu: &Gpu, resolution: u32) -> (Renderer, Result<(), GpuError>) {
    let mut s = common::small_settings(8, 8);
    s.scene.generator.strands = 20;
    s.render.map_resolution = resolution;
    let scene = s.scene.build().unwrap();
    let mut r = Renderer::new(gpu, &scene, resolution).unwrap();
    let result = r.render_light(&crate::common::light_frame(
        &s,
        registry::find("occupancy").unwrap(),
        &ParamValues::new(),
    ));
    (r, result)
}

#[test]
fn memory_and_geometry_passes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (r, result) = render_light_at(&gpu, 512);
    result.unwrap();
    let m = r.method_gpu(registry::find("occupancy").unwrap()).unwrap();
    // Bitmap 16 + slab counts 16 + the shared depth-range maps 8 + the null render target 1 byte per texel:
    // 10.25 MiB at 512² (Sintorn & Assarsson §4: 10 MB for their depth-range, occupancy and slab maps).
    assert_eq!(m.memory_bytes(), 512 * 512 * 41);
    assert_eq!(m.geometry_passes(), 1);
}

#[test]
fn maps_beyond_the_storage_binding_size_are_refused() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let limits = gpu.device.limits();
    let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    // The largest map resolution hairlab allows; 256 MiB per buffer, twice lavapipe's 128 MiB binding limit.
    let resolution = 4096u32;
    let bytes = resolution as u64 * resolution as u64 * 16;
    let (_r, result) = render_light_at(&gpu, resolution);
    if bytes > limit {
        match result {
            Err(GpuError::TooLarge {
                bytes: b,
                limit: l,
                what,
            }) => {
                assert_eq!((b, l), (bytes, limit));
                assert!(what.contains("occupancy"), "{what}");
            }
            other => panic!("expected TooLarge, got {other:?}"),
        }
    } else {
        result.unwrap();
    }
}
