//! Long jobs off the UI thread. A [`Job`] runs its work on a worker thread; the work reports its stage and
//! how far it got through a [`JobCtl`] (the library loops' [`crate::progress::Progress`]) at its natural steps
//! (a batch of strands, a method's map error, ...), and stops early once cancelled or stopped. The UI thread
//! polls the job each frame and applies a finished result in one go, so while it runs the window keeps drawing
//! the previous state. One rule for every job: **Cancel** drops the job and its result, leaving that state
//! exactly as it was; **Stop**, offered by a job that keeps partial work ([`Job::stoppable`]: the bench, the
//! report export, the motion measurement), asks the work to end at its next natural step and keeps what it made
//! (the library's [`crate::progress::Outcome::Stopped`]). Dropping a job cancels it, which is how a second job
//! of the same kind replaces the first. [`jobs_bar`] draws every running job: its name, stage, a progress bar
//! with the time left, Stop where offered, and Cancel.
//!
//! Also here: [`Settle`], the one place that decides when the input has settled enough for the exact
//! reference and the whole-map statistics to run again.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, mpsc};
use std::time::{Duration, Instant};

/// How long the UI thread waits for a job it just started before it shows progress: a job done by then
/// (a small scene) is applied in the frame that asked for it, without a progress bar flashing.
pub const PATIENCE: Duration = Duration::from_millis(200);

/// How long after the last change of the settings (or with a pointer button down) the input counts as busy.
pub const SETTLE_S: f64 = 0.2;

/// A test hook: jobs started while a gate is set wait at each of their steps until it opens (or they are
/// cancelled), so a test controls exactly when a job may finish instead of guessing with sleeps.
#[derive(Clone, Default)]
pub struct JobGate(Arc<(Mutex<bool>, Condvar)>);

impl JobGate {
    /// Lets every job waiting on this gate go on.
    pub fn open(&self) {
        let (open, cv) = &*self.0;
        *open.lock().unwrap_or_else(|e| e.into_inner()) = true;
        cv.notify_all();
    }

    /// Waits until the gate opens or `ended()` (the job was cancelled or stopped).
    fn pass(&self, ended: impl Fn() -> bool) {
        let (open, cv) = &*self.0;
        let mut is_open = open.lock().unwrap_or_else(|e| e.into_inner());
        while !*is_open && !ended() {
            is_open = cv
                .wait_timeout(is_open, Duration::from_millis(10))
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
    }
}

/// What a job reported last.
#[derive(Clone, Debug, Default)]
struct Stage {
    label: String,
    fraction: f32,
}

/// The worker's side of a job: reports progress and tells whether to go on.
#[derive(Clone)]
pub struct JobCtl {
    /// Cancel: the result is dropped.
    cancel: Arc<AtomicBool>,
    /// Stop: the work ends at its next step and its result (what it made so far) is kept.
    stop: Arc<AtomicBool>,
    stage: Arc<Mutex<Stage>>,
    gate: Option<JobGate>,
    ctx: egui::Context,
}

impl JobCtl {
    /// Reports `label` at `fraction` (0..=1) of the whole job; `false` once the job is cancelled or stopped
    /// (the work should then end: cancelled, its result is dropped whatever it returns; stopped, it returns what
    /// it made). Waits here while a test's [`JobGate`] is closed.
    pub fn step(&self, label: &str, fraction: f32) -> bool {
        if let Some(g) = &self.gate {
            g.pass(|| self.cancelled() || self.stopped());
        }
        {
            let mut s = self.stage.lock().unwrap_or_else(|e| e.into_inner());
            if s.label != label {
                s.label = label.to_string();
            }
            s.fraction = fraction.clamp(0.0, 1.0);
        }
        self.ctx.request_repaint();
        !(self.cancelled() || self.stopped())
    }

    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Whether Stop was asked for.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

impl crate::progress::Progress for JobCtl {
    fn step(&mut self, label: &str, fraction: f32) -> bool {
        JobCtl::step(self, label, fraction)
    }
}

/// A running job as the progress bar shows it.
#[derive(Clone, Debug)]
pub struct JobStatus {
    /// What the job does ("scene", "whole-map statistics", ...).
    pub name: &'static str,
    /// The stage it reported last.
    pub stage: String,
    pub fraction: f32,
    pub elapsed: Duration,
    cancel: Arc<AtomicBool>,
    /// The job's Stop flag, when it keeps partial work ([`Job::stoppable`]).
    stop: Option<Arc<AtomicBool>>,
}

impl JobStatus {
    /// The time left, extrapolated from the time taken so far and the fraction done; `None` until the
    /// fraction says enough (2 %).
    pub fn eta(&self) -> Option<Duration> {
        (self.fraction >= 0.02).then(|| {
            self.elapsed
                .mul_f64(f64::from((1.0 - self.fraction) / self.fraction))
        })
    }

