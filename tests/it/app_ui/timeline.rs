//! A motion in the window: played and scrubbed, the light fitted to the whole motion, a hair point followed in the
//! time view, and the frames exported (and an export cancelled).

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::{AdapterPreference, Gpu};
use hairlab::scene::LightFit;

/// A preset with a motion plays in the window: the timeline bar shows; Right steps to frame k, whose strands are the
/// motion's frame k (the same bits as a fresh simulation's, on the window's scene and drawn by its renderer);
/// Space plays (the frame advances, the image changes) and pauses; scrubbing back lands on the same bits.
#[test]
fn the_window_plays_a_motion() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = hairlab::settings::Settings::load_preset(
        "wind",
        &[
            "scene.generator.strands=200".into(),
            "scene.generator.segments=8".into(),
            "render.width=160".into(),
            "render.height=120".into(),
            "render.map_resolution=128".into(),
            "motion.frames=12".into(),
        ],
    )
    .unwrap();
    let (_, mut fresh) = settings.open_motion().unwrap();
    let frame3 = fresh.frame(3).unwrap().to_vec();
    let mut harness = Harness::builder()
        .with_size([1000.0, 640.0])
        .with_step_dt(1.0 / 30.0)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    assert!(harness.state().timeline().is_moving());
    assert_eq!(harness.state().timeline().frame_count(), 12);
    harness.get_by_label("Play");
    let image = |h: &Harness<'_, HairlabApp>| h.state().viewport_image().expect("a rendered frame");
    let still = image(&harness);
    for _ in 0..3 {
        harness.key_combination(&[egui::Key::ArrowRight]);
        harness.run();
    }
    assert_eq!(harness.state().timeline().frame(), 3);
    assert_eq!(harness.state().scene().unwrap().strands.points, frame3);
    let moved = image(&harness);
    let differing = still.pixels().zip(moved.pixels()).filter(|(a, b)| a != b).count();
    assert!(
        differing > 50,
        "frame 3 differs from frame 0 in only {differing} pixels"
    );

    harness.key_combination(&[egui::Key::Space]);
    harness.run_steps(4);
    let playing = harness.state().timeline().frame();
    assert!(harness.state().timeline().is_playing());
    assert!(playing > 3, "four steps of play left the frame at {playing}");
    harness.key_combination(&[egui::Key::Space]);
    harness.run();
    assert!(!harness.state().timeline().is_playing());

    harness.state_mut().timeline_mut().seek(3);
    harness.run();
    assert_eq!(harness.state().scene().unwrap().strands.points, frame3);
    assert_eq!(
        image(&harness),
        moved,
        "frame 3 scrubbed back to draws what frame 3 drew"
    );
}

/// `light.fit = bound` in the window: the whole motion's box is found on a worker and the hair maps' light frame
/// fits it (the box `render` and `measure motion` fit, `Motion::bound`, equal to the last bit); per frame goes back
/// to the strands of the frame shown, and bound again reuses the box found.
#[test]
fn the_window_fits_the_light_to_the_whole_motion() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut settings = small_wind(10);
    settings.light.fit = LightFit::Bound;
    let (scene, mut fresh) = settings.open_motion().unwrap();
    let whole = fresh.bound(&settings.motion).unwrap();
    let frame0 = scene.strand_bounds();
    assert_ne!(whole, frame0, "the wind moves the strands out of their rest box");
    let mut harness = Harness::builder()
        .with_size([1000.0, 640.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    harness.state_mut().finish_jobs();
    harness.run();
    assert_eq!(harness.state().light_fit_box(), Some(whole));
    harness.state_mut().settings_mut().light.fit = LightFit::PerFrame;
    harness.run();
    assert_eq!(harness.state().light_fit_box(), Some(frame0));
    harness.state_mut().settings_mut().light.fit = LightFit::Bound;
    harness.run();
    assert!(harness.state().jobs().is_empty(), "the box found is reused");
    assert_eq!(harness.state().light_fit_box(), Some(whole));
}

/// The `wind` preset at test size (150 strands of 8 segments, 160×120, a 64² map) with `frames` frames.
fn small_wind(frames: u32) -> hairlab::settings::Settings {
    let set: Vec<String> = [
        "scene.generator.strands=150",
        "scene.generator.segments=8",
        "render.width=160",
        "render.height=120",
        "render.map_resolution=64",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("motion.frames={frames}")])
    .collect();
    hairlab::settings::Settings::load_preset("wind", &set).unwrap()
}

