//! The compare view: the occupancy paper's Fig. 2 layout — four eye transparency techniques side by side
//! (reference | selected | weighted average | opaque by default, each slot any registered technique), each
//! labelled with its GPU time and frame rate, and the difference heat map `|slot − slot 1|` (max channel, in
//! 1/255 steps, times a gain of ×1…×64) or FLIP's map of the slot against the first, with every image metric of
//! `transparency::metrics::compare` beside it.
//!
//! The frames are rendered on demand (a button, or when the settings change while "auto" is on and no drag is
//! under way) with the current settings at the aspect of `render.width`×`render.height`. A render is a job
//! (`jobs.rs`): a worker thread with a renderer of its own, made from a clone of the window's `Gpu`, the scene on
//! screen and its fur, reports each slot to the job bar, and Cancel keeps the previous images; the window keeps
//! drawing meanwhile. The same render reads the exact per-pixel lists (the hair mask of the metrics, what the pixel
//! inspector shows) and the opaque image under the hair (the inspector's backgrounds).

use super::jobs::{Job, JobGate, JobStatus, Poll};
use crate::methods::ParamValues;
use crate::render::transparency::{EyeTransparency, registry};
use crate::settings::Settings;
use crate::transparency::ImageMetrics;
use image::RgbaImage;

mod frames;
pub mod truth;

use frames::render_job;
pub use frames::{
    CompareFrames, CompareImage, CompareSource, DepthComplexity, difference_image, heat, render_compare,
};

/// Image widths offered (the height follows the viewport's aspect).
pub const WIDTHS: &[u32] = &[160, 240, 320, 480, 640, 960];
/// Range of the difference gain.
pub const GAIN_RANGE: std::ops::RangeInclusive<f32> = 1.0..=64.0;

/// What one of the four images shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// The side panel's technique, with its parameters.
    Selected,
    /// A registered technique with its default parameters.
    Technique(&'static str),
    /// The scene path-traced on the CPU (round fibres, multiple scattering) at `render.spp` samples per pixel:
    /// the light the techniques and the shadow method approximate (`path_view.rs`).
    PathTraced,
}

/// The path-traced slot's name in exported files and its label.
pub const PATH_TRACED: (&str, &str) = ("path-traced", "path-traced (fibres)");

impl Slot {
    /// The technique shown and its parameters under `settings`.
    pub(super) fn resolve<'a>(
        self,
        settings: &'a Settings,
        defaults: &'a ParamValues,
    ) -> Result<(&'static dyn EyeTransparency, &'a ParamValues), String> {
        match self {
            Slot::Selected => settings
                .transparency
                .technique()
                .map(|t| (t, &settings.transparency.params))
                .map_err(|e| format!("{e:#}")),
            Slot::Technique(name) => registry::find(name)
                .map(|t| {
                    let params = if t.name() == settings.transparency.name {
                        &settings.transparency.params
                    } else {
                        defaults
                    };
                    (t, params)
                })
                .map_err(|e| e.to_string()),
            Slot::PathTraced => Err("the path-traced slot has no transparency technique".to_string()),
        }
    }

    fn text(self, settings: &Settings) -> String {
        match self {
            Slot::Selected => format!("selected ({})", settings.transparency.name),
            Slot::Technique(name) => {
                registry::find(name).map_or(name.to_string(), |t| t.info().label.to_string())
            }
            Slot::PathTraced => PATH_TRACED.1.to_string(),
        }
    }
}

/// The default slots: the reference, the selected technique, then weighted average and opaque where they are
/// registered (else the next registered techniques).
fn default_slots() -> [Slot; 4] {
    let reference = registry::reference().name();
    let [third, fourth] = registry::fig2_comparisons().map(|t| t.name());
    [
        Slot::Technique(reference),
        Slot::Selected,
        Slot::Technique(third),
        Slot::Technique(fourth),
    ]
}

/// What the compare window asks of the app.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompareAction {
    /// Render the four images now.
    Render,
    /// Inspect this pixel of the compared images.
    Pick([u32; 2]),
    /// Write the images, the difference and FLIP maps and the metrics to a folder.
    Export,
    /// Decompose the selected method's error against the path-traced truth ([`truth`]).
    Decompose,
}

/// The settings, slots and size a render was made for.
type CompareKey = (Settings, [Slot; 4], u32, u32);

