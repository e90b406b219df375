//! The window: the scene shown, a generator parameter changed through the UI, a screenshot saved without a
//! dialog and a UI snapshot; the side panel's Render, Transparency and Fur sections, undo and redo, a parameter's
//! reset, the About window, and malformed files dropped on the window.

use super::{open_transparency_section, small_window, tall_harness};
use crate::common;
use egui_kittest::kittest::Queryable;
use egui_kittest::{Harness, SnapshotOptions};
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::{AdapterPreference, Gpu};
use hairlab::render::transparency::registry as techniques;
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

/// Under the fibres model with the path-traced probe the window does not stop for the probe's bake: a frame is
/// drawn while it bakes on another thread and the status line says so; once it is kept the frame is drawn again
/// with it and the line is gone.
#[test]
fn the_window_draws_while_the_traced_probe_bakes() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut settings = common::small_settings(320, 240);
    settings.render.hair_model = hairlab::shading::HairModel::Fibres;
    settings.render.probe = hairlab::shading::mesh_bounce::Probe::Traced;
    let mut harness = Harness::builder()
        .with_size([1000.0, 640.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    let baking = "path-traced probe: baking on the CPU, drawn meanwhile with the last one";
    let start = std::time::Instant::now();
    let mut seen = false;
    loop {
        harness.step();
        let shown = harness.query_all_by_label(baking).next().is_some();
        seen |= shown;
        if seen && !shown {
            break;
        }
        assert!(
            start.elapsed().as_secs() < 180,
            "after 180 s: the baking line {}",
            if seen { "still shown" } else { "never shown" }
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
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
