//! Progress and cancellation of long library loops, as one parameter: every loop that takes long (a bench sweep,
//! a report, a motion measurement, the path tracer, a scene build) takes a `&mut dyn Progress`, tells it what it
//! does and how far it got at its natural steps, and stops early once [`Progress::step`] answers `false`. The
//! window's jobs (`app::jobs::JobCtl`), the terminal's bar with Ctrl-C (`cli::progress`), a closure and
//! [`Quiet`] (never stops) implement it; [`Part`] maps a phase onto a sub-range of the whole. A loop that keeps
//! what it made when stopped returns an [`Outcome`]: complete, or stopped with what was kept.

/// Told how far a long loop got; answers whether to go on.
pub trait Progress {
    /// `label`: what runs now; `fraction` (0..=1): the share of the whole done. `false` asks the loop to stop
    /// (at its next natural step: a loop never stops in the middle of a unit it writes whole).
    #[must_use = "`false` asks the loop to stop at its next natural step"]
    fn step(&mut self, label: &str, fraction: f32) -> bool;

    /// This progress seen from a phase that covers `start..end` of the whole.
    fn part(&mut self, start: f32, end: f32) -> Part<'_>
    where
        Self: Sized,
    {
        Part {
            whole: self,
            start,
            end,
        }
    }
}

impl<F: FnMut(&str, f32) -> bool> Progress for F {
    fn step(&mut self, label: &str, fraction: f32) -> bool {
        self(label, fraction)
    }
}

/// Progress nobody watches: never stops (the CLI's quiet paths, the tests).
pub struct Quiet;

impl Progress for Quiet {
    fn step(&mut self, _: &str, _: f32) -> bool {
        true
    }
}

/// A phase of a longer run: its fractions 0..=1 map onto `start..=end` of the whole.
pub struct Part<'a> {
    whole: &'a mut dyn Progress,
    start: f32,
    end: f32,
}

impl<'a> Part<'a> {
    /// `whole`'s phase `start..end`, for a `&mut dyn Progress` (which [`Progress::part`] cannot take).
    pub fn of(whole: &'a mut dyn Progress, start: f32, end: f32) -> Part<'a> {
        Part { whole, start, end }
    }
}

impl Progress for Part<'_> {
    fn step(&mut self, label: &str, fraction: f32) -> bool {
        let f = fraction.clamp(0.0, 1.0);
        self.whole.step(label, self.start + (self.end - self.start) * f)
    }
}

/// The end of a long loop that keeps its partial work: every unit done, or stopped (its [`Progress`] said so)
/// with the units finished before the stop. The one way a library loop says it was stopped; it dereferences to
/// what it holds either way.
#[must_use = "a stopped run kept only part of its work: say so, or pass the outcome on"]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome<T> {
    Complete(T),
    Stopped(T),
}

impl<T> Outcome<T> {
    /// `value`, stopped or complete.
    pub fn new(value: T, stopped: bool) -> Self {
        if stopped {
            Outcome::Stopped(value)
        } else {
            Outcome::Complete(value)
        }
    }

    pub fn is_stopped(&self) -> bool {
        matches!(self, Outcome::Stopped(_))
    }

    /// What the run made (all of it, or what it kept when stopped).
    pub fn kept(self) -> T {
        match self {
            Outcome::Complete(t) | Outcome::Stopped(t) => t,
        }
    }

    pub fn as_ref(&self) -> Outcome<&T> {
        Outcome::new(&**self, self.is_stopped())
    }

    /// The same end, holding `f` of the value.
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Outcome<U> {
        let stopped = self.is_stopped();
        Outcome::new(f(self.kept()), stopped)
    }

    /// [`Outcome::map`] through a step that may fail.
    pub fn try_map<U, E>(self, f: impl FnOnce(T) -> Result<U, E>) -> Result<Outcome<U>, E> {
        let stopped = self.is_stopped();
        Ok(Outcome::new(f(self.kept())?, stopped))
    }

    /// Stopped if this was, or if a later phase of the same run was (`stopped`).
    pub fn or_stopped(self, stopped: bool) -> Self {
        let stopped = stopped || self.is_stopped();
        Outcome::new(self.kept(), stopped)
    }
}

impl<T> std::ops::Deref for Outcome<T> {
    type Target = T;

    fn deref(&self) -> &T {
        match self {
            Outcome::Complete(t) | Outcome::Stopped(t) => t,
        }
    }
}

impl<T> std::ops::DerefMut for Outcome<T> {
    fn deref_mut(&mut self) -> &mut T {
        match self {
            Outcome::Complete(t) | Outcome::Stopped(t) => t,
        }
    }
}

/// The error of a run that cannot keep partial work (a streamed output that must not be left half-written, e.g.
/// an animation renamed into place once every frame is in) when its [`Progress`] asked it to stop: such a run
/// is all or nothing, so it fails instead of returning an [`Outcome`].
#[derive(Debug, thiserror::Error)]
#[error("stopped")]
pub struct Stopped;

/// `done` of `total` steps as a fraction (0 of 0 is done: 1).
pub fn share(done: usize, total: usize) -> f32 {
    if total == 0 {
        1.0
    } else {
        (done as f64 / total as f64) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_part_maps_its_fractions_into_its_range_and_passes_the_answer_back() {
        let mut seen = Vec::new();
        let mut whole = |label: &str, f: f32| {
            seen.push((label.to_string(), f));
            f < 0.7
        };
        let mut phase = Part::of(&mut whole, 0.5, 0.75);
        assert!(phase.step("a", 0.0));
        assert!(phase.step("b", 0.5));
        assert!(!phase.step("c", 1.0), "0.75 ≥ 0.7: the whole says stop");
        assert!(!phase.step("d", 2.0), "clamped to the phase's end");
        assert_eq!(
            seen,
            [("a", 0.5), ("b", 0.625), ("c", 0.75), ("d", 0.75)].map(|(l, f)| (l.to_string(), f))
        );
    }

    #[test]
    fn an_outcome_keeps_its_value_and_whether_it_was_stopped() {
        let done = Outcome::new(vec![1, 2, 3], false);
        assert_eq!(done, Outcome::Complete(vec![1, 2, 3]));
        assert!(!done.is_stopped());
        assert_eq!(done.len(), 3, "reads through to the value");
        let cut = Outcome::new(vec![1], true);
        assert_eq!(cut.as_ref(), Outcome::Stopped(&vec![1]));
        assert_eq!(cut.clone().map(|v| v.len()), Outcome::Stopped(1));
        assert_eq!(cut.clone().try_map(|v| Err::<usize, _>(v[0])), Err(1));
        assert_eq!(cut.kept(), [1]);
        assert_eq!(done.clone().or_stopped(false), Outcome::Complete(vec![1, 2, 3]));
        assert_eq!(done.or_stopped(true), Outcome::Stopped(vec![1, 2, 3]));
        assert_eq!(Outcome::Stopped(2).or_stopped(false), Outcome::Stopped(2));
    }

    #[test]
    fn quiet_goes_on_and_shares_count_steps() {
        assert!(Quiet.step("x", 0.5));
        assert_eq!(share(3, 4), 0.75);
        assert_eq!(share(0, 0), 1.0);
    }
}