/// The texel inspector's time view: a hair point clicked in the viewport and followed with "Time view" over the
/// motion's frames on a worker thread while the window keeps drawing and answering; its figures are those
/// `measure motion --point` computes for the same point; Cancel drops a run and keeps the figures shown, and so
/// does a Stop before any configuration finished.
#[test]
fn the_time_view_follows_a_clicked_hair_point_over_the_motion() {
    use hairlab::measure::motion::{MotionConfig, MotionOptions, measure_motion};
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = small_wind(4);
    let mut harness = Harness::builder()
        .with_size([1100.0, 760.0])
        .with_step_dt(1.0 / 30.0)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    // The nearest segment midpoint to the viewport's centre among the strands' middle segments, clicked.
    let app = harness.state();
    let strands = &app.scene().unwrap().strands;
    let centre = app
        .viewport_position(glam::Vec3::from(app.settings().camera.target))
        .expect("the camera target shows");
    let pos = strands
        .ranges()
        .filter_map(|(start, n)| {
            let i = start + n / 2;
            app.viewport_position((strands.points[i] + strands.points[i + 1]) * 0.5)
        })
        .min_by(|a, b| a.distance(centre).total_cmp(&b.distance(centre)))
        .unwrap();
    harness.hover_at(pos);
    harness.step();
    harness.drag_at(pos);
    harness.step();
    harness.drop_at(pos);
    harness.run();
    assert!(
        harness.state().inspector().open,
        "a click on hair opens the inspector"
    );
    harness.get_by_label("Time view").click();
    harness.step();
    assert!(
        harness.state().time_view().is_running(),
        "the time view measures on a worker"
    );
    assert!(
        harness.state().jobs().iter().any(|j| j.name == "time view"),
        "a job in the job bar"
    );
    // The window keeps drawing and answering while it runs: a timeline step lands.
    harness.key_combination(&[egui::Key::ArrowRight]);
    harness.step();
    assert_eq!(harness.state().timeline().frame(), 1);
    let mut waited = 0;
    while harness.state().time_view().is_running() {
        std::thread::sleep(std::time::Duration::from_millis(200));
        harness.step();
        waited += 1;
        assert!(waited < 3000, "the time view did not finish in 10 minutes");
    }
    harness.step();
    let view = harness.state().time_view();
    // The frame axis spans exactly the frames computed, and the legend sits beside the chart, not over it.
    let layout = view.layout().expect("the figures were drawn");
    assert_eq!(layout.x_bounds, [0.0, 3.0]);
    assert!(
        layout.plot.is_positive() && layout.legend.is_positive(),
        "{layout:?}"
    );
    assert!(!layout.legend.intersects(layout.plot), "{layout:?}");
    let point = view.point().expect("a followed point");
    let shown = view.result().expect("the time view's figures").clone();
    let (followed, reference) = shown.followed.clone().expect("the followed series");
    assert_eq!(followed, point);
    assert_eq!(reference.len(), 4);
    assert!(shown.rows.iter().all(|r| r.followed.len() == 4));
    // The headless measurement of the same point gives the same figures, bit for bit.
    let configs = hairlab::measure::motion::usual_configs();
    let gpu = Gpu::for_tests().unwrap();
    let options = MotionOptions {
        follow: Some(point),
        after_each: None,
    };
    let measured = harness.state().settings().clone();
    let headless = measure_motion(
        &gpu,
        &measured,
        &configs,
        4,
        options,
        &mut hairlab::progress::Quiet,
    )
    .unwrap();
    assert_eq!(headless.followed.as_ref().unwrap().1, reference);
    for (a, b) in headless.rows.iter().zip(&shown.rows) {
        assert_eq!(a.config, b.config);
        assert_eq!(a.followed, b.followed, "{}", a.config.label());
    }
    assert_eq!(
        configs.iter().map(MotionConfig::label).collect::<Vec<_>>(),
        shown.rows.iter().map(|r| r.config.label()).collect::<Vec<_>>()
    );
    // The job bar's Cancel stops a new run at once and keeps the figures shown.
    harness.get_by_label("Run").click();
    harness.step();
    assert!(harness.state().time_view().is_running());
    // The job bar and its Cancel button are drawn from the next frame on.
    harness.step();
    harness.get_by_label("Cancel").click();
    harness.step();
    assert!(!harness.state().time_view().is_running());
    assert_eq!(
        harness.state().time_view().result().unwrap().followed,
        shown.followed
    );
    // Its Stop, held at the first step, ends the run there: nothing measured, the figures shown stay, and the
    // view says so.
    let gate = harness.state_mut().hold_jobs();
    harness.get_by_label("Run").click();
    harness.step();
    harness.step();
    assert!(
        harness
            .state()
            .jobs()
            .iter()
            .any(|j| j.name == "time view" && j.stoppable())
    );
    harness.get_by_label("Stop").click();
    let start = std::time::Instant::now();
    while harness.state().time_view().is_running() {
        assert!(start.elapsed().as_secs() < 60, "the stopped run did not end");
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.step();
    }
    harness.step();
    assert_eq!(
        harness.state().time_view().result().unwrap().followed,
        shown.followed
    );
    assert!(
        harness
            .query_by_label_contains("stopped before any configuration finished")
            .is_some()
    );
    gate.open();
}

