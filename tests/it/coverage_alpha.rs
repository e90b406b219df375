//! Strand opacity from thickness (issue 9): in `render.alpha = "coverage"` mode a strand twice as thick gives
//! twice the alpha (up to clamping) in the exact light reference lists and in the exact eye lists, on the same
//! fragments; a directional light's texels give every fragment of a uniform strand the same alpha, its coverage
//! of the texel; in constant mode the thickness changes nothing and every alpha is `render.hair_alpha` (the eye's
//! to within the few ulps of perspective-correct interpolation).

use crate::common::small_settings;
use crate::transparency_gpu::eye_frame;
use hairlab::gpu::Gpu;
use hairlab::render::passes::abuffer::RefFragment;
use hairlab::render::transparency::registry;
use hairlab::render::{AlphaMode, Renderer};
use hairlab::scene::Scene;
use hairlab::settings::Settings;
use hairlab::transparency::EyeFragment;

/// The exact light lists and eye lists of `scene` with every point `thickness` thick.
fn lists(
    gpu: &Gpu,
    s: &Settings,
    scene: &Scene,
    thickness: f32,
) -> (Vec<Vec<RefFragment>>, Vec<Vec<EyeFragment>>) {
    let mut scene = scene.clone();
    scene.strands.thickness = Some(vec![thickness; scene.strands.point_count()]);
    let mut r = Renderer::new(gpu, &scene, s.render.map_resolution).unwrap();
    let light = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    let eye = r
        .eye_lists(&eye_frame(s, registry::reference(), &s.transparency.params))
        .unwrap();
    (light, eye)
}

/// Every fragment's (depth bits, segment) and alpha, light lists then eye lists, texel by texel and pixel by pixel.
fn fragments(l: &(Vec<Vec<RefFragment>>, Vec<Vec<EyeFragment>>)) -> (Vec<(u32, u32)>, Vec<f32>) {
    let light =
        l.0.iter()
            .flatten()
            .map(|f| ((f.depth.to_bits(), f.segment), f.alpha));
    let eye =
        l.1.iter()
            .flatten()
            .map(|f| ((f.depth.to_bits(), f.segment), f.alpha));
    light.chain(eye).unzip()
}

fn scene_settings() -> (Settings, Scene) {
    let mut s = small_settings(64, 48);
    s.scene.generator.strands = 200;
    s.scene.generator.segments = 8;
    s.render.map_resolution = 64;
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    (s, scene)
}

#[test]
fn coverage_alpha_doubles_with_thickness_and_constant_alpha_ignores_it() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = scene_settings();

    // Constant mode: every fragment has alpha = hair_alpha, bit for bit, whatever the thickness.
    let thin = lists(&gpu, &s, &scene, 1.0);
    let thick = lists(&gpu, &s, &scene, 2.0);
    assert_eq!(
        thin.0, thick.0,
        "constant mode: the light lists depend on the thickness"
    );
    assert_eq!(
        thin.1, thick.1,
        "constant mode: the eye lists depend on the thickness"
    );
    let (keys, alphas) = fragments(&thin);
    let light_count = thin.0.iter().map(Vec::len).sum::<usize>();
    let eye_count = thin.1.iter().map(Vec::len).sum::<usize>();
    assert!(
        light_count > 2000 && eye_count > 500,
        "{light_count} light, {eye_count} eye fragments"
    );
    // The light frame is orthographic (clip w = 1): bit for bit. The eye's perspective-correct interpolation of
    // two equal vertex values lands within a few ulps of them (measured: 5).
    let alpha = s.render.hair_alpha;
    assert!(
        alphas[..light_count]
            .iter()
            .all(|a| a.to_bits() == alpha.to_bits())
    );
    let ulps = alphas[light_count..]
        .iter()
        .map(|a| a.to_bits().abs_diff(alpha.to_bits()))
        .max()
        .unwrap();
    assert!(
        ulps <= 8,
        "constant mode: an eye alpha {ulps} ulps off hair_alpha"
    );
    eprintln!("constant: eye alphas within {ulps} ulps of hair_alpha");

    // Coverage mode, thin enough that no point of the doubled strands reaches alpha 1: twice the alpha on the
    // same fragments (measured: exactly; doubling commutes with the linear interpolation).
    s.render.alpha = AlphaMode::Coverage;
    s.render.strand_width = 1.5e-3;
    let (k1, a1) = fragments(&lists(&gpu, &s, &scene, 1.0));
    let (k2, a2) = fragments(&lists(&gpu, &s, &scene, 2.0));
    assert_eq!(k1, keys, "coverage mode changed the fragments");
    assert_eq!(k2, keys);
    let max = a1.iter().copied().fold(0.0f32, f32::max);
    assert!(max < 0.45 && a1.iter().all(|&a| a > 0.0), "max thin alpha {max}");
    let worst = a1
        .iter()
        .zip(&a2)
        .map(|(a, b)| (b / a - 2.0).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-6, "thick/thin alpha ratio off 2 by up to {worst}");
    eprintln!("unclamped: thin alpha up to {max}, thick/thin - 2 at most {worst:.1e}");

    // Wide enough that the doubled strands clamp: twice the alpha where that stays below 1, never more than 1.
    s.render.strand_width = 1.2e-2;
    let (_, a1) = fragments(&lists(&gpu, &s, &scene, 1.0));
    let (_, a2) = fragments(&lists(&gpu, &s, &scene, 2.0));
    let clamped = a2.iter().filter(|&&a| a == 1.0).count();
    assert!(clamped > 100, "only {clamped} fragments clamp at 12 mm");
    for (a, b) in a1.iter().zip(&a2) {
        assert!(
            *b >= *a && *b <= (2.0 * a).min(1.0) * (1.0 + 1e-5),
            "thin {a}, thick {b}"
        );
    }
    eprintln!("clamped: {clamped} of {} thick fragments at alpha 1", a2.len());
}

