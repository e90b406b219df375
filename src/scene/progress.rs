//! Progress of a long scene build: the generator's strand loop tells its [`Progress`] every [`BATCH`] strands;
//! the scene loader reads the files that can be large (`.hair`, `.tfx`, `.data`) through [`read_file`], which
//! steps every [`crate::io::READ_CHUNK`] bytes over the first [`READ_SHARE`] of the load, and the `.data` parser
//! steps every [`BATCH`] strands over the rest ([`parsed`]; the `.hair` and `.tfx` arrays convert in bulk). Once
//! the progress answers `false` the loop or the read stops: a stopped read fails
//! ([`std::io::ErrorKind::Interrupted`]), a stopped loop keeps what it made so far, and the caller (the window's
//! scene job) drops either.

use crate::progress::Progress;
use std::path::Path;

/// Strands grown or parsed between two steps.
pub const BATCH: usize = 1024;

/// The share of a file load that reading its bytes stands for; parsing them is the rest.
pub const READ_SHARE: f32 = 0.5;

/// The label of a load's steps.
const LOADING: &str = "loading the strands";

/// Reads `path` as [`crate::io::read_regular_file`] does, stepping `progress` through `0..READ_SHARE` as the
/// bytes come.
pub fn read_file(path: &Path, progress: &mut dyn Progress) -> std::io::Result<Vec<u8>> {
    crate::io::read_regular_file_observed(path, &mut |read, size| {
        progress.step(LOADING, READ_SHARE * (read as f64 / size.max(1) as f64) as f32)
    })
}

/// Steps `progress` to `READ_SHARE + (1 - READ_SHARE) × done / total` (parsing after [`read_file`]) when `done`
/// is a multiple of [`BATCH`]; `false` when the parse should stop.
pub fn parsed(done: usize, total: usize, progress: &mut dyn Progress) -> bool {
    !done.is_multiple_of(BATCH)
        || progress.step(
            LOADING,
            READ_SHARE + (1.0 - READ_SHARE) * (done as f64 / total.max(1) as f64) as f32,
        )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::generate::{GenParams, generate, generate_with};

    #[test]
    fn a_stopped_generation_keeps_the_first_batch_and_a_full_one_is_unchanged() {
        let p = GenParams {
            strands: 3 * BATCH as u32,
            segments: 4,
            ..GenParams::default()
        };
        let plain = generate(&p).unwrap();
        let mut fractions = Vec::new();
        let full = generate_with(&p, &mut |_: &str, f: f32| {
            fractions.push(f);
            true
        })
        .unwrap();
        assert_eq!(full.strands.points, plain.strands.points);
        assert_eq!(fractions, vec![0.0, 1.0 / 3.0, 2.0 / 3.0]);
        // Stopped at the second step: the first batch of strands only.
        let mut calls = 0;
        let stopped = generate_with(&p, &mut |_: &str, _: f32| {
            calls += 1;
            calls < 2
        })
        .unwrap();
        assert_eq!(stopped.strands.strand_count(), BATCH);
    }

    /// Loading a `.hair`, `.tfx` or `.data` file of 1.6 MB (two read chunks; 3 × BATCH strands) reports
    /// rising fractions inside the load, through the read and, for `.data`, the parse, and gives the same scene
    /// as a load without the hook; a step answering `false` drops the load.
    #[test]
    fn a_load_reports_its_progress_and_gives_the_same_scene() {
        use crate::scene::load::{load_scene, load_scene_with, save_strands};
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
            let mut f = Vec::new();
            let hooked = load_scene_with(&path, &mut |_: &str, x: f32| {
                f.push(x);
                true
            })
            .unwrap();
            assert!(hooked == plain, "{ext}: the same scene with the hook");
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
            // Stopped at the first step: the read fails, naming the file.
            let stopped = load_scene_with(&path, &mut |_: &str, _: f32| false);
            let e = format!("{:#}", stopped.expect_err("stopped"));
            assert!(e.contains(&format!("s.{ext}")), "{ext}: {e}");
        }
    }
}
