//! Writing `.usda` and reading it back: every array kept, one groom in three formats, frames round-tripped;
//! `info` and `convert` on a stage, and the hand stage rendered and played as a motion.

use super::{HAND_STAGE, write};
use glam::Vec3;
use hairlab::scene::Strands;
use hairlab::scene::hair::{HairFile, write_hair_file};
use hairlab::scene::load::{load_scene, save_strands};
use hairlab::scene::usd::read_usd_frames;
use hairlab::scene::usda_write::write_usda;

#[test]
fn hair_to_usda_to_hair_keeps_every_array() {
    let dir = tempfile::tempdir().unwrap();
    let groom = crate::groom_formats::uniform_groom();
    let hair = dir.path().join("g.hair");
    write_hair_file(&hair, &HairFile::from_strands(&groom, "groom").unwrap()).unwrap();
    let usda = dir.path().join("g.usda");
    save_strands(&usda, &load_scene(&hair).unwrap().strands, "").unwrap();
    let back = dir.path().join("back.hair");
    save_strands(&back, &load_scene(&usda).unwrap().strands, "").unwrap();
    assert_eq!(load_scene(&back).unwrap().strands, groom);
}

#[test]
fn one_groom_as_usda_tfx_and_data_gives_the_same_strands() {
    use hairlab::scene::tfx::{TfxFile, write_tfx_file};
    use hairlab::scene::usc_data::write_data_file;
    let dir = tempfile::tempdir().unwrap();
    let groom = crate::groom_formats::uniform_groom();
    let (usda, tfx, data) = (
        dir.path().join("g.usda"),
        dir.path().join("g.tfx"),
        dir.path().join("g.data"),
    );
    std::fs::write(&usda, write_usda(std::slice::from_ref(&groom), 24.0).unwrap()).unwrap();
    write_tfx_file(&tfx, &TfxFile::from_strands(&groom).unwrap()).unwrap();
    write_data_file(&data, &groom).unwrap();
    let from_usda = load_scene(&usda).unwrap().strands;
    assert_eq!(from_usda, load_scene(&tfx).unwrap().strands);
    let from_data = load_scene(&data).unwrap().strands;
    assert_eq!(
        (&from_usda.points, &from_usda.counts),
        (&from_data.points, &from_data.counts)
    );
}

#[test]
fn several_frames_round_trip_through_usda_frame_by_frame() {
    let dir = tempfile::tempdir().unwrap();
    let a = crate::groom_formats::uniform_groom();
    let mut b = a.clone();
    b.points
        .iter_mut()
        .for_each(|p| *p += Vec3::new(0.5, -0.25, 0.125));
    let path = dir.path().join("m.usda");
    std::fs::write(&path, write_usda(&[a.clone(), b.clone()], 30.0).unwrap()).unwrap();
    let f = read_usd_frames(&path).unwrap();
    assert_eq!(f.time_codes, [0.0, 1.0]);
    assert_eq!(f.time_codes_per_second, 30.0);
    assert_eq!(f.frames, [a, b]);
    let e = write_usda(&[Strands::default(), crate::groom_formats::uniform_groom()], 24.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("frame 1"), "{e}");
}

