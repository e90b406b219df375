//! The timeline of a moving scene (`[motion]`): play and pause (Space), step one frame (Left and Right), scrub, loop,
//! playback speed, and the frame and time shown. Frame `k` is the motion's frame `k` whatever was played before
//! it (every motion source is deterministic), so stepping, scrubbing and playing show the same bits; the window
//! moves the renderer's strands through its one write path (`Renderer::update_points`) and every panel stays
//! live while playing.

use crate::motion::{Motion, MotionSettings};
use glam::Vec3;

/// Playback speeds offered.
const SPEEDS: [f32; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];

pub struct Timeline {
    /// The opened motion; `None` when the scene stands still.
    motion: Option<Motion>,
    /// Frames in the motion and its rate.
    count: u32,
    fps: f32,
    /// The frame shown.
    frame: u32,
    playing: bool,
    looping: bool,
    speed: f32,
    /// Seconds into the motion while playing (the frame shown is `floor(clock · fps)`).
    clock: f64,
    /// The frame whose points the renderer holds.
    uploaded: Option<u32>,
    /// The `[motion]` settings the motion was opened with.
    opened_with: Option<MotionSettings>,
}

impl Default for Timeline {
    fn default() -> Self {
        Timeline {
            motion: None,
            count: 1,
            fps: 30.0,
            frame: 0,
            playing: false,
            looping: true,
            speed: 1.0,
            clock: 0.0,
            uploaded: None,
            opened_with: None,
        }
    }
}

impl Timeline {
    /// Takes the scene's new motion (a still one: no timeline), at frame 0, paused; the renderer holds frame 0
    /// (the scene as built).
    pub fn set_motion(&mut self, motion: Motion, settings: &MotionSettings) {
        *self = Timeline {
            count: motion.frame_count(settings).max(1),
            fps: settings.fps,
            motion: (!motion.is_still()).then_some(motion),
            uploaded: Some(0),
            opened_with: Some(settings.clone()),
            looping: self.looping,
            speed: self.speed,
            ..Timeline::default()
        };
    }

    /// The `[motion]` settings of the motion held (to notice when it must be opened again).
    pub fn opened_with(&self) -> Option<&MotionSettings> {
        self.opened_with.as_ref()
    }

    /// Whether the scene moves (the timeline is shown).
    pub fn is_moving(&self) -> bool {
        self.motion.is_some()
    }

    pub fn frame(&self) -> u32 {
        self.frame
    }

    pub fn frame_count(&self) -> u32 {
        self.count
    }

    pub fn is_playing(&self) -> bool {
        self.playing
    }

    /// Shows frame `k` (clamped to the motion), paused.
    pub fn seek(&mut self, k: u32) {
        self.playing = false;
        self.show(k.min(self.count - 1));
    }

    pub fn toggle_play(&mut self) {
        if !self.is_moving() {
            return;
        }
        if !self.playing && !self.looping && self.frame + 1 >= self.count {
            self.show(0);
        }
        self.playing = !self.playing;
    }

    /// One frame forward (`+1`) or back (`-1`), paused; wraps when looping.
    pub fn step(&mut self, by: i64) {
        self.playing = false;
        let n = self.count as i64;
        let k = self.frame as i64 + by;
        let k = if self.looping {
            k.rem_euclid(n)
        } else {
            k.clamp(0, n - 1)
        };
        self.show(k as u32);
    }

    fn show(&mut self, k: u32) {
        self.frame = k;
        self.clock = k as f64 / self.fps as f64;
    }

    /// Moves the clock by `dt` seconds of wall time at the playback speed.
    pub fn advance(&mut self, dt: f64) {
        if !self.playing {
            return;
        }
        self.clock += dt * self.speed as f64;
        let mut k = (self.clock * self.fps as f64).floor() as u64;
        if k >= self.count as u64 {
            if self.looping {
                k %= self.count as u64;
                self.clock = k as f64 / self.fps as f64;
            } else {
                k = self.count as u64 - 1;
                self.playing = false;
            }
        }
        self.frame = k as u32;
    }

    /// The points of the frame shown when the renderer does not hold them yet; the caller uploads them and
    /// then calls [`Timeline::uploaded`].
    pub fn pending(&mut self) -> Option<anyhow::Result<&[Vec3]>> {
        if self.uploaded == Some(self.frame) {
            return None;
        }
        let motion = self.motion.as_mut()?;
        Some(motion.frame(self.frame))
    }

    /// The pose of the meshes on the root frame at the frame shown (their indices and transform), `None` when
    /// nothing moves them.
    pub fn mesh_pose(&self) -> Option<(Vec<usize>, glam::Affine3A)> {
        let (meshes, pose) = self.motion.as_ref()?.mesh_pose(self.frame)?;
        Some((meshes.to_vec(), pose))
    }