/// A directional light's texels are the same size at every depth: each light fragment of strands of one width
/// has alpha hair_alpha · width / texel, the texel's side √(frustum width · height) / resolution, measured by
/// unprojecting the fitted light frame's clip-space edges.
#[test]
fn directional_coverage_alpha_is_width_over_texel_side() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = scene_settings();
    s.render.alpha = AlphaMode::Coverage;
    s.render.strand_width = 1e-3;
    let r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let clip_to_view = r.hair_light_frame(&s.light).view_to_clip.inverse();
    let span = |a: glam::Vec3, b: glam::Vec3| {
        clip_to_view
            .project_point3(a)
            .distance(clip_to_view.project_point3(b))
    };
    let width = span(glam::Vec3::new(-1.0, 0.0, 0.5), glam::Vec3::new(1.0, 0.0, 0.5));
    let height = span(glam::Vec3::new(0.0, -1.0, 0.5), glam::Vec3::new(0.0, 1.0, 0.5));
    let texel = (width * height).sqrt() / s.render.map_resolution as f32;
    let expected = s.render.hair_alpha * s.render.strand_width / texel;
    assert!(expected > 0.01 && expected < 1.0, "expected alpha {expected}");
    let (light, _) = lists(&gpu, &s, &scene, 1.0);
    let worst = light
        .iter()
        .flatten()
        .map(|f| (f.alpha / expected - 1.0).abs())
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-5,
        "light alpha off {expected} by up to {worst:.1e} relative"
    );
    eprintln!("texel {texel:.3e}, alpha {expected:.4}, largest relative error {worst:.1e}");
}

/// The panel: the alpha mode from the hair-alpha label's context menu (the slider keeps its value); in coverage mode an "alpha mode" combo
/// box and a "strand width" slider, which set the settings; back to constant, both rows go.
#[test]
fn the_render_panel_sets_the_alpha_mode_and_the_strand_width() {
    use egui::accesskit::Role;
    use egui_kittest::Harness;
    use egui_kittest::kittest::{By, Queryable};
    use hairlab::app::HairlabApp;
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = small_settings(160, 120);
    let mut harness = crate::common::snapshot_harness(settings, [1000.0, 640.0]);
    let width_slider =
        |h: &Harness<'_, HairlabApp>| h.query_by_role_and_label(Role::Slider, "strand width").is_some();
    assert!(!width_slider(&harness), "strand width shown in constant mode");

    harness
        .get(By::new().role(Role::Label).value("hair alpha"))
        .click_secondary();
    harness.run();
    harness.get_by_label("coverage").click();
    harness.run();
    assert_eq!(harness.state().settings().render.alpha, AlphaMode::Coverage);
    assert_eq!(harness.state().settings().render.hair_alpha, 0.35);
    harness
        .get_by_role_and_label(Role::Slider, "strand width")
        .set_value_accesskit(2e-3);
    harness.run();
    assert_eq!(harness.state().settings().render.strand_width, 2e-3);

    harness
        .get_by_role_and_label(Role::ComboBox, "alpha mode")
        .click();
    harness.run();
    harness.get_by_label("constant").click();
    harness.run();
    assert_eq!(harness.state().settings().render.alpha, AlphaMode::Constant);
    assert!(
        !width_slider(&harness),
        "strand width shown after going back to constant"
    );
}
