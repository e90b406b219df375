//! `hairlab report` (issue 36): the page of a small study parsed with an HTML5 parser (`scraper`). Every `img`,
//! `source`, `a` and `link` reference is a file in the report's folder and no file of it names an `http` or
//! `https` address (the SVG namespace identifier `xmlns="http://www.w3.org/2000/svg"` aside, which SVG needs and
//! nothing fetches); each table's cells are its CSV's text (a rounded cell's in its title); each section is on
//! the page exactly when its data is; `--from` the folders of a finished study gives the same tables; bad input is one error naming the file,
//! with no page written.

use crate::common::cli::{assert_fails, hairlab, stderr};
use hairlab::gpu::Gpu;
use scraper::{Html, Selector};
use std::path::Path;

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

fn page(dir: &Path) -> Html {
    Html::parse_document(&std::fs::read_to_string(dir.join("index.html")).unwrap())
}

fn select<'a>(html: &'a Html, css: &str) -> Vec<scraper::ElementRef<'a>> {
    html.select(&Selector::parse(css).unwrap()).collect()
}

/// The ids of the page's sections, in order.
fn sections(html: &Html) -> Vec<String> {
    select(html, "section")
        .iter()
        .map(|s| s.value().attr("id").unwrap().to_string())
        .collect()
}

/// The table `id`'s header and body cells as text, a rounded cell's whole text (its title) in its place.
fn table(html: &Html, id: &str) -> (Vec<String>, Vec<Vec<String>>) {
    cells(html, id, |c| {
        c.value()
            .attr("title")
            .map_or_else(|| c.text().collect(), str::to_string)
    })
}

/// The table `id`'s header and body cells as the page shows them.
fn shown_table(html: &Html, id: &str) -> (Vec<String>, Vec<Vec<String>>) {
    cells(html, id, |c| c.text().collect())
}

fn cells(
    html: &Html,
    id: &str,
    text: impl Fn(&scraper::ElementRef) -> String,
) -> (Vec<String>, Vec<Vec<String>>) {
    let header = select(html, &format!("table#{id} thead th"))
        .iter()
        .map(|c| c.text().collect())
        .collect();
    let rows = select(html, &format!("table#{id} tbody tr"))
        .iter()
        .map(|r| {
            r.select(&Selector::parse("td").unwrap())
                .map(|c| text(&c))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The CSV file's header and rows, read by the `csv` crate.
fn csv_file(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header = r.headers().unwrap().iter().map(str::to_string).collect();
    let rows = r
        .records()
        .map(|rec| rec.unwrap().iter().map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// Every reference of the page is a file in `dir`; no file in `dir` names an http(s) address; every image has
/// alt text; every table has header cells.
fn assert_self_contained(dir: &Path) {
    let html = page(dir);
    let mut refs = 0;
    for (css, attr) in [("img", "src"), ("source", "src"), ("a", "href"), ("link", "href")] {
        for e in select(&html, css) {
            let target = e
                .value()
                .attr(attr)
                .unwrap_or_else(|| panic!("a {css} without {attr}"));
            assert!(
                dir.join(target).is_file(),
                "{css} {attr}={target} is not a file in the report"
            );
            refs += 1;
        }
    }
    assert!(refs > 0, "no references checked");
    for img in select(&html, "img") {
        let alt = img.value().attr("alt").unwrap_or("");
        assert!(
            alt.len() > 20,
            "an image without alt text naming it: {:?}",
            img.value()
        );
    }
    for t in select(&html, "table") {
        assert!(
            t.select(&Selector::parse("th").unwrap()).count() > 0,
            "a table without headers"
        );
    }
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let Ok(text) = std::fs::read_to_string(&path) else {
                continue;
            };
            let text = text.replace("xmlns=\"http://www.w3.org/2000/svg\"", "");
            assert!(
                !text.contains("http:") && !text.contains("https:"),
                "{} names an address",
                path.display()
            );
        }
    }
}

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
        2 * 2 * 7,
        "two configurations under two models, six steps and the total each"
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
