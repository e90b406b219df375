//! `measure shadows --shading` and `--truth path-traced`: each configuration's image error under each shading
//! model, and with the path-traced truth its error by physical effect (`crate::measure::truth`).

use crate::settings::Settings;
use crate::shading::ShadingModel;
use anyhow::Result;
use std::path::{Path, PathBuf};

/// `--shading` and `--truth path-traced`: every configuration's image error under each shading model, printed
/// as a table (and shading.csv with `--out`); with the path-traced truth, the decomposition table too (and
/// decomposition.csv, the truth's images and the speed chart against the truth) into `out`; returns the files
/// written. `models` empty: all of them.
pub(super) fn shading_table(
    models: &[ShadingModel],
    path_traced: bool,
    out: Option<&Path>,
    settings: &Settings,
    configs: &[crate::measure::MethodConfig],
    result: &crate::bench::BenchResult,
) -> Result<Vec<PathBuf>> {
    use crate::gpu::{AdapterPreference, Gpu};
    let models = if models.is_empty() {
        ShadingModel::ALL.to_vec()
    } else {
        models.to_vec()
    };
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let (truth, table) = match path_traced {
        false => {
            let table =
                crate::measure::shading::shading_errors_on(&gpu, settings, configs, &models, None, |m| {
                    eprintln!("shading {m}…")
                })?;
            (None, table)
        }
        true => {
            // Ctrl-C answers the bar's next step with a stop.
            let mut bar = super::progress::TerminalProgress::new();
            let measured =
                crate::measure::shading::against_truth(&gpu, settings, configs, &models, &mut bar)?;
            drop(bar);
            let Some((t, table)) = measured else {
                return Err(crate::cli::interrupt::Interrupted { done: configs.len() }.into());
            };
            eprintln!("path-traced truth: {} spp in {:.1} s", t.spp, t.seconds);
            if let Some(note) = crate::pathtrace::accumulation::dropped_note(t.dropped) {
                eprintln!("{note}");
            }
            (Some(t), table)
        }
    };
    let rows = &table.rows;
    let width = rows
        .iter()
        .map(|r| r.config.label().chars().count())
        .max()
        .unwrap_or(0)
        .max(6);
    let mut header = format!("{:<width$}", "method");
    for m in &models {
        header += &format!(
            " {:>24} {:>24}",
            format!("{} img RMSE", m.word()),
            format!("{} FLIP", m.word())
        );
    }
    println!("\nimage error per shading model (each against the reference image under the same model)");
    println!("{header}");
    for r in rows {
        let mut line = format!("{:<width$}", r.config.label());
        for e in &r.errors {
            line += &format!(" {:>24.5} {:>24.5}", e.image_rmse, e.image_flip);
        }
        println!("{line}");
    }
    if let Some(t) = &truth {
        print_decomposition(t, &table.decomposition, width);
        for m in &models {
            if let Some(s) = crate::measure::decompose::separation(&table.decomposition, m.word()) {
                println!(
                    "under {}: {}",
                    m.word(),
                    crate::bench::truth_chart::separation_note(&s)
                );
            }
        }
    }
    let mut written = Vec::new();
    if let Some(dir) = out {
        let path = dir.join("shading.csv");
        crate::io::write_atomic(&path, crate::measure::shading::csv(&models, rows)?.as_bytes())?;
        written.push(path);
        if let Some(t) = &truth {
            let shading = crate::measure::truth::chart_shading(settings, &models);
            written.extend(crate::bench::truth_chart::write_truth(
                dir,
                t,
                &table.decomposition,
                result,
                shading,
            )?);
        }
    }
    Ok(written)
}

/// The decomposition by effect as a table: per configuration and shading model, each step's RMSE (noise
/// removed) and mean ratio over the hair and over the shadow receivers.
fn print_decomposition(
    t: &crate::measure::truth::Truth,
    rows: &[crate::measure::decompose::Decomposition],
    width: usize,
) {
    println!(
        "\nerror by effect against the path-traced truth ({} spp, {} hair and {} receiver pixels): RMSE of sRGB \
         with the noise removed and (±) how far the truth's noise moves it, the ratio of mean linear luminance \
         (later image over earlier), the hair's structure (the RMSE left once the later image's channels are scaled to the earlier's means) and its \
         coarse RMSE (over {}×{} blocks wholly in the hair, their noise removed)",
        t.spp,
        t.masks.hair.iter().filter(|&&m| m).count(),
        t.masks.receivers.iter().filter(|&&m| m).count(),
        crate::measure::decompose::BLOCK,
        crate::measure::decompose::BLOCK,
    );
    println!(
        "{:<width$} {:<15} {:<19} {:>9} {:>7} {:>9} {:>9} {:>9}   {:>9} {:>9}",
        "method", "shading", "effect", "hair RMSE", "±", "ratio", "structure", "coarse", "recv RMSE", "ratio"
    );
    for d in rows {
        println!(
            "{:<width$} {:<15} {:<19} {:>9.4} {:>7.4} {:>9.3} {:>9.4} {:>9.4}   {:>9.4} {:>9.3}",
            d.method,
            d.shading,
            d.effect,
            d.hair_rmse,
            d.hair_gap.abs(),
            d.hair_ratio,
            d.hair_structure,
            d.hair_coarse,
            d.receivers_rmse,
            d.receivers_ratio
        );
    }
}