/// The compare window's state.
pub struct CompareView {
    pub open: bool,
    pub slots: [Slot; 4],
    /// Image width in pixels.
    pub width: u32,
    /// Render again whenever the settings change (off: only on the button).
    pub auto: bool,
    /// The slot (1…3) the difference view compares with the first.
    pub diff_slot: usize,
    pub gain: f32,
    /// The map shown under the images: the scaled difference, or FLIP's.
    pub flip_map: bool,
    frames: Option<CompareFrames>,
    /// Counts renders (the pixel inspector's cache key).
    generation: u64,
    rendered: Option<CompareKey>,
    error: Option<String>,
    textures: Vec<egui::TextureHandle>,
    diff: Option<((usize, u32, u64, bool), egui::TextureHandle)>,
    rects: [Option<egui::Rect>; 4],
    /// The render under way.
    job: Option<Job<Result<CompareFrames, String>>>,
    /// The decomposition against the path-traced truth.
    pub truth: truth::TruthPanel,
}

impl Default for CompareView {
    fn default() -> Self {
        CompareView {
            open: false,
            slots: default_slots(),
            width: 320,
            auto: true,
            diff_slot: 1,
            gain: 8.0,
            flip_map: false,
            frames: None,
            generation: 0,
            rendered: None,
            error: None,
            textures: Vec::new(),
            diff: None,
            rects: [None; 4],
            job: None,
            truth: truth::TruthPanel::default(),
        }
    }
}

impl CompareView {
    /// The last render, when one succeeded.
    pub fn frames(&self) -> Option<&CompareFrames> {
        self.frames.as_ref()
    }

    /// Increases with every render.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Why the last render failed.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Where image `slot` was drawn in the last frame of the window (screen points).
    pub fn image_rect(&self, slot: usize) -> Option<egui::Rect> {
        self.rects.get(slot).copied().flatten()
    }

    pub fn depth_complexity(&self) -> Option<DepthComplexity> {
        self.frames.as_ref().map(CompareFrames::depth_complexity)
    }

    /// The image size: [`CompareView::width`] at the aspect of `render.width`×`render.height` (the image
    /// `hairlab render` makes).
    pub fn size(&self, render: &crate::render::RenderSettings) -> (u32, u32) {
        let h = (u64::from(self.width) * u64::from(render.height) / u64::from(render.width.max(1))) as u32;
        (self.width, h.clamp(1, 8192))
    }

    /// Whether a render for `settings` at `size` is due (auto mode and something changed).
    pub fn stale(&self, settings: &Settings, (w, h): (u32, u32)) -> bool {
        self.rendered
            .as_ref()
            .is_none_or(|(s, slots, rw, rh)| s != settings || *slots != self.slots || (*rw, *rh) != (w, h))
    }

    /// Starts rendering the four images of `settings` at `size` on a worker (a render under way is cancelled);
    /// [`CompareView::poll`] applies the outcome. A cancelled render is not started again by "auto" until the
    /// settings change.
    pub fn start(
        &mut self,
        source: CompareSource,
        settings: &Settings,
        size: (u32, u32),
        ctx: &egui::Context,
        gate: Option<JobGate>,
    ) {
        self.rendered = Some((settings.clone(), self.slots, size.0, size.1));
        let (settings, slots) = (settings.clone(), self.slots);
        self.job = Some(Job::spawn("compare", ctx, gate, move |ctl| {
            render_job(&source, &settings, &slots, size, ctl)
        }));
    }

    /// The render under way, as the job bar shows it.
    pub fn job_status(&self) -> Option<JobStatus> {
        self.job.as_ref().map(Job::status)
    }

    /// Takes the render's outcome when it is done (waiting up to `patience`): new frames replace the last ones,
    /// an error replaces them too (kept until the next render), a cancelled render leaves them. Returns the
    /// status line's message: `Ok` for news, `Err` for an error.
    pub fn poll(
        &mut self,
        patience: std::time::Duration,
        ctx: &egui::Context,
    ) -> Option<Result<String, String>> {
        let polled = self.job.as_ref()?.wait(patience);
        match polled {
            Poll::Running => None,
            Poll::Done(result) => {
                self.job = None;
                match result {
                    Ok(frames) => {
                        self.apply(frames, ctx);
                        None
                    }
                    Err(e) => {
                        self.error = Some(e.clone());
                        self.frames = None;
                        self.textures.clear();
                        Some(Err(e))
                    }
                }
            }
            Poll::Gone => {
                let cancelled = self.job.take().is_some_and(|j| j.cancelled());
                Some(if cancelled {
                    Ok("compare: cancelled; the previous images stay".to_string())
                } else {
                    Err("compare: the worker stopped without a result".to_string())
                })
            }
        }
    }

