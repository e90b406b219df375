//! Progress and cancellation of long library loops, as one parameter: every loop that takes long (a bench sweep,
//! a report, a motion measurement, the path tracer, a scene build) takes a `&mut dyn Progress`, tells it what it
//! does and how far it got at its natural steps, and stops early once [`Progress::step`] answers `false`. The
//! window's jobs (`app::jobs::JobCtl`), the terminal's bar with Ctrl-C (`cli::progress`), a closure and
//! [`Quiet`] (never stops) implement it; [`Part`] maps a phase onto a sub-range of the whole.

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

/// The error of a run that stops only by failing (a streamed output that must not be left half-written) when its
/// [`Progress`] asked it to stop.
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
    fn quiet_goes_on_and_shares_count_steps() {
        assert!(Quiet.step("x", 0.5));
        assert_eq!(share(3, 4), 0.75);
        assert_eq!(share(0, 0), 1.0);
    }
}
