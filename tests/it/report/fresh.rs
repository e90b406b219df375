//! A fresh report of a small study: every section and each table equal to its CSV (and `--from` its folders the
//! same), a consistent page of what finished after Ctrl-C, and the window's Export report….

use super::{assert_self_contained, csv_file, page, sections, select, table};
use crate::common::cli::{hairlab, stderr};
use hairlab::gpu::Gpu;
use scraper::Html;

/// A small study: the stray-sweep scene at 300 strands of 12 segments (3,600 segments), a 128² map, a 320×240
/// view, two methods, two transparency techniques, two motion frames.
const SMALL: &[&str] = &[
    "--preset",
    "stray-sweep",
    "--set",
    "scene.generator.strands=300",
    "--set",
    "scene.generator.segments=12",
    "--set",
    "render.map_resolution=128",
    "--set",
    "render.width=320",
    "--set",
    "render.height=240",
    "--config",
    "dom:layers=3",
    "--config",
    "occupancy",
    "--technique",
    "occupancy-order",
    "--technique",
    "weighted-average",
    "--frames",
    "1",
];

const SECTIONS: [&str; 7] = [
    "scene",
    "machine",
    "speed-accuracy",
    "configurations",
    "transparency",
    "motion",
    "claims",
];

/// A fresh report of the small study with its motion: every section, each table equal to its CSV, the page
/// self-contained; then `--from` its three data folders gives the same tables and sections (the command line
/// aside).
#[test]
fn a_fresh_report_has_every_section_its_tables_equal_the_csv_and_from_gives_the_same() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("r");
    let mut args = vec!["report"];
    args.extend_from_slice(SMALL);
    args.extend(["--motion", "--out", out.to_str().unwrap()]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_self_contained(&out);
    let html = page(&out);
    assert_eq!(sections(&html), SECTIONS);
    for (id, csv) in [
        ("results", "data/shadows/results.csv"),
        ("transparency", "data/transparency/transparency.csv"),
        ("motion", "data/motion/motion_summary.csv"),
    ] {
        let (header, rows) = csv_file(&out.join(csv));
        assert_eq!(table(&html, id), (header, rows.clone()), "{id}");
        assert_eq!(rows.len(), 2, "{id}: two configurations");
    }
    let claims: Vec<String> = select(&html, "table#claims tbody th")
        .iter()
        .map(|c| c.text().collect())
        .collect();
    assert_eq!(claims, ["MC-1", "TC-1"]);
    let command: String = select(&html, "#machine code")[0].text().collect();
    assert!(
        command.contains("report --preset stray-sweep") && command.contains("--motion"),
        "{command}"
    );

    let again = tmp.path().join("again");
    let o = hairlab(&[
        "report",
        "--from",
        out.join("data/shadows").to_str().unwrap(),
        "--from",
        out.join("data/transparency").to_str().unwrap(),
        "--from",
        out.join("data/motion").to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_self_contained(&again);
    let from = page(&again);
    // No thumbnail and no light without a fresh run, but the scene's figures from results.json and the
    // histogram.
    assert_eq!(sections(&from), SECTIONS);
    for id in ["results", "transparency", "motion", "claims"] {
        assert_eq!(table(&from, id), table(&html, id), "{id}");
    }
    let srcs = |html: &Html, css: &str| -> Vec<String> {
        select(html, css)
            .iter()
            .map(|i| i.value().attr("src").unwrap().to_string())
            .collect()
    };
    assert_eq!(
        srcs(&html, "#scene img"),
        ["scene.png", "data/shadows/depth_complexity.svg"]
    );
    assert_eq!(srcs(&from, "#scene img"), ["data/shadows/depth_complexity.svg"]);
    // Per configuration: its image, the reference, the difference, FLIP and V(z) at its 3 worst texels.
    let configurations = srcs(&html, "#configurations img");
    assert_eq!(configurations.len(), 2 * 7, "{configurations:?}");
    assert_eq!(srcs(&from, "#configurations img"), configurations);
    // Motion: the per-frame chart, then each configuration's animation beside the reference's.
    let motion = srcs(&html, "#motion img");
    assert_eq!(
        motion,
        [
            "data/motion/motion_map_error_per_frame.svg",
            "data/motion/animations/0.gif",
            "data/motion/animations/reference.gif",
            "data/motion/animations/1.gif",
            "data/motion/animations/reference.gif",
        ]
    );
    assert_eq!(srcs(&from, "#motion img"), motion);
    // Transparency: the chart, then the Fig. 2 rows: the reference and each technique's image, the
    // differences, the FLIP maps.
    let images = "data/transparency/images";
    let mut expected = vec![
        "data/transparency/transparency_speed_vs_accuracy.svg".to_string(),
        format!("{images}/reference.png"),
    ];
    for suffix in ["", "_difference", "_flip"] {
        for k in 0..2 {
            expected.push(format!("{images}/{k}{suffix}.png"));
        }
    }
    assert_eq!(srcs(&html, "#transparency img"), expected);
    assert_eq!(srcs(&from, "#transparency img"), srcs(&html, "#transparency img"));
}

/// Ctrl-C once the first configuration's row is written: the run stops after the configuration in progress
/// (exit code 130) and the page holds what finished: the shadow methods' rows so far (fewer than asked), equal to
/// their CSV, and no section of the parts never started; no draft folder is left beside it.
#[test]
fn ctrl_c_writes_a_consistent_page_of_what_finished() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("r");
    let mut args: Vec<&str> = vec!["report"];
    args.extend_from_slice(SMALL);
    args.extend(["--config", "osm:slices=16", "--config", "dom:layers=4"]);
    args.extend(["--motion", "--out", out.to_str().unwrap()]);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args(&args)
        .env("RUST_LOG", "warn")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    let first_row_written = || {
        std::fs::read_dir(tmp.path()).unwrap().any(|e| {
            let p = e.unwrap().path();
            p.join("data/shadows/results.csv").is_file()
        })
    };
    while !first_row_written() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the report ended before its first row"
        );
        assert!(start.elapsed().as_secs() < 300, "no row after 5 minutes");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert_self_contained(&out);
    let html = page(&out);
    assert_eq!(sections(&html), ["scene", "machine", "speed-accuracy"]);
    let (header, rows) = csv_file(&out.join("data/shadows/results.csv"));
    assert!(
        !rows.is_empty() && rows.len() < 4,
        "stopped after the configuration in progress: {rows:?}"
    );
    assert_eq!(table(&html, "results"), (header, rows));
    let names: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["r"], "a draft left behind");
}

