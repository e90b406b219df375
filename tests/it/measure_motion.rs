//! `measure --motion` (`hairlab::measure::motion`): a motion that does not move gives no flicker, pop or image
//! flicker for any method and the same errors every frame (the reference and the method are compared on the same
//! frame, point by point); the CLI writes the two CSV files whole with their stated columns and refuses a preset
//! without motion in one line.

use crate::common::cli::{assert_fails, hairlab, interrupt_once_written, stderr};
use hairlab::gpu::Gpu;
use hairlab::measure::motion::{MotionConfig, MotionOptions, measure_motion};
use hairlab::measure::temporal::{FollowedPoint, followed_pops};
use hairlab::methods::LightMethod;
use hairlab::methods::bom::Bom;
use hairlab::methods::dom::Dom;
use hairlab::methods::occupancy::Occupancy;
use hairlab::methods::osm::Osm;
use hairlab::scene::hair::{HairFile, write_hair_file};
use hairlab::settings::Settings;

const SMALL: [&str; 3] = [
    "scene.generator.strands=300",
    "scene.generator.segments=12",
    "render.map_resolution=128",
];

#[test]
fn a_motion_that_does_not_move_has_no_flicker_and_the_same_errors_every_frame() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let small: Vec<String> = SMALL.iter().map(|s| s.to_string()).collect();
    let strands = Settings::load_preset("default", &small)
        .unwrap()
        .scene
        .build()
        .unwrap()
        .strands;
    let dir = tempfile::tempdir().unwrap();
    for k in 0..3 {
        write_hair_file(
            &dir.path().join(format!("f{k}.hair")),
            &HairFile::from_strands(&strands, "test").unwrap(),
        )
        .unwrap();
    }
    let mut set = small.clone();
    set.push("motion.source=sequence".to_string());
    set.push(format!("motion.path={}", dir.path().display()));
    let settings = Settings::load_preset("default", &set).unwrap();
    let configs: Vec<MotionConfig> = [
        format!("{}:slices=16", Osm.name()),
        format!("{}:layers=3", Dom.name()),
        format!("{}:layers=4,split_ratio=auto-per-frame", Bom.name()),
        Occupancy.name().to_string(),
    ]
    .iter()
    .map(|c| MotionConfig::parse(c).unwrap())
    .collect();
    // Strand 0's middle segment (12 segments: points 0..=12), followed.
    let options = MotionOptions {
        follow: Some(FollowedPoint { first: 6, t: 0.5 }),
        after_each: None,
    };
    let m = measure_motion(
        &gpu,
        &settings,
        &configs,
        3,
        options,
        &mut hairlab::progress::Quiet,
    )
    .unwrap();
    let (_, reference) = m.followed.clone().expect("the followed point's series");
    assert_eq!(reference.len(), 3);
    assert!(reference.iter().all(|v| *v == reference[0]), "{reference:?}");
    for r in &m.rows {
        let label = r.config.label();
        assert!(
            r.followed.len() == 3 && r.followed.iter().all(|v| *v == r.followed[0]),
            "{label}: the followed point's V moves in a still motion: {:?}",
            r.followed
        );
        assert!(followed_pops(&r.followed, &reference).is_empty());
    }
    for r in &m.rows {
        let label = r.config.label();
        let f = &r.flicker;
        assert!(
            r.frames.iter().all(|x| x.tracked_points > 1000),
            "{label}: tracked points {:?}",
            r.frames
        );
        assert_eq!(
            f.points,
            2 * r.frames[0].tracked_points,
            "{label}: every point is tracked in both frames"
        );
        assert_eq!(
            (f.mean, f.p99, f.pop_rate, f.max_pop, r.image_flicker),
            (0.0, 0.0, 0.0, 0.0, 0.0),
            "{label}: a still motion flickers"
        );
        // The errors are the method's, not zero, and the same bits every frame.
        assert!(
            r.map_error.mean > 1e-3 && r.shading_error.mean > 1e-3 && r.image_flip > 0.0,
            "{label}: {r:?}"
        );
        for x in &r.frames[1..] {
            assert_eq!(
                (x.map_error, x.shading_error, x.image_flip),
                (
                    r.frames[0].map_error,
                    r.frames[0].shading_error,
                    r.frames[0].image_flip
                ),
                "{label} frame {}",
                x.frame
            );
        }
    }
}

