//! Progress and cancellation of a long scene build on the current thread, without threading a callback
//! through every builder: [`observed`] installs a step function for the duration of one build, and the
//! generator's strand loop calls [`step`] every [`BATCH`] strands. Once the step function answers `false`
//! the loop stops growing, and [`observed`] drops the partial result and returns `None`. Builds outside
//! [`observed`] (the CLI, the tests) never stop.

use std::cell::RefCell;

/// Strands grown between two calls of the step function.
pub const BATCH: usize = 1024;

type StepFn = Box<dyn FnMut(f32) -> bool>;

thread_local! {
    /// The step function of the build under way on this thread, and whether it asked to stop.
    static OBSERVER: RefCell<Option<(StepFn, bool)>> = const { RefCell::new(None) };
}

/// Runs `build` with `step(fraction of the strands grown)` called as the generator grows them; `None` when
/// `step` answered `false` (the build stopped early and its partial result is dropped).
pub fn observed<R>(step: impl FnMut(f32) -> bool + 'static, build: impl FnOnce() -> R) -> Option<R> {
    OBSERVER.with(|o| *o.borrow_mut() = Some((Box::new(step), false)));
    let result = build();
    let stopped = OBSERVER.with(|o| o.borrow_mut().take().is_some_and(|(_, stopped)| stopped));
    (!stopped).then_some(result)
}

/// Reports `fraction` of the strands grown; `false` when the build should stop.
pub fn step(fraction: f32) -> bool {
    OBSERVER.with(|o| match o.borrow_mut().as_mut() {
        Some((f, stopped)) => {
            *stopped = *stopped || !f(fraction);
            !*stopped
        }
        None => true,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::generate::{GenParams, generate};

    #[test]
    fn a_stopped_generation_returns_nothing_and_a_full_one_is_unchanged() {
        let p = GenParams {
            strands: 3 * BATCH as u32,
            segments: 4,
            ..GenParams::default()
        };
        let plain = generate(&p).unwrap();
        let fractions = std::rc::Rc::new(RefCell::new(Vec::new()));
        let seen = fractions.clone();
        let full = observed(
            move |f| {
                seen.borrow_mut().push(f);
                true
            },
            || generate(&p).unwrap(),
        )
        .expect("not stopped");
        assert_eq!(full.strands.points, plain.strands.points);
        assert_eq!(*fractions.borrow(), vec![0.0, 1.0 / 3.0, 2.0 / 3.0]);
        let mut calls = 0;
        let stopped = observed(
            move |_| {
                calls += 1;
                calls < 2
            },
            || generate(&p).unwrap(),
        );
        assert!(stopped.is_none());
        assert!(step(0.5), "outside a build nothing stops");
    }
}
