//! `bench fur`: `measure fur`'s rows (each blending of Andersen et al. 2016 against the reference, virtual
//! fragments of one step) written as `fur.csv` (one row per blending: error, fragments, the paper's Table 1 rows)
//! and `fur.json` (the same with the scene, the view and the device).

use super::report::write_files;
use crate::fur::table::Table1;
use crate::io::csv_text;
use crate::measure::fur::{
    FurConfig, FurMeasurement, FurSceneStats, REFERENCE_LABEL, measure_each, usual_configs,
};
use crate::progress::Outcome;
use crate::settings::Settings;
use anyhow::{Context, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

pub struct FurBench {
    pub preset: String,
    pub frames: u32,
    pub stats: FurSceneStats,
    pub rows: Vec<FurMeasurement>,
}

/// One blending, flattened for the CSV (Table 1's rows by number: `t1_ms` … `t7_ms`, `m1_bytes` … `m6_bytes`).
#[derive(Serialize)]
struct Row {
    configuration: String,
    blending: &'static str,
    group_steps: u32,
    rmse: f64,
    max_error: f32,
    flip: f64,
    flip_hair: f64,
    flip_p95_hair: f64,
    flip_p99_hair: f64,
    explicit_fragments: u64,
    shell_fragments: u64,
    deepest: u32,
    t1_ms: f64,
    t2_ms: f64,
    t3_ms: f64,
    t4_ms: f64,
    t5_ms: f64,
    t6_ms: f64,
    t7_ms: f64,
    preprocess_ms: f64,
    online_ms: f64,
    total_ms: f64,
    m1_bytes: u64,
    m2_bytes: u64,
    m3_bytes: u64,
    m4_bytes: u64,
    m5_bytes: u64,
    m6_bytes: u64,
    total_bytes: u64,
}

impl Row {
    fn of(label: String, config: Option<&FurConfig>, m: Option<&FurMeasurement>, t: &Table1) -> Row {
        Row {
            configuration: label,
            blending: config.map_or("virtual", |c| c.blending.word()),
            group_steps: config.map_or(1, |c| c.group_steps),
            rmse: m.map_or(0.0, |m| m.rmse),
            max_error: m.map_or(0.0, |m| m.max_error),
            flip: m.map_or(0.0, |m| m.flip.mean),
            flip_hair: m.map_or(0.0, |m| m.flip.mean_hair),
            flip_p95_hair: m.map_or(0.0, |m| m.flip.p95_hair),
            flip_p99_hair: m.map_or(0.0, |m| m.flip.p99_hair),
            explicit_fragments: m.map_or(0, |m| m.explicit_fragments),
            shell_fragments: m.map_or(0, |m| m.shell_fragments),
            deepest: m.map_or(0, |m| m.deepest),
            t1_ms: t.times[0],
            t2_ms: t.times[1],
            t3_ms: t.times[2],
            t4_ms: t.times[3],
            t5_ms: t.times[4],
            t6_ms: t.times[5],
            t7_ms: t.times[6],
            preprocess_ms: t.preprocess_ms(),
            online_ms: t.online_ms(),
            total_ms: t.total_ms(),
            m1_bytes: t.memory[0],
            m2_bytes: t.memory[1],
            m3_bytes: t.memory[2],
            m4_bytes: t.memory[3],
            m5_bytes: t.memory[4],
            m6_bytes: t.memory[5],
            total_bytes: t.total_bytes(),
        }
    }
}

#[derive(Serialize)]
struct Json<'a> {
    preset: &'a str,
    device: &'a str,
    frames: u32,
    view: [u32; 2],
    triangles: usize,
    sub_elements: u64,
    guard_hairs: usize,
    fur_pixels: usize,
    time_rows: [&'static str; 7],
    memory_rows: [&'static str; 6],
    rows: Vec<Row>,
}

impl FurBench {
    /// Measures the usual blendings on `settings`' fur.
    pub fn run(settings: &Settings, preset: &str, frames: u32) -> Result<FurBench> {
        let configs = usual_configs();
        Self::run_each(
            settings,
            preset,
            &configs,
            frames,
            &mut crate::progress::Quiet,
            |_| Ok(()),
        )
        .map(Outcome::kept)
    }

    /// `configs` measured, `progress` told each as it starts, `after` called with the bench so far after each
    /// (to write it): its error ends the run with it; a stop `progress` asks for (Ctrl-C) ends it:
    /// [`Outcome::Stopped`] with the rows so far.
    pub fn run_each(
        settings: &Settings,
        preset: &str,
        configs: &[FurConfig],
        frames: u32,
        progress: &mut dyn crate::progress::Progress,
        mut after: impl FnMut(&FurBench) -> Result<()>,
    ) -> Result<Outcome<FurBench>> {
        let bench = |stats: &FurSceneStats, rows: &[FurMeasurement]| FurBench {
            preset: preset.to_string(),
            frames,
            stats: stats.clone(),
            rows: rows.to_vec(),
        };
        let (stats, rows) = measure_each(settings, configs, frames, progress, |stats, rows| {
            after(&bench(stats, rows))
        })?;
        // `measure_each` ends early only when stopped.
        Ok(Outcome::new(bench(&stats, &rows), rows.len() < configs.len()))
    }

    /// The reference's row first, then each blending's.
    fn rows(&self) -> Vec<Row> {
        std::iter::once(Row::of(REFERENCE_LABEL.into(), None, None, &self.stats.reference))
            .chain(
                self.rows
                    .iter()
                    .map(|m| Row::of(m.config.label(), Some(&m.config), Some(m), &m.table)),
            )
            .collect()
    }

    pub fn to_csv(&self) -> Result<String> {
        csv_text("fur.csv", self.rows())
    }

    pub fn to_json(&self) -> Result<String> {
        let s = &self.stats;
        serde_json::to_string_pretty(&Json {
            preset: &self.preset,
            device: &s.device,
            frames: self.frames,
            view: [s.width, s.height],
            triangles: s.triangles,
            sub_elements: s.sub_elements,
            guard_hairs: s.strands,
            fur_pixels: s.fur_pixels,
            time_rows: crate::fur::table::TIME_ROWS,
            memory_rows: crate::fur::table::MEMORY_ROWS,
            rows: self.rows(),
        })
        .context("cannot encode fur.json")
    }

    /// Writes `fur.csv` and `fur.json` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        write_files(
            dir,
            vec![
                ("fur.csv".to_string(), self.to_csv()?.into_bytes()),
                ("fur.json".to_string(), self.to_json()?.into_bytes()),
            ],
        )
    }
}