#[test]
fn the_cli_writes_both_csv_files_and_refuses_a_still_preset_in_one_line() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().to_str().unwrap();
    let (dom3, occ) = (format!("{}:layers=3", Dom.name()), Occupancy.name().to_string());
    let o = hairlab(&[
        "measure",
        "--motion",
        "--preset",
        "stray-sweep",
        "--set",
        "scene.generator.strands=200",
        "--set",
        "render.map_resolution=64",
        "--frames",
        "3",
        "--config",
        &dom3,
        "--config",
        &occ,
        "--out",
        dir,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |name: &str| std::fs::read_to_string(out.path().join(name)).unwrap();
    let summary = read("motion_summary.csv");
    let lines: Vec<&str> = summary.lines().collect();
    assert_eq!(
        lines[0],
        "config,map_error,shading_error,flicker,flicker_p99,pop_rate,max_pop,image_flicker,gpu_ms,image_flip"
    );
    assert_eq!(lines.len(), 3, "{summary}");
    assert!(lines[1].starts_with(&format!("{dom3},")) && lines[2].starts_with(&format!("{occ},")));
    let frames = read("motion_frames.csv");
    let lines: Vec<&str> = frames.lines().collect();
    assert_eq!(
        lines[0],
        "config,frame,map_error,shading_error,tracked_points,flicker,flicker_p99,pop_rate,max_pop,image_flicker,gpu_ms,image_flip"
    );
    assert_eq!(lines.len(), 1 + 2 * 3, "{frames}");
    // Frame 0 has no pair before it: its flicker columns are empty.
    assert!(
        lines[1].starts_with(&format!("{dom3},0,")) && lines[1].contains(",,,,,"),
        "{}",
        lines[1]
    );
    // Only the two files, no temporary left behind.
    assert_eq!(std::fs::read_dir(out.path()).unwrap().count(), 2);

    let o = hairlab(&["measure", "--motion", "--preset", "patch", "--out", dir]);
    assert_fails(&o, &["no motion"]);
    let o = hairlab(&[
        "measure",
        "--motion",
        "--preset",
        "stray-sweep",
        "--frames",
        "1",
        "--out",
        dir,
    ]);
    assert_fails(&o, &["--frames 1"]);
}

/// `measure motion --point FIRST:T` writes `motion_point.csv` (a row per configuration and frame, the pop empty
/// in frame 0) beside the other two files; a point that starts no segment is one clear error.
#[test]
fn the_cli_follows_one_point_and_refuses_a_point_off_the_strands() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().to_str().unwrap();
    let dom3 = format!("{}:layers=3", Dom.name());
    let args = |point: &'static str| {
        vec![
            "measure".to_string(),
            "motion".into(),
            "--preset".into(),
            "wind".into(),
            "--set".into(),
            "scene.generator.strands=100".into(),
            "--set".into(),
            "render.map_resolution=64".into(),
            "--frames".into(),
            "3".into(),
            "--config".into(),
            dom3.clone(),
            "--point".into(),
            point.into(),
            "--out".into(),
            dir.into(),
        ]
    };
    let run = |a: Vec<String>| hairlab(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let o = run(args("5:0.25"));
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.path().join("motion_point.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "config,frame,v,reference,pop");
    assert_eq!(lines.len(), 1 + 3, "{csv}");
    assert!(
        lines[1].starts_with(&format!("{dom3},0,")) && lines[1].ends_with(','),
        "{}",
        lines[1]
    );
    assert!(!lines[2].ends_with(','), "frame 1 has a pop: {}", lines[2]);
    assert_eq!(std::fs::read_dir(out.path()).unwrap().count(), 3);
    let o = run(args("99999999"));
    assert_fails(&o, &["point 99999999", "not the first point of a segment"]);
    let o = run(args("5:2"));
    assert_fails(&o, &["--point '5:2'", "[0, 1]"]);
}

/// `bench motion` charts GPU time against the chosen temporal metric with the Pareto front and writes the two
/// CSV files and the chart whole.
#[test]
fn bench_motion_writes_the_csv_files_and_the_chart() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().to_str().unwrap();
    let (dom3, osm16) = (
        format!("{}:layers=3", Dom.name()),
        format!("{}:slices=16", Osm.name()),
    );
    let o = hairlab(&[
        "bench",
        "motion",
        "--preset",
        "wind",
        "--set",
        "scene.generator.strands=100",
        "--set",
        "render.map_resolution=64",
        "--frames",
        "3",
        "--config",
        &dom3,
        "--config",
        &osm16,
        "--metric",
        "pop-rate",
        "--out",
        dir,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("Pareto front of GPU ms against pop_rate"),
        "{stdout}"
    );
    let mut names: Vec<String> = std::fs::read_dir(out.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "motion_frames.csv",
            "motion_speed_vs_pop_rate.png",
            "motion_speed_vs_pop_rate.svg",
            "motion_summary.csv"
        ]
    );
    let png = image::open(out.path().join("motion_speed_vs_pop_rate.png")).unwrap();
    assert_eq!((png.width(), png.height()), (1200, 800));
    let summary = std::fs::read_to_string(out.path().join("motion_summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 3, "{summary}");
}

/// Ctrl-C (SIGINT to the `hairlab` process) stops `measure motion` at the next frame, leaving the configuration
/// in progress out: motion_summary.csv and motion_frames.csv hold every finished configuration, whole and in order (a row each,
/// and a row per frame), and the run exits 130 saying how many.
#[test]
fn sigint_leaves_complete_motion_csvs_of_the_finished_configurations() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let frames = 6;
    let configs: Vec<String> = [4, 8, 16, 32, 64, 128]
        .iter()
        .map(|n| format!("{}:slices={n}", Osm.name()))
        .collect();
    let mut args: Vec<String> = [
        "measure",
        "motion",
        "--preset",
        "stray-sweep",
        "--set",
        "scene.generator.strands=200",
        "--set",
        "render.map_resolution=64",
        "--frames",
        &frames.to_string(),
        "--out",
        out.path().to_str().unwrap(),
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for c in &configs {
        args.extend(["--config".to_string(), c.clone()]);
    }
    // The first configuration's rows are written; then Ctrl-C.
    let o = interrupt_once_written(&args, &out.path().join("motion_summary.csv"));
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    let rows = |name: &str| -> Vec<Vec<String>> {
        let mut r = csv::Reader::from_path(out.path().join(name)).unwrap();
        let width = r.headers().unwrap().len();
        r.records()
            .map(|rec| {
                let rec = rec.unwrap();
                assert_eq!(rec.len(), width, "{name}: a whole row: {rec:?}");
                rec.iter().map(str::to_string).collect()
            })
            .collect()
    };
    let done = rows("motion_summary.csv");
    assert!(
        !done.is_empty() && done.len() < configs.len(),
        "stopped before the last configuration: {done:?}"
    );
    for (r, expected) in done.iter().zip(&configs) {
        assert_eq!(&r[0], expected);
        let error: f64 = r[1].parse().unwrap();
        assert!(error.is_finite() && error > 0.0, "{r:?}");
    }
    let frame_rows = rows("motion_frames.csv");
    assert_eq!(
        frame_rows.len(),
        done.len() * frames,
        "a row per finished configuration and frame"
    );
    for (i, r) in frame_rows.iter().enumerate() {
        assert_eq!(&r[0], &configs[i / frames]);
        assert_eq!(r[1], (i % frames).to_string());
    }
    let errors = crate::common::cli::error_lines(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("interrupted")
            && errors[0].contains(&format!("after {} configurations", done.len())),
        "{errors:?}"
    );
}
