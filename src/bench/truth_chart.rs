//! The speed chart judged by the path-traced truth (`speed_vs_truth.svg`): each configuration's GPU time against
//! its total error over the hair under one shading model (`crate::measure::decompose`), and the files a truth
//! measurement writes.

use super::BenchResult;
use super::chart::{self, Chart};
use super::report::{chart_files, write_files};
use anyhow::Result;
use std::path::{Path, PathBuf};

/// The speed chart of `result` against the path-traced truth: each configuration's GPU time against its RMSE
/// over the hair against the path-traced image under `shading` (a shading model's word; the decomposition's
/// total, the truth's noise removed), with its Pareto front; a configuration with no total under `shading`
/// stays off it. A note under the title says whether the truth tells them apart ([`separation_note`]).
pub fn truth_chart(
    result: &BenchResult,
    decomposition: &[crate::measure::decompose::Decomposition],
    shading: &str,
) -> Chart {
    let total = |r: &super::BenchRow| {
        let label = r.config.label();
        decomposition
            .iter()
            .find(|d| {
                d.method == label && d.shading == shading && d.effect == crate::measure::decompose::TOTAL
            })
            .map_or(f64::NAN, |d| d.hair_rmse)
    };
    let mut chart = chart::speed_chart_by(
        result,
        &total,
        &format!("hair RMSE against the path-traced truth ({shading} shading)"),
        "Speed vs accuracy against the path-traced truth",
    );
    if let Some(s) = crate::measure::decompose::separation(decomposition, shading) {
        chart.notes.push(separation_note(&s));
    }
    chart
}

/// One line saying how far apart the configurations are against what the truth's noise does to them: the
/// spread of their totals over the noise on one configuration's figure against the others' (from the truth's
/// two renders, [`crate::measure::decompose::Separation`]), and over the truth's noise per pixel.
pub fn separation_note(s: &crate::measure::decompose::Separation) -> String {
    let times = |noise: f64| {
        let t = s.spread / noise;
        if t < 10.0 {
            format!("{t:.2}×")
        } else {
            format!("{t:.0}×")
        }
    };
    let mut against = Vec::new();
    if s.figure_noise > 0.0 {
        against.push(format!(
            "{} the truth's noise on a figure (±{:.4})",
            times(s.figure_noise),
            s.figure_noise
        ));
    }
    if s.pixel_noise > 0.0 {
        against.push(format!(
            "{} its noise per pixel ({:.3})",
            times(s.pixel_noise),
            s.pixel_noise
        ));
    }
    let apart = format!("{} configurations {:.4} apart", s.configurations, s.spread);
    if against.is_empty() {
        apart
    } else {
        format!("{apart}: {}", against.join(", "))
    }
}

/// Writes [`truth_chart`] as `measure::truth::TRUTH_CHART_FILES` into `dir`.
pub fn write_truth_chart(
    dir: &Path,
    result: &BenchResult,
    decomposition: &[crate::measure::decompose::Decomposition],
    shading: &str,
) -> Result<Vec<PathBuf>> {
    let chart = truth_chart(result, decomposition, shading);
    write_files(
        dir,
        chart_files(crate::measure::truth::TRUTH_CHART, &chart)?.to_vec(),
    )
}

/// What `measure shadows --truth path-traced --out` and a report write of a truth, in one place: writes `decomposition.csv`, the truth's image and the speed chart against the truth under `chart_shading`
/// into `dir`, each atomically; returns their paths.
pub fn write_truth(
    dir: &Path,
    truth: &crate::measure::truth::Truth,
    decomposition: &[crate::measure::decompose::Decomposition],
    result: &BenchResult,
    chart_shading: crate::shading::ShadingModel,
) -> Result<Vec<PathBuf>> {
    let csv = dir.join(crate::measure::truth::DECOMPOSITION_CSV);
    crate::io::write_atomic(
        &csv,
        crate::io::csv_text(crate::measure::truth::DECOMPOSITION_CSV, decomposition)?.as_bytes(),
    )?;
    let mut written = vec![csv];
    for (name, stage) in truth.chain_images() {
        let image = dir.join(name);
        crate::io::write_png(&image, &stage.image)?;
        written.push(image);
    }
    written.extend(write_truth_chart(
        dir,
        result,
        decomposition,
        chart_shading.word(),
    )?);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::report::tests::result;

    #[test]
    fn the_truth_chart_plots_each_rows_total_error_under_the_shading_model() {
        use crate::measure::decompose::{Decomposition, METHOD, RegionError, StepError, TOTAL};
        let r = result();
        let e = |rmse| {
            let region = RegionError {
                rmse,
                ratio: 1.0,
                noise: 0.0,
                structure: rmse,
                coarse: rmse,
                gap: rmse / 10.0,
            };
            StepError {
                hair: region,
                receivers: region,
                image_rmse: 0.0,
                image_flip: 0.0,
            }
        };
        // Each configuration's method step (which the chart must not take) and its total.
        let d = |k: usize, shading, total| {
            let label = r.rows[k].config.label();
            [
                Decomposition::new(&label, shading, METHOD, &e(0.05)),
                Decomposition::new(&label, shading, TOTAL, &e(total)),
            ]
        };
        // Under Kajiya-Kay method-b is more accurate against the truth than method-a: both are on the front
        // (method-a faster, method-b more accurate), unlike under the bench's own metric.
        let decomposition = [
            d(0, "kajiya-kay", 0.3),
            d(1, "kajiya-kay", 0.2),
            d(0, "marschner", 0.9),
        ]
        .concat();
        let ys = |c: &Chart| -> Vec<f64> {
            c.series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.y))
                .collect()
        };
        let chart = truth_chart(&r, &decomposition, "kajiya-kay");
        assert_eq!(ys(&chart), [0.3, 0.2]);
        let note = chart.notes.last().unwrap();
        assert!(
            note == "2 configurations 0.1000 apart: 14× the truth's noise on a figure (±0.0071)",
            "{note}"
        );
        assert_eq!(chart.front.unwrap().points.len(), 2);
        // Under Marschner only method-a has a row: method-b is left off rather than drawn at a made-up error.
        let chart = truth_chart(&r, &decomposition, "marschner");
        assert!(ys(&chart)[0] == 0.9 && ys(&chart)[1].is_nan());
        assert_eq!(chart.front.unwrap().points.len(), 1);
        let dir = tempfile::tempdir().unwrap();
        let written = write_truth_chart(dir.path(), &r, &decomposition, "kajiya-kay").unwrap();
        assert_eq!(written.len(), 2);
        let svg = std::fs::read_to_string(dir.path().join("speed_vs_truth.svg")).unwrap();
        assert!(svg.contains("hair RMSE against the path-traced truth (kajiya-kay shading)"));
    }
}
