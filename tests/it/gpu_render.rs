//! GPU tests on the software adapter (Mesa lavapipe in CI): the render path against a snapshot image, and the
//! light-depth pass against the strands it was drawn from. With no adapter these fail with what to install,
//! unless HAIRLAB_SKIP_GPU_TESTS=1 is set.

use crate::common;

use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;

fn render(gpu: &Gpu, settings: &mut Settings) -> (Renderer, image::RgbaImage) {
    let scene = settings.scene.build().unwrap();
    settings.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(gpu, &scene, settings.render.map_resolution).unwrap();
    let method = registry::find(&settings.method.name).unwrap();
    r.render(&common::frame_input(settings, method)).unwrap();
    let img = r.read_output().unwrap();
    (r, img)
}

#[test]
fn default_scene_matches_snapshot() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = common::small_settings(160, 120);
    let (_, img) = render(&gpu, &mut s);
    // Up to 1% of pixels may differ by more than 8/255 (rasterisation differences between driver versions).
    common::compare_snapshot("render_default", &img, 8, 0.01);
}

#[test]
fn hair_shadow_darkens_the_image() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut lit = common::small_settings(160, 120);
    lit.method.name = "none".into();
    let mut shadowed = lit.clone();
    shadowed.method.name = "opaque-shadow-map".into();
    let (_, a) = render(&gpu, &mut lit);
    let (_, b) = render(&gpu, &mut shadowed);
    let sum = |img: &image::RgbaImage| {
        img.pixels()
            .map(|p| p.0[0] as u64 + p.0[1] as u64 + p.0[2] as u64)
            .sum::<u64>()
    };
    let darker = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| q.0[0] < p.0[0])
        .count();
    let brighter = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| q.0[0] > p.0[0])
        .count();
    assert!(sum(&b) < sum(&a), "opaque shadow map must darken the image");
    assert!(darker > 100, "only {darker} pixels darker");
    assert_eq!(brighter, 0, "a shadow can never brighten a pixel");
}

#[test]
fn light_depth_maps_bound_the_strands() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = common::small_settings(64, 64);
    let (r, _) = render(&gpu, &mut s);
    let near = r.read_light_depth(false).unwrap();
    let far = r.read_light_depth(true).unwrap();
    let scene = s.scene.build().unwrap();
    let frame = r.hair_light_frame(&s.light);
    let depths: Vec<f32> = scene.strands.points.iter().map(|p| frame.depth(*p)).collect();
    let (dmin, dmax) = depths
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), d| (a.min(*d), b.max(*d)));
    // The frame is fitted to the strand bounds: the strands span nearly all of [0,1] in depth.
    assert!(
        dmin >= 0.0 && dmax <= 1.0,
        "points outside the fitted range: {dmin}..{dmax}"
    );
    let covered: Vec<usize> = (0..near.len()).filter(|&i| near[i] <= far[i]).collect();
    assert!(
        covered.len() > near.len() / 10,
        "only {} of {} texels covered",
        covered.len(),
        near.len()
    );
    for i in 0..near.len() {
        if near[i] > far[i] {
            assert_eq!(
                (near[i], far[i]),
                (1.0, 0.0),
                "texel {i}: empty texels keep their clear values"
            );
        } else {
            assert!(
                near[i] >= dmin - 1e-4 && far[i] <= dmax + 1e-4,
                "texel {i}: {}..{} outside {dmin}..{dmax}",
                near[i],
                far[i]
            );
        }
    }
    // Line rasterisation samples at pixel centres, so the extremes come within a texel's worth of depth of the
    // extreme points; the strands are short relative to the map, so 2% of the range is a tight bound here.
    let nmin = covered.iter().map(|&i| near[i]).fold(f32::MAX, f32::min);
    let fmax = covered.iter().map(|&i| far[i]).fold(f32::MIN, f32::max);
    assert!(
        (nmin - dmin).abs() < 0.02,
        "nearest fragment {nmin} vs nearest point {dmin}"
    );
    assert!(
        (fmax - dmax).abs() < 0.02,
        "furthest fragment {fmax} vs furthest point {dmax}"
    );
}

#[test]
fn pcf_and_jitter_filter_the_shadows() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut plain = common::small_settings(160, 120);
    plain.method.name = "occupancy".into();
    plain.render.map_resolution = 64;
    let (_, a) = render(&gpu, &mut plain.clone());
    let mut unshadowed = plain.clone();
    unshadowed.method.name = "none".into();
    let (_, lit) = render(&gpu, &mut unshadowed);
    for (flag, set) in [("pcf", (true, false)), ("jitter", (false, true))] {
        let mut s = plain.clone();
        (s.render.pcf, s.render.jitter) = set;
        let (_, b) = render(&gpu, &mut s);
        let changed = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
        assert!(changed > 200, "{flag} changed only {changed} pixels");
        // Filtering moves visibility between texels' values, never above the unshadowed image.
        let brighter = b
            .pixels()
            .zip(lit.pixels())
            .filter(|(q, l)| (0..3).any(|i| q.0[i] > l.0[i].saturating_add(1)))
            .count();
        assert_eq!(
            brighter, 0,
            "{flag}: a filtered shadow brightened a pixel beyond the unshadowed image"
        );
    }
}

/// The eye targets are the colour and depth images (4 + 4 bytes per pixel) and weighted-blended OIT's two targets
/// (Rgba16Float + R16Float: 8 + 2), held for the technique of the last frame and re-sized with the viewport.
#[test]
fn eye_targets_hold_the_technique_of_the_last_frame() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = common::small_settings(64, 48);
    let (mut r, _) = render(&gpu, &mut s);
    let m = r.memory();
    assert_eq!(m.transparency_name, "wboit");
    assert_eq!(m.transparency_targets, 64 * 48 * 10);
    assert_eq!(m.eye_targets, 64 * 48 * 19);
    let method = registry::find(&s.method.name).unwrap();
    let frame = |render, width, height| FrameInput {
        camera: &s.camera,
        light: &s.light,
        render,
        method,
        method_params: &s.method.params,
        technique: s.transparency.technique().unwrap(),
        technique_params: &s.transparency.params,
        width,
        height,
    };
    r.render(&frame(&s.render, 32, 16)).unwrap();
    assert_eq!(r.memory().transparency_targets, 32 * 16 * 10);
    assert_eq!(r.memory().eye_targets, 32 * 16 * 19);
}
