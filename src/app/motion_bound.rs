//! `light.fit = bound` (and `stable`, which takes the box's bounding sphere) in the window: the light's frame
//! fitted once to the box of the whole motion, so the hair maps do not rescale from frame to frame
//! (docs/design.md, "A scene that moves"). The box needs every frame of
//! the motion, so it is found on a worker (a job in the bottom bar, with progress and Cancel) from the settings the
//! scene on screen was built with, the way `render` and `measure motion` find it in line (`Motion::bound`). Until
//! it arrives, the renderer fits to the scene as uploaded joined with the frame shown, as before.

use super::jobs::{Job, JobGate, JobStatus, Poll};
use crate::motion::MotionSettings;
use crate::scene::Aabb;
use crate::settings::{SceneSettings, Settings};
use std::time::Duration;

/// What the bound is found for: the scene's and the motion's settings.
type Key = (SceneSettings, MotionSettings);

#[derive(Default)]
pub struct MotionBound {
    /// The motion the bound below (or the job under way) belongs to.
    key: Option<Key>,
    job: Option<Job<Result<Aabb, String>>>,
    bound: Option<Aabb>,
    /// Whether the renderer holds `bound` (a new scene upload drops it).
    applied: bool,
}

/// What the window should do with the renderer's fit bound after [`MotionBound::update`].
#[derive(Debug, PartialEq)]
pub enum Apply {
    Nothing,
    /// Fit to this box (the whole motion's).
    Bound(Aabb),
    /// Go back to the scene's own box.
    Clear,
    /// The job failed: say so.
    Failed(String),
}

impl MotionBound {
    /// The scene was uploaded again: its renderer no longer holds the bound.
    pub fn scene_uploaded(&mut self) {
        self.applied = false;
    }

    /// Starts, polls or drops the job for the motion on screen. `wanted`: the scene's and motion's settings when
    /// `light.fit` is `bound` or `stable` and the scene moves, else `None`. `settings` supplies everything else the motion needs.
    pub fn update(
        &mut self,
        wanted: Option<Key>,
        settings: &Settings,
        ctx: &egui::Context,
        gate: Option<JobGate>,
        patience: Duration,
    ) -> Apply {
        let Some(key) = wanted else {
            self.job = None;
            let was = self.applied;
            self.applied = false;
            return if was { Apply::Clear } else { Apply::Nothing };
        };
        if self.key.as_ref() != Some(&key) {
            self.key = Some(key.clone());
            self.bound = None;
            let mut s = settings.clone();
            (s.scene, s.motion) = key;
            self.job = Some(Job::spawn("light fit", ctx, gate, move |ctl| {
                ctl.step("fitting the light to the whole motion", 0.0)
                    .then_some(())?;
                let bound = s
                    .open_motion()
                    .and_then(|(_, mut motion)| motion.bound_with(&s.motion, &mut ctl.clone()));
                match bound {
                    Ok(b) => b.map(Ok),
                    Err(e) => Some(Err(format!("light fit: {e:#}"))),
                }
            }));
        }
        if let Some(job) = &self.job {
            match job.wait(patience) {
                Poll::Running => {}
                Poll::Done(Ok(b)) => {
                    self.job = None;
                    self.bound = Some(b);
                }
                Poll::Done(Err(e)) => {
                    self.job = None;
                    return Apply::Failed(e);
                }
                // Cancelled: the bound stays unknown for this motion until its settings change.
                Poll::Gone => self.job = None,
            }
        }
        match self.bound {
            Some(b) if !self.applied => {
                self.applied = true;
                Apply::Bound(b)
            }
            _ => Apply::Nothing,
        }
    }

    pub fn status(&self) -> Option<JobStatus> {
        self.job.as_ref().map(|j| j.status())
    }
}