    /// Shows `frames` in place of the last ones.
    fn apply(&mut self, frames: CompareFrames, ctx: &egui::Context) {
        self.textures = frames
            .images
            .iter()
            .enumerate()
            .map(|(i, img)| ctx.load_texture(format!("compare{i}"), color_image(&img.image), NEAREST))
            .collect();
        self.frames = Some(frames);
        self.generation += 1;
        self.diff = None;
        self.error = None;
    }

    /// Draws the window's contents; `hide_times` replaces the measured times (UI snapshots).
    pub fn ui(&mut self, ui: &mut egui::Ui, settings: &Settings, hide_times: bool) -> Option<CompareAction> {
        let mut action = None;
        ui.horizontal(|ui| {
            if ui.button("Render").clicked() {
                action = Some(CompareAction::Render);
            }
            ui.checkbox(&mut self.auto, "auto")
                .on_hover_text("render again when the settings change (slow on software adapters)");
            egui::ComboBox::from_label("width")
                .selected_text(format!("{} px", self.width))
                .show_ui(ui, |ui| {
                    for &w in WIDTHS {
                        ui.selectable_value(&mut self.width, w, format!("{w} px"));
                    }
                });
            if let Some(f) = &self.frames {
                ui.label(format!(
                    "{}×{} · click hair to inspect the pixel, right-click an image to copy it",
                    f.width, f.height
                ));
                if ui
                    .button("Export images…")
                    .on_hover_text(
                        "each image, the difference and FLIP maps against the first, and metrics.csv",
                    )
                    .clicked()
                {
                    action = Some(CompareAction::Export);
                }
            }
        });
        if let Some(e) = &self.error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        self.rects = [None; 4];
        ui.columns(4, |cols| {
            for (i, ui) in cols.iter_mut().enumerate() {
                if let Some(p) = self.slot_column(ui, i, settings, hide_times) {
                    action = Some(CompareAction::Pick(p));
                }
            }
        });
        ui.separator();
        if let Some(p) = self.difference_ui(ui) {
            action = Some(CompareAction::Pick(p));
        }
        ui.separator();
        egui::CollapsingHeader::new("Against the path-traced truth")
            .id_salt("compare_truth")
            .show(ui, |ui| {
                if self.truth.ui(ui, settings) {
                    action = Some(CompareAction::Decompose);
                }
            });
        action
    }

    /// One slot: its technique combo, image and caption; a click on the image returns the pixel.
    fn slot_column(
        &mut self,
        ui: &mut egui::Ui,
        i: usize,
        settings: &Settings,
        hide_times: bool,
    ) -> Option<[u32; 2]> {
        let slot = &mut self.slots[i];
        egui::ComboBox::new(("compare_slot", i), format!("{}", i + 1))
            .selected_text(slot.text(settings))
            // Room for the label beside it.
            .width((ui.available_width() - 32.0).max(40.0))
            .show_ui(ui, |ui| {
                if i == 1 {
                    let text = Slot::Selected.text(settings);
                    ui.selectable_value(slot, Slot::Selected, text);
                }
                for t in registry::all() {
                    ui.selectable_value(slot, Slot::Technique(t.name()), t.info().label)
                        .on_hover_text(t.info().paper);
                }
                ui.selectable_value(slot, Slot::PathTraced, PATH_TRACED.1).on_hover_text(
                    "the scene path-traced on the CPU at render.spp samples per pixel (Chiang et al. 2016's fibres)",
                );
            });
        let (frames, tex) = (self.frames.as_ref()?, self.textures.get(i)?);
        let img = frames.images.get(i)?;
        let size = image_size(ui.available_width(), frames.width, frames.height);
        let response = ui.add(egui::Image::new((tex.id(), size)).sense(egui::Sense::click()));
        response.context_menu(|ui| {
            if ui.button("Copy image").clicked() {
                ui.ctx().copy_image(color_image(&img.image));
                ui.close();
            }
        });
        self.rects[i] = Some(response.rect);
        ui.label(caption(img, hide_times));
        clicked_pixel(&response, frames.width, frames.height)
    }

