//! Deep Opacity Maps on the GPU (`hairlab::methods::dom`) against the CPU model `visibility::dom`, fed each
//! texel's exact fragment list from the reference A-buffer: 1 to 16 layers, both spacings, the three options for
//! fragments beyond the last layer, depth spans from 1e-4 to 1; map resolutions 1 and 2048; memory, geometry
//! passes and the uniform layout.

use crate::common;

use crate::common::{Setup, gpu_cpu_difference, max_gpu_cpu_difference};
use hairlab::gpu::Gpu;
use hairlab::methods::{ParamValues, registry};
use hairlab::render::Renderer;

/// The layer of a fragment is chosen by the same f32 comparisons `dz < scale * d_k` as on the CPU, with the same
/// `d_k` (uniform filled from `layer_ends`); additive blending sums the same f32 values in another order, and
/// `exp`/`log` round differently: only rounding differs.
const TOLERANCE: f32 = 1e-4;

/// (layers, depth_span, spacing, beyond).
const CONFIGS: &[(f32, f32, f32, f32)] = &[
    // The paper's setting (and the defaults).
    (3.0, 0.25, 0.0, 1.0),
    (1.0, 0.25, 0.0, 0.0),
    (1.0, 0.25, 0.0, 1.0),
    (1.0, 0.25, 0.0, 2.0),
    (16.0, 0.25, 0.0, 0.0),
    (16.0, 0.25, 0.0, 1.0),
    (16.0, 0.25, 0.0, 2.0),
    (16.0, 0.25, 1.0, 1.0),
    (5.0, 0.05, 1.0, 0.0),
    (7.0, 1.0, 1.0, 2.0),
    // Layers thinner than the depth rounding of a fragment: nearly all fragments lie beyond the last layer.
    (4.0, 1e-4, 0.0, 1.0),
    (4.0, 1e-4, 0.0, 2.0),
];

fn params(&(layers, depth_span, spacing, beyond): &(f32, f32, f32, f32)) -> [(&'static str, f32); 4] {
    [
        ("layers", layers),
        ("depth_span", depth_span),
        ("spacing", spacing),
        ("beyond", beyond),
    ]
}

#[test]
fn dom_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for config in CONFIGS {
        let (worst, n) = max_gpu_cpu_difference(&gpu, "dom", &params(config), 64);
        eprintln!("dom {config:?} at 64²: max |ΔV| = {worst:e} over {n} samples");
        assert!(n > 5000, "only {n} samples");
        assert!(worst <= TOLERANCE, "dom {config:?}: max |ΔV| = {worst}");
    }
}

#[test]
fn extreme_resolutions_and_parameters() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let extremes = [
        (1.0, 1e-4, 0.0, 0.0),
        (1.0, 1.0, 1.0, 2.0),
        (16.0, 1e-4, 1.0, 2.0),
        (16.0, 1.0, 0.0, 1.0),
        (16.0, 0.25, 0.0, 0.0),
    ];
    for (strands, resolution) in common::EXTREME_SETUPS {
        for config in &extremes {
            let (worst, n) =
                gpu_cpu_difference(&gpu, "dom", &params(config), Setup::new(strands, resolution));
            eprintln!(
                "dom {config:?}, {strands} strands at {resolution}²: max |ΔV| = {worst:e} over {n} samples"
            );
            assert!(n > 10, "only {n} samples");
            assert!(
                worst <= TOLERANCE,
                "dom {config:?} at {resolution}²: max |ΔV| = {worst}"
            );
        }
    }
}

#[test]
fn memory_and_geometry_passes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = common::small_settings(8, 8);
    s.scene.generator.strands = 20;
    s.render.map_resolution = 512;
    let scene = s.scene.build().unwrap();
    let mut r = Renderer::new(&gpu, &scene, 512).unwrap();
    let method = registry::find("dom").unwrap();
    // Layers (one RGBA32F texel per 4 layers) + the near map z0 (4 bytes), + the far map for the stretch.
    for (config, bytes_per_texel) in [
        ((3.0, 0.25, 0.0, 1.0), 16 + 4),
        ((4.0, 0.25, 0.0, 0.0), 16 + 4),
        ((5.0, 0.25, 0.0, 1.0), 32 + 4),
        ((16.0, 0.25, 1.0, 2.0), 64 + 8),
    ] {
        let values: ParamValues = params(&config).iter().map(|(k, v)| (k.to_string(), *v)).collect();
        r.render_light(&crate::common::light_frame(&s, method, &values))
            .unwrap();
        let m = r.method_gpu(method).unwrap();
        assert_eq!(m.memory_bytes(), 512 * 512 * bytes_per_texel, "{config:?}");
        assert_eq!(m.geometry_passes(), 1, "{config:?}");
    }
}