    /// The renderer now holds the frame shown.
    pub fn uploaded(&mut self) {
        self.uploaded = Some(self.frame);
    }

    /// The frame shown could not be made or uploaded: pause on it rather than ask again every frame.
    pub fn failed(&mut self) {
        self.playing = false;
        self.uploaded = Some(self.frame);
    }

    /// Space plays or pauses, Left and Right step, unless a text field has the keyboard.
    pub fn keys(&mut self, ctx: &egui::Context) {
        if !self.is_moving() || ctx.egui_wants_keyboard_input() {
            return;
        }
        let (space, left, right) = ctx.input_mut(|i| {
            (
                i.consume_key(egui::Modifiers::NONE, egui::Key::Space),
                i.consume_key(egui::Modifiers::NONE, egui::Key::ArrowLeft),
                i.consume_key(egui::Modifiers::NONE, egui::Key::ArrowRight),
            )
        });
        if space {
            self.toggle_play();
        }
        if left {
            self.step(-1);
        }
        if right {
            self.step(1);
        }
    }

    /// The timeline bar: play/pause, step, scrub, loop, speed, frame and time.
    /// The bar; returns whether the animation export was asked for.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> bool {
        let mut export = false;
        ui.horizontal(|ui| {
            let play = if self.playing { "Pause" } else { "Play" };
            if ui.button(play).on_hover_text("play / pause (Space)").clicked() {
                self.toggle_play();
            }
            if ui.button("-1").on_hover_text("one frame back (Left)").clicked() {
                self.step(-1);
            }
            if ui
                .button("+1")
                .on_hover_text("one frame forward (Right)")
                .clicked()
            {
                self.step(1);
            }
            let mut k = self.frame;
            let last = self.count - 1;
            let scrub = ui.add(egui::Slider::new(&mut k, 0..=last).text("frame"));
            if scrub.changed() {
                self.seek(k);
            }
            ui.checkbox(&mut self.looping, "loop");
            egui::ComboBox::from_id_salt("playback_speed")
                .selected_text(format!("{}×", self.speed))
                .show_ui(ui, |ui| {
                    for s in SPEEDS {
                        ui.selectable_value(&mut self.speed, s, format!("{s}×"));
                    }
                })
                .response
                .on_hover_text("playback speed");
            ui.label(format!(
                "{} / {} · t = {:.2} s of {:.2} s at {} fps",
                self.frame,
                last,
                self.frame as f32 / self.fps,
                last as f32 / self.fps,
                self.fps
            ));
            export = ui
                .button("Export…")
                .on_hover_text("the motion's frames as a PNG sequence or an animated GIF")
                .clicked();
        });
        export
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moving(frames: u32) -> Timeline {
        let settings = MotionSettings {
            frames,
            fps: 10.0,
            ..MotionSettings::default()
        };
        let mut t = Timeline::default();
        t.set_motion(Motion::Still(vec![Vec3::ZERO]), &settings);
        // A still motion hides the timeline; give it a sequence-like motion of `frames` frames.
        t.motion = Some(Motion::Still(vec![Vec3::ZERO]));
        t
    }

    #[test]
    fn playing_follows_the_clock_and_loops() {
        let mut t = moving(5);
        t.toggle_play();
        t.advance(0.25);
        assert_eq!(t.frame(), 2, "0.25 s at 10 fps");
        t.advance(0.3);
        assert_eq!(t.frame(), 0, "5.5 frames into a 5-frame loop");
        t.looping = false;
        t.advance(0.6);
        assert_eq!(t.frame(), 4);
        assert!(
            !t.is_playing(),
            "a motion that does not loop stops at its last frame"
        );
    }

    #[test]
    fn stepping_and_seeking_pause_and_stay_in_range() {
        let mut t = moving(5);
        t.toggle_play();
        t.step(-1);
        assert!(!t.is_playing());
        assert_eq!(t.frame(), 4, "back from frame 0 wraps when looping");
        t.looping = false;
        t.step(1);
        assert_eq!(t.frame(), 4);
        t.seek(99);
        assert_eq!(t.frame(), 4);
        t.seek(2);
        t.toggle_play();
        t.advance(0.1);
        assert_eq!(t.frame(), 3, "playing resumes from the frame sought");
    }

    #[test]
    fn a_frame_is_pending_until_uploaded() {
        let mut t = moving(5);
        assert!(t.pending().is_none(), "frame 0 is the scene as uploaded");
        t.step(1);
        assert!(t.pending().is_some());
        t.uploaded();
        assert!(t.pending().is_none());
    }
}
