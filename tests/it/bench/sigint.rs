//! Ctrl-C during a bench: the CSV files hold complete rows of the configurations, techniques and densities that
//! finished.

use super::{TINY, column, read_csv};
use crate::common::cli::{error_lines, interrupt_once_written, stderr};
use hairlab::gpu::Gpu;

/// Ctrl-C stops `bench scaling` after the density in progress: scaling_points.csv holds every point of the
/// finished densities, whole, and the run exits 130 saying how many configurations it timed.
#[test]
fn sigint_leaves_complete_scaling_rows_of_the_finished_densities() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let args = [
        "bench",
        "scaling",
        "--methods",
        "occupancy",
        "--points",
        "6",
        "--max-segments",
        "30000",
        "--warmup",
        "1",
    ];
    // Six densities, each with the configuration's row and the shared light passes'.
    let (_dir, _out, header, rows) = sigint_after_the_first_file(&args, "scaling_points.csv", 2, 12);
    let mut last = 0;
    for r in rows.iter().filter(|r| r[0] == "occupancy") {
        assert_eq!(r[column(&header, "raster")], "hardware");
        let segments: usize = r[column(&header, "segments")].parse().unwrap();
        assert!(segments > last, "densities in order: {rows:?}");
        last = segments;
        let ms: f64 = r[column(&header, "gpu_ms_median")].parse().unwrap();
        assert!(ms.is_finite() && ms > 0.0, "{r:?}");
    }
}

/// Ctrl-C (SIGINT to the `hairlab` process) stops `bench shadows` and `measure shadows` after the configuration
/// in progress: results.csv and results.json hold every finished configuration, whole and in order, and the run
/// exits 130 saying how many.
#[test]
fn sigint_leaves_a_complete_csv_of_the_finished_configurations() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let sweep = [4, 8, 16, 32, 64, 128, 256].map(|n| format!("osm:slices={n}"));
    sigint_after_the_first_row(&["bench", "shadows", "--methods", "osm"], &sweep);
    let mut measure = vec!["measure", "shadows"];
    for c in &sweep {
        measure.extend(["--config", c.as_str()]);
    }
    sigint_after_the_first_row(&measure, &sweep);
}

/// Ctrl-C stops `measure transparency` after the configuration in progress: transparency.csv and
/// transparency.json hold every finished technique, whole and in order, and the run exits 130 saying how many.
#[test]
fn sigint_leaves_a_complete_csv_of_the_finished_transparency_techniques() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let labels: Vec<String> = hairlab::render::transparency::registry::all()
        .iter()
        .map(|t| t.name().to_string())
        .collect();
    let mut args = vec!["measure", "transparency"];
    for t in &labels {
        args.extend(["--technique", t.as_str()]);
    }
    let (_dir, out, header, rows) = sigint_after_the_first_file(&args, "transparency.csv", 1, labels.len());
    for (r, expected) in rows.iter().zip(&labels) {
        assert_eq!(&r[column(&header, "configuration")], expected);
        let error: f64 = r[column(&header, "rmse_hair")].parse().unwrap();
        assert!(error.is_finite() && error >= 0.0, "{r:?}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("transparency.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(rows.len()), "{json}");
}

/// Runs `hairlab ARGS` (the tiny scene, 40 timed frames, `--out`) until results.csv appears, sends SIGINT, and
/// checks what it left: fewer rows than `labels`, each whole, in that order.
fn sigint_after_the_first_row(args: &[&str], labels: &[String]) {
    let (_dir, out, header, rows) = sigint_after_the_first_file(args, "results.csv", 1, labels.len());
    for (r, expected) in rows.iter().zip(labels) {
        assert_eq!(&r[column(&header, "label")], expected);
        let error: f64 = r[column(&header, "map_error")].parse().unwrap();
        assert!(error.is_finite() && error > 0.0, "{r:?}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(rows.len()), "{json}");
    assert!(out.join("speed_vs_accuracy.png").is_file());
}

/// Runs `hairlab ARGS` (the tiny scene, 40 timed frames, `--out`) until `csv` appears in the output folder, sends
/// SIGINT, and checks that the run exits 130 with one error naming how many configurations it finished, and that
/// `csv` holds `rows_per_config` whole rows for each, fewer than `rows` in all. Returns the temporary folder, the
/// output folder in it, the header and the rows.
fn sigint_after_the_first_file(
    args: &[&str],
    csv: &str,
    rows_per_config: usize,
    all_rows: usize,
) -> (
    tempfile::TempDir,
    std::path::PathBuf,
    Vec<String>,
    Vec<Vec<String>>,
) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut args = args.to_vec();
    args.extend_from_slice(TINY);
    args.extend(["--frames", "40", "--out", out.to_str().unwrap()]);
    // The first configuration's rows are written; then Ctrl-C.
    let csv = out.join(csv);
    let o = interrupt_once_written(&args, &csv);
    assert_eq!(o.status.code(), Some(130), "{args:?}: {}", stderr(&o));
    let (header, rows) = read_csv(&csv);
    assert!(
        !rows.is_empty() && rows.len() < all_rows && rows.len() % rows_per_config == 0,
        "stopped after the configuration in progress: {rows:?}"
    );
    for r in &rows {
        assert_eq!(r.len(), header.len(), "a whole row: {r:?}");
    }
    let errors = error_lines(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("interrupted")
            && errors[0].contains(&format!("after {} configurations", rows.len() / rows_per_config)),
        "{errors:?}"
    );
    (dir, out, header, rows)
}
