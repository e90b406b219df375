//! The real workbench app driven headless by egui_kittest on the software adapter: it shows the scene, reacts to
//! a parameter change through the UI, saves a screenshot without a dialog, and matches a UI snapshot; the eye
//! transparency section, the compare view and the pixel inspector.

use crate::common;

use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::{Harness, SnapshotOptions};
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::{AdapterPreference, Gpu};
use hairlab::render::transparency::registry as techniques;
use hairlab::scene::LightFit;
use hairlab::scene::generate::HairStyle;

#[test]
fn workbench_headless() {
    // Fails with what to install when there is no adapter (or skips on explicit request).
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = common::small_settings(320, 240);
    let mut harness = crate::common::snapshot_harness(settings, [1000.0, 640.0]);
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
    let settings = common::small_settings(320, 240);
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

/// The Render section's shading selector offers every strand shading model and switches `render.shading`.
#[test]
fn render_section_switches_the_shading_model() {
    use hairlab::shading::ShadingModel;
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = tall_harness();
    harness.run();
    assert_eq!(harness.state().settings().render.shading, ShadingModel::KajiyaKay);
    harness.get_by_label("shading").click();
    harness.run();
    for model in ShadingModel::ALL {
        assert!(
            harness.query_all_by_label(model.label()).next().is_some(),
            "{} is not offered",
            model.word()
        );
    }
    harness.get_by_label(ShadingModel::Marschner.label()).click();
    harness.run();
    assert_eq!(harness.state().settings().render.shading, ShadingModel::Marschner);
}

#[test]
fn transparency_section_lists_every_technique_and_switches_it() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = tall_harness();
    harness.run();
    open_transparency_section(&mut harness);
    let before = harness.state().settings().transparency.name.clone();
    harness.get_by_label("technique").click();
    harness.run();
    // Every registered technique is offered (the current one is also the combo's text).
    for t in techniques::all() {
        assert!(
            harness.query_all_by_label(t.info().label).next().is_some(),
            "{} is not offered",
            t.name()
        );
    }
    let other = techniques::all()
        .iter()
        .find(|t| t.name() != before)
        .expect("a second technique");
    harness.get_by_label(other.info().label).click();
    harness.run();
    assert_eq!(harness.state().settings().transparency.name, other.name());
    // Its paper is shown under the combo, and the held technique's cost once the viewport rendered it.
    assert!(harness.query_by_label(other.info().paper).is_some());
    assert!(
        harness
            .query_by_label_contains(&format!("held: {} · ", other.name()))
            .is_some()
    );
}

