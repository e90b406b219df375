//! The real workbench app driven headless by egui_kittest on the software adapter, a file per concern: the
//! window and its side panel (`window`), the compare view and the pixel inspector (`compare`), a motion played,
//! followed and exported (`timeline`), long jobs and their Cancel (`jobs`). The harnesses they share are here.

mod compare;
mod jobs;
mod timeline;
mod window;

use crate::common;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::AdapterPreference;

/// The workbench on the small generated scene, its first scene built.
fn small_window() -> Harness<'static, HairlabApp> {
    let settings = common::small_settings(320, 240);
    let mut harness = Harness::builder()
        .with_size([1000.0, 640.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    harness
}

/// The workbench at a height where the side panel's Transparency section and the compare window fit.
fn tall_harness() -> Harness<'static, HairlabApp> {
    tall_harness_on(common::small_settings(320, 240))
}

/// [`tall_harness`] on `settings`.
fn tall_harness_on(settings: hairlab::settings::Settings) -> Harness<'static, HairlabApp> {
    Harness::builder()
        .with_size([1400.0, 1500.0])
        .with_max_steps(8)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)))
}

/// Opens the side panel's Transparency section.
fn open_transparency_section(harness: &mut Harness<'_, HairlabApp>) {
    harness.get_by_label("Transparency").click();
    harness.run();
}

/// Clicks `pixel` of the compare view's reference image; the pixel inspector opens on it.
fn click_pixel(harness: &mut Harness<'_, HairlabApp>, pixel: [u32; 2]) {
    let app = harness.state();
    let frames = app.compare().frames().expect("compare frames rendered");
    let (w, h) = (frames.width, frames.height);
    let rect = app.compare().image_rect(0).expect("reference image drawn");
    let pos = rect.min
        + egui::vec2(
            (pixel[0] as f32 + 0.5) * rect.width() / w as f32,
            (pixel[1] as f32 + 0.5) * rect.height() / h as f32,
        );
    harness.hover_at(pos);
    harness.step();
    harness.drag_at(pos);
    harness.step();
    harness.drop_at(pos);
    harness.run();
    let app = harness.state();
    assert!(app.pixel_inspector().open, "a click opens the pixel inspector");
    assert_eq!(
        app.pixel_inspector().pixel,
        Some(pixel),
        "clicked {pos:?} in {rect:?}"
    );
}

/// Opens the compare window and lets it render.
fn open_compare(harness: &mut Harness<'_, HairlabApp>) {
    open_transparency_section(harness);
    harness.get_by_label("Compare").click();
    harness.run();
    // The render is a job: wait for it.
    harness.state_mut().finish_jobs();
    harness.run();
    assert_eq!(harness.state().compare().error(), None);
    // The new window sizes itself to its contents over a few frames.
    for _ in 0..10 {
        let rect = harness.state().compare().image_rect(0);
        harness.run();
        if harness.state().compare().image_rect(0) == rect {
            return;
        }
    }
    panic!("the compare window does not settle");
}
