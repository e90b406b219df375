//! Long jobs off the UI thread: a scene build and a Compare render held at a test gate while the window keeps
//! answering, their Cancel, and what they give when let through.

use super::{open_compare, small_window, tall_harness};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::HairlabApp;
use hairlab::gpu::Gpu;
use hairlab::render::transparency::registry as techniques;
use hairlab::scene::generate::HairStyle;

/// A scene build is a job: while a test gate holds it at its first step, the window keeps drawing and answering
/// (a build on the UI thread would never return from the frame while the gate is shut), its progress bar and
/// Cancel show, the previous scene stays on screen; Cancel leaves the previous scene and settings; a build let
/// through applies its scene.
#[test]
fn a_long_job_keeps_the_window_interactive_and_cancel_restores_the_scene() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = small_window();
    let points_before = harness
        .state()
        .scene()
        .expect("scene loaded")
        .strands
        .points
        .clone();
    assert_eq!(points_before.len(), 600 * 13);
    let settings_before = harness.state().settings().clone();
    let gate = harness.state_mut().hold_jobs();

    harness.get_by_label("straight").click();
    // One frame takes the click and starts the job, the next shows its progress bar.
    harness.step();
    harness.step();
    assert!(
        harness.query_by_label_contains("growing the strands").is_none(),
        "held before its first step"
    );
    held_job_leaves_the_window_answering(&mut harness, "scene");
    assert_eq!(
        harness.state().scene().unwrap().strands.points,
        points_before,
        "the previous scene stays on screen"
    );
    assert_eq!(harness.state().jobs().len(), 1, "still held");

    // Cancel: the previous scene and settings, exactly.
    harness.get_by_label("Cancel").click();
    harness.step();
    harness.run();
    assert!(harness.state().jobs().is_empty());
    assert_eq!(harness.state().scene().unwrap().strands.points, points_before);
    assert!(
        *harness.state().settings() == settings_before,
        "the settings before the change"
    );
    says_cancelled(&harness);
    assert!(
        harness.query_by_label("Cancel").is_none(),
        "the progress bar is gone"
    );

    // The same change again, let through: its scene replaces the previous one.
    harness.get_by_label("straight").click();
    harness.step();
    assert_eq!(harness.state().jobs().len(), 1);
    gate.open();
    harness.state_mut().finish_jobs();
    harness.run();
    assert!(harness.state().jobs().is_empty());
    assert_eq!(
        harness.state().settings().scene.generator.style,
        HairStyle::Straight
    );
    let points_after = &harness.state().scene().unwrap().strands.points;
    assert_eq!(points_after.len(), 600 * 13);
    assert_ne!(
        *points_after, points_before,
        "straight hair, not the wavy scene before"
    );
}

/// A Compare render is a job with a renderer of its own: while a test gate holds it, the window keeps drawing and
/// answering (Help opens and closes), the job bar shows it with Cancel, and the previous images stay; Cancel
/// leaves them exactly; a render let through gives, byte for byte, the images, lists and opaque image of the
/// synchronous `render_compare` on a renderer made from the same scene.
#[test]
fn a_compare_render_is_a_job_that_cancel_leaves_and_that_renders_what_render_compare_does() {
    use egui::accesskit::Role;
    use hairlab::app::compare_view::render_compare;
    use hairlab::render::Renderer;
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut harness = tall_harness();
    harness.run();
    open_compare(&mut harness);
    let (generation, before): (u64, Vec<image::RgbaImage>) = {
        let c = harness.state().compare();
        let f = c.frames().expect("compare frames rendered");
        (c.generation(), f.images.iter().map(|i| i.image.clone()).collect())
    };
    let gate = harness.state_mut().hold_jobs();

    // A render held at its first step.
    harness.get_by_role_and_label(Role::Button, "Render").click();
    harness.step();
    harness.step();
    held_job_leaves_the_window_answering(&mut harness, "compare");
    assert_eq!(harness.state().jobs().len(), 1, "still held");
    assert_eq!(harness.state().compare().generation(), generation);

    // Cancel: the previous images, exactly.
    harness.get_by_label("Cancel").click();
    harness.step();
    harness.run();
    assert!(harness.state().jobs().is_empty());
    let c = harness.state().compare();
    assert_eq!(c.generation(), generation, "no new frames");
    let kept: Vec<&image::RgbaImage> = c.frames().unwrap().images.iter().map(|i| &i.image).collect();
    assert!(
        kept.iter().zip(&before).all(|(a, b)| *a == b),
        "the previous images stay"
    );
    says_cancelled(&harness);

    // Another slot, let through: its frames replace the previous ones.
    let reference = techniques::reference().name();
    harness.state_mut().compare_mut().slots[2] = hairlab::app::compare_view::Slot::Technique(reference);
    harness.get_by_role_and_label(Role::Button, "Render").click();
    harness.step();
    assert_eq!(harness.state().jobs().len(), 1);
    gate.open();
    harness.state_mut().finish_jobs();
    harness.run();
    assert!(harness.state().jobs().is_empty());
    let app = harness.state();
    assert_eq!(app.compare().generation(), generation + 1);
    let frames = app.compare().frames().unwrap();
    assert_eq!(frames.images[2].name, reference);
    assert!(
        frames.images[2].image == frames.images[0].image,
        "slot 3 shows the reference now"
    );

    // The same as the synchronous render on a renderer of the test's own.
    let scene = app.scene().unwrap();
    let mut r = Renderer::new(&gpu, scene, frames.settings.render.map_resolution).unwrap();
    let slots = app.compare().slots;
    let sync = render_compare(
        &mut r,
        scene,
        &frames.settings,
        &slots,
        frames.width,
        frames.height,
    )
    .unwrap();
    for (k, (a, b)) in frames.images.iter().zip(&sync.images).enumerate() {
        assert_eq!(a.name, b.name);
        assert!(
            a.image == b.image,
            "slot {}: the job's image differs from render_compare's",
            k + 1
        );
    }
    assert!(frames.lists == sync.lists, "the exact lists");
    assert!(frames.background == sync.background, "the opaque image");
}

/// A job held at its gate: it is the one job in the bar, shown as "starting 0%", and the window answers meanwhile
/// (the Help window opens and closes).
fn held_job_leaves_the_window_answering(harness: &mut Harness<'_, HairlabApp>, name: &str) {
    let jobs = harness.state().jobs();
    assert_eq!(jobs.len(), 1, "one {name} job");
    assert_eq!(jobs[0].name, name);
    assert!(
        harness.query_by_label_contains("starting 0%").is_some(),
        "the progress bar shows"
    );
    assert!(harness.query_by_label("Drop a file").is_none());
    harness.get_by_label("Help").click();
    harness.step();
    harness.step();
    assert!(
        harness.query_by_label("Drop a file").is_some(),
        "Help opened during the {name} job"
    );
    harness.key_press(egui::Key::F1);
    harness.step();
    harness.step();
    assert!(
        harness.query_by_label("Drop a file").is_none(),
        "Help closed during the {name} job"
    );
}

/// The status line's last message is the (non-error) one a cancelled job leaves.
fn says_cancelled(harness: &Harness<'_, HairlabApp>) {
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, err)| !err && m.contains("cancelled")),
        "{:?}",
        harness.state().message()
    );
}
