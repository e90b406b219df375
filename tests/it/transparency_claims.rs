//! Sintorn & Assarsson 2009 §3.4's claims about occupancy-ordered blending as measured tests (spec TC-1…TC-8),
//! each against the exact reference (`sorted`) on the GPU, with the measured values printed beside the frozen
//! thresholds.

use crate::common::small_settings;
use crate::transparency_gpu::{eye_frame, eye_scene};
use glam::Vec3;
use hairlab::gpu::Gpu;
use hairlab::measure::transparency::{TechniqueConfig, measure_on};
use hairlab::render::method::{ParamValues, Role};
use hairlab::render::transparency::registry;
use hairlab::render::{FrameInput, Renderer};
use hairlab::scene::{Mesh, Scene};
use hairlab::settings::Settings;
use hairlab::transparency::metrics::compare;

/// The Fig. 2-like preset shrunk for the tests: the head at 1500 strands, occupancy shadows, α = 0.35.
fn fig2_settings() -> Settings {
    crate::common::measured_preset(
        "transparency-head",
        &[
            "scene.generator.strands=1500".into(),
            "render.map_resolution=256".into(),
        ],
    )
}

fn configs(texts: &[&str]) -> Vec<TechniqueConfig> {
    texts.iter().map(|t| TechniqueConfig::parse(t).unwrap()).collect()
}

/// TC-1 and TC-3: occupancy ordering is far closer to the exact composite than weighted average (less than half
/// its hair-pixel RMSE, higher SSIM) and than WBOIT. Weighted average's "very dull" image (§2.2) shows here as a
/// darker mean (mean luminance ratio 0.969 measured, occupancy 1.005), not as lost contrast: the σ of luminance is
/// kept (κ 1.004 against occupancy's 1.000), so only the mean is asserted.
#[test]
fn occupancy_order_is_nearly_exact_and_weighted_average_is_dull() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let s = fig2_settings();
    let (stats, rows) = measure_on(
        &gpu,
        &s,
        &configs(&["occupancy-order", "weighted-average", "wboit"]),
        0,
        &mut hairlab::progress::Quiet,
    )
    .unwrap();
    let [occ, wa, wboit] = [&rows[0].metrics, &rows[1].metrics, &rows[2].metrics];
    for (name, m) in [
        ("occupancy-order", occ),
        ("weighted-average", wa),
        ("wboit", wboit),
    ] {
        println!(
            "{name}: hair RMSE {:.5}, SSIM {:.4}, >8/255 {:.2}%, κ {:.3}, luminance {:.3} ({} hair pixels, deepest {})",
            m.rmse_hair,
            m.ssim_hair,
            100.0 * m.share_over[2],
            m.contrast_retention,
            m.mean_luminance_ratio,
            stats.hair_pixels,
            stats.max_depth_complexity
        );
    }
    assert!(stats.max_depth_complexity >= 32, "a deep view: {stats:?}");
    // The report's claims table judges with the same function (`hairlab::report::claims`).
    let tc1 = hairlab::report::claims::tc1(occ.rmse_hair, wa.rmse_hair);
    assert!(tc1.holds, "{}", tc1.measured);
    assert!(
        occ.rmse_hair < wboit.rmse_hair,
        "{} vs {}",
        occ.rmse_hair,
        wboit.rmse_hair
    );
    assert!(occ.ssim_hair > wa.ssim_hair);
    assert!(wa.mean_luminance_ratio < 0.99, "{}", wa.mean_luminance_ratio);
    assert!((1.0 - occ.mean_luminance_ratio).abs() < (1.0 - wa.mean_luminance_ratio).abs());
    // "Virtually indistinguishable": frozen from the measured 0.00% with margin.
    assert!(occ.share_over[2] < 0.005, "{}", occ.share_over[2]);
}

/// TC-2 and TC-10: occupancy ordering draws the strands 3 times on every view (depth range, occupancy + slabs,
/// hair), opaque once, depth peeling once per layer of the deepest pixel plus its count pass.
#[test]
fn geometry_passes_are_three_for_occupancy_and_the_deepest_layer_count_for_peeling() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 96, 72);
    let deepest = lists.iter().map(Vec::len).max().unwrap() as u32;
    let empty = ParamValues::new();
    for (name, passes) in [
        ("occupancy-order", 3),
        ("opaque", 1),
        ("weighted-average", 1),
        ("depth-peel", deepest + 1),
    ] {
        r.render(&eye_frame(&s, registry::find(name).unwrap(), &empty))
            .unwrap();
        assert_eq!(
            r.eye_geometry_passes(),
            passes,
            "{name} (deepest pixel {deepest})"
        );
    }
}