#[test]
fn compare_view_renders_four_labelled_images_and_their_metrics() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = tall_harness();
    harness.run();
    open_compare(&mut harness);
    let app = harness.state();
    let frames = app.compare().frames().expect("compare frames rendered");
    assert_eq!(frames.images.len(), 4);
    assert_eq!(frames.images[0].name, techniques::reference().name());
    assert_eq!(frames.images[1].name, app.settings().transparency.name);
    assert_eq!(frames.lists.len(), (frames.width * frames.height) as usize);
    let hair = frames.hair.iter().filter(|&&h| h).count();
    assert!(hair > 500, "only {hair} hair pixels");
    for (i, img) in frames.images.iter().enumerate() {
        assert_eq!(img.image.dimensions(), (frames.width, frames.height));
        assert!(app.compare().image_rect(i).is_some(), "image {i} not drawn");
        // Outside the hair every technique shows the opaque image alone.
        let differ = img
            .image
            .pixels()
            .zip(frames.images[0].image.pixels())
            .zip(&frames.hair)
            .filter(|((p, q), h)| !**h && p != q)
            .count();
        assert_eq!(
            differ, 0,
            "{}: pixels without hair differ from the reference",
            img.name
        );
    }
    // Four captions, each naming its technique and its GPU time (or why there is none).
    let captions: Vec<String> = harness
        .query_all_by_label_contains(" — GPU")
        .map(|n| n.accesskit_node().value().unwrap_or_default())
        .collect();
    assert_eq!(captions.len(), 4, "{captions:?}");
    for (c, img) in captions.iter().zip(&frames.images) {
        assert!(c.starts_with(&format!("{} — GPU", img.label)), "{c}");
    }
    // The metrics of the selected technique against the reference: a real difference on the hair.
    let m = &frames.images[1].metrics;
    assert!(m.rmse_hair > 0.0 && m.rmse_hair > m.rmse, "{m:?}");
    assert!(harness.query_by_label("RMSE hair").is_some());
    assert!(harness.query_by_label("contrast retention").is_some());
    // FLIP beside them: the hair differs, so its hair mean is above the all-pixel one (no difference elsewhere).
    assert!(m.flip.mean_hair > m.flip.mean && m.flip.mean > 0.0, "{m:?}");
    assert!(harness.query_by_label("FLIP hair").is_some());
    // The FLIP map in place of the difference.
    let caption = format!(
        "FLIP of {} against {}",
        frames.images[1].label, frames.images[0].label
    );
    harness.get_by_label("FLIP map").click();
    harness.run();
    assert!(harness.state().compare().flip_map);
    harness.get_by_label_contains(&caption);

    // Export: every image, the difference and FLIP maps and metrics.csv, into a folder set in place of the dialog.
    let export = tempfile::tempdir().unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    harness.get_by_label("Export images…").click();
    harness.run();
    let frames = harness.state().compare().frames().unwrap();
    let open = |name: String| image::open(export.path().join(name)).unwrap().to_rgba8();
    for (i, img) in frames.images.iter().enumerate() {
        let k = i + 1;
        assert!(
            open(format!("{k}_{}.png", img.name)) == img.image,
            "image {k} written as shown"
        );
        if i > 0 {
            for map in ["difference", "flip"] {
                let written = open(format!("{map}_{k}_{}.png", img.name));
                assert_eq!(written.dimensions(), (frames.width, frames.height), "{map} {k}");
            }
        }
    }
    let mut csv = csv::Reader::from_path(export.path().join("metrics.csv")).unwrap();
    let header = csv.headers().unwrap().clone();
    assert_eq!(
        &header.iter().take(4).collect::<Vec<_>>(),
        &["slot", "technique", "label", "rmse"]
    );
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = csv.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 3);
    for (r, img) in rows.iter().zip(&frames.images[1..]) {
        assert_eq!(&r[column("technique")], img.name);
        assert_eq!(
            r[column("rmse_hair")].parse::<f64>().unwrap(),
            img.metrics.rmse_hair
        );
        assert_eq!(
            r[column("flip_hair")].parse::<f64>().unwrap(),
            img.metrics.flip.mean_hair
        );
    }
}

#[test]
fn pixel_inspector_shows_the_list_of_a_clicked_hair_pixel() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = tall_harness();
    harness.run();
    open_compare(&mut harness);
    // The hair pixel with the most fragments, clicked in the reference image.
    let app = harness.state();
    let frames = app.compare().frames().expect("compare frames rendered");
    let (index, list) = frames
        .lists
        .iter()
        .enumerate()
        .max_by_key(|(_, l)| l.len())
        .unwrap();
    let expected = list.clone();
    let (w, h) = (frames.width, frames.height);
    let pixel = [index as u32 % w, index as u32 / w];
    let rect = app.compare().image_rect(0).expect("reference image drawn");
    let pos = rect.min
        + egui::vec2(
            (pixel[0] as f32 + 0.5) * rect.width() / w as f32,
            (pixel[1] as f32 + 0.5) * rect.height() / h as f32,
        );
    let gpu_reference = frames.images[0].image.get_pixel(pixel[0], pixel[1]).0;
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
    let report = app.pixel_inspector().report().expect("a report of the pixel");
    assert_eq!(report.fragments, expected);
    assert!(
        expected.len() >= 2,
        "deepest pixel holds {} fragments",
        expected.len()
    );
    assert!(expected.windows(2).all(|p| p[0].depth <= p[1].depth));
    // The transmittance behind the last fragment is the product of (1 - a), in f64 here.
    let through: f64 = expected.iter().map(|f| 1.0 - f64::from(f.alpha)).product();
    assert!((f64::from(*report.transmittance.last().unwrap()) - through).abs() < 1e-5);
    // The exact model's colour, sRGB encoded, is the GPU reference's pixel (8-bit rounding of both, and of the
    // background the model is fed).
    let encoded: egui::Color32 =
        egui::Rgba::from_rgb(report.reference[0], report.reference[1], report.reference[2]).into();
    for (c, g) in [encoded.r(), encoded.g(), encoded.b()].iter().zip(gpu_reference) {
        assert!(
            c.abs_diff(g) <= 2,
            "CPU exact {encoded:?} vs GPU {gpu_reference:?}"
        );
    }
    assert_eq!(report.composites.len(), techniques::all().len());
    let reference = &report.composites[0];
    assert_eq!(
        (reference.name, reference.delta),
        (techniques::reference().name(), 0.0)
    );
    let title = format!(
        "pixel ({}, {}) · {} fragments",
        pixel[0],
        pixel[1],
        expected.len()
    );
    assert!(harness.query_by_label(&title).is_some(), "{title} not shown");

    // The fragment table and the plot leave the window: pixel.csv and the plot's PNG into a folder set in place
    // of the dialog, and the table's text copied to the clipboard.
    let export = tempfile::tempdir().unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    harness.get_by_label("Export table and plot…").click();
    harness.run();
    let plot = image::open(export.path().join("pixel_transmittance.png")).unwrap();
    assert_eq!((plot.width(), plot.height()), hairlab::bench::CHART_SIZE);
    let text = std::fs::read_to_string(export.path().join("pixel.csv")).unwrap();
    let mut lines = text.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("rank,depth,segment,alpha,r,g,b,transmittance,weight")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), expected.len());
    for (k, (r, f)) in rows.iter().zip(&expected).enumerate() {
        assert_eq!(r[0], k.to_string());
        assert_eq!(r[1].parse::<f32>().unwrap(), f.depth);
        assert_eq!(r[2], f.segment.to_string());
    }
    harness.get_by_label("Copy table").click();
    harness.step();
    let copied = harness
        .output()
        .platform_output
        .commands
        .iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyText(t) => Some(t.clone()),
            _ => None,
        })
        .expect("the table copied");
    assert_eq!(copied, text);
}

