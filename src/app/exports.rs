//! Results leave the windows. The Bench window: the files `hairlab bench` writes (`results.csv`, `results.json`,
//! `speed_vs_accuracy.png` and `.svg`, through the same writer, [`crate::bench::write_results`]), and the table
//! (as CSV text) and the chart (as an image) copied to the clipboard. The Compare window: each image, the
//! difference and FLIP maps against the first, and the metrics as CSV ([`compare_files`]). The pixel inspector:
//! its fragment table as CSV and its transmittance plot as PNG and SVG. The texel inspector: its `V(z)` plot (and
//! its count plot when shown) as PNG and SVG, drawn by the bench's chart writer, and the plot shown copied to the
//! clipboard (its curves as CSV go through their own file dialog). An export asks for a
//! folder with the file dialog, or writes straight into the folder set by [`HairlabApp::set_export_dir`].

use super::compare_view::{CompareFrames, difference_image};
use super::inspector::PlotKind;
use super::{DialogPurpose, HairlabApp};
use crate::bench;
use crate::bench::report::{chart_files, write_files};
use crate::io::{csv_text, encode_png};
use std::path::{Path, PathBuf};

/// What a window exports into a folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Export {
    Bench,
    Compare,
    Pixel,
    Texel,
    Report,
}

impl Export {
    /// The folder dialog's title.
    pub fn title(self) -> &'static str {
        match self {
            Export::Bench => "Export bench results to a folder",
            Export::Compare => "Export the compared images to a folder",
            Export::Pixel => "Export the pixel's fragments and plot to a folder",
            Export::Texel => "Export the texel inspector's plot to a folder",
            Export::Report => "Export a report of the current scene to a folder",
        }
    }
}

impl HairlabApp {
    /// Exports write into `dir` without asking (`None`: the file dialog asks for a folder each time).
    pub fn set_export_dir(&mut self, dir: Option<PathBuf>) {
        self.export_dir = dir;
    }

    /// Starts the export `what`: into the export folder when one is set, else a folder picked in the dialog.
    pub(super) fn request_export(&mut self, what: Export, ctx: &egui::Context) {
        match self.export_dir.clone() {
            Some(dir) => self.export(what, &dir),
            None => self.open_dialog(DialogPurpose::Export(what), ctx),
        }
    }

    /// Writes the export `what` into the folder `dir`.
    pub(super) fn export(&mut self, what: Export, dir: &Path) {
        match what {
            Export::Bench => self.export_bench(dir),
            Export::Compare => self.export_compare(dir),
            Export::Pixel => self.export_pixel(dir),
            Export::Texel => self.export_texel(dir),
            Export::Report => self.start_report_export(dir),
        }
    }

    /// Writes the Bench window's result into `dir` as `hairlab bench --out dir` does.
    fn export_bench(&mut self, dir: &Path) {
        let Some(result) = self.bench_result() else {
            return;
        };
        match bench::write_results(dir, result) {
            Ok(files) => self.info(format!("bench: wrote {} files to {}", files.len(), dir.display())),
            Err(e) => self.error(format!("bench export: {e:#}")),
        }
    }

    /// Copies the Bench window's table to the clipboard as the CSV text of `results.csv`.
    pub(super) fn copy_bench_table(&mut self, ctx: &egui::Context) {
        let Some(result) = self.bench_result() else {
            return;
        };
        match bench::to_csv(result) {
            Ok(text) => {
                ctx.copy_text(text);
                self.info("bench: table copied (CSV)");
            }
            Err(e) => self.error(format!("bench copy: {e:#}")),
        }
    }

    /// Copies the Bench window's chart to the clipboard as the image of `speed_vs_accuracy.png`.
    pub(super) fn copy_bench_chart(&mut self, ctx: &egui::Context) {
        let Some(result) = self.bench_result() else {
            return;
        };
        match copy_chart(ctx, &bench::speed_accuracy_chart(result)) {
            Ok(()) => self.info("bench: chart copied (image)"),
            Err(e) => self.error(format!("bench copy: {e:#}")),
        }
    }

    /// The texel inspector's plots to write: `V(z)`, and the count plot when the window shows it.
    fn texel_plots(&self) -> Vec<PlotKind> {
        let mut kinds = vec![PlotKind::Visibility];
        if self.inspector.show_count {
            kinds.push(PlotKind::Count);
        }
        kinds
    }

    /// Writes the texel inspector's plots into `dir`: `texel_v.png` and `.svg`, and `texel_count.png` and `.svg`
    /// when the count plot is shown.
    fn export_texel(&mut self, dir: &Path) {
        let Some(curves) = self.inspector.curves() else {
            return self.error("texel inspector: nothing to export (select a texel first)");
        };
        let mut files = Vec::new();
        for kind in self.texel_plots() {
            let Some(chart) = curves.chart(kind) else {
                return self.error("texel inspector: nothing to export (select a texel first)");
            };
            match chart_files(kind.stem(), &chart) {
                Ok(f) => files.extend(f),
                Err(e) => return self.error(format!("texel inspector export: {e:#}")),
            }
        }
        match write_files(dir, files) {
            Ok(files) => self.info(format!(
                "texel inspector: wrote {} files to {}",
                files.len(),
                dir.display()
            )),
            Err(e) => self.error(format!("texel inspector export: {e:#}")),
        }
    }

