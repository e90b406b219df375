//! Bounding Opacity Maps on the GPU (`hairlab::methods::bom`) against the CPU model `visibility::bom`, fed each
//! texel's exact fragment list from the reference A-buffer: 1 to 32 layers, split ratios from linear to
//! logarithmic; map resolutions 1 and 2048; memory, geometry passes, the uniform layout; and the automatic split
//! ratio (thesis §5.2.3-5.2.4) on a rendered map.

use crate::common;

use crate::common::{Setup, gpu_cpu_difference, max_gpu_cpu_difference};
use hairlab::gpu::Gpu;
use hairlab::methods::bom::automatic_split_ratio;
use hairlab::methods::{ParamValues, registry};
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;
use hairlab::visibility::SplitCriterion;

/// The linear split is the same f32 expressions as on the CPU; for `r > 0` the GPU's `log2` is not correctly
/// rounded (a few ULP), which moves `s` by about 1e-7 (the lookup's interpolation weight by `K` times that: a
/// few 1e-6 in V at 32 layers). A fragment within that distance of a layer boundary could change layer; none
/// does in these scenes (that would show as a |ΔV| of the order of the fragment's opacity, far above this).
const TOLERANCE: f32 = 1e-4;

/// (layers, split_ratio).
const CONFIGS: &[(f32, f32)] = &[
    // The defaults: one RGBA target, linear split (thesis §5).
    (4.0, 0.0),
    (1.0, 0.0),
    (1.0, 1.0),
    (4.0, 0.5),
    (4.0, 1.0),
    (7.0, 0.3),
    (32.0, 0.0),
    (32.0, 0.1),
    (32.0, 0.5),
    (32.0, 0.9),
    (32.0, 1.0),
];

fn params(&(layers, split_ratio): &(f32, f32)) -> [(&'static str, f32); 2] {
    [("layers", layers), ("split_ratio", split_ratio)]
}

fn values(params: &[(&str, f32)]) -> ParamValues {
    params.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

#[test]
fn bom_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for config in CONFIGS {
        let (worst, n) = max_gpu_cpu_difference(&gpu, "bom", &params(config), 64);
        eprintln!("bom {config:?} at 64²: max |ΔV| = {worst:e} over {n} samples");
        assert!(n > 5000, "only {n} samples");
        assert!(worst <= TOLERANCE, "bom {config:?}: max |ΔV| = {worst}");
    }
}

/// The test scene with `strands` strands and its camera framed.
fn scene_settings(strands: u32, resolution: u32) -> (Settings, hairlab::scene::Scene) {
    common::setup_scene(common::Setup::new(strands, resolution))
}

fn frame<'a>(s: &'a Settings, method: &str, params: &'a ParamValues) -> FrameInput<'a> {
    crate::common::light_frame(s, registry::find(method).unwrap(), params)
}

#[test]
fn extreme_resolutions_and_parameters() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let extremes = [(1.0, 0.0), (1.0, 1.0), (32.0, 0.0), (32.0, 1.0)];
    for (strands, resolution) in common::EXTREME_SETUPS {
        for config in &extremes {
            let (worst, n) =
                gpu_cpu_difference(&gpu, "bom", &params(config), Setup::new(strands, resolution));
            eprintln!(
                "bom {config:?}, {strands} strands at {resolution}²: max |ΔV| = {worst:e} over {n} samples"
            );
            assert!(n > 10, "only {n} samples");
            assert!(
                worst <= TOLERANCE,
                "bom {config:?} at {resolution}²: max |ΔV| = {worst}"
            );
        }
    }
}

#[test]
fn memory_and_geometry_passes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, scene) = scene_settings(20, 512);
    let mut r = Renderer::new(&gpu, &scene, 512).unwrap();
    let method = registry::find("bom").unwrap();
    // Layers (one RGBA32F texel per 4 layers) + the start and end depth maps (4 bytes each).
    for (config, bytes_per_texel) in [
        ((4.0, 0.0), 16 + 8),
        ((1.0, 0.0), 16 + 8),
        ((5.0, 0.5), 32 + 8),
        ((32.0, 1.0), 128 + 8),
    ] {
        let values = values(&params(&config));
        r.render_light(&frame(&s, "bom", &values)).unwrap();
        let m = r.method_gpu(method).unwrap();
        assert_eq!(m.memory_bytes(), 512 * 512 * bytes_per_texel, "{config:?}");
        assert_eq!(m.geometry_passes(), 1, "{config:?}");
    }
}

#[test]
fn automatic_split_ratio_on_a_rendered_map() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, scene) = scene_settings(300, 64);
    let mut r = Renderer::new(&gpu, &scene, 64).unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    assert_eq!(lists.len(), 64 * 64);
    for layers in [2, 4, 8, 32] {
        let search = automatic_split_ratio(&lists, layers);
        let summary: Vec<String> = search
            .scores
            .iter()
            .map(|s| format!("{:.1}: C {:.4} SAD {:.1}", s.ratio, s.correlation, s.sad))
            .collect();
        eprintln!("{layers} layers: {}", summary.join(", "));
        assert_eq!(search.scores.len(), 11, "{layers} layers");
        for (i, score) in search.scores.iter().enumerate() {
            assert_eq!(score.ratio, i as f32 / 10.0);
            assert!(
                (-1.0..=1.0).contains(&score.correlation) && score.sad.is_finite() && score.sad > 0.0,
                "{layers} layers: {score:?}"
            );
        }
        // The ratios give different layer images on this map.
        assert!(
            search
                .scores
                .iter()
                .any(|s| s.correlation != search.scores[0].correlation),
            "{layers} layers: every ratio scores the same"
        );
        // The chosen ratio is the least correlated one (the first of them on ties).
        let least = search
            .scores
            .iter()
            .fold(None::<&hairlab::visibility::SplitScore>, |best, s| match best {
                Some(b) if b.correlation <= s.correlation => Some(b),
                _ => Some(s),
            })
            .unwrap();
        assert_eq!(
            search.best(SplitCriterion::CrossCorrelation),
            least.ratio,
            "{layers} layers"
        );
    }
}
