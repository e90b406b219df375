//! Undo and redo of every settings change, and the Help window listing the window's shortcuts.
//!
//! Every frame feeds the whole [`Settings`] to egui's [`Undoer`]: a change becomes an undo step once the settings
//! have stayed the same for [`STABLE_TIME`] seconds, so a slider drag (many small changes a frame apart) is one
//! step. A preset or a dropped `.toml` that replaces every setting is committed as its own step at once
//! ([`HairlabApp::replace_settings`]). Undoing restores the settings; the scene is rebuilt only when the scene
//! settings differ from those of the loaded scene.

use super::HairlabApp;
use crate::settings::Settings;
use egui::util::undoer::{self, Undoer};

/// Seconds the settings must stay unchanged before a change becomes an undo step (egui's default).
pub const STABLE_TIME: f32 = 1.0;

/// The undoer's settings: 100 steps, a step once the settings are stable for [`STABLE_TIME`] s, and at least one
/// step every 30 s of continuous change.
pub fn undoer_settings() -> undoer::Settings {
    undoer::Settings {
        max_undos: 100,
        stable_time: STABLE_TIME,
        auto_save_interval: 30.0,
    }
}

/// A new undoer with [`undoer_settings`].
pub fn new_undoer() -> Undoer<Settings> {
    Undoer::with_settings(undoer_settings())
}

/// The window's shortcuts, for the Help window: (keys, what they do).
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("Left drag", "orbit the camera"),
    ("Middle drag / Shift + left drag", "pan"),
    ("Wheel", "zoom"),
    ("Right drag", "move the light"),
    ("Click on hair", "inspect its light-map texel"),
    ("F", "frame the scene"),
    ("Ctrl+S", "export a screenshot (file dialog)"),
    ("F12", "save hairlab-<time>.png in the working folder"),
    ("Ctrl+Z", "undo a settings change"),
    ("Ctrl+Shift+Z / Ctrl+Y", "redo"),
    ("Space", "play / pause the scene's motion"),
    ("Left / Right", "one motion frame back / forward"),
    ("F1", "this help"),
    ("Drop a file", ".toml: load a preset; otherwise open a scene"),
];

impl HairlabApp {
    /// Replaces every setting (a preset or a dropped `.toml`) as one undo step and rebuilds the scene: the
    /// settings before (even in the middle of a change) are committed as a step first.
    pub(super) fn replace_settings(&mut self, settings: Settings) {
        self.undoer.add_undo(&self.settings);
        self.settings = settings;
        // The new settings become the next step as the frames feed them (with any adjustment the rebuild or the
        // next frames make, such as framing the camera), so one Ctrl+Z returns to the settings before.
        self.rebuild_scene();
    }

    /// Whether there is a settings change to undo.
    pub fn can_undo(&self) -> bool {
        self.undoer.has_undo(&self.settings)
    }

    /// Whether there is an undone settings change to redo.
    pub fn can_redo(&self) -> bool {
        self.undoer.has_redo(&self.settings)
    }

    /// Undoes the last settings change (no-op when there is none).
    pub fn undo(&mut self) {
        if let Some(s) = self.undoer.undo(&self.settings).cloned() {
            self.restore(s);
        }
    }

    /// Redoes the last undone settings change (no-op when there is none).
    pub fn redo(&mut self) {
        if let Some(s) = self.undoer.redo(&self.settings).cloned() {
            self.restore(s);
        }
    }

    fn restore(&mut self, settings: Settings) {
        self.settings = settings;
        if self.built_scene.as_ref() != Some(&self.settings.scene)
            || self.timeline.opened_with() != Some(&self.settings.motion)
        {
            self.rebuild_scene();
        }
    }

