//! Long jobs off the UI thread: a scene build and a Compare render held at a test gate while the window keeps
//! answering, their Cancel, and what they give when let through; the one stop rule of the jobs that keep partial
//! work (the bench, the report export): Stop keeps, Cancel drops.

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

/// Steps the window until `done` (a job's end or a file it writes), at most five minutes.
fn step_until(
    harness: &mut Harness<'_, HairlabApp>,
    what: &str,
    done: impl Fn(&Harness<'_, HairlabApp>) -> bool,
) {
    let start = std::time::Instant::now();
    while !done(harness) {
        assert!(
            start.elapsed().as_secs() < 300,
            "{what} after 5 minutes: {:?}",
            harness.state().message()
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
        harness.step();
    }
}

/// The status line's last message, which must not be an error.
fn message(harness: &Harness<'_, HairlabApp>) -> String {
    let (m, error) = harness.state().message().expect("a message");
    assert!(!error, "{m}");
    m.to_string()
}

/// One stop rule for the jobs that keep partial work, both in the job bar. The bench (OSM's sweep of 7): Stop
/// once the first configuration is measured ends it after the configuration in progress and keeps those
/// measured, saying "stopped"; Cancel drops a run and leaves that result. The report export: Cancel writes no
/// page (an earlier report in the folder stays as it was, no draft is left); Stop once the shadow methods' table
/// is written gives the page of what finished, without the techniques never started.
#[test]
fn the_bench_and_the_report_export_keep_their_work_on_stop_and_drop_it_on_cancel() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness =
        crate::common::snapshot_harness(crate::common::small_settings(320, 240), [1200.0, 900.0]);
    crate::common::bench_window_on_osm(&mut harness);
    let sweep = hairlab::methods::registry::find("osm").unwrap().sweep().len();

    // Bench: the bar's fraction passes the bench's tuning share (0.1) once a configuration is measured. Stop
    // then keeps the rows measured.
    let one_measured =
        |h: &Harness<'_, HairlabApp>| h.state().jobs().first().is_some_and(|j| j.fraction > 0.15);
    harness.get_by_label("Run bench").click();
    harness.step();
    let jobs = harness.state().jobs();
    assert!(jobs.len() == 1 && jobs[0].name == "bench" && jobs[0].stoppable());
    step_until(&mut harness, "no configuration measured", one_measured);
    harness.get_by_label("Stop").click();
    step_until(&mut harness, "the stopped bench runs on", |h| {
        !h.state().bench_running()
    });
    let kept = harness.state().bench_result().expect("the rows measured").clone();
    assert!(kept.is_stopped());
    assert!(
        (1..sweep).contains(&kept.rows.len()),
        "{} of {sweep}",
        kept.rows.len()
    );
    let said = message(&harness);
    assert!(said.starts_with("bench stopped: kept"), "{said}");
    // Cancel at the same point drops the run: the stopped run's rows stay.
    harness.get_by_label("Run bench").click();
    harness.step();
    step_until(&mut harness, "no configuration measured", one_measured);
    harness.get_by_label("Cancel").click();
    harness.step();
    harness.step();
    assert!(!harness.state().bench_running());
    assert!(
        harness.state().bench_result() == Some(&kept),
        "the result before stays"
    );
    says_cancelled(&harness);

    // Report: Cancel once the shadow methods' table is in the draft writes nothing; the earlier report stays.
    let export = tempfile::tempdir().unwrap();
    let out = export.path().join("hairlab-report");
    std::fs::create_dir(&out).unwrap();
    let earlier = "<p>an earlier report</p>";
    std::fs::write(out.join("index.html"), earlier).unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    let entries = || -> Vec<String> {
        std::fs::read_dir(export.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect()
    };
    let table_written = |_: &Harness<'_, HairlabApp>| {
        std::fs::read_dir(export.path())
            .unwrap()
            .any(|e| e.unwrap().path().join("data/shadows/results.csv").is_file())
    };
    harness.get_by_label("Export report…").click();
    harness.step();
    let jobs = harness.state().jobs();
    let names: Vec<&str> = jobs.iter().map(|j| j.name).collect();
    assert!(names == ["report"] && jobs[0].stoppable(), "{names:?}");
    step_until(&mut harness, "no table", table_written);
    harness.get_by_label("Cancel").click();
    harness.step();
    harness.step();
    assert!(harness.state().jobs().is_empty());
    says_cancelled(&harness);
    step_until(&mut harness, "the cancelled report's draft left", |_| {
        entries() == ["hairlab-report"]
    });
    assert_eq!(std::fs::read_to_string(out.join("index.html")).unwrap(), earlier);

    // Stop at the same point writes the page of what finished.
    harness.get_by_label("Export report…").click();
    harness.step();
    step_until(&mut harness, "no table", table_written);
    harness.get_by_label("Stop").click();
    step_until(&mut harness, "the stopped report runs on", |h| {
        h.state().jobs().is_empty()
    });
    let said = message(&harness);
    assert!(
        said.starts_with("report stopped: kept 1 configurations"),
        "{said}"
    );
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        page != earlier && page.contains("results"),
        "the new page replaces the earlier one"
    );
    let rows = std::fs::read_to_string(out.join("data/shadows/results.csv")).unwrap();
    assert_eq!(
        rows.lines().count(),
        2,
        "a header and the window's method: {rows}"
    );
    assert!(
        !out.join("data/transparency").exists(),
        "the techniques never started"
    );
    assert_eq!(entries(), ["hairlab-report"], "a draft left behind");
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
