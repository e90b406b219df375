//! The Bench window driven headless: a run, a point clicked, its configuration applied.

use super::{column, read_csv};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::HairlabApp;
use hairlab::gpu::Gpu;
use hairlab::settings::Settings;

#[test]
fn bench_window_runs_and_a_clicked_point_becomes_the_method() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = Settings::load_preset(
        "default",
        &[
            "scene.generator.strands=200".into(),
            "render.map_resolution=64".into(),
            "render.width=160".into(),
            "render.height=120".into(),
            "method.name=opaque-shadow-map".into(),
        ],
    )
    .unwrap();
    let mut harness = crate::common::snapshot_harness(settings, [1200.0, 900.0]);
    crate::common::bench_window_on_osm(&mut harness);
    harness.get_by_label("Run bench").click();
    harness.step();
    assert!(harness.state().bench_running());
    let start = std::time::Instant::now();
    while harness.state().bench_running() {
        assert!(start.elapsed().as_secs() < 300, "the bench did not finish");
        std::thread::sleep(std::time::Duration::from_millis(50));
        harness.step();
    }
    harness.run();
    let result = harness.state().bench_result().expect("a result").clone();
    assert!(!result.is_stopped());
    let labels: Vec<String> = result.rows.iter().map(|r| r.config.label()).collect();
    let osm = hairlab::methods::registry::find("osm").unwrap();
    assert_eq!(labels.len(), osm.sweep().len(), "{labels:?}");
    assert!(labels.iter().all(|l| l.starts_with("osm:slices=")), "{labels:?}");
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, e)| !e && m.contains("7 configurations")),
        "{:?}",
        harness.state().message()
    );

    // Export: the files `hairlab bench` writes, into a folder set in place of the dialog.
    let export = tempfile::tempdir().unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    harness.get_by_label("Export results…").click();
    harness.run();
    let (header, rows) = read_csv(&export.path().join("results.csv"));
    let exported: Vec<&String> = rows.iter().map(|r| &r[column(&header, "label")]).collect();
    assert_eq!(exported, labels.iter().collect::<Vec<_>>());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(export.path().join("results.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(labels.len()));
    let png = image::open(export.path().join("speed_vs_accuracy.png")).unwrap();
    assert_eq!((png.width(), png.height()), hairlab::bench::CHART_SIZE);
    let svg = std::fs::read_to_string(export.path().join("speed_vs_accuracy.svg")).unwrap();
    assert!(
        svg.contains("<svg") && svg.trim_end().ends_with("</svg>"),
        "not an SVG document"
    );
    // Copies: the table as the exported CSV's text, the chart as an image of the exported PNG's size.
    let copied = |harness: &mut Harness<'_, HairlabApp>, button: &str| {
        harness.get_by_label(button).click();
        harness.step();
        harness.output().platform_output.commands.clone()
    };
    let text = copied(&mut harness, "Copy table")
        .into_iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyText(t) => Some(t),
            _ => None,
        })
        .expect("the table copied");
    assert_eq!(
        text,
        std::fs::read_to_string(export.path().join("results.csv")).unwrap()
    );
    let image = copied(&mut harness, "Copy chart")
        .into_iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyImage(i) => Some(i),
            _ => None,
        })
        .expect("the chart copied");
    assert_eq!(image.size, [png.width() as usize, png.height() as usize]);
    harness.run();

    // Click the 64-slice point: the app now uses OSM with 64 slices.
    let pos = harness.state().bench_point_position(4).expect("point drawn");
    harness.hover_at(pos);
    harness.step();
    harness.drag_at(pos);
    harness.step();
    harness.drop_at(pos);
    harness.run();
    let method = &harness.state().settings().method;
    assert_eq!(method.name, "osm");
    assert_eq!(method.params.get("slices"), Some(&64.0));
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, _)| m.contains("applied osm:slices=64")),
        "{:?}",
        harness.state().message()
    );
}
