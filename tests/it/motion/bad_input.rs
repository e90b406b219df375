//! Bad motion input: sequences, parameters and the command line's flags, each one error naming the file or key.

use super::small;
use crate::common::cli::{assert_fails, hairlab};
use glam::Vec3;
use hairlab::scene::hair::{HairFile, write_hair_file};
use hairlab::settings::Settings;
use std::path::Path;

/// Writes a sequence of `n` frames of the test head into `dir` (points offset per frame).
fn write_frames(dir: &Path, n: usize) -> hairlab::scene::Strands {
    let s = small("default", &[]);
    let strands = s.scene.build().unwrap().strands;
    for k in 0..n {
        let mut f = strands.clone();
        f.points.iter_mut().for_each(|p| *p += Vec3::X * 0.001 * k as f32);
        write_hair_file(
            &dir.join(format!("f{k:02}.hair")),
            &HairFile::from_strands(&f, "test").unwrap(),
        )
        .unwrap();
    }
    strands
}

fn open_err(dir: &Path) -> String {
    let path = format!("motion.path={}", dir.display());
    let s = small("default", &["motion.source=sequence", &path]);
    match s.open_motion() {
        Ok(_) => panic!("{} opened", dir.display()),
        Err(e) => format!("{e:#}"),
    }
}

#[test]
fn bad_sequences_are_one_error_naming_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    // A missing folder.
    let missing = tmp.path().join("nowhere");
    let e = open_err(&missing);
    assert!(
        e.contains("motion.path") && e.contains("nowhere") && e.contains("cannot read"),
        "{e}"
    );
    // A folder with no frames.
    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let e = open_err(&empty);
    assert!(e.contains("holds no .hair files"), "{e}");
    // A frame with another topology: one strand fewer.
    let shaped = tmp.path().join("shaped");
    std::fs::create_dir(&shaped).unwrap();
    let mut strands = write_frames(&shaped, 3);
    strands.counts.pop();
    let keep: u32 = strands.counts.iter().sum();
    strands.points.truncate(keep as usize);
    write_hair_file(
        &shaped.join("f01.hair"),
        &HairFile::from_strands(&strands, "fewer").unwrap(),
    )
    .unwrap();
    let e = open_err(&shaped);
    assert!(
        e.contains("frame 1")
            && e.contains("f01.hair")
            && e.contains("topology differs")
            && e.contains("f00.hair"),
        "{e}"
    );
    // An unreadable frame (not a .hair file inside), and one that is not a file at all.
    let garbled = tmp.path().join("garbled");
    std::fs::create_dir(&garbled).unwrap();
    write_frames(&garbled, 3);
    std::fs::write(garbled.join("f02.hair"), b"not a hair file").unwrap();
    let e = open_err(&garbled);
    assert!(e.contains("frame 2") && e.contains("f02.hair"), "{e}");
    std::fs::remove_file(garbled.join("f02.hair")).unwrap();
    std::fs::create_dir(garbled.join("f02.hair")).unwrap();
    let e = open_err(&garbled);
    assert!(e.contains("frame 2") && e.contains("f02.hair"), "{e}");
    // Same point count, different strand lengths.
    let regrown = tmp.path().join("regrown");
    std::fs::create_dir(&regrown).unwrap();
    let mut strands = write_frames(&regrown, 2);
    strands.counts[0] -= 1;
    strands.counts[1] += 1;
    write_hair_file(
        &regrown.join("f01.hair"),
        &HairFile::from_strands(&strands, "regrown").unwrap(),
    )
    .unwrap();
    let e = open_err(&regrown);
    assert!(
        e.contains("points per strand differ") && e.contains("f01.hair"),
        "{e}"
    );
    // A good folder opens, and asking past its end names the range.
    let good = tmp.path().join("good");
    std::fs::create_dir(&good).unwrap();
    write_frames(&good, 3);
    let path = format!("motion.path={}", good.display());
    let s = small("default", &["motion.source=sequence", &path]);
    let (_, mut m) = s.open_motion().unwrap();
    assert_eq!(m.frame_count(&s.motion), 3);
    let e = format!("{:#}", m.frame(3).unwrap_err());
    assert!(e.contains("frame 3 is beyond the sequence's 3 frames"), "{e}");
}

