//! The real workbench app driven headless by egui_kittest on the software adapter: it shows the scene, reacts to
//! a parameter change through the UI, saves a screenshot without a dialog, and matches a UI snapshot.

use crate::common;

use egui_kittest::kittest::Queryable;
use egui_kittest::{Harness, SnapshotOptions};
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::{AdapterPreference, Gpu};
use hairlab::scene::generate::HairStyle;

#[test]
fn workbench_headless() {
    // Fails with what to install when there is no adapter (or skips on explicit request).
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = common::small_settings(320, 240);
    let mut harness = Harness::builder()
        .with_size([1000.0, 640.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| {
            let mut app = HairlabApp::new(cc, Some(settings));
            app.set_snapshot_mode(true);
            app
        });
    harness.run();
    let segments_before = harness
        .state()
        .scene()
        .expect("scene loaded")
        .strands
        .segment_count();
    assert_eq!(segments_before, 600 * 12);
    assert!(
        harness.state().message().is_some_and(|(_, err)| !err),
        "{:?}",
        harness.state().message()
    );

    // Change a generator parameter through the UI: the scene is rebuilt with straight hair.
    harness.get_by_label("straight").click();
    harness.run();
    assert_eq!(
        harness.state().settings().scene.generator.style,
        HairStyle::Straight
    );
    let straight = harness.state().scene().unwrap().strands.points.clone();
    assert_eq!(straight.len(), 600 * 13);

    // The screenshot path, without a dialog: the viewport at full resolution as PNG.
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("shot.png");
    harness.state_mut().request_screenshot(shot.clone());
    harness.run();
    let img = image::open(&shot).expect("screenshot written").to_rgba8();
    assert!(
        img.width() > 400 && img.height() > 400,
        "viewport size {}x{}",
        img.width(),
        img.height()
    );
    let bg = [0.12f32, 0.13, 0.15].map(|c| (c.powf(1.0 / 2.2) * 255.0) as i32);
    let hair_pixels = img
        .pixels()
        .filter(|p| (0..3).any(|i| (p.0[i] as i32 - bg[i]).abs() > 12))
        .count();
    assert!(
        hair_pixels > 5000,
        "only {hair_pixels} non-background pixels in the screenshot"
    );
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, _)| m.contains("screenshot saved"))
    );

    harness.snapshot_options(
        "workbench",
        &SnapshotOptions::new().threshold(2.0).max_failed_pixels(200),
    );
}