/// The Fur section of a fur preset: its mode switches the shell on and off, and the paper's Table 1 for the
/// frame is shown, row by row.
#[test]
fn fur_section_switches_the_mode_and_shows_table_1() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = hairlab::settings::Settings::load_preset(
        "fur-cylinder",
        &[
            "render.width=160".into(),
            "render.height=120".into(),
            "scene.generator.strands=200".into(),
            "fur.layers=4".into(),
            "fur.max_level=2".into(),
            "fur.max_steps=48".into(),
            // Far away: the viewport is the window's size, and a small cylinder keeps lavapipe's march short.
            "camera.distance=4".into(),
        ],
    )
    .unwrap();
    let mut harness = Harness::builder()
        .with_size([1400.0, 1800.0])
        .with_max_steps(8)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    // The section opens by itself when the preset has fur; the frame drawn, Table 1 lists every row.
    harness.run();
    for row in hairlab::fur::table::TIME_ROWS
        .iter()
        .chain(&hairlab::fur::table::MEMORY_ROWS)
    {
        assert!(
            harness.query_all_by_label(row).next().is_some(),
            "no Table 1 row '{row}'"
        );
    }
    assert!(
        harness
            .query_by_label_contains("3584 triangles · 229376 sub-elements")
            .is_some()
    );
    harness.get_by_label("mode").click();
    harness.run();
    harness.get_by_label("implicit").click();
    harness.run();
    assert_eq!(
        harness.state().settings().fur.mode,
        hairlab::fur::settings::FurMode::Implicit
    );
}

/// Lets the undoer take its step: the settings stay unchanged for longer than its stable time (1 s; 8 steps of
/// the harness's 0.25 s).
fn settle(harness: &mut Harness<'_, HairlabApp>) {
    harness.run_steps(8);
}