    /// Ctrl+Z, Ctrl+Shift+Z, Ctrl+Y and F1 (not while a text field has the keyboard: it has its own undo).
    pub(super) fn undo_input(&mut self, ctx: &egui::Context) {
        if ctx.text_edit_focused() {
            return;
        }
        let shift_cmd = egui::Modifiers::COMMAND | egui::Modifiers::SHIFT;
        let (redo, undo, help) = ctx.input_mut(|i| {
            // Ctrl+Shift+Z first: the plain Ctrl+Z pattern also matches it.
            let redo = i.consume_key(shift_cmd, egui::Key::Z)
                | i.consume_key(egui::Modifiers::COMMAND, egui::Key::Y);
            let undo = i.consume_key(egui::Modifiers::COMMAND, egui::Key::Z);
            (redo, undo, i.consume_key(egui::Modifiers::NONE, egui::Key::F1))
        });
        if redo {
            self.redo();
        }
        if undo {
            self.undo();
        }
        if help {
            self.help_open = !self.help_open;
        }
    }

    /// Feeds this frame's settings to the undoer (after every widget and input of the frame changed them).
    pub(super) fn feed_undoer(&mut self, ctx: &egui::Context) {
        let now = ctx.input(|i| i.time);
        self.undoer.feed_state(now, &self.settings);
        if self.undoer.is_in_flux() {
            // A frame once the stable time has passed takes the step, even with no input meanwhile: otherwise the
            // next change, however much later, would join this one.
            ctx.request_repaint_after(std::time::Duration::from_secs_f32(STABLE_TIME));
        }
    }

    /// The Undo, Redo, Help and About buttons.
    pub(super) fn undo_buttons(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let can_undo = self.can_undo();
            if ui
                .add_enabled(can_undo, egui::Button::new("Undo"))
                .on_hover_text("Ctrl+Z: undo the last settings change")
                .clicked()
            {
                self.undo();
            }
            let can_redo = self.can_redo();
            if ui
                .add_enabled(can_redo, egui::Button::new("Redo"))
                .on_hover_text("Ctrl+Shift+Z or Ctrl+Y")
                .clicked()
            {
                self.redo();
            }
            if ui
                .button("Help")
                .on_hover_text("F1: the window's shortcuts")
                .clicked()
            {
                self.help_open = !self.help_open;
            }
            if ui
                .button("About")
                .on_hover_text("version, adapter, and every method's and technique's citation")
                .clicked()
            {
                self.about_open = !self.about_open;
            }
        });
    }

    /// The Help window: every shortcut of the window.
    pub(super) fn help_window(&mut self, ctx: &egui::Context) {
        let mut open = self.help_open;
        egui::Window::new("Help")
            .open(&mut open)
            .resizable(false)
            .show(ctx, |ui| {
                egui::Grid::new("shortcuts")
                    .num_columns(2)
                    .striped(true)
                    .show(ui, |ui| {
                        for (keys, what) in SHORTCUTS {
                            ui.strong(*keys);
                            ui.label(*what);
                            ui.end_row();
                        }
                    });
                if ui.button("About hairlab").clicked() {
                    self.about_open = true;
                }
            });
        self.help_open = open;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn app_undo_a_drag_of_many_small_changes_is_one_step() {
        let mut u = new_undoer();
        let mut s = Settings::default();
        let original = s.clone();
        let mut t = 0.0;
        u.feed_state(t, &s);
        // A slider drag: 120 frames at 60 Hz, each a small change.
        for _ in 0..120 {
            t += 1.0 / 60.0;
            s.render.hair_alpha += 0.001;
            u.feed_state(t, &s);
        }
        let dragged = s.clone();
        // The drag ends; the settings stay unchanged past the stable time.
        for _ in 0..90 {
            t += 1.0 / 60.0;
            u.feed_state(t, &s);
        }
        assert!(u.has_undo(&s));
        let back = u.undo(&s).cloned().expect("one undo step");
        assert_eq!(back, original);
        assert!(!u.has_undo(&back), "the drag is more than one step");
        assert_eq!(u.redo(&back).cloned(), Some(dragged));
    }
}