    /// The heat map of the chosen slot against the first, its gain, and the metrics of every slot.
    fn difference_ui(&mut self, ui: &mut egui::Ui) -> Option<[u32; 2]> {
        let frames = self.frames.as_ref()?;
        let mut pick = None;
        ui.horizontal_top(|ui| {
            ui.vertical(|ui| {
                ui.horizontal(|ui| {
                    egui::ComboBox::from_label(format!("− {}", frames.images[0].label))
                        .selected_text(frames.images[self.diff_slot].label)
                        .show_ui(ui, |ui| {
                            for (k, img) in frames.images.iter().enumerate().skip(1) {
                                ui.selectable_value(&mut self.diff_slot, k, img.label);
                            }
                        });
                });
                ui.horizontal(|ui| {
                    ui.selectable_value(&mut self.flip_map, false, "difference");
                    ui.selectable_value(&mut self.flip_map, true, "FLIP map");
                });
                if !self.flip_map {
                    ui.add(
                        egui::Slider::new(&mut self.gain, GAIN_RANGE)
                            .logarithmic(true)
                            .text("gain ×"),
                    );
                }
                let key = (
                    self.diff_slot,
                    self.gain.to_bits(),
                    self.generation,
                    self.flip_map,
                );
                if self.diff.as_ref().is_none_or(|(k, _)| *k != key) {
                    let image = map_image(frames, self.diff_slot, self.flip_map, self.gain);
                    let tex = ui.ctx().load_texture("compare_difference", image, NEAREST);
                    self.diff = Some((key, tex));
                }
                if let Some((_, tex)) = &self.diff {
                    // As large as the images above (a size from the available width would feed back into the
                    // window's).
                    let width = self.rects[0].map_or(frames.width as f32, |r| r.width());
                    let size = image_size(width, frames.width, frames.height);
                    let r = ui.add(egui::Image::new((tex.id(), size)).sense(egui::Sense::click()));
                    r.context_menu(|ui| {
                        if ui.button("Copy map").clicked() {
                            let map = map_image(frames, self.diff_slot, self.flip_map, self.gain);
                            ui.ctx().copy_image(map);
                            ui.close();
                        }
                    });
                    pick = clicked_pixel(&r, frames.width, frames.height);
                    ui.label(if self.flip_map {
                        format!(
                            "FLIP of {} against {} (magma: black 0, light yellow the largest)",
                            frames.images[self.diff_slot].label, frames.images[0].label
                        )
                    } else {
                        format!(
                            "|{} − {}| max channel × {:.0} (white: ≥ {:.0}/255)",
                            frames.images[self.diff_slot].label,
                            frames.images[0].label,
                            self.gain,
                            255.0 / self.gain
                        )
                    });
                }
            });
            metrics_grid(ui, frames);
        });
        pick
    }
}

const NEAREST: egui::TextureOptions = egui::TextureOptions::NEAREST;

/// The map under the images: FLIP's heat map of `slot` against the first image, or their difference × `gain`.
fn map_image(frames: &CompareFrames, slot: usize, flip: bool, gain: f32) -> egui::ColorImage {
    let (test, reference) = (&frames.images[slot].image, &frames.images[0].image);
    if flip {
        let map = crate::transparency::FlipMap::new(test, reference).heat_map();
        egui::ColorImage::from_rgb([map.width() as usize, map.height() as usize], map.as_raw())
    } else {
        color_image(&difference_image(test, reference, gain))
    }
}

fn color_image(img: &RgbaImage) -> egui::ColorImage {
    egui::ColorImage::from_rgba_unmultiplied([img.width() as usize, img.height() as usize], img.as_raw())
}

/// The largest size of a `w`×`h` image in `width` points, never above 2× its pixels.
fn image_size(width: f32, w: u32, h: u32) -> egui::Vec2 {
    let scale = (width / w.max(1) as f32).min(2.0);
    egui::vec2(w as f32 * scale, h as f32 * scale)
}

/// The pixel of a `w`×`h` image under a click on `response`.
fn clicked_pixel(response: &egui::Response, w: u32, h: u32) -> Option<[u32; 2]> {
    if !response.clicked() {
        return None;
    }
    let pos = response.interact_pointer_pos()?;
    let r = response.rect;
    let u = ((pos.x - r.min.x) / r.width()).clamp(0.0, 1.0);
    let v = ((pos.y - r.min.y) / r.height()).clamp(0.0, 1.0);
    Some([
        ((u * w as f32) as u32).min(w.saturating_sub(1)),
        ((v * h as f32) as u32).min(h.saturating_sub(1)),
    ])
}