#[test]
fn undo_and_redo_step_through_settings_changed_in_the_ui() {
    use egui::accesskit::Role;
    use egui_kittest::kittest::By;
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = tall_harness();
    harness.run();
    settle(&mut harness);
    let original = harness.state().settings().clone();
    let original_points = harness.state().scene().unwrap().strands.points.clone();
    assert!(!harness.state().can_undo());
    let mut states = vec![original.clone()];

    // A slider, moved by three arrow-key presses within the stable time: one step.
    harness.get_by_role_and_label(Role::Slider, "hair alpha").focus();
    harness.run();
    for _ in 0..3 {
        harness.key_press(egui::Key::ArrowRight);
        harness.run();
    }
    settle(&mut harness);
    assert!(harness.state().settings().render.hair_alpha > original.render.hair_alpha);
    states.push(harness.state().settings().clone());

    // A checkbox.
    harness.get_by_role_and_label(Role::CheckBox, "PCF 3×3").click();
    harness.run();
    settle(&mut harness);
    assert_ne!(harness.state().settings().render.pcf, original.render.pcf);
    states.push(harness.state().settings().clone());

    // A combo box.
    harness
        .get_by_role_and_label(Role::ComboBox, "map resolution")
        .click();
    harness.run();
    harness.get_by_label("128²").click();
    harness.run();
    settle(&mut harness);
    assert_eq!(harness.state().settings().render.map_resolution, 128);
    states.push(harness.state().settings().clone());

    // A scene setting: the scene is rebuilt with straight hair.
    harness.get_by_label("straight").click();
    harness.run();
    settle(&mut harness);
    assert_ne!(harness.state().scene().unwrap().strands.points, original_points);
    states.push(harness.state().settings().clone());
    for w in states.windows(2) {
        assert_ne!(w[0], w[1]);
    }
    let last = states.len() - 1;

    // Ctrl+Z, step by step back to the original settings (and scene).
    for i in (0..last).rev() {
        assert!(harness.state().can_undo());
        harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
        harness.run();
        assert_eq!(
            harness.state().settings(),
            &states[i],
            "after undoing to step {i}"
        );
    }
    assert!(!harness.state().can_undo());
    assert_eq!(harness.state().settings(), &original);
    assert_eq!(harness.state().scene().unwrap().strands.points, original_points);

    // Ctrl+Shift+Z forward to the final settings.
    for (i, state) in states.iter().enumerate().skip(1) {
        assert!(harness.state().can_redo());
        harness.key_press_modifiers(egui::Modifiers::COMMAND | egui::Modifiers::SHIFT, egui::Key::Z);
        harness.run();
        assert_eq!(harness.state().settings(), state, "after redoing to step {i}");
    }
    assert!(!harness.state().can_redo());
    assert_eq!(harness.state().settings(), &states[last]);
    assert_eq!(
        harness.state().settings().scene.generator.style,
        HairStyle::Straight
    );

    // The Undo button, then Ctrl+Y.
    harness.get_by_label("Undo").click();
    harness.run();
    assert_eq!(harness.state().settings(), &states[last - 1]);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    harness.run();
    assert_eq!(harness.state().settings(), &states[last]);

    // A preset replaces every setting as one step.
    harness.get_by_label("Presets").click();
    harness.run();
    harness.get_by_label("stray-strand").click();
    harness.run();
    assert_ne!(harness.state().settings(), &states[last]);
    settle(&mut harness);
    let preset = harness.state().settings().clone();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run();
    assert_eq!(harness.state().settings(), &states[last]);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    harness.run();
    assert_eq!(harness.state().settings(), &preset);

    // F1 opens the Help window with the shortcuts.
    harness.key_press(egui::Key::F1);
    harness.run();
    assert!(
        harness
            .query(By::new().role(Role::Label).value("Ctrl+Shift+Z / Ctrl+Y"))
            .is_some()
    );
}

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

