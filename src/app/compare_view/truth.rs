//! The compare window's decomposition against the path-traced truth (`docs/truth.md`): the selected shadow
//! method under `render.shading` with its error split by physical effect, the rows `measure shadows --truth
//! path-traced` writes to `decomposition.csv` (`measure::shading::against_truth`, one place for the CLI, the
//! report and the window). The chain path-traces six images of the still scene at [`crate::measure::IMAGE_SIZE`],
//! so it runs on demand only (a button, never "auto"), as a job: Cancel leaves the last table. The table gives
//! each step's RMSE (the truth's noise removed) and luminance ratio over the hair and over the shadow receivers;
//! the pixel inspector reads the chain's images at its pixel ([`Decomposed::at`]).

use super::super::jobs::{Job, JobGate, JobStatus, Poll};
use crate::gpu::Gpu;
use crate::measure::MethodConfig;
use crate::measure::decompose::Decomposition;
use crate::settings::Settings;
use crate::transparency::metrics::srgb_to_linear;
use image::RgbaImage;

/// A finished decomposition and what it was made for.
pub struct Decomposed {
    /// The settings it was made under (the table says when they changed since).
    pub settings: Settings,
    /// The configuration's rows under its shading model, in the chain's order, the total last.
    pub rows: Vec<Decomposition>,
    /// The chain's images (sRGB over black; the path-traced ones, then the reference's), labelled, in the
    /// chain's order.
    pub stages: Vec<(String, RgbaImage)>,
    /// The truth's samples per pixel.
    pub spp: u32,
    pub seconds: f64,
}

impl Decomposed {
    /// Each stage's linear colour at `pixel` of a `width × height` image (the compare view's), read at the
    /// nearest pixel of the chain's images.
    pub fn at(&self, pixel: [u32; 2], (width, height): (u32, u32)) -> Vec<(&str, [f32; 3])> {
        self.stages
            .iter()
            .map(|(label, image)| {
                let scale = |p: u32, from: u32, to: u32| {
                    ((u64::from(p) * u64::from(to) / u64::from(from.max(1))) as u32).min(to.saturating_sub(1))
                };
                let x = scale(pixel[0], width, image.width());
                let y = scale(pixel[1], height, image.height());
                let c = image.get_pixel(x, y).0;
                (label.as_str(), [0, 1, 2].map(|i| srgb_to_linear(c[i]) as f32))
            })
            .collect()
    }
}

/// A stage's label from its file name: `truth_one_event.png` → `one event`.
fn label(file: &str) -> String {
    let stem = file.trim_end_matches(".png");
    stem.strip_prefix("truth_").unwrap_or(stem).replace('_', " ")
}

/// The decomposition of `settings`' method under its shading model: a job's work.
fn decompose(
    gpu: &Gpu,
    settings: &Settings,
    progress: &mut dyn crate::progress::Progress,
) -> Option<Result<Decomposed, String>> {
    let config = MethodConfig::new(&settings.method.name, settings.method.params.clone());
    let models = [settings.render.shading];
    let outcome = crate::measure::shading::against_truth(gpu, settings, &[config], &models, progress);
    match outcome {
        Err(e) => Some(Err(format!("truth: {e:#}"))),
        Ok(None) => None,
        Ok(Some((truth, table))) => Some(Ok(Decomposed {
            settings: settings.clone(),
            rows: table.decomposition,
            stages: truth
                .chain_images()
                .into_iter()
                .map(|(file, stage)| (label(&file), stage.image.clone()))
                .collect(),
            spp: truth.spp,
            seconds: truth.seconds,
        })),
    }
}

/// The decomposition's state in the compare window.
#[derive(Default)]
pub struct TruthPanel {
    job: Option<Job<Result<Decomposed, String>>>,
    result: Option<Decomposed>,
    error: Option<String>,
}

impl TruthPanel {
    /// The last decomposition that finished.
    pub fn result(&self) -> Option<&Decomposed> {
        self.result.as_ref()
    }

    /// Why the last decomposition failed.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Starts decomposing `settings` on a worker with `gpu` (a decomposition under way is cancelled).
    pub fn start(&mut self, gpu: Gpu, settings: &Settings, ctx: &egui::Context, gate: Option<JobGate>) {
        let settings = settings.clone();
        self.job = Some(Job::spawn("truth", ctx, gate, move |ctl| {
            decompose(&gpu, &settings, &mut ctl.clone())
        }));
    }

    /// The decomposition under way, as the job bar shows it.
    pub fn job_status(&self) -> Option<JobStatus> {
        self.job.as_ref().map(Job::status)
    }

