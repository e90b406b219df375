//! The window's path-traced view (`render.mode = path`), driven headless by egui_kittest: it converges to
//! `render.spp` on a worker, its image equals pixel for pixel the library's path-traced image of the same scene,
//! camera and size and `hairlab render` of the window's settings (an independent route: the CLI's passes, its
//! linear EXR), raising `render.spp` goes on from the samples taken, a change starts it again, the window answers
//! while a pass is held, and a screenshot saves the image shown.

use crate::common;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::path_view::{MAX_SIDE, render_image};
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::{AdapterPreference, Gpu};
use hairlab::render::render_settings::RenderMode;

fn path_window(spp: u32) -> Harness<'static, HairlabApp> {
    let mut settings = common::small_settings(320, 240);
    settings.render.mode = RenderMode::Path;
    settings.render.spp = spp;
    // Over black, the view shows the radiance alone, as `hairlab render` writes it.
    settings.render.background = [0.0; 3];
    let mut harness = Harness::builder()
        .with_size([900.0, 800.0])
        .with_max_steps(16)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    harness
}

/// Runs frames until the view has converged (the job finished and its last image shown): the scene's job
/// first, then the path-traced view's, which the first frame with a renderer starts.
fn converge(harness: &mut Harness<'static, HairlabApp>) {
    for _ in 0..2 {
        harness.state_mut().finish_jobs();
        harness.run();
    }
}

/// The library's image of what the window shows, at the window's image size.
fn expected(harness: &Harness<'static, HairlabApp>, size: (u32, u32)) -> image::RgbaImage {
    let app = harness.state();
    let scene = app.scene().expect("a scene");
    render_image(app.settings(), scene, &scene.bounds(), size).unwrap()
}

