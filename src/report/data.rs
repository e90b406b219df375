//! What a report reads: the folders `hairlab bench shadows`, `bench transparency` and `measure motion` write,
//! each table checked against the columns its writer gives (an unknown column, a missing one, a short row or a
//! value that is not a number is one error naming the file). The cells are kept as the CSV text; the page
//! rounds what it shows of a number and keeps that text in the cell's title (`page::shown`).

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// A fresh study's additions to the bench's folder: the light map's depth-complexity histogram, and the
/// images folder (each configuration's image, maps and `V(z)` curves at its [`WORST_TEXELS`] worst texels).
pub const HISTOGRAM_CSV: &str = "depth_complexity.csv";
pub const IMAGES: &str = "images";
pub const WORST_TEXELS: usize = 3;
/// The path-traced truth beside `results.csv` (`measure shadows --truth path-traced`, `report --truth`).
pub use crate::measure::truth::{DECOMPOSITION_CSV, TRUTH_CHART_FILES, TRUTH_PNG};
/// A fresh study's looping animations in the motion's folder.
pub const ANIMATIONS: &str = "animations";

/// The file of configuration `k`'s curves at its worst texel `rank` (0: the worst).
pub fn vz_file(k: usize, rank: usize) -> String {
    format!("{k}_vz_{rank}.svg")
}

/// One CSV file as read: its header and its rows, each cell the file's text.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub file: PathBuf,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// The index of `column`.
    pub fn column(&self, column: &str) -> Option<usize> {
        self.header.iter().position(|h| h == column)
    }

    /// `row`'s cell of `column` as a number (`None` when the column is absent or the cell empty).
    pub fn number(&self, row: usize, column: &str) -> Option<f64> {
        let c = self.column(column)?;
        self.rows[row][c].parse().ok()
    }

    /// `row`'s cell of `column`.
    pub fn text(&self, row: usize, column: &str) -> Option<&str> {
        let c = self.column(column)?;
        Some(self.rows[row][c].as_str())
    }
}

/// How a column's cells must read.
#[derive(Clone, Copy, PartialEq)]
enum Cell {
    Text,
    Number,
    /// A number or empty (frame 0's flicker).
    OptionalNumber,
    Bool,
}

/// The columns `results.csv` has ([`crate::bench::to_csv`]): the head, every metric, the tail.
fn results_columns() -> Vec<(String, Cell)> {
    let head = [
        ("method", Cell::Text),
        ("params", Cell::Text),
        ("label", Cell::Text),
        ("note", Cell::Text),
        ("gpu_ms_median", Cell::Number),
        ("gpu_ms_min", Cell::Number),
        ("gpu_ms_max", Cell::Number),
        ("memory_bytes", Cell::Number),
        ("build_memory_bytes", Cell::Number),
        ("geometry_passes", Cell::Number),
    ];
    let tail = [
        ("pareto", Cell::Bool),
        ("passes", Cell::Text),
        ("device", Cell::Text),
    ];
    let metrics = crate::bench::METRICS.iter().map(|m| (m.name, Cell::Number));
    head.into_iter()
        .chain(metrics)
        .chain(tail)
        .map(|(n, c)| (n.to_string(), c))
        .collect()
}

fn columns(names: &[&str], first_text: usize, last: Cell) -> Vec<(String, Cell)> {
    names
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let cell = if i < first_text {
                Cell::Text
            } else if i + 1 == names.len() {
                last
            } else {
                Cell::Number
            };
            (n.to_string(), cell)
        })
        .collect()
}

/// `transparency.csv`'s columns ([`crate::bench::transparency::TransparencyBench::to_csv`]).
fn transparency_columns() -> Vec<(String, Cell)> {
    columns(
        &[
            "configuration",
            "gpu_ms",
            "rmse_hair",
            "psnr_hair",
            "rmse",
            "ssim_hair",
            "flip",
            "flip_hair",
            "flip_p95_hair",
            "flip_p99_hair",
            "max_error",
            "p99",
            "share_over_1",
            "share_over_4",
            "share_over_8",
            "contrast_retention",
            "mean_luminance_ratio",
            "memory_bytes",
            "geometry_passes",
            "pareto",
        ],
        1,
        Cell::Bool,
    )
}

/// `motion_summary.csv`'s columns ([`crate::measure::motion::MotionMeasurement::summary_csv`]).
fn motion_summary_columns() -> Vec<(String, Cell)> {
    columns(
        &[
            "config",
            "map_error",
            "shading_error",
            "flicker",
            "flicker_p99",
            "pop_rate",
            "max_pop",
            "image_flicker",
            "gpu_ms",
            "image_flip",
        ],
        1,
        Cell::Number,
    )
}