/// "label — GPU x ms · y fps · n geometry passes".
fn caption(img: &CompareImage, hide_times: bool) -> String {
    let time = match (img.gpu_ms(), img.cpu_seconds) {
        _ if hide_times => "GPU time hidden".to_string(),
        (_, Some(s)) => format!("CPU {s:.1} s"),
        (Some(ms), None) => format!("GPU {ms:.2} ms · {:.0} fps", 1000.0 / ms.max(1e-6)),
        (None, None) => "GPU: no timestamp queries".to_string(),
    };
    format!("{} — {time} · {} geometry passes", img.label, img.geometry_passes)
}

/// A metric's name and how it is written.
type MetricRow = (&'static str, fn(&ImageMetrics) -> String);

/// Every metric of each slot against the first.
fn metrics_grid(ui: &mut egui::Ui, frames: &CompareFrames) {
    let hair = frames.hair.iter().filter(|&&h| h).count();
    ui.vertical(|ui| {
        ui.strong(format!(
            "against {} · hair: {hair} pixels (exact list non-empty)",
            frames.images[0].label
        ));
        egui::Grid::new("compare_metrics").striped(true).show(ui, |ui| {
            ui.label("");
            for (k, img) in frames.images.iter().enumerate().skip(1) {
                ui.strong(format!("{} · {}", k + 1, img.label));
            }
            ui.end_row();
            let rows: [MetricRow; 16] = [
                ("RMSE all", |m| format!("{:.5}", m.rmse)),
                ("PSNR all dB", |m| format!("{:.2}", m.psnr)),
                ("RMSE hair", |m| format!("{:.5}", m.rmse_hair)),
                ("PSNR hair dB", |m| format!("{:.2}", m.psnr_hair)),
                ("SSIM", |m| format!("{:.4}", m.ssim)),
                ("SSIM hair", |m| format!("{:.4}", m.ssim_hair)),
                ("max /255", |m| format!("{:.0}", m.max_error)),
                ("p99 /255", |m| format!("{:.0}", m.p99)),
                ("> 1/255", |m| format!("{:.2} %", 100.0 * m.share_over[0])),
                ("> 4/255", |m| format!("{:.2} %", 100.0 * m.share_over[1])),
                ("> 8/255", |m| format!("{:.2} %", 100.0 * m.share_over[2])),
                ("contrast retention", |m| format!("{:.3}", m.contrast_retention)),
                ("FLIP all", |m| format!("{:.4}", m.flip.mean)),
                ("FLIP hair", |m| format!("{:.4}", m.flip.mean_hair)),
                ("FLIP hair p95", |m| format!("{:.4}", m.flip.p95_hair)),
                ("FLIP hair p99", |m| format!("{:.4}", m.flip.p99_hair)),
            ];
            for (name, value) in rows {
                ui.label(name);
                for img in &frames.images[1..] {
                    ui.label(value(&img.metrics));
                }
                ui.end_row();
            }
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heat_ramp_ends_and_stops() {
        assert_eq!(heat(0.0), [0, 0, 0]);
        assert_eq!(heat(1.0), [255, 255, 255]);
        assert_eq!(heat(2.0), [255, 255, 255]);
        // The second stop, [0.35, 0, 0.55] × 255 rounded, and half way from it to the third, [0.9, 0.1, 0.1].
        assert_eq!(heat(0.25), [89, 0, 140]);
        assert_eq!(heat(0.375), [159, 13, 83]);
    }

    #[test]
    fn difference_is_the_max_channel_error_times_the_gain() {
        let a = RgbaImage::from_pixel(2, 1, image::Rgba([10, 20, 30, 255]));
        let mut b = a.clone();
        // Pixel 1 differs by 4, 0 and 1 steps: max channel 4.
        b.put_pixel(1, 0, image::Rgba([14, 20, 29, 255]));
        let d = difference_image(&a, &b, 1.0);
        assert_eq!(d.get_pixel(0, 0).0, [0, 0, 0, 255]);
        let [r, g, bl] = heat(4.0 / 255.0);
        assert_eq!(d.get_pixel(1, 0).0, [r, g, bl, 255]);
        // Gain 64: 4 steps become 256/255, clamped to white.
        assert_eq!(
            difference_image(&a, &b, 64.0).get_pixel(1, 0).0,
            [255, 255, 255, 255]
        );
    }

    #[test]
    fn default_slots_start_with_the_reference_and_the_selected_technique() {
        let s = default_slots();
        assert_eq!(s[0], Slot::Technique(registry::reference().name()));
        assert_eq!(s[1], Slot::Selected);
        for slot in &s[2..] {
            let Slot::Technique(name) = slot else {
                panic!("{slot:?}")
            };
            assert!(registry::find(name).is_ok(), "{name}");
        }
    }
}
