//! The window's animation export: frames `A..B` of the scene's motion at a chosen image size, as a numbered PNG
//! sequence in a folder or one looping animated GIF, rendered offscreen by [`crate::animation`] — the
//! code of `hairlab render --frames A..B --out …`, so the files are the CLI's bit for bit — on a worker thread
//! with a progress bar and Cancel. Nothing is written until every frame is rendered, and each file is written
//! whole, so a cancelled or failed export leaves no partial file.

use crate::animation::{animated_gif, render_frames_on, write_png_sequence};
use crate::gpu::Gpu;
use crate::settings::Settings;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};

/// What the worker tells the window.
enum Message {
    /// Frames rendered so far.
    Rendered(u32),
    Done(Result<String, String>),
}

/// An export under way.
struct Running {
    messages: mpsc::Receiver<Message>,
    cancel: Arc<AtomicBool>,
    rendered: u32,
    total: u32,
}

/// A stop asked through Cancel.
#[derive(Debug, thiserror::Error)]
#[error("the export was cancelled")]
struct Cancelled;

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
    running: Option<Running>,
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
        self.running.is_some()
    }

    /// The last export's outcome: what was written, or the error.
    pub fn outcome(&self) -> Option<&Result<String, String>> {
        self.outcome.as_ref()
    }

    /// Starts rendering and writing on a worker thread with `gpu` and the window's `settings`.
    fn start(&mut self, gpu: Gpu, settings: &Settings, ctx: &egui::Context) {
        let mut s = settings.clone();
        (s.render.width, s.render.height) = (self.width, self.height);
        if let Err(e) = s.validate() {
            self.outcome = Some(Err(format!("export size: {e:#}")));
            return;
        }
        let path = PathBuf::from(self.path.trim());
        if self.gif
            && let Err(e) = crate::io::check_output(&path, "gif")
        {
            self.outcome = Some(Err(format!("{e:#}")));
            return;
        }
        let (tx, rx) = mpsc::channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let (stop, ctx) = (cancel.clone(), ctx.clone());
        let (frames, end, gif) = ((self.start..self.end).collect::<Vec<u32>>(), self.end, self.gif);
        std::thread::spawn(move || {
            let mut images = Vec::with_capacity(frames.len());
            let mut keep = |k: u32, image: image::RgbaImage| -> anyhow::Result<()> {
                if stop.load(Ordering::Relaxed) {
                    return Err(Cancelled.into());
                }
                images.push((k, image));
                let _ = tx.send(Message::Rendered(images.len() as u32));
                ctx.request_repaint();
                Ok(())
            };
            let written = render_frames_on(&gpu, &mut s, &frames, &mut |_| {}, &mut keep).and_then(|()| {
                let range = format!("{}..{end}", frames[0]);
                if gif {
                    let only: Vec<image::RgbaImage> = images.into_iter().map(|(_, i)| i).collect();
                    crate::io::write_atomic(&path, &animated_gif(&only, s.motion.fps)?)?;
                    Ok(format!(
                        "wrote frames {range} to {} as an animated GIF",
                        path.display()
                    ))
                } else {
                    write_png_sequence(&path, &images, end)?;
                    Ok(format!("wrote frames {range} to {} as PNG files", path.display()))
                }
            });
            let _ = tx.send(Message::Done(written.map_err(|e| format!("{e:#}"))));
            ctx.request_repaint();
        });
        self.outcome = None;
        self.running = Some(Running {
            messages: rx,
            cancel,
            rendered: 0,
            total: self.end - self.start,
        });
    }

    /// Stops the export under way; nothing is written.
    pub fn cancel(&mut self) {
        if let Some(r) = self.running.take() {
            r.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Takes the worker's messages.
    pub fn poll(&mut self) {
        let Some(r) = &mut self.running else { return };
        while let Ok(m) = r.messages.try_recv() {
            match m {
                Message::Rendered(n) => r.rendered = n,
                Message::Done(outcome) => {
                    self.outcome = Some(outcome);
                    self.running = None;
                    return;
                }
            }
        }
    }

    /// The window's contents, for a motion of `frame_count` frames; `gpu` gives the device an export runs on.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        frame_count: u32,
        settings: &Settings,
        gpu: impl FnOnce() -> Option<Gpu>,
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
        ui.horizontal(|ui| {
            if let Some(r) = &self.running {
                ui.add(
                    egui::ProgressBar::new(r.rendered as f32 / r.total.max(1) as f32)
                        .desired_width(220.0)
                        .text(format!("frame {} of {}", r.rendered, r.total)),
                );
                if ui.button("Cancel").clicked() {
                    self.cancel();
                }
            } else if ui.button("Export").clicked() {
                match gpu() {
                    Some(g) => self.start(g, settings, ui.ctx()),
                    None => self.outcome = Some(Err("no GPU renderer".to_string())),
                }
            }
        });
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
