//! Progress and cancellation of a long scene build on the current thread, without threading a callback
//! through every builder: [`observed`] installs a step function for the duration of one build, and the
//! generator's strand loop calls [`step`] every [`BATCH`] strands. The scene loader reads the files that can be
//! large (`.hair`, `.tfx`, `.data`) through [`read_file`], which steps every [`crate::io::READ_CHUNK`] bytes
//! over the first [`READ_SHARE`] of the load; the `.data` parser steps every [`BATCH`] strands over the rest
//! (the `.hair` and `.tfx` arrays convert in bulk). Once the step function answers `false` the loop or the
//! read stops, and [`observed`] drops the partial result (or the error) and returns `None`. Builds outside
//! [`observed`] (the CLI, the tests) never stop.

use std::cell::RefCell;
use std::path::Path;

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

/// The share of a file load that reading its bytes stands for; parsing them is the rest.
pub const READ_SHARE: f32 = 0.5;

/// Reads `path` as [`crate::io::read_regular_file`] does, stepping through `0..READ_SHARE` as the bytes come.
pub fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    crate::io::read_regular_file_observed(path, &mut |read, size| {
        step(READ_SHARE * (read as f64 / size.max(1) as f64) as f32)
    })
}

/// Steps to `READ_SHARE + (1 - READ_SHARE) × done / total` (parsing after [`read_file`]) when `done` is a
/// multiple of [`BATCH`]; `false` when the parse should stop.
pub fn parsed(done: usize, total: usize) -> bool {
    !done.is_multiple_of(BATCH)
        || step(READ_SHARE + (1.0 - READ_SHARE) * (done as f64 / total.max(1) as f64) as f32)
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

    /// Loading a `.hair`, `.tfx` or `.data` file of 1.6 MB (two read chunks; 3 × BATCH strands) reports
    /// rising fractions inside the load, through the read and, for `.data`, the parse, and gives the same scene
    /// as a load without the hook; a step answering `false` drops the load.
    #[test]
    fn a_load_reports_its_progress_and_gives_the_same_scene() {
        use crate::scene::load::{load_scene, save_strands};
        let p = GenParams {
            strands: 3 * BATCH as u32,
            segments: 40,
            ..GenParams::default()
        };
        let strands = generate(&p).unwrap().strands;
        let dir = tempfile::tempdir().unwrap();
        for ext in ["hair", "tfx", "data"] {
            let path = dir.path().join(format!("s.{ext}"));
            save_strands(&path, &strands, "progress test").unwrap();
            let size = std::fs::metadata(&path).unwrap().len();
            assert!(size > crate::io::READ_CHUNK, "{ext}: {size} bytes, one chunk");
            let plain = load_scene(&path).unwrap();
            let fractions = std::rc::Rc::new(RefCell::new(Vec::new()));
            let seen = fractions.clone();
            let hooked = observed(
                move |f| {
                    seen.borrow_mut().push(f);
                    true
                },
                || load_scene(&path).unwrap(),
            )
            .expect("not stopped");
            assert!(hooked == plain, "{ext}: the same scene with the hook");
            let f = fractions.borrow();
            assert!(f.windows(2).all(|w| w[0] <= w[1]), "{ext}: {f:?}");
            assert!(f.iter().all(|x| (0.0..=1.0).contains(x)), "{ext}: {f:?}");
            let reads = f.iter().filter(|&&x| x <= READ_SHARE).count();
            assert!(reads >= 2, "{ext}: a step per chunk read: {f:?}");
            assert!(
                f.iter().any(|&x| x > 0.0 && x < READ_SHARE),
                "{ext}: inside the read: {f:?}"
            );
            if ext == "data" {
                // Strands 0, BATCH, 2 × BATCH: 0.5, 0.5 + 0.5 / 3, 0.5 + 1 / 3.
                assert_eq!(f.iter().filter(|&&x| x >= READ_SHARE).count(), 4, "{ext}: {f:?}");
                assert!((f[f.len() - 1] - (READ_SHARE + 2.0 / 3.0 * (1.0 - READ_SHARE))).abs() < 1e-6);
            }
            let path = dir.path().join(format!("s.{ext}"));
            assert!(
                observed(|_| false, || load_scene(&path)).is_none(),
                "{ext}: stopped"
            );
        }
    }
}
