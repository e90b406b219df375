//! The window's live shaders (`--shaders DIR`, `crate::live_shaders`): the folder is polled every half second; a
//! change that validates rebuilds every pipeline, one that does not shows its `file:line:column` error in the
//! message line while the shaders in use stay.

use super::HairlabApp;
use crate::live_shaders::{POLL_INTERVAL, Watch};
use std::path::Path;

impl HairlabApp {
    /// Reads the shaders from `dir` over the embedded ones from the next frame on, and again whenever it changes.
    pub fn watch_shaders(&mut self, dir: &Path) {
        self.shaders = Some(Watch::new(dir));
    }

    pub(super) fn poll_shaders(&mut self, ctx: &egui::Context) {
        let Some(watch) = &mut self.shaders else {
            return;
        };
        ctx.request_repaint_after(POLL_INTERVAL);
        match watch.poll() {
            None => {}
            Some(Ok(folder)) => {
                if let Some(r) = &mut self.renderer {
                    r.reload_shaders();
                }
                self.last_rendered = None;
                let (replaced, embedded) = folder.coverage();
                self.info(format!(
                    "shaders: {replaced} from {}, {embedded} embedded",
                    folder.dir().display()
                ));
            }
            Some(Err(e)) => self.error(format!("{e} (the shaders in use stay)")),
        }
    }
}