    /// Asks the job to end; its owner drops it (and its result) at its next poll.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// Whether the job offers Stop (it keeps partial work).
    pub fn stoppable(&self) -> bool {
        self.stop.is_some()
    }

    /// Asks the job to end at its next step and keep what it made (nothing for a job that does not offer Stop).
    pub fn stop(&self) {
        if let Some(stop) = &self.stop {
            stop.store(true, Ordering::Relaxed);
        }
    }
}

/// What polling a job found.
pub enum Poll<T> {
    Running,
    Done(T),
    /// Cancelled, or the worker stopped without a result.
    Gone,
}

/// A job running on a worker thread; dropping it cancels it.
pub struct Job<T> {
    name: &'static str,
    started: Instant,
    ctl: JobCtl,
    /// Offers Stop.
    stoppable: bool,
    rx: mpsc::Receiver<Option<T>>,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work` on a worker thread; it may return `None` when it ended because it was cancelled (a
    /// cancelled job's result is dropped either way).
    pub fn spawn(
        name: &'static str,
        ctx: &egui::Context,
        gate: Option<JobGate>,
        work: impl FnOnce(&JobCtl) -> Option<T> + Send + 'static,
    ) -> Job<T> {
        let ctl = JobCtl {
            cancel: Arc::new(AtomicBool::new(false)),
            stop: Arc::new(AtomicBool::new(false)),
            stage: Arc::new(Mutex::new(Stage {
                label: "starting".to_string(),
                fraction: 0.0,
            })),
            gate,
            ctx: ctx.clone(),
        };
        let (tx, rx) = mpsc::channel();
        let worker = ctl.clone();
        std::thread::spawn(move || {
            let result = work(&worker);
            let _ = tx.send(result);
            worker.ctx.request_repaint();
        });
        Job {
            name,
            started: Instant::now(),
            ctl,
            stoppable: false,
            rx,
        }
    }
}

impl<T> Job<T> {
    /// This job offering Stop: its work keeps what it made when [`JobCtl::step`] answers `false` for a stop
    /// (and returns it, e.g. as an [`crate::progress::Outcome`]).
    pub fn stoppable(mut self) -> Self {
        self.stoppable = true;
        self
    }

    /// The result, once the job finished and was not cancelled.
    pub fn poll(&self) -> Poll<T> {
        self.take(
            self.rx
                .try_recv()
                .map_err(|e| e == mpsc::TryRecvError::Disconnected),
        )
    }

    /// Like [`Job::poll`], waiting up to `patience` for the job to finish.
    pub fn wait(&self, patience: Duration) -> Poll<T> {
        self.take(
            self.rx
                .recv_timeout(patience)
                .map_err(|e| e == mpsc::RecvTimeoutError::Disconnected),
        )
    }

    /// `received`: the worker's answer, or whether the worker is gone (`Err(true)`) rather than busy.
    fn take(&self, received: Result<Option<T>, bool>) -> Poll<T> {
        if self.ctl.cancelled() {
            return Poll::Gone;
        }
        match received {
            Ok(Some(t)) => Poll::Done(t),
            Ok(None) | Err(true) => Poll::Gone,
            Err(false) => Poll::Running,
        }
    }

    /// Whether Cancel was asked for.
    pub fn cancelled(&self) -> bool {
        self.ctl.cancelled()
    }

    pub fn status(&self) -> JobStatus {
        let s = self.ctl.stage.lock().unwrap_or_else(|e| e.into_inner()).clone();
        JobStatus {
            name: self.name,
            stage: s.label,
            fraction: s.fraction,
            elapsed: self.started.elapsed(),
            cancel: self.ctl.cancel.clone(),
            stop: self.stoppable.then(|| self.ctl.stop.clone()),
        }
    }
}

impl<T> Drop for Job<T> {
    fn drop(&mut self) {
        self.ctl.cancel.store(true, Ordering::Relaxed);
    }
}

/// One row per running job: its name and stage, a progress bar with the time left, Stop (a job that keeps
/// partial work) and Cancel. `hide_times` replaces the times (UI snapshots).
pub fn jobs_bar(ui: &mut egui::Ui, jobs: &[JobStatus], hide_times: bool) {
    for job in jobs {
        ui.horizontal(|ui| {
            ui.strong(job.name);
            let left = match job.eta() {
                _ if hide_times => String::new(),
                Some(eta) => format!(" · {:.0} s left", eta.as_secs_f64().ceil()),
                None => " · estimating the time left".to_string(),
            };
            if job.stoppable()
                && ui
                    .button("Stop")
                    .on_hover_text("end this job at its next step and keep what it made so far")
                    .clicked()
            {
                job.stop();
            }
            let cancel = ui
                .button("Cancel")
                .on_hover_text("end this job and keep everything as it was before it started");
            if cancel.clicked() {
                job.cancel();
            }
            ui.add(egui::ProgressBar::new(job.fraction).text(format!(
                "{} {:.0}%{left}",
                job.stage,
                100.0 * job.fraction
            )));
        });
    }
}

/// Whether the input has settled: no pointer button down and the settings unchanged for [`SETTLE_S`]. Work
/// too slow for every frame of a drag or an orbit (the exact reference lists, the compare renders) waits
/// for it.
#[derive(Default)]
pub struct Settle {
    last: Option<crate::settings::Settings>,
    changed_at: f64,
}

impl Settle {
    /// Notes the settings of the frame at time `now` (seconds) and whether a pointer button is down; returns
    /// how long until the input counts as settled (zero when it is).
    pub fn note(&mut self, settings: &crate::settings::Settings, pointer_down: bool, now: f64) -> f64 {
        if pointer_down || self.last.as_ref() != Some(settings) {
            self.changed_at = now;
            if self.last.as_ref() != Some(settings) {
                self.last = Some(settings.clone());
            }
        }
        (self.changed_at + SETTLE_S - now).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_job_reports_progress_and_hands_over_its_result() {
        let ctx = egui::Context::default();
        let gate = JobGate::default();
        let (go_tx, go_rx) = mpsc::channel::<()>();
        let job = Job::spawn("test", &ctx, Some(gate.clone()), move |ctl| {
            // Waits for the test at the gate, then reports half way and waits for the test again.
            ctl.step("first half", 0.5).then_some(())?;
            go_rx.recv().ok()?;
            Some(42)
        });
        assert!(matches!(job.poll(), Poll::Running));
        assert_eq!(
            job.status().fraction,
            0.0,
            "held at the gate before its first step"
        );
        gate.open();
        while job.status().fraction < 0.5 {
            std::thread::yield_now();
        }
        let s = job.status();
        assert_eq!(s.stage, "first half");
        assert!(s.eta().is_some());
        go_tx.send(()).unwrap();
        assert!(matches!(job.wait(Duration::from_secs(60)), Poll::Done(42)));
    }

    #[test]
    fn a_cancelled_job_drops_its_result() {
        let ctx = egui::Context::default();
        let gate = JobGate::default();
        let job = Job::spawn("test", &ctx, Some(gate), |ctl| {
            ctl.step("held", 0.0);
            Some(1)
        });
        job.status().cancel();
        // The cancel frees the job from the closed gate; its result is dropped even though it returned one.
        assert!(matches!(job.wait(Duration::from_secs(60)), Poll::Gone));
        assert!(job.cancelled());
    }

    /// Stop ends the work at its next step and hands over what it made; the job bar offers Stop only for such
    /// a job.
    #[test]
    fn a_stopped_job_keeps_what_it_made() {
        let ctx = egui::Context::default();
        let gate = JobGate::default();
        let job = Job::spawn("test", &ctx, Some(gate), |ctl| {
            let mut made = vec![1];
            while ctl.step("held", 0.0) {
                made.push(made.len() + 1);
            }
            Some(made)
        })
        .stoppable();
        assert!(job.status().stoppable());
        job.status().stop();
        // The stop frees the job from the closed gate; its first step answers `false`.
        assert!(matches!(job.wait(Duration::from_secs(60)), Poll::Done(made) if made == [1]));
        assert!(!job.cancelled());
        let plain = Job::spawn("test", &ctx, None, |_| Some(0));
        assert!(!plain.status().stoppable());
    }

    #[test]
    fn eta_extrapolates_the_elapsed_time() {
        let status = |fraction| JobStatus {
            name: "test",
            stage: String::new(),
            fraction,
            elapsed: Duration::from_secs(3),
            cancel: Arc::default(),
            stop: None,
        };
        assert_eq!(status(0.25).eta(), Some(Duration::from_secs(9)));
        assert_eq!(status(0.0).eta(), None);
    }

    #[test]
    fn input_settles_after_the_last_change() {
        let mut settle = Settle::default();
        let mut s = crate::settings::Settings::default();
        let busy = |left: f64| (left - SETTLE_S).abs() < 1e-9;
        assert!(busy(settle.note(&s, false, 10.0)));
        assert_eq!(settle.note(&s, false, 10.0 + SETTLE_S), 0.0);
        s.light.intensity += 1.0;
        assert!(busy(settle.note(&s, false, 20.0)), "a change restarts the wait");
        assert!(busy(settle.note(&s, true, 30.0)), "a pointer down keeps it busy");
        assert_eq!(settle.note(&s, false, 30.0 + SETTLE_S), 0.0);
    }
}
