//! The window's file dialogs (open a scene, save a screenshot or a preset) and what their answers do.

use super::*;

impl HairlabApp {
    /// Opens a native file dialog on a worker thread so the window never freezes.
    pub(super) fn open_dialog(&mut self, purpose: DialogPurpose, ctx: &egui::Context) {
        if self.dialog.is_some() {
            return;
        }
        let (tx, rx) = mpsc::channel();
        let ctx = ctx.clone();
        std::thread::spawn(move || {
            type Pick = std::pin::Pin<Box<dyn std::future::Future<Output = Option<rfd::FileHandle>> + Send>>;
            let d = rfd::AsyncFileDialog::new();
            let fut: Pick = match purpose {
                DialogPurpose::OpenScene => Box::pin(
                    d.add_filter(
                        "hair, glTF, TressFX, USC-HairSalon or USD",
                        crate::scene::load::SCENE_EXTENSIONS,
                    )
                    .set_title("Load strands")
                    .pick_file(),
                ),
                DialogPurpose::SaveScreenshot => Box::pin(
                    d.add_filter("PNG", &["png"])
                        .set_file_name("hairlab.png")
                        .set_title("Export screenshot")
                        .save_file(),
                ),
                DialogPurpose::LoadPreset => Box::pin(
                    d.add_filter("preset", &["toml"])
                        .set_directory("presets")
                        .pick_file(),
                ),
                DialogPurpose::SavePreset => Box::pin(
                    d.add_filter("preset", &["toml"])
                        .set_directory("presets")
                        .set_file_name("my-preset.toml")
                        .save_file(),
                ),
                DialogPurpose::ExportCurves => Box::pin(
                    d.add_filter("CSV", &["csv"])
                        .set_file_name("texel-curves.csv")
                        .set_title("Export texel curves")
                        .save_file(),
                ),
                DialogPurpose::Export(what) => Box::pin(d.set_title(what.title()).pick_folder()),
            };
            let picked = pollster::block_on(fut).map(|h| h.path().to_path_buf());
            let _ = tx.send(picked);
            ctx.request_repaint();
        });
        self.dialog = Some((purpose, rx));
    }

    pub(super) fn poll_dialog(&mut self) {
        let Some((purpose, rx)) = &self.dialog else { return };
        let purpose = *purpose;
        let picked = match rx.try_recv() {
            Ok(p) => p,
            Err(mpsc::TryRecvError::Empty) => return,
            Err(mpsc::TryRecvError::Disconnected) => None,
        };
        self.dialog = None;
        let Some(path) = picked else {
            self.info(
                "no file chosen (if no dialog appeared, no desktop portal is running: drop files on the window, \
                 press F12 for a quick screenshot, or use the CLI)",
            );
            return;
        };
        match purpose {
            DialogPurpose::OpenScene => self.open_scene_file(path),
            DialogPurpose::SaveScreenshot => self.screenshot_request = Some(path),
            DialogPurpose::LoadPreset => match Settings::load_preset(&path.to_string_lossy(), &[]) {
                Ok(s) => {
                    self.replace_settings(s);
                    self.info(format!("preset loaded: {}", path.display()));
                }
                Err(e) => self.error(format!("{e:#}")),
            },
            DialogPurpose::SavePreset => match self.settings.save_preset(&path) {
                Ok(()) => self.info(format!("preset saved: {}", path.display())),
                Err(e) => self.error(format!("{e:#}")),
            },
            DialogPurpose::ExportCurves => self.export_inspector_csv(&path),
            DialogPurpose::Export(what) => self.export(what, &path),
        }
    }

    pub(super) fn open_scene_file(&mut self, path: PathBuf) {
        self.settings.scene.file = Some(path);
        self.rebuild_scene();
    }

    pub(super) fn save_screenshot(&mut self, path: PathBuf) {
        let Some(r) = &self.renderer else {
            self.error("no viewport to save");
            return;
        };
        // The path-traced view saves the image it shows (at its own size), the raster view its frame.
        let shown = match self.path_view.latest() {
            Some(p) if self.settings.render.mode == crate::render::render_settings::RenderMode::Path => {
                Ok(p.image)
            }
            _ => r.read_output().map_err(anyhow::Error::from),
        };
        let result = shown.and_then(|img| {
            crate::io::write_png(&path, &img)?;
            Ok((img.width(), img.height()))
        });
        match result {
            Ok((w, h)) => self.info(format!("screenshot saved: {} ({w}×{h})", path.display())),
            Err(e) => self.error(format!("screenshot failed: {e:#}")),
        }
    }
}