/// TC-8: a pixel with one fragment is exact for every transparency technique (within one 8-bit step of the
/// reference); the baseline without transparency is not one.
#[test]
fn single_fragment_pixels_are_exact_for_every_technique() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 160, 120);
    let empty = ParamValues::new();
    r.render(&eye_frame(&s, registry::reference(), &empty)).unwrap();
    let reference = r.read_output().unwrap();
    let single: Vec<usize> = (0..lists.len()).filter(|&p| lists[p].len() == 1).collect();
    assert!(single.len() > 100, "{} single-fragment pixels", single.len());
    for t in registry::all().iter().filter(|t| t.info().role != Role::Baseline) {
        r.render(&eye_frame(&s, *t, &empty)).unwrap();
        let image = r.read_output().unwrap();
        let worst = single
            .iter()
            .map(|&p| {
                let (x, y) = ((p % 160) as u32, (p / 160) as u32);
                let (a, b) = (image.get_pixel(x, y).0, reference.get_pixel(x, y).0);
                (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap()
            })
            .max()
            .unwrap();
        println!(
            "{}: worst single-fragment pixel {worst}/255 over {}",
            t.name(),
            single.len()
        );
        assert!(worst <= 1, "{}: {worst}/255", t.name());
    }
}

/// TC-4 and TC-5 on the dense view: 16-bit accumulation of occupancy ordering measurably departs from 32-bit
/// (the paper: "a 32-bit float rendertarget is necessary"), and the Λ correction lowers the error where 64 or
/// more fragments fall into a pixel.
#[test]
fn half_precision_departs_and_the_lambda_correction_helps_deep_pixels() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = crate::common::measured_preset("transparency-dense", &["render.map_resolution=256".into()]);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let empty = ParamValues::new();
    let lists = r
        .eye_lists(&eye_frame(&s, registry::reference(), &empty))
        .unwrap();
    let deep: Vec<bool> = lists.iter().map(|l| l.len() >= 64).collect();
    let deep_count = deep.iter().filter(|&&d| d).count();
    assert!(deep_count > 50, "{deep_count} pixels with n >= 64");
    r.render(&eye_frame(&s, registry::reference(), &empty)).unwrap();
    let reference = r.read_output().unwrap();
    let occupancy = registry::find("occupancy-order").unwrap();
    let image_with = |r: &mut Renderer, text: &str| {
        let c = TechniqueConfig::parse(text).unwrap();
        r.render(&eye_frame(&s, occupancy, &c.params)).unwrap();
        r.read_output().unwrap()
    };
    let on = compare(&image_with(&mut r, "occupancy-order"), &reference, &deep);
    let off = compare(
        &image_with(&mut r, "occupancy-order:correction=off"),
        &reference,
        &deep,
    );
    println!(
        "n >= 64 ({deep_count} pixels): hair RMSE with the correction {:.5}, without {:.5}",
        on.rmse_hair, off.rmse_hair
    );
    // Measured 0.00713 against 0.0271 (×0.26; 0.0212 against 0.0295 when first written).
    assert!(on.rmse_hair < 0.8 * off.rmse_hair);
    let capture = |r: &mut Renderer, text: &str| {
        let c = TechniqueConfig::parse(text).unwrap();
        r.render_capture(&eye_frame(&s, occupancy, &c.params)).unwrap()
    };
    let f32 = capture(&mut r, "occupancy-order");
    let f16 = capture(&mut r, "occupancy-order:precision=f16");
    let worst = f32
        .iter()
        .zip(&f16)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0f32, f32::max);
    println!("max |f16 - f32| accumulation = {worst:.2e} (linear)");
    assert!(worst > 1e-4, "16-bit accumulation departs measurably: {worst}");
}

/// A quad facing the camera halfway between the eye and the hair, wide enough to hide all of it.
fn screen_in_front(s: &Settings, scene: &Scene) -> Mesh {
    let eye = s.camera.eye();
    let target = Vec3::from(s.camera.target);
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let b = scene.framing_bounds();
    let nearest = eye.clamp(b.min, b.max).distance(eye);
    let centre = eye + forward * (0.5 * nearest);
    let half = 4.0 * (b.max - b.min).length();
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    Mesh {
        positions: corners
            .iter()
            .map(|(x, y)| centre + half * (x * right + y * up))
            .collect(),
        normals: vec![-forward; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
        color: Vec3::splat(0.5),
    }
}

/// TC-7 (S&A §3.5: hair behind opaque objects is discarded in every eye map): with every strand behind an opaque
/// quad, every technique's resolve adds nothing — its captured hair colour and coverage are zero at every pixel.
#[test]
fn hair_entirely_behind_an_opaque_object_changes_no_image() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = small_settings(96, 72);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let mut meshes = scene.meshes.clone();
    meshes.push(screen_in_front(&s, &scene));
    let hidden = Scene::new(scene.strands.clone(), meshes);
    let mut r = Renderer::new(&gpu, &hidden, s.render.map_resolution).unwrap();
    let empty = ParamValues::new();
    for t in registry::all() {
        let frame: FrameInput = eye_frame(&s, *t, &empty);
        let captured = r.render_capture(&frame).unwrap();
        let lit = captured.iter().filter(|p| p.iter().any(|&c| c != 0.0)).count();
        assert_eq!(lit, 0, "{}: {lit} pixels of hidden hair", t.name());
    }
}