/// A method parameter's right-click menu resets it to its default; its tooltip states the default, the range,
/// the preset key and the paper.
#[test]
fn a_parameter_resets_to_its_default() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut settings = common::small_settings(160, 120);
    settings.method.name = "osm".into();
    settings.method.params.insert("slices".into(), 7.0);
    let method = hairlab::methods::registry::find("osm").unwrap();
    let spec = method.params().iter().find(|p| p.key == "slices").unwrap();
    let default = spec.default;
    // Tall enough that the method's slider stays in view below the Light section's selectors.
    let mut harness = Harness::builder()
        .with_size([1000.0, 1400.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    let slider = || egui::accesskit::Role::Slider;
    harness.get_by_role_and_label(slider(), spec.label).hover();
    harness.run();
    let tip = format!("default {}; whole numbers 1 to 256", default as i64);
    harness.get_by_label_contains(&tip);
    harness.get_by_label_contains(&format!(
        "method.params.slices (right-click: reset)\n{}",
        method.info().paper
    ));
    harness
        .get_by_role_and_label(slider(), spec.label)
        .click_secondary();
    harness.run();
    harness
        .get_by_label(&format!("Reset to default ({})", default as i64))
        .click();
    harness.run();
    assert_eq!(
        harness.state().settings().method.params.get("slices"),
        Some(&default)
    );
}

/// The About window opens from the Help window and from its button, shows hairlab's version and the adapter in
/// use, and the first method's "Copy BibTeX" puts that method's entry of `docs/citations.bib` on the clipboard (egui's copy command in the frame's output).
#[test]
fn about_window_shows_the_version_and_the_adapter_and_copies_a_bibtex_entry() {
    use egui::accesskit::Role;
    use egui_kittest::kittest::By;
    let Some(gpu) = Gpu::for_tests() else {
        return;
    };
    let adapter = hairlab::gpu::describe(&gpu.info);
    let mut harness = tall_harness();
    harness.run();
    let version = format!("hairlab {}", env!("CARGO_PKG_VERSION"));
    let shows_version =
        |h: &Harness<'_, HairlabApp>| h.query(By::new().role(Role::Label).value(&version)).is_some();
    // From the Help window (F1), then the About button next to Help closes and reopens it.
    harness.key_press(egui::Key::F1);
    harness.run();
    harness.get_by_label("About hairlab").click();
    harness.run();
    assert!(shows_version(&harness), "About hairlab in Help did not open it");
    harness.key_press(egui::Key::F1);
    harness.run();
    harness.get_by_role_and_label(Role::Button, "About").click();
    harness.run();
    assert!(!shows_version(&harness), "the About button did not close it");
    harness.get_by_role_and_label(Role::Button, "About").click();
    harness.run();
    for text in [version.clone(), format!("Adapter: {adapter}")] {
        assert!(
            harness.query(By::new().role(Role::Label).value(&text)).is_some(),
            "the About window does not show {text:?}"
        );
    }

    let bib = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/citations.bib"))
        .expect("docs/citations.bib");
    let first = hairlab::methods::registry::all()[0].name();
    let head = bib
        .lines()
        .find(|l| l.starts_with('@') && l.ends_with(&format!("{{{first},")))
        .unwrap_or_else(|| panic!("docs/citations.bib has no entry '{first}'"));
    harness
        .get_all_by_label("Copy BibTeX")
        .next()
        .expect("a Copy BibTeX button")
        .click();
    // The click lands in the next frame; collect every frame's copy commands until the output settles.
    let mut copied = Vec::new();
    for _ in 0..4 {
        harness.step();
        copied.extend(
            harness
                .output()
                .platform_output
                .commands
                .iter()
                .filter_map(|c| match c {
                    egui::OutputCommand::CopyText(text) => Some(text.clone()),
                    _ => None,
                }),
        );
    }
    assert_eq!(copied.len(), 1, "copied {copied:?}");
    assert!(
        copied[0].starts_with(head) && copied[0].ends_with('}'),
        "copied {:?}, expected the entry starting {head:?}",
        copied[0]
    );
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
/// `measure motion --point` computes for the same point; Cancel stops a run and keeps the figures shown.
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

/// A file dropped on the window, as the native integration hands it over.
#[derive(Debug)]
struct Dropped(std::path::PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &std::path::Path {
        &self.0
    }
    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// Issue 34: each malformed binary USD reproducer dropped on the window is refused in the status line by its file
/// name; the window lives on and the scene on screen stays.
#[test]
fn malformed_usdc_files_dropped_on_the_window_are_refused_by_name() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = small_window();
    assert!(harness.state().scene().is_some(), "scene loaded");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/usdc-malformed");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), 17, "the reproducers in {}", dir.display());
    let mut refused = 0;
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let before = harness.state().scene().unwrap().strands.clone();
        harness
            .input_mut()
            .dropped_files
            .push(std::sync::Arc::new(Dropped(file.clone())));
        harness.run();
        let app = harness.state();
        let scene = app.scene().expect("the window still has a scene");
        match app.message() {
            Some((m, true)) => {
                assert!(m.contains(&name), "{name}: the error does not name the file: {m}");
                assert!(!m.contains("panicked"), "{name}: {m}");
                assert!(scene.strands == before, "{name}: the previous scene stays");
                refused += 1;
            }
            // 05's corrupt tokens sit in a field hairlab never reads: it opens as an empty stage.
            other => assert!(name.starts_with("05-"), "{name}: not refused: {other:?}"),
        }
    }
    assert_eq!(refused, 16);
}