    /// Takes the decomposition when it is done (waiting up to `patience`): a table replaces the last, an error
    /// is shown in its place, a cancelled one leaves the last. The status line's message, `Err` for an error.
    pub fn poll(&mut self, patience: std::time::Duration) -> Option<Result<String, String>> {
        match self.job.as_ref()?.wait(patience) {
            Poll::Running => None,
            Poll::Done(Ok(d)) => {
                self.job = None;
                self.error = None;
                let message = format!(
                    "truth: {} under {} decomposed ({} spp, {:.1} s)",
                    d.settings.method.name,
                    d.settings.render.shading.word(),
                    d.spp,
                    d.seconds
                );
                self.result = Some(d);
                Some(Ok(message))
            }
            Poll::Done(Err(e)) => {
                self.job = None;
                self.error = Some(e.clone());
                Some(Err(e))
            }
            Poll::Gone => {
                self.job = None;
                Some(Ok("truth: cancelled; the last table stays".to_string()))
            }
        }
    }

    /// The section's contents; `true` when the button asks for a decomposition.
    pub fn ui(&mut self, ui: &mut egui::Ui, settings: &Settings) -> bool {
        let mut start = false;
        ui.horizontal(|ui| {
            let running = self.job.is_some();
            if ui
                .add_enabled(!running, egui::Button::new("Decompose against the truth"))
                .on_hover_text(
                    "path-trace the still scene's chain (docs/truth.md) and split the selected method's error \
                     by physical effect, as measure shadows --truth path-traced does",
                )
                .clicked()
            {
                start = true;
            }
            let (w, h) = crate::measure::IMAGE_SIZE;
            ui.label(format!(
                "{} under {}, {w}×{h}, {} spp",
                settings.method.name,
                settings.render.shading.word(),
                settings.render.spp
            ));
        });
        if let Some(e) = &self.error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        if let Some(d) = &self.result {
            if d.settings != *settings {
                ui.label("(made under other settings: decompose again to update)");
            }
            table(ui, d);
        }
        start
    }
}

/// The rows: effect, then RMSE and ratio over the hair and over the receivers; the noise removed below.
fn table(ui: &mut egui::Ui, d: &Decomposed) {
    let number = |v: f64| {
        if v.is_nan() {
            "–".to_string()
        } else {
            format!("{v:.3}")
        }
    };
    egui::Grid::new("truth_decomposition")
        .striped(true)
        .show(ui, |ui| {
            let block = crate::measure::decompose::BLOCK;
            for h in [
                "effect".to_string(),
                "hair RMSE".to_string(),
                "hair ratio".to_string(),
                format!("hair {block}×{block} RMSE"),
                "receivers RMSE".to_string(),
                "receivers ratio".to_string(),
            ] {
                ui.strong(h);
            }
            ui.end_row();
            for r in &d.rows {
                ui.label(r.effect);
                ui.label(number(r.hair_rmse));
                ui.label(number(r.hair_ratio));
                ui.label(number(r.hair_coarse));
                ui.label(number(r.receivers_rmse));
                ui.label(number(r.receivers_ratio));
                ui.end_row();
            }
        });
    if let Some(total) = d.rows.last() {
        ui.label(format!(
            "{} under {}: RMSE of sRGB with the truth's noise removed (hair {}, receivers {}; that noise moves \
             the hair's total by ±{:.4}, from the figures its two renders give); {b}×{b}: over blocks of {b} × \
             {b} pixels wholly in the hair, the error at the scale of locks; ratio: the step's later image's mean \
             luminance over the earlier's. The steps' ratios multiply to the total's.",
            d.settings.method.name,
            total.shading,
            number(total.hair_noise),
            number(total.receivers_noise),
            total.hair_gap.abs(),
            b = crate::measure::decompose::BLOCK,
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage_labels_come_from_the_file_names() {
        assert_eq!(label("truth_path_traced.png"), "path traced");
        assert_eq!(label("truth_one_event.png"), "one event");
        assert_eq!(
            label("truth_raster_dual-scattering.png"),
            "raster dual-scattering"
        );
    }

    /// A pixel of a larger image reads the chain image's pixel at the same place (nearest), linear.
    #[test]
    fn at_reads_the_nearest_pixel_of_each_stage() {
        let mut image = RgbaImage::new(4, 2);
        image.put_pixel(3, 1, image::Rgba([255, 0, 188, 255]));
        let d = Decomposed {
            settings: Settings::default(),
            rows: Vec::new(),
            stages: vec![("path traced".to_string(), image)],
            spp: 1,
            seconds: 0.0,
        };
        let [(name, c)] = d.at([7, 3], (8, 4))[..] else {
            panic!("one stage")
        };
        assert_eq!(name, "path traced");
        assert_eq!(c[0], 1.0);
        assert_eq!(c[1], 0.0);
        assert!(
            (c[2] - 0.5029).abs() < 1e-3,
            "sRGB 188 is linear 0.5029, got {}",
            c[2]
        );
    }
}
