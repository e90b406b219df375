//! `hairlab report --from`: folders typed here (no GPU) give only the sections their data gives, markup shown as
//! text, figures rounded, and bad input one error with nothing written; the folders of finished `bench` and
//! `measure` runs give their tables and the path-traced truth's decomposition.

use super::{assert_self_contained, csv_file, page, sections, select, shown_table, table};
use crate::common::cli::{assert_fails, hairlab, stderr};
use hairlab::gpu::Gpu;
use std::path::Path;

const SUMMARY: &str = "config,map_error,shading_error,flicker,flicker_p99,pop_rate,max_pop,image_flicker,gpu_ms,\
                       image_flip\ndom:layers=3,0.05,0.07,0.01,0.37,0.027,0.79,0.005,3.6,0.0125\n\
                       occupancy,0.016,0.034,0.0016,0.05,0.0047,0.29,0.0016,9.4,0.0072\n";

const FRAMES: &str = "config,frame,map_error,shading_error,tracked_points,flicker,flicker_p99,pop_rate,max_pop,\
                      image_flicker,gpu_ms,image_flip\ndom:layers=3,0,0.05,0.07,100,,,,,,3.6,0.0125\n\
                      dom:layers=3,1,0.06,0.07,100,0.01,0.37,0.027,0.79,0.005,3.6,0.0125\n\
                      occupancy,0,0.016,0.034,100,,,,,,9.4,0.0072\n\
                      occupancy,1,0.017,0.034,100,0.0016,0.05,0.0047,0.29,0.0016,9.4,0.0072\n";

fn motion_folder(root: &Path, summary: &str) -> std::path::PathBuf {
    motion_folder_of(root, summary, FRAMES)
}

fn motion_folder_of(root: &Path, summary: &str, frames: &str) -> std::path::PathBuf {
    let dir = root.join("motion");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("motion_summary.csv"), summary).unwrap();
    std::fs::write(dir.join("motion_frames.csv"), frames).unwrap();
    dir
}