/// The Bench window's **Export report…**: the page of the window's scene, method and technique, written by a job
/// into `hairlab-report/` of the folder, with the window's settings beside it and the command that reproduces
/// it from them.
#[test]
fn the_window_exports_a_report_of_its_scene_and_selection() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = hairlab::settings::Settings::load_preset(
        "stray-strand",
        &[
            "scene.generator.strands=300".into(),
            "scene.generator.segments=12".into(),
            "render.map_resolution=128".into(),
            "render.width=320".into(),
            "render.height=240".into(),
            "method.name=dom".into(),
        ],
    )
    .unwrap();
    let mut harness = egui_kittest::Harness::builder()
        .with_size([1200.0, 900.0])
        .wgpu_setup(hairlab::app::wgpu_setup(
            hairlab::gpu::AdapterPreference::Software,
        ))
        .build_eframe(move |cc| hairlab::app::HairlabApp::new(cc, Some(settings)));
    harness.run();
    use egui_kittest::kittest::Queryable;
    harness.get_by_label("Bench").click();
    harness.run();
    let export = tempfile::tempdir().unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    harness.get_by_label("Export report…").click();
    harness.step();
    let start = std::time::Instant::now();
    let wrote = |h: &egui_kittest::Harness<'_, hairlab::app::HairlabApp>| {
        h.state()
            .message()
            .is_some_and(|(m, _)| m.starts_with("report: wrote"))
    };
    while !wrote(&harness) {
        let message = harness.state().message().map(|(m, e)| (m.to_string(), e));
        assert!(!message.as_ref().is_some_and(|(_, e)| *e), "{message:?}");
        assert!(
            start.elapsed().as_secs() < 300,
            "no report after 5 minutes: {message:?}"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
        harness.step();
    }
    let out = export.path().join("hairlab-report");
    assert_self_contained(&out);
    let html = page(&out);
    assert_eq!(
        sections(&html),
        [
            "scene",
            "machine",
            "speed-accuracy",
            "configurations",
            "transparency"
        ]
    );
    let (header, rows) = csv_file(&out.join("data/shadows/results.csv"));
    assert_eq!(table(&html, "results"), (header, rows.clone()));
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0][2], "dom");
    let command: String = select(&html, "#machine code")[0].text().collect();
    let toml = out.join("settings.toml");
    assert!(
        command.starts_with(&format!(
            "hairlab report --preset {} --config dom --technique",
            toml.display()
        )),
        "{command}"
    );
    let saved = hairlab::settings::Settings::load_preset(toml.to_str().unwrap(), &[]).unwrap();
    assert_eq!(saved.method.name, "dom");
    assert_eq!(saved.scene.generator.strands, 300);
}