/// `hairlab render` of the window's settings (written out as a preset) at `size`, its linear EXR encoded to 8-bit
/// sRGB: pixel for pixel the view's image (measured 0 levels apart), so a view that scales, drops or mixes up its
/// samples fails where its comparison with `render_image` (the same code path) would not.
fn cli_image(harness: &Harness<'static, HairlabApp>, size: (u32, u32)) -> image::RgbaImage {
    let dir = tempfile::tempdir().unwrap();
    let (preset, out) = (dir.path().join("window.toml"), dir.path().join("cli.exr"));
    std::fs::write(&preset, harness.state().settings().to_toml()).unwrap();
    let (w, h) = (size.0.to_string(), size.1.to_string());
    let o = common::cli::hairlab(&[
        "render",
        "--preset",
        preset.to_str().unwrap(),
        "--width",
        &w,
        "--height",
        &h,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", common::cli::stderr(&o));
    let linear = image::open(&out).unwrap().to_rgb32f();
    image::RgbaImage::from_fn(size.0, size.1, |x, y| {
        let [r, g, b] = linear.get_pixel(x, y).0.map(hairlab::io::srgb8);
        image::Rgba([r, g, b, 255])
    })
}

/// The largest difference of any channel of any pixel between two images of one size.
fn max_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> u8 {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels()
        .zip(b.pixels())
        .flat_map(|(p, q)| (0..4).map(move |k| p.0[k].abs_diff(q.0[k])))
        .max()
        .unwrap_or(0)
}

#[test]
fn the_path_traced_view_converges_to_the_librarys_image_and_goes_on_when_spp_rises() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = path_window(2);
    converge(&mut harness);
    assert_eq!(harness.state().path_view().error(), None);
    let shown = harness
        .state()
        .path_view()
        .latest()
        .expect("an image after converging");
    assert_eq!(shown.spp, 2);
    assert!(!harness.state().path_view().is_converging());
    let size = shown.image.dimensions();
    assert!(
        size.0.max(size.1) <= MAX_SIDE && size.0 > 100 && size.1 > 100,
        "{size:?}"
    );
    // Passes of one sample each add each pixel's samples in order: the same sums as one pass of two.
    assert!(
        shown.image == expected(&harness, size),
        "the view's 2-spp image differs from the library's"
    );
    let worst = max_difference(&shown.image, &cli_image(&harness, size));
    eprintln!("the view against `hairlab render`: at most {worst} levels apart");
    assert_eq!(worst, 0, "the view's 2-spp image differs from `hairlab render`'s");
    let hair = shown
        .image
        .pixels()
        .filter(|p| p.0 != shown.image.get_pixel(0, 0).0)
        .count();
    assert!(
        hair > 2000,
        "only {hair} pixels differ from the corner's background"
    );

    // More samples go on from the two taken (the job bar showed it; its result equals a fresh 3-spp render).
    harness.state_mut().settings_mut().render.spp = 3;
    harness.run();
    converge(&mut harness);
    let shown = harness.state().path_view().latest().unwrap();
    assert_eq!(shown.spp, 3);
    assert_eq!(shown.image.dimensions(), size, "the viewport kept its size");
    assert!(
        shown.image == expected(&harness, size),
        "going on to 3 spp differs from rendering 3 spp"
    );

    // The screenshot saves the path-traced image shown.
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("path.png");
    harness.state_mut().request_screenshot(shot.clone());
    harness.run();
    let saved = image::open(&shot).expect("screenshot written").to_rgba8();
    assert!(
        saved == shown.image,
        "the screenshot is not the path-traced image shown"
    );
}

#[test]
fn a_change_restarts_the_view_and_the_window_answers_while_a_pass_is_held() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = path_window(1);
    converge(&mut harness);
    let before = harness.state().path_view().latest().unwrap();
    let gate = harness.state_mut().hold_jobs();
    harness.state_mut().settings_mut().camera.yaw_deg += 30.0;
    harness.run();
    // The new job waits at the gate: no image of the old camera is shown as if it were the new one's.
    assert!(harness.state().path_view().is_converging());
    assert!(
        harness.state().path_view().latest().is_none(),
        "a stale image survived the change"
    );
    // The window answers meanwhile: switching the viewport back to raster takes effect and drops the job.
    harness.get_by_label("GPU raster").click();
    harness.run();
    assert_eq!(harness.state().settings().render.mode, RenderMode::Raster);
    assert!(!harness.state().path_view().is_converging());
    gate.open();
    // Back to path-traced: the new camera's image, not the old one.
    harness.state_mut().settings_mut().render.mode = RenderMode::Path;
    harness.run();
    converge(&mut harness);
    let after = harness.state().path_view().latest().unwrap();
    assert!(
        after.image != before.image,
        "the turned camera shows the same image"
    );
    assert!(after.image == expected(&harness, after.image.dimensions()));
}

/// The compare view's path-traced slot: the window's compare job renders it as the library's path-traced image of
/// the scene at the compare size, beside the raster slots, with its CPU time and its metrics against slot 1.
#[test]
fn the_compare_views_path_traced_slot_is_the_path_traced_image() {
    use egui::accesskit::Role;
    use hairlab::app::compare_view::{PATH_TRACED, Slot};
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut settings = common::small_settings(320, 240);
    settings.render.spp = 2;
    let mut harness = Harness::builder()
        .with_size([1400.0, 1200.0])
        .with_max_steps(16)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    {
        let c = harness.state_mut().compare_mut();
        c.slots[3] = Slot::PathTraced;
        c.open = true;
    }
    harness.run();
    harness.get_by_role_and_label(Role::Button, "Render").click();
    harness.run();
    converge(&mut harness);
    let app = harness.state();
    assert_eq!(app.compare().error(), None);
    let frames = app.compare().frames().expect("compare frames");
    let slot = &frames.images[3];
    assert_eq!((slot.name, slot.label), PATH_TRACED);
    assert!(slot.cpu_seconds.is_some() && slot.passes.is_empty());
    let scene = app.scene().unwrap();
    let want = render_image(
        app.settings(),
        scene,
        &scene.bounds(),
        (frames.width, frames.height),
    )
    .unwrap();
    assert!(
        slot.image == want,
        "slot 4 is not the path-traced image at the compare size"
    );
    assert!(
        slot.metrics.rmse > 0.0 && slot.metrics.rmse < 0.5,
        "rmse {} against the exact sort: the fibres differ from the strands' fragments, but not wholly",
        slot.metrics.rmse
    );
}