/// `hairlab report --from DIR --out OUT`.
fn report_from(dir: &Path, out: &Path) -> std::process::Output {
    hairlab(&[
        "report",
        "--from",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

/// A motion folder alone (typed here, no GPU): the machine, the motion and the claim it holds the figures of
/// (MC-1: pop rate 2.7 % against 0.47 %, 5.7×, above 2.5×), and no scene, speed or transparency section.
#[test]
fn sections_appear_only_where_their_data_is() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = motion_folder(tmp.path(), SUMMARY);
    let out = tmp.path().join("r");
    let o = report_from(&dir, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_self_contained(&out);
    let html = page(&out);
    assert_eq!(sections(&html), ["machine", "motion", "claims"]);
    let (header, rows) = table(&html, "motion");
    assert_eq!(header[0], "config");
    assert_eq!(
        rows[1],
        "occupancy,0.016,0.034,0.0016,0.05,0.0047,0.29,0.0016,9.4,0.0072"
            .split(',')
            .collect::<Vec<_>>()
    );
    let verdict: String = select(&html, "table#claims td.holds")
        .iter()
        .map(|c| c.text().collect::<String>())
        .collect();
    assert_eq!(verdict, "yes");
    // Without the occupancy row no claim can be checked: no claims section.
    let only_dom: String = SUMMARY.lines().take(2).map(|l| format!("{l}\n")).collect();
    let dir = motion_folder(&tmp.path().join("b"), &only_dom);
    let out = tmp.path().join("r2");
    let o = report_from(&dir, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(sections(&page(&out)), ["machine", "motion"]);
    // An earlier report is replaced whole, leaving nothing beside it.
    let o = report_from(&dir, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(sections(&page(&out)), ["machine", "motion"]);
    let mut names: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["b", "motion", "r", "r2"]);
}

/// A configuration whose label holds markup and figures with every digit (typed here, no GPU): the page shows
/// the label as text (no element made of it) and the figures to 4 significant digits, a time to 3, each rounded
/// cell's whole number in its title; the CSV keeps every digit.
#[test]
fn a_label_with_markup_is_text_and_long_figures_are_rounded() {
    let tmp = tempfile::tempdir().unwrap();
    let header = SUMMARY.lines().next().unwrap();
    let label = "a<b>\"c\"";
    let summary = format!(
        "{header}\n\"a<b>\"\"c\"\"\",0.05675050708926869,0.07,0.01,0.37,0.027,0.79,0.005,3.501971,0.0125569467718559\n"
    );
    let frames_header = FRAMES.lines().next().unwrap();
    let frames = format!("{frames_header}\n\"a<b>\"\"c\"\"\",0,0.05,0.07,100,,,,,,3.6,0.0125\n");
    let dir = motion_folder_of(tmp.path(), &summary, &frames);
    let out = tmp.path().join("r");
    let o = report_from(&dir, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let raw = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(!raw.contains("<b>"), "the label's markup reached the page");
    let html = page(&out);
    assert!(select(&html, "b").is_empty());
    let (_, shown) = shown_table(&html, "motion");
    assert_eq!(
        shown[0],
        [
            label, "0.05675", "0.07", "0.01", "0.37", "0.027", "0.79", "0.005", "3.5", "0.01256"
        ]
    );
    let (_, whole) = table(&html, "motion");
    assert_eq!(whole[0][1], "0.05675050708926869");
    assert_eq!(whole[0][8], "3.501971");
    assert_eq!(whole[0][9], "0.0125569467718559");
    let csv = std::fs::read_to_string(out.join("data/motion/motion_summary.csv")).unwrap();
    assert_eq!(csv, summary);
}

/// Nothing but the temporary folder's parent's own files: no report, no leftover draft.
fn assert_nothing_written(root: &Path, keep: &[&str]) {
    let mut names: Vec<String> = std::fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, keep, "something was written");
}

#[test]
fn bad_input_is_one_error_naming_the_file_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path();
    let out = root.join("r");
    let run = |from: &Path| report_from(from, &out);

    let empty = root.join("empty");
    std::fs::create_dir(&empty).unwrap();
    assert_fails(&run(&empty), &["empty", "no results here"]);
    assert_nothing_written(root, &["empty"]);

    let cut = &SUMMARY[..SUMMARY.len() - 20];
    let dir = motion_folder(&root.join("cut"), cut);
    assert_fails(&run(&dir), &["cut/motion/motion_summary.csv"]);
    assert_nothing_written(root, &["cut", "empty"]);

    let renamed = SUMMARY.replacen("pop_rate", "pops", 1);
    let dir = motion_folder(&root.join("col"), &renamed);
    assert_fails(
        &run(&dir),
        &["col/motion/motion_summary.csv", "unknown column 'pops'"],
    );
    assert_nothing_written(root, &["col", "cut", "empty"]);

    // A folder that is not an earlier report is never written over.
    let good = motion_folder(&root.join("good"), SUMMARY);
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    assert_fails(&run(&good), &["exists and is not an earlier report"]);
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
    assert_nothing_written(root, &["col", "cut", "empty", "good", "r"]);
}

/// `--from` the folders a finished `bench shadows`, `bench transparency` and `measure motion` wrote: every
/// table equals its CSV, and the sections are those their data gives (the scene from results.json and
/// transparency.json, no per-configuration images, which only a fresh study renders).
#[test]
fn from_the_folders_of_finished_bench_and_measure_runs_gives_their_tables() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = |name: &str| tmp.path().join(name).to_str().unwrap().to_string();
    let small = [
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
    ];
    let runs: [Vec<&str>; 3] = [
        vec![
            "bench",
            "shadows",
            "--preset",
            "stray-strand",
            "--methods",
            "dom",
            "--frames",
            "1",
        ],
        vec![
            "bench",
            "transparency",
            "--preset",
            "stray-strand",
            "--frames",
            "1",
        ],
        vec![
            "measure",
            "motion",
            "--preset",
            "stray-sweep",
            "--config",
            "dom:layers=3",
            "--config",
            "occupancy",
            "--frames",
            "2",
        ],
    ];
    let outs = [dir("shadows"), dir("transparency"), dir("motion")];
    for (args, out) in runs.iter().zip(&outs) {
        let mut args = args.clone();
        args.extend(small);
        args.extend(["--out", out]);
        let o = hairlab(&args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    }
    let report = dir("r");
    let o = hairlab(&[
        "report", "--from", &outs[0], "--from", &outs[1], "--from", &outs[2], "--out", &report,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = Path::new(&report);
    assert_self_contained(report);
    let html = page(report);
    assert_eq!(
        sections(&html),
        [
            "scene",
            "machine",
            "speed-accuracy",
            "transparency",
            "motion",
            "claims"
        ]
    );
    for (id, csv) in [
        ("results", Path::new(&outs[0]).join("results.csv")),
        ("transparency", Path::new(&outs[1]).join("transparency.csv")),
        ("motion", Path::new(&outs[2]).join("motion_summary.csv")),
    ] {
        let (header, rows) = csv_file(&csv);
        assert!(!rows.is_empty(), "{id}");
        assert_eq!(table(&html, id), (header, rows), "{id}");
    }
}

/// `--from` the folder of `measure shadows --truth path-traced` adds the truth section: the path-traced image
/// and the decomposition table, cell for cell `decomposition.csv` (one row per configuration, model and effect).
#[test]
fn from_a_measurement_against_the_path_traced_truth_gives_its_decomposition() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let measured = tmp.path().join("measured");
    let o = hairlab(&[
        "measure",
        "shadows",
        "--preset",
        "stray-strand",
        "--config",
        "dom:layers=3",
        "--config",
        "occupancy",
        "--frames",
        "1",
        "--truth",
        "path-traced",
        "--shading",
        "kajiya-kay,marschner",
        "--set",
        "scene.generator.strands=300",
        "--set",
        "scene.generator.segments=12",
        "--set",
        "render.map_resolution=128",
        "--set",
        "render.spp=1",
        "--out",
        measured.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = tmp.path().join("r");
    let o = hairlab(&[
        "report",
        "--from",
        measured.to_str().unwrap(),
        "--out",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_self_contained(&report);
    let html = page(&report);
    assert_eq!(sections(&html), ["scene", "machine", "speed-accuracy", "truth"]);
    let (header, rows) = csv_file(&measured.join("decomposition.csv"));
    assert_eq!(
        rows.len(),
        2 * 2 * 8,
        "two configurations under two models, seven steps and the total each"
    );
    assert_eq!(table(&html, "decomposition"), (header, rows));
    // The truth's image and the speed chart judged by it, whose points are the two configurations.
    assert_eq!(select(&html, "section#truth img").len(), 2);
    let svg = std::fs::read_to_string(measured.join("speed_vs_truth.svg")).unwrap();
    assert!(
        svg.contains("path-traced truth (kajiya-kay shading)"),
        "the y axis names the truth"
    );
    assert!(
        svg.contains("\ndom\n") && svg.contains("\noccupancy\n"),
        "both methods in the legend"
    );
}