#[test]
fn info_and_convert_report_the_stage_and_keep_its_frames() {
    use crate::common::cli::hairlab;
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "hand.usda", HAND_STAGE);
    let o = hairlab(&["info", path.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    for line in [
        "stage:     upAxis Z, metersPerUnit 0.01 (read as Y-up metres), 2 time samples at 12 time codes per second",
        "arrays:    points, widths, displayColor, displayOpacity",
        "converted: /Groom/Bezier: cubic bezier → polylines at 4 segments per span (1 curves)",
        "converted: /Groom/Bspline: cubic bspline → polylines at 4 segments per span (1 curves)",
        "converted: /Groom/Linear: primvars:displayColor uniform → per point",
        "converted: upAxis Z → Y-up (x, y, z) → (x, z, −y)",
        "converted: metersPerUnit 0.01 → metres",
        "meshes:    0 (0 triangles)",
        "strands:   4",
        "points:    19",
        "segments:  15",
        "bounds:    min (0.1000, 0.0000, -0.1200) max (0.4600, 0.2400, 0.0000)",
    ] {
        assert!(out.lines().any(|l| l == line), "{line:?} missing from:\n{out}");
    }
    let out_path = dir.path().join("out.usda");
    let o = hairlab(&["convert", path.to_str().unwrap(), out_path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("frames:    2 (time-sampled points)"));
    let (a, b) = (
        read_usd_frames(&path).unwrap(),
        read_usd_frames(&out_path).unwrap(),
    );
    assert_eq!(a.frames, b.frames);
    // The written stage plays its frames at time codes 0, 1 at the source's rate.
    assert_eq!(
        (b.time_codes.as_slice(), b.time_codes_per_second),
        ([0.0, 1.0].as_slice(), 12.0)
    );
}

/// The hand stage as a preset's scene renders hair, and as `motion.path` plays as a motion of its two time codes:
/// frame 1 (time code 2, the bezier moved by 2 cm) differs from frame 0 on screen and equals, bit for bit, a
/// fresh render of a still stage holding time code 2's points (one camera, and `light.fit = per-frame` so
/// each frame's light frame is fitted to its own strands as the still render's is).
#[test]
fn the_hand_stage_renders_and_plays_as_a_motion() {
    let Some(_gpu) = hairlab::gpu::Gpu::for_tests() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    write(&dir, "hand.usda", HAND_STAGE);
    let preset = dir.path().join("hand.toml");
    std::fs::write(
        &preset,
        "[scene]\nfile = \"hand.usda\"\n[render]\nwidth = 96\nheight = 72\nmap_resolution = 128\n\
         [motion]\nsource = \"sequence\"\npath = \"hand.usda\"\n",
    )
    .unwrap();
    let load = || hairlab::settings::Settings::load_preset(preset.to_str().unwrap(), &[]).unwrap();
    let (_, motion) = load().open_motion().unwrap();
    assert_eq!(motion.frame_count(&load().motion), 2);
    let background = load().render.background;
    let [first, second] = [0, 1].map(|k| hairlab::cli::render::render_frame_image(&mut load(), k).unwrap());
    let hair = first
        .pixels()
        .filter(|p| {
            let bg = background.map(|c| (c.powf(1.0 / 2.2) * 255.0) as i32);
            (0..3).any(|i| (p.0[i] as i32 - bg[i]).abs() > 16)
        })
        .count();
    assert!(hair > 50, "only {hair} pixels differ from the background");
    let moved = first
        .pixels()
        .zip(second.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(moved > 0, "time code 2 moved nothing on screen");
    let sample0 = "0: [(0, 0, 0), (0, 8, 4), (0, 8, 8), (0, 0, 12)],\n";
    let sample2 = "2: [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12)],\n";
    let timed =
        format!("point3f[] points.timeSamples = {{\n            {sample0}            {sample2}        }}");
    assert!(HAND_STAGE.contains(&timed), "the stage's time samples");
    let still_stage = HAND_STAGE.replace(
        &timed,
        "point3f[] points = [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12)]",
    );
    write(&dir, "hand-at-2.usda", &still_stage);
    let still_preset = dir.path().join("hand-at-2.toml");
    std::fs::write(
        &still_preset,
        "[scene]\nfile = \"hand-at-2.usda\"\n[render]\nwidth = 96\nheight = 72\nmap_resolution = 128\n",
    )
    .unwrap();
    let (scene, _) = load().open_motion().unwrap();
    let mut camera = load().camera;
    camera.frame(&scene.framing_bounds());
    let pinned = |mut s: hairlab::settings::Settings| {
        s.camera = camera;
        s.light.fit = hairlab::scene::LightFit::PerFrame;
        s
    };
    let played = hairlab::cli::render::render_frame_image(&mut pinned(load()), 1).unwrap();
    let still = hairlab::settings::Settings::load_preset(still_preset.to_str().unwrap(), &[]).unwrap();
    let fresh = hairlab::cli::render::render_frame_image(&mut pinned(still), 0).unwrap();
    assert_eq!(
        played.as_raw(),
        fresh.as_raw(),
        "frame 1 against a still render of time code 2"
    );
}