/// `motion_frames.csv`'s columns ([`crate::measure::motion::FrameRow`]).
fn motion_frames_columns() -> Vec<(String, Cell)> {
    let mut c = columns(
        &[
            "config",
            "frame",
            "map_error",
            "shading_error",
            "tracked_points",
            "flicker",
            "flicker_p99",
            "pop_rate",
            "max_pop",
            "image_flicker",
            "gpu_ms",
            "image_flip",
        ],
        1,
        Cell::Number,
    );
    for (name, cell) in &mut c {
        if ["flicker", "flicker_p99", "pop_rate", "max_pop", "image_flicker"].contains(&name.as_str()) {
            *cell = Cell::OptionalNumber;
        }
    }
    c
}

/// Reads `path` as a table with exactly `expected`'s columns (any order), every row whole and every cell of its
/// column's kind.
fn read_table(path: &Path, expected: &[(String, Cell)]) -> Result<Table> {
    let text =
        crate::io::read_regular_text(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .with_context(|| format!("{}: not a CSV table", path.display()))?
        .iter()
        .map(str::to_string)
        .collect();
    if header.iter().all(|h| h.is_empty()) {
        bail!("{}: empty (no header)", path.display());
    }
    let kinds: Vec<Cell> = header
        .iter()
        .map(|h| {
            expected
                .iter()
                .find(|(n, _)| n == h)
                .map(|(_, c)| *c)
                .with_context(|| format!("{}: unknown column '{h}'", path.display()))
        })
        .collect::<Result<_>>()?;
    if let Some((missing, _)) = expected.iter().find(|(n, _)| !header.contains(n)) {
        bail!("{}: no column '{missing}'", path.display());
    }
    let mut rows = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let line = i + 2;
        let record = record.with_context(|| format!("{}: line {line}: a broken row", path.display()))?;
        let row: Vec<String> = record.iter().map(str::to_string).collect();
        for ((cell, kind), name) in row.iter().zip(&kinds).zip(&header) {
            let ok = match kind {
                Cell::Text => true,
                Cell::Number => cell.parse::<f64>().is_ok(),
                Cell::OptionalNumber => cell.is_empty() || cell.parse::<f64>().is_ok(),
                Cell::Bool => cell == "true" || cell == "false",
            };
            if !ok {
                bail!("{}: line {line}: column '{name}' holds '{cell}'", path.display());
            }
        }
        rows.push(row);
    }
    if !text.ends_with('\n') {
        bail!("{}: truncated (the last line does not end)", path.display());
    }
    Ok(Table {
        file: path.to_path_buf(),
        header,
        rows,
    })
}

fn read_json(path: &Path) -> Result<Option<serde_json::Value>> {
    if !path.exists() {
        return Ok(None);
    }
    let text =
        crate::io::read_regular_text(path).with_context(|| format!("{}: cannot read", path.display()))?;
    serde_json::from_str(&text)
        .map(Some)
        .with_context(|| format!("{}: not JSON", path.display()))
}

fn existing(path: PathBuf) -> Option<PathBuf> {
    path.is_file().then_some(path)
}

/// `bench shadows`' folder: `results.csv`, with `results.json` (the scene) and the chart where written.
#[derive(Clone, Debug)]
pub struct Shadows {
    pub dir: PathBuf,
    pub results: Table,
    pub json: Option<serde_json::Value>,
    pub chart: Option<PathBuf>,
    /// The light map's depth-complexity histogram (a fresh study's).
    pub depth_complexity: Option<Table>,
}

/// The path-traced truth in the shadows' folder: `decomposition.csv` and the image where written.
#[derive(Clone, Debug)]
pub struct Truth {
    pub table: Table,
    pub image: Option<PathBuf>,
    /// The speed chart against the truth (`speed_vs_truth.svg`) where written.
    pub chart: Option<PathBuf>,
}

/// `decomposition.csv`'s columns ([`crate::measure::decompose::Decomposition`]).
fn decomposition_columns() -> Vec<(String, Cell)> {
    columns(
        &[
            "method",
            "shading",
            "effect",
            "hair_rmse",
            "hair_ratio",
            "hair_noise",
            "hair_structure",
            "hair_coarse",
            "hair_gap",
            "receivers_rmse",
            "receivers_ratio",
            "receivers_noise",
            "receivers_structure",
            "receivers_coarse",
            "receivers_gap",
            "image_rmse",
            "image_flip",
        ],
        3,
        Cell::Number,
    )
}

/// `bench transparency`'s folder.
#[derive(Clone, Debug)]
pub struct Transparency {
    pub dir: PathBuf,
    pub table: Table,
    pub json: Option<serde_json::Value>,
    pub chart: Option<PathBuf>,
}

/// `measure motion`'s folder.
#[derive(Clone, Debug)]
pub struct Motion {
    pub dir: PathBuf,
    pub summary: Table,
    pub frames: Table,
}

/// What a report shows: each part present where its folder was given.
#[derive(Clone, Debug, Default)]
pub struct Study {
    pub shadows: Option<Shadows>,
    pub transparency: Option<Transparency>,
    pub motion: Option<Motion>,
    pub truth: Option<Truth>,
}

