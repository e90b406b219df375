//! The window's animation export: frames `A..B` of the scene's motion at a chosen image size, as a numbered PNG
//! sequence in a folder or one looping animated GIF, rendered offscreen by [`crate::animation`] and streamed by
//! [`AnimationOut::write`] — the code of `hairlab render --frames A..B --out …`, so the files are the CLI's bit
//! for bit. It is a [`Job`] in the window's job bar (progress, time left, Cancel). Each frame is written as it
//! renders into a temporary file or folder beside the target, renamed into place once every frame is in, so a
//! cancelled or failed export leaves nothing at the target.

use super::jobs::{Job, JobGate, JobStatus, Poll};
use crate::animation::{AnimationOut, render_frames_on};
use crate::gpu::Gpu;
use crate::settings::Settings;
use std::path::PathBuf;

/// The export window's state.
#[derive(Default)]
pub struct AnimationExport {
    pub open: bool,
    /// Frames `start..end` (end exclusive).
    pub start: u32,
    pub end: u32,
    pub width: u32,
    pub height: u32,
    /// One animated GIF (else a numbered PNG sequence in a folder).
    pub gif: bool,
    /// The GIF file or the folder.
    pub path: String,
    /// The export under way: what was written, or the error; `None` when cancelled.
    job: Option<Job<Result<String, String>>>,
    /// The last export's outcome.
    outcome: Option<Result<String, String>>,
}

impl AnimationExport {
    /// Opens the window on the whole motion of `frame_count` frames at the render size of `settings`.
    pub fn show(&mut self, frame_count: u32, settings: &Settings) {
        self.open = true;
        if self.end == 0 || self.end > frame_count {
            (self.start, self.end) = (0, frame_count);
        }
        if self.width == 0 {
            (self.width, self.height) = (settings.render.width, settings.render.height);
        }
        if self.path.is_empty() {
            self.path = "hairlab-frames".to_string();
        }
    }

    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// The last export's outcome: what was written, or the error.
    pub fn outcome(&self) -> Option<&Result<String, String>> {
        self.outcome.as_ref()
    }

    /// The export under way, as the job bar shows it.
    pub fn job_status(&self) -> Option<JobStatus> {
        self.job.as_ref().map(Job::status)
    }

    /// Starts rendering and writing with `gpu` and the window's `settings` (a job; an export under way is
    /// cancelled).
    fn start(&mut self, gpu: Gpu, settings: &Settings, ctx: &egui::Context, gate: Option<JobGate>) {
        self.job = None;
        let mut s = settings.clone();
        (s.render.width, s.render.height) = (self.width, self.height);
        if let Err(e) = s.validate() {
            self.outcome = Some(Err(format!("export size: {e:#}")));
            return;
        }
        let path = PathBuf::from(self.path.trim());
        let out = if self.gif {
            AnimationOut::Gif {
                file: path,
                fps: s.motion.fps,
            }
        } else {
            AnimationOut::Pngs {
                dir: path,
                end: self.end,
            }
        };
        if let Err(e) = out.check() {
            self.outcome = Some(Err(format!("{e:#}")));
            return;
        }
        let frames: Vec<u32> = (self.start..self.end).collect();
        let range = format!("{}..{}", self.start, self.end);
        self.outcome = None;
        self.job = Some(Job::spawn("animation export", ctx, gate, move |ctl| {
            let result = out
                .write(|sink| render_frames_on(&gpu, &mut s, &frames, &mut |_| {}, &mut ctl.clone(), sink));
            let (how, target) = match &out {
                AnimationOut::Gif { file, .. } => ("an animated GIF", file),
                AnimationOut::Pngs { dir, .. } => ("PNG files", dir),
            };
            match result {
                Ok(()) => Some(Ok(format!(
                    "wrote frames {range} to {} as {how}",
                    target.display()
                ))),
                Err(_) if ctl.cancelled() => None,
                Err(e) => Some(Err(format!("{e:#}"))),
            }
        }));
    }

    /// Stops the export under way; nothing is written.
    pub fn cancel(&mut self) {
        if self.job.take().is_some() {
            self.outcome = Some(Ok("the export was cancelled: nothing was written".to_string()));
        }
    }

    /// Takes the export's outcome once it is done.
    pub fn poll(&mut self) {
        let Some(job) = &self.job else { return };
        match job.poll() {
            Poll::Running => {}
            Poll::Done(outcome) => {
                self.job = None;
                self.outcome = Some(outcome);
            }
            Poll::Gone if job.cancelled() => self.cancel(),
            Poll::Gone => {
                self.job = None;
                self.outcome = Some(Err("the export stopped without a result".to_string()));
            }
        }
    }

    /// The window's contents, for a motion of `frame_count` frames; `gpu` gives the device an export runs on,
    /// `gate` the test hook of [`Job::spawn`].
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        frame_count: u32,
        settings: &Settings,
        gpu: impl FnOnce() -> Option<Gpu>,
        gate: Option<JobGate>,
    ) {
        let last = frame_count.max(1);
        egui::Grid::new("animation_export").num_columns(2).show(ui, |ui| {
            ui.label("frames");
            ui.horizontal(|ui| {
                let named = |ui: &mut egui::Ui, v: &mut u32, range, name: &str| {
                    let label = ui.label(name);
                    ui.add(egui::DragValue::new(v).range(range)).labelled_by(label.id);
                };
                named(ui, &mut self.start, 0..=last - 1, "from");
                named(ui, &mut self.end, 1..=last, "to (excluded)");
            });
            ui.end_row();
            ui.label("size");
            ui.horizontal(|ui| {
                let named = |ui: &mut egui::Ui, v: &mut u32, name: &str| {
                    let label = ui.label(name);
                    ui.add(egui::DragValue::new(v).range(16..=8192))
                        .labelled_by(label.id);
                };
                named(ui, &mut self.width, "width");
                named(ui, &mut self.height, "height");
            });
            ui.end_row();
            ui.label("as");
            ui.horizontal(|ui| {
                ui.selectable_value(&mut self.gif, false, "PNG sequence");
                ui.selectable_value(&mut self.gif, true, "animated GIF");
            });
            ui.end_row();
            let label = ui.label(if self.gif { "GIF file" } else { "folder" });
            ui.add(egui::TextEdit::singleline(&mut self.path).desired_width(260.0))
                .labelled_by(label.id);
            ui.end_row();
        });
        self.end = self.end.max(self.start + 1).min(last);
        self.start = self.start.min(self.end - 1);
        let export = ui
            .add_enabled(!self.is_running(), egui::Button::new("Export"))
            .on_disabled_hover_text("exporting: the job bar under the viewport shows how far, with Cancel");
        if export.clicked() {
            match gpu() {
                Some(g) => self.start(g, settings, ui.ctx(), gate),
                None => self.outcome = Some(Err("no GPU renderer".to_string())),
            }
        }
        match &self.outcome {
            Some(Ok(m)) => {
                ui.label(m);
            }
            Some(Err(e)) => {
                ui.colored_label(ui.visuals().error_fg_color, e);
            }
            None => {}
        }
    }
}