/// The window on a small wind motion with the timeline's Export… window open.
fn export_window() -> Harness<'static, HairlabApp> {
    let settings = small_wind(4);
    let mut harness = Harness::builder()
        .with_size([1100.0, 700.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    harness.get_by_label("Export…").click();
    harness.run();
    harness
}

/// The timeline's Export…: frames of the motion at a chosen size as a PNG sequence and as an animated GIF,
/// rendered in a job and streamed frame by frame; the files are, byte for byte, what the export wrote when it held
/// every frame and encoded them at the end (each frame of the CLI's `render --frames A..B` encoded as PNG, and
/// all of them as one GIF).
#[test]
fn the_window_exports_the_motion_as_the_cli_does() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = export_window();
    let dir = tempfile::tempdir().unwrap();
    let export = |harness: &mut Harness<'_, HairlabApp>, gif: bool, path: std::path::PathBuf| {
        let e = harness.state_mut().animation_export_mut();
        assert!(e.open, "Export… opens the export window");
        (e.start, e.end, e.width, e.height, e.gif) = (1, 3, 96, 72, gif);
        e.path = path.display().to_string();
        harness.get_by_label("Export").click();
        harness.step();
        let mut waited = 0;
        while harness.state_mut().animation_export_mut().is_running() {
            std::thread::sleep(std::time::Duration::from_millis(100));
            harness.step();
            waited += 1;
            assert!(waited < 3000, "the export did not finish in 5 minutes");
        }
        let outcome = harness.state_mut().animation_export_mut().outcome().cloned();
        assert!(matches!(outcome, Some(Ok(_))), "{outcome:?}");
    };
    export(&mut harness, false, dir.path().join("frames"));
    export(&mut harness, true, dir.path().join("anim.gif"));
    // The CLI's frames for the window's settings at the chosen size.
    let mut s = harness.state().settings().clone();
    (s.render.width, s.render.height) = (96, 72);
    let mut cli = Vec::new();
    hairlab::cli::render::render_frames(&mut s, &[1, 2], &mut |_, image| {
        cli.push(image);
        Ok(())
    })
    .unwrap();
    let names: Vec<String> = {
        let mut n: Vec<String> = std::fs::read_dir(dir.path().join("frames"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    };
    assert_eq!(names, ["frame_0001.png", "frame_0002.png"]);
    for (name, expected) in names.iter().zip(&cli) {
        let bytes = std::fs::read(dir.path().join("frames").join(name)).unwrap();
        assert_eq!(
            image::load_from_memory(&bytes).unwrap().to_rgba8().dimensions(),
            (96, 72)
        );
        assert!(
            bytes == hairlab::io::encode_png(expected).unwrap(),
            "{name} differs from the CLI's frame"
        );
    }
    let gif = std::fs::read(dir.path().join("anim.gif")).unwrap();
    // The GIF as the export encoded it when it held every frame: all at once by the image crate.
    let mut whole = Vec::new();
    {
        use image::codecs::gif::{GifEncoder, Repeat};
        let mut encoder = GifEncoder::new_with_speed(&mut whole, 10);
        encoder.set_repeat(Repeat::Infinite).unwrap();
        let delay = image::Delay::from_numer_denom_ms(1000, s.motion.fps.round() as u32);
        encoder
            .encode_frames(
                cli.iter()
                    .map(|i| image::Frame::from_parts(i.clone(), 0, 0, delay)),
            )
            .unwrap();
    }
    assert!(
        gif == whole,
        "the window's GIF differs from the CLI's frames encoded whole"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "no temporary left beside the targets"
    );
}

/// An export cancelled from the job bar while a test gate holds it after its first frame: nothing appears at the
/// target (a PNG folder, then a GIF), and the temporary it was writing beside the target goes.
#[test]
fn a_cancelled_export_leaves_nothing_at_the_target() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = export_window();
    let dir = tempfile::tempdir().unwrap();
    let listing = || -> Vec<std::path::PathBuf> {
        std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect()
    };
    let gate = harness.state_mut().hold_jobs();
    for gif in [false, true] {
        let target = dir.path().join(if gif { "anim.gif" } else { "frames" });
        let e = harness.state_mut().animation_export_mut();
        (e.start, e.end, e.width, e.height, e.gif) = (0, 3, 64, 48, gif);
        e.path = target.display().to_string();
        harness.get_by_label("Export").click();
        harness.step();
        harness.step();
        let jobs = harness.state().jobs();
        assert_eq!(jobs.len(), 1, "{jobs:?}");
        assert_eq!(jobs[0].name, "animation export");
        // Held at its first step, after the first frame went into the temporary (a PNG sequence's first file).
        let mut waited = 0;
        loop {
            let partial = listing();
            let written = partial
                .iter()
                .any(|p| gif || p.is_dir() && std::fs::read_dir(p).unwrap().next().is_some());
            if written {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
            waited += 1;
            assert!(waited < 3000, "no frame written in 5 minutes: {partial:?}");
        }
        assert!(!target.exists(), "nothing at the target while it runs");
        harness.get_by_label("Cancel").click();
        harness.step();
        let e = harness.state_mut().animation_export_mut();
        assert!(!e.is_running());
        let outcome = e.outcome().cloned();
        assert!(
            matches!(&outcome, Some(Ok(m)) if m.contains("cancelled")),
            "{outcome:?}"
        );
        // The worker stops at the gate and removes its temporary.
        let mut waited = 0;
        while !listing().is_empty() {
            std::thread::sleep(std::time::Duration::from_millis(50));
            waited += 1;
            assert!(waited < 1200, "left behind: {:?}", listing());
        }
        assert!(!target.exists());
    }
    drop(gate);
}