/// The files of a study folder a report reads.
pub const STUDY_FILES: [&str; 3] = ["results.csv", "transparency.csv", "motion_summary.csv"];

impl Study {
    /// The configurations measured, over every part.
    pub fn configurations(&self) -> usize {
        self.shadows.as_ref().map_or(0, |s| s.results.rows.len())
            + self.transparency.as_ref().map_or(0, |t| t.table.rows.len())
            + self.motion.as_ref().map_or(0, |m| m.summary.rows.len())
    }

    /// Reads each of `dirs`: every folder must hold at least one of [`STUDY_FILES`], and no part may come from
    /// two folders.
    pub fn read(dirs: &[PathBuf]) -> Result<Study> {
        let mut study = Study::default();
        for dir in dirs {
            if !dir.is_dir() {
                bail!("{}: not a folder", dir.display());
            }
            let mut found = false;
            if let Some(csv) = existing(dir.join("results.csv")) {
                found = true;
                let part = Shadows {
                    dir: dir.clone(),
                    results: read_table(&csv, &results_columns())?,
                    json: read_json(&dir.join("results.json"))?,
                    chart: existing(dir.join("speed_vs_accuracy.svg")),
                    depth_complexity: existing(dir.join(HISTOGRAM_CSV))
                        .map(|p| read_table(&p, &columns(&["depth_complexity", "texels"], 0, Cell::Number)))
                        .transpose()?,
                };
                set_once(&mut study.shadows, part, &csv)?;
                if let Some(path) = existing(dir.join(DECOMPOSITION_CSV)) {
                    study.truth = Some(Truth {
                        table: read_table(&path, &decomposition_columns())?,
                        image: existing(dir.join(TRUTH_PNG)),
                        chart: existing(dir.join(TRUTH_CHART_FILES[1])),
                    });
                }
            }
            if let Some(csv) = existing(dir.join("transparency.csv")) {
                found = true;
                let part = Transparency {
                    dir: dir.clone(),
                    table: read_table(&csv, &transparency_columns())?,
                    json: read_json(&dir.join("transparency.json"))?,
                    chart: existing(dir.join("transparency_speed_vs_accuracy.svg")),
                };
                set_once(&mut study.transparency, part, &csv)?;
            }
            if let Some(csv) = existing(dir.join("motion_summary.csv")) {
                found = true;
                let frames_path = dir.join("motion_frames.csv");
                if !frames_path.is_file() {
                    bail!("{}: missing beside motion_summary.csv", frames_path.display());
                }
                let part = Motion {
                    dir: dir.clone(),
                    summary: read_table(&csv, &motion_summary_columns())?,
                    frames: read_table(&frames_path, &motion_frames_columns())?,
                };
                set_once(&mut study.motion, part, &csv)?;
            }
            if !found {
                bail!(
                    "{}: no results here (none of {})",
                    dir.display(),
                    STUDY_FILES.join(", ")
                );
            }
        }
        Ok(study)
    }
}

fn set_once<T>(slot: &mut Option<T>, part: T, file: &Path) -> Result<()> {
    if slot.is_some() {
        bail!("{}: a second folder of the same results", file.display());
    }
    *slot = Some(part);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> Result<Table> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("motion_summary.csv");
        std::fs::write(&path, text).unwrap();
        read_table(&path, &motion_summary_columns())
    }

    const HEADER: &str = "config,map_error,shading_error,flicker,flicker_p99,pop_rate,max_pop,image_flicker,gpu_ms,image_flip\n";

    #[test]
    fn a_whole_table_reads_as_its_text() {
        let t = table(&format!(
            "{HEADER}\"dom:layers=3\",0.5,0.25,1e-3,0.002,0,0.1,0.02,1.5,0.125\n"
        ))
        .unwrap();
        assert_eq!(t.rows[0][0], "dom:layers=3");
        assert_eq!(t.rows[0][3], "1e-3");
        assert_eq!(t.number(0, "gpu_ms"), Some(1.5));
    }

    #[test]
    fn bad_tables_are_refused_naming_the_file_and_the_fault() {
        let e = |text: &str| format!("{:#}", table(text).unwrap_err());
        let short = e(&format!("{HEADER}dom,0.5,0.25\n"));
        assert!(
            short.contains("motion_summary.csv: line 2: a broken row"),
            "{short}"
        );
        let cut = e(&format!("{HEADER}dom,0.5,0.25,1,2,3,4,5,6,0.1"));
        assert!(cut.contains("motion_summary.csv: truncated"), "{cut}");
        let unknown = e(&HEADER.replace("max_pop", "max_pops"));
        assert!(
            unknown.contains("motion_summary.csv: unknown column 'max_pops'"),
            "{unknown}"
        );
        let word = e(&format!("{HEADER}dom,0.5,0.25,x,2,3,4,5,6,0.1\n"));
        assert!(word.contains("line 2: column 'flicker' holds 'x'"), "{word}");
        assert!(e("").contains("motion_summary.csv: empty"));
    }
}