    /// Copies the texel inspector's plot shown (`V(z)` or the count) to the clipboard as the image of its PNG.
    pub(super) fn copy_texel_plot(&mut self, ctx: &egui::Context) {
        let kind = if self.inspector.show_count {
            PlotKind::Count
        } else {
            PlotKind::Visibility
        };
        let Some(chart) = self.inspector.curves().and_then(|c| c.chart(kind)) else {
            return self.error("texel inspector: nothing to copy (select a texel first)");
        };
        match copy_chart(ctx, &chart) {
            Ok(()) => self.info("texel inspector: plot copied (image)"),
            Err(e) => self.error(format!("texel inspector copy: {e:#}")),
        }
    }

    /// Writes the pixel inspector's fragment table (`pixel.csv`, [`super::pixel_inspector::PixelReport::csv`])
    /// and transmittance plot (`pixel_transmittance.png` and `.svg`) into `dir`.
    fn export_pixel(&mut self, dir: &Path) {
        let Some(report) = self.pixel_inspector.report() else {
            return;
        };
        let files = report.csv().and_then(|csv| {
            let mut files = vec![("pixel.csv".to_string(), csv.into_bytes())];
            files.extend(chart_files("pixel_transmittance", &report.chart())?);
            Ok(files)
        });
        match files.and_then(|files| write_files(dir, files)) {
            Ok(files) => self.info(format!("pixel: wrote {} files to {}", files.len(), dir.display())),
            Err(e) => self.error(format!("pixel export: {e:#}")),
        }
    }

    /// Writes the Compare window's frames into `dir` ([`compare_files`]).
    fn export_compare(&mut self, dir: &Path) {
        let Some(frames) = self.compare.frames() else {
            return;
        };
        match compare_files(frames, self.compare.gain).and_then(|files| write_files(dir, files)) {
            Ok(files) => self.info(format!(
                "compare: wrote {} files to {}",
                files.len(),
                dir.display()
            )),
            Err(e) => self.error(format!("compare export: {e:#}")),
        }
    }
}

/// One compared slot's metrics against the first image: every row of the Compare window's grid.
#[derive(serde::Serialize)]
struct MetricsRow {
    slot: usize,
    technique: &'static str,
    label: &'static str,
    rmse: f64,
    psnr: f64,
    rmse_hair: f64,
    psnr_hair: f64,
    ssim: f64,
    ssim_hair: f64,
    max_error: f64,
    p99: f64,
    share_over_1: f64,
    share_over_4: f64,
    share_over_8: f64,
    contrast_retention: f64,
    mean_luminance_ratio: f64,
    flip: f64,
    flip_hair: f64,
    flip_p95_hair: f64,
    flip_p99_hair: f64,
}

/// Copies `chart` to the clipboard as the image its PNG file holds.
fn copy_chart(ctx: &egui::Context, chart: &bench::chart::Chart) -> anyhow::Result<()> {
    let (w, h) = bench::CHART_SIZE;
    let rgba = image::load_from_memory(&bench::chart::png(chart, w, h)?)?.to_rgba8();
    let size = [rgba.width() as usize, rgba.height() as usize];
    ctx.copy_image(egui::ColorImage::from_rgba_unmultiplied(size, rgba.as_raw()));
    Ok(())
}

/// The compared frames as files: `<k>_<technique>.png` for each slot's image (`k` from 1); for every slot after
/// the first, `difference_<k>_<technique>.png` (the largest channel error against the first × `gain`, as the
/// window shows it) and `flip_<k>_<technique>.png` (FLIP's heat map); and `metrics.csv`, one row per slot after
/// the first.
pub fn compare_files(frames: &CompareFrames, gain: f32) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let reference = &frames.images[0].image;
    let mut files = Vec::new();
    let mut rows = Vec::new();
    for (i, img) in frames.images.iter().enumerate() {
        let k = i + 1;
        files.push((format!("{k}_{}.png", img.name), encode_png(&img.image)?));
        if i == 0 {
            continue;
        }
        files.push((
            format!("difference_{k}_{}.png", img.name),
            encode_png(&difference_image(&img.image, reference, gain))?,
        ));
        let flip = crate::transparency::FlipMap::new(&img.image, reference).heat_map();
        files.push((format!("flip_{k}_{}.png", img.name), encode_png(&flip)?));
        let m = &img.metrics;
        rows.push(MetricsRow {
            slot: k,
            technique: img.name,
            label: img.label,
            rmse: m.rmse,
            psnr: m.psnr,
            rmse_hair: m.rmse_hair,
            psnr_hair: m.psnr_hair,
            ssim: m.ssim,
            ssim_hair: m.ssim_hair,
            max_error: m.max_error,
            p99: m.p99,
            share_over_1: m.share_over[0],
            share_over_4: m.share_over[1],
            share_over_8: m.share_over[2],
            contrast_retention: m.contrast_retention,
            mean_luminance_ratio: m.mean_luminance_ratio,
            flip: m.flip.mean,
            flip_hair: m.flip.mean_hair,
            flip_p95_hair: m.flip.p95_hair,
            flip_p99_hair: m.flip.p99_hair,
        });
    }
    files.push((
        "metrics.csv".to_string(),
        csv_text("metrics.csv", rows)?.into_bytes(),
    ));
    Ok(files)
}