#[test]
fn bad_motion_parameters_are_refused_naming_the_key() {
    for (set, needle) in [
        (
            "motion.fps=-30",
            "motion.fps must be a finite number in (0, 1000]",
        ),
        ("motion.fps=nan", "motion.fps must be a finite number"),
        ("motion.fps=0", "the time step 1/fps must be a positive"),
        ("motion.substeps=0", "motion.substeps must be in 1..=64 (got 0)"),
        (
            "motion.local_stiffness=1.5",
            "motion.local_stiffness must be in [0, 1] (got 1.5)",
        ),
        (
            "motion.global_stiffness=-0.1",
            "motion.global_stiffness must be in [0, 1]",
        ),
        ("motion.ftl_damping=nan", "motion.ftl_damping must be in [0, 1]"),
        (
            "motion.damping=-1",
            "motion.damping must be a finite number in [0, 100]",
        ),
        ("motion.gravity=inf", "motion.gravity must be a finite number"),
        (
            "motion.wind_dir=[0.0, 0.0, 0.0]",
            "motion.wind_dir must be three finite numbers",
        ),
        ("motion.head_period=0", "motion.head_period must be positive"),
        ("motion.frames=0", "motion.frames must be in 1..="),
        ("motion.source=sequence", "motion.path must name a folder"),
        ("motion.wnd=3", "wnd"),
        ("motion.source=replay", "replay"),
    ] {
        let e = Settings::load_preset("wind", &[set.to_string()]).unwrap_err();
        let text = format!("{e:#}");
        assert!(text.contains(needle), "{set}: {text}");
    }
    // The simulation of a preset that passes validation never produces a non-finite point in its frames: at
    // the edge of the accepted values (one substep, the stiffest local constraint), every point of every frame.
    let s = small("wind", &["motion.substeps=1", "motion.local_stiffness=1"]);
    let (_, mut m) = s.open_motion().unwrap();
    let frames = m.frame_count(&s.motion);
    assert!(frames >= 60, "wind plays {frames} frames");
    for k in 0..frames {
        let points = m.frame(k).unwrap();
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            panic!("frame {k}: point {i} is {}", points[i]);
        }
    }
}

#[test]
fn the_cli_refuses_bad_motion_input_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let o = hairlab(&["simulate", "--preset", "default", "--frames", "2"]);
    assert_fails(&o, &["preset 'default' is still"]);
    let o = hairlab(&[
        "simulate",
        "--preset",
        "wind",
        "--set",
        "motion.substeps=0",
        "--frames",
        "2",
    ]);
    assert_fails(&o, &["motion.substeps must be in 1..=64"]);
    std::fs::write(tmp.path().join("x.hair"), b"").unwrap();
    let out = tmp.path().to_str().unwrap();
    let o = hairlab(&[
        "simulate",
        "--preset",
        "wind",
        "--set",
        "scene.generator.strands=20",
        "--frames",
        "2",
        "--out",
        out,
    ]);
    assert_fails(&o, &["already holds .hair files"]);
    let seq = format!("motion.path={out}");
    let png = tmp.path().join("a.png");
    let o = hairlab(&[
        "render",
        "--preset",
        "default",
        "--set",
        "motion.source=sequence",
        "--set",
        &seq,
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_fails(&o, &["motion.path: frame 0", "x.hair"]);
    assert!(!png.exists(), "nothing written");
    let o = hairlab(&["render", "--preset", "wind", "--frames", "5..2", "--out", out]);
    assert_fails(&o, &["--frames '5..2'"]);
}
