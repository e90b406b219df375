//! Fourier Opacity Mapping on the GPU (`hairlab::methods::fom`) against the CPU model `visibility::fom`, fed
//! each texel's exact fragment list from the reference A-buffer: 1 to 16 terms with both windows, a dense
//! hair alpha, map resolutions 1 and 2048; memory and geometry passes (two for K = 16: 33 coefficients in
//! 9 layers).

use crate::common;

use crate::common::{Setup, gpu_cpu_difference, max_gpu_cpu_difference};
use hairlab::gpu::Gpu;
use hairlab::methods::{ParamValues, registry};
use hairlab::render::Renderer;

/// The GPU's sin/cos differ from Rust's in the last bits, and additive blending sums the coefficients in
/// another order; each coefficient sums `2b cos(2πkd)` over every fragment of the texel, so both errors grow
/// with the texel's depth complexity. Measured on lavapipe: max |ΔV| 1.0e-6 at 64² (K = 15), 2.1e-6 at hair
/// alpha 0.9 (K = 4), 3.2e-6 with every fragment of 300 strands in one texel (1², K = 16, no window): the
/// method's stated tolerance (`methods::fom`, 2e-5) holds here too.
const TOLERANCE: f32 = 2e-5;

/// (terms, window): 0 none, 1 Fejér.
const CONFIGS: &[(f32, f32)] = &[
    (1.0, 0.0),
    (2.0, 0.0),
    (3.0, 0.0),
    (3.0, 1.0),
    (4.0, 0.0),
    (7.0, 1.0),
    (8.0, 0.0),
    (15.0, 0.0),
    (16.0, 0.0),
    (16.0, 1.0),
];

fn params(&(terms, window): &(f32, f32)) -> [(&'static str, f32); 2] {
    [("terms", terms), ("window", window)]
}

#[test]
fn fom_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for config in CONFIGS {
        let (worst, n) = max_gpu_cpu_difference(&gpu, "fom", &params(config), 64);
        eprintln!("fom {config:?} at 64²: max |ΔV| = {worst:e} over {n} samples");
        assert!(n > 5000, "only {n} samples");
        assert!(worst <= TOLERANCE, "fom {config:?}: max |ΔV| = {worst}");
    }
}

/// Hair alpha 0.9: each fragment's b is 2.3, the coefficient sums reach hundreds and the ringing is at its worst.
#[test]
fn dense_hair() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for config in [(4.0, 0.0), (16.0, 0.0), (16.0, 1.0)] {
        let setup = Setup {
            hair_alpha: Some(0.9),
            ..Setup::new(300, 64)
        };
        let (worst, n) = gpu_cpu_difference(&gpu, "fom", &params(&config), setup);
        eprintln!("fom {config:?}, hair alpha 0.9: max |ΔV| = {worst:e} over {n} samples");
        assert!(n > 5000, "only {n} samples");
        assert!(worst <= TOLERANCE, "fom {config:?}: max |ΔV| = {worst}");
    }
}

#[test]
fn extreme_resolutions_and_parameters() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (strands, resolution) in common::EXTREME_SETUPS {
        for config in [(1.0, 0.0), (16.0, 0.0), (16.0, 1.0)] {
            let (worst, n) =
                gpu_cpu_difference(&gpu, "fom", &params(&config), Setup::new(strands, resolution));
            eprintln!(
                "fom {config:?}, {strands} strands at {resolution}²: max |ΔV| = {worst:e} over {n} samples"
            );
            assert!(n > 10, "only {n} samples");
            assert!(
                worst <= TOLERANCE,
                "fom {config:?} at {resolution}²: max |ΔV| = {worst}"
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
    let method = registry::find("fom").unwrap();
    // ceil((2K + 1) / 4) RGBA32F layers of 16 bytes; 8 layers per geometry pass.
    for (terms, bytes_per_texel, passes) in [
        (1.0, 16, 1),
        (3.0, 32, 1),
        (4.0, 48, 1),
        (8.0, 80, 1),
        (15.0, 128, 1),
        (16.0, 144, 2),
    ] {
        let values: ParamValues = params(&(terms, 0.0))
            .iter()
            .map(|(k, v)| (k.to_string(), *v))
            .collect();
        r.render_light(&crate::common::light_frame(&s, method, &values))
            .unwrap();
        let m = r.method_gpu(method).unwrap();
        assert_eq!(m.memory_bytes(), 512 * 512 * bytes_per_texel, "K = {terms}");
        assert_eq!(m.shared_bytes(), 0, "K = {terms}");
        assert_eq!(m.geometry_passes(), passes, "K = {terms}");
    }
}
