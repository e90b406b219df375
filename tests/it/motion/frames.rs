//! Frame `k` is the same bits after playing, scrubbing or fresh, in the strands and in every method's image; a
//! baked simulation plays back bit for bit (as `.usda` and as a sequence); rendered frames as PNGs and a GIF; a
//! bound light fit covers the whole motion.

use super::small;
use crate::common;
use crate::common::cli::{hairlab, stderr};
use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::render::Renderer;
use std::path::Path;

#[test]
fn frame_k_is_the_same_bits_after_playing_scrubbing_or_fresh() {
    // The head shaking in the wind: root motion and gusts together.
    let s = small("wind", &["motion.head=shake", "motion.head_period=1"]);
    let k = 25;
    let (_, mut played) = s.open_motion().unwrap();
    let mut frames = Vec::new();
    for f in 0..=k {
        frames.push(played.frame(f).unwrap().to_vec());
    }
    let (_, mut fresh) = s.open_motion().unwrap();
    assert_eq!(
        fresh.frame(k).unwrap(),
        &frames[k as usize][..],
        "fresh frame {k}"
    );
    // Scrub back and forth, then a second run from scratch: the same bits everywhere.
    for f in [3, 20, 0, 17, k, 1] {
        assert_eq!(
            fresh.frame(f).unwrap(),
            &frames[f as usize][..],
            "frame {f} scrubbed to"
        );
    }
    let (_, mut again) = s.open_motion().unwrap();
    for f in 0..=k {
        assert_eq!(
            again.frame(f).unwrap(),
            &frames[f as usize][..],
            "second run, frame {f}"
        );
    }
    assert_ne!(frames[0], frames[k as usize], "the hair moves");
}

#[test]
fn rendering_frame_k_after_playing_equals_a_fresh_render_for_every_method() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = small("wind", &["motion.head=shake", "motion.head_period=1"]);
    let (mut scene, mut motion) = s.open_motion().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let k = 8;
    let methods = registry::all();
    // Both renderers fit the light to the whole motion's bound, as `render --frames` and `measure motion` do
    // under the default `light.fit = stable` (a renderer left to its own would fit the strands it was made on).
    let bound = motion.bound(&s.motion).unwrap();
    // Played: frames 0..k−1 rendered in order, each with a different method, through the one write path.
    let mut played = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    played.set_fit_bound(Some(bound));
    for f in 0..k {
        played.update_points(motion.frame(f).unwrap()).unwrap();
        played
            .render(&common::frame_input(&s, methods[f as usize % methods.len()]))
            .unwrap();
    }
    let points_k = motion.frame(k).unwrap().to_vec();
    played.update_points(&points_k).unwrap();
    // Fresh: a new simulation asked for frame k only, and a renderer created on that frame's scene.
    let (_, mut fresh_motion) = s.open_motion().unwrap();
    assert_eq!(fresh_motion.frame(k).unwrap(), &points_k[..]);
    scene.set_strand_points(&points_k).unwrap();
    let mut fresh = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    fresh.set_fit_bound(Some(bound));
    for &m in methods {
        played.render(&common::frame_input(&s, m)).unwrap();
        let a = played.read_output().unwrap();
        fresh.render(&common::frame_input(&s, m)).unwrap();
        let b = fresh.read_output().unwrap();
        let differing = a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count();
        assert_eq!(differing, 0, "{}: frame {k} played vs fresh", m.name());
    }
}

/// A simulation baked to one `.usda` file (time-sampled points) plays back through `motion.path` as the live
/// simulation, point for point, bit for bit; the stage holds one time sample per frame.
#[test]
fn a_simulation_baked_to_usda_plays_back_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("baked.usda");
    let sets = ["scene.generator.strands=120", "scene.generator.segments=8"];
    let mut args = vec!["simulate", "--preset", "wind", "--frames", "6"];
    for s in &sets {
        args.extend(["--set", s]);
    }
    args.extend(["--out", out.to_str().unwrap()]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("points.timeSamples"), "no time samples in\n{text}");

    let live = small("wind", &sets);
    let path = format!("motion.path={}", out.display());
    let mut with_seq: Vec<&str> = sets.to_vec();
    with_seq.extend(["motion.source=sequence", &path]);
    let seq_settings = small("wind", &with_seq);
    let (live_scene, mut live_motion) = live.open_motion().unwrap();
    let (seq_scene, mut seq_motion) = seq_settings.open_motion().unwrap();
    assert_eq!(seq_motion.frame_count(&seq_settings.motion), 6);
    assert_eq!(seq_scene.strands.counts, live_scene.strands.counts);
    for k in 0..6 {
        assert_eq!(
            seq_motion.frame(k).unwrap(),
            live_motion.frame(k).unwrap(),
            "frame {k}"
        );
    }
}

#[test]
fn a_baked_simulation_plays_back_as_a_sequence_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("baked");
    let sets = [
        "scene.generator.strands=300",
        "scene.generator.segments=12",
        "render.width=96",
        "render.height=72",
        "render.map_resolution=128",
    ];
    let mut args = vec!["simulate", "--preset", "head-turn", "--frames", "12"];
    for s in &sets {
        args.extend(["--set", s]);
    }
    args.extend(["--out", out.to_str().unwrap()]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("frame_0000.hair").is_file() && out.join("frame_0011.hair").is_file());
    assert!(!out.join("frame_0012.hair").exists());

    // The live motion cut to the 12 frames baked, so both have one whole-motion bound to fit the light to.
    let live = small("head-turn", &["motion.frames=12"]);
    let path = format!("motion.path={}", out.display());
    let mut seq_settings = small("head-turn", &["motion.source=sequence", &path]);
    let (live_scene, mut live_motion) = live.open_motion().unwrap();
    let (seq_scene, mut seq_motion) = seq_settings.open_motion().unwrap();
    assert_eq!(seq_motion.frame_count(&seq_settings.motion), 12);
    assert_eq!(
        seq_scene.meshes, live_scene.meshes,
        "the preset's meshes are kept"
    );
    assert_eq!(seq_scene.strands.counts, live_scene.strands.counts);
    for k in 0..12 {
        assert_eq!(
            seq_motion.frame(k).unwrap(),
            live_motion.frame(k).unwrap(),
            "frame {k}"
        );
    }
    // And the same image (rendered through the CLI's path: frame 11 fresh from each source).
    if Gpu::for_tests().is_some() {
        let mut live = live;
        let a = hairlab::cli::render::render_frame_image(&mut live, 11).unwrap();
        let b = hairlab::cli::render::render_frame_image(&mut seq_settings, 11).unwrap();
        assert_eq!(a.as_raw(), b.as_raw(), "frame 11 live vs played back");
    }
}

#[test]
fn a_png_sequence_renders_the_frames_a_fresh_render_gives() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let sets = [
        "scene.generator.strands=200",
        "scene.generator.segments=8",
        "render.map_resolution=128",
    ];
    let mut args = vec!["render", "--preset", "wind", "--width", "64", "--height", "48"];
    for s in &sets {
        args.extend(["--set", s]);
    }
    let mut seq = args.clone();
    let dir = tmp.path().join("seq");
    seq.extend(["--frames", "2..5", "--out", dir.to_str().unwrap()]);
    let o = hairlab(&seq);
    assert!(o.status.success(), "{}", stderr(&o));
    let one = tmp.path().join("k4.png");
    let mut single = args.clone();
    single.extend(["--frame", "4", "--out", one.to_str().unwrap()]);
    let o = hairlab(&single);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!dir.join("frame_0001.png").exists() && dir.join("frame_0002.png").is_file());
    let a = image::open(dir.join("frame_0004.png")).unwrap().to_rgba8();
    let b = image::open(&one).unwrap().to_rgba8();
    assert_eq!(a.as_raw(), b.as_raw(), "frame 4 of the sequence vs --frame 4");
    let c = image::open(dir.join("frame_0002.png")).unwrap().to_rgba8();
    assert_ne!(a.as_raw(), c.as_raw(), "the frames differ");
    let _ = common::small_settings;
}

/// `hairlab render --frames A..B --out x.gif`: one animated GIF, whole, with a frame per motion frame at the
/// motion's rate, each frame the PNG sequence's frame (within the GIF's 256-colour quantisation: mean channel
/// error under 2 of 255; measured 0.49 to 0.61), and the hair moving between them.
#[test]
fn render_frames_as_an_animated_gif() {
    if Gpu::for_tests().is_none() {
        return;
    }
    use image::AnimationDecoder;
    let dir = tempfile::tempdir().unwrap();
    let gif = dir.path().join("wind.gif");
    let pngs = dir.path().join("frames");
    let sets = [
        "scene.generator.strands=150",
        "scene.generator.segments=8",
        "render.map_resolution=128",
    ];
    for out in [&gif, &pngs] {
        let mut args = vec![
            "render", "--preset", "wind", "--frames", "2..6", "--width", "80", "--height", "60",
        ];
        for s in &sets {
            args.extend(["--set", s]);
        }
        args.extend(["--out", out.to_str().unwrap()]);
        let o = hairlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let file = std::fs::File::open(&gif).unwrap();
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(file)).unwrap();
    let frames = decoder.into_frames().collect_frames().unwrap();
    assert_eq!(frames.len(), 4);
    let (num, den) = frames[0].delay().numer_denom_ms();
    assert!(
        (num as f32 / den as f32 - 1000.0 / 30.0).abs() <= 5.0,
        "delay {num}/{den} ms at 30 fps"
    );
    for (i, f) in frames.iter().enumerate() {
        let png = image::open(pngs.join(format!("frame_{:04}.png", i + 2)))
            .unwrap()
            .to_rgba8();
        assert_eq!(f.buffer().dimensions(), (80, 60));
        let err: f64 = f
            .buffer()
            .as_raw()
            .iter()
            .zip(png.as_raw())
            .map(|(a, b)| (*a as f64 - *b as f64).abs())
            .sum::<f64>()
            / png.as_raw().len() as f64;
        eprintln!("frame {}: mean channel error {err:.2}", i + 2);
        assert!(err < 2.0, "frame {}: mean channel error {err}", i + 2);
    }
    assert_ne!(frames[0].buffer(), frames[3].buffer(), "the hair moves");
}

/// Under `light.fit = bound` the hair maps of every frame are fitted to the box of the whole motion: frame 3
/// rendered alone equals frame 3 of a rendered range, bit for bit, though the ranges played differ; and the image
/// differs from the per-frame fit's.
#[test]
fn a_bound_fit_covers_the_whole_motion_whichever_frames_are_rendered() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let sets = [
        "scene.generator.strands=150",
        "scene.generator.segments=8",
        "render.map_resolution=128",
        "motion.frames=8",
    ];
    fn run<'a>(sets: &[&'a str], extra: &[&'a str], out: &'a Path) -> Vec<&'a str> {
        let mut args = vec!["render", "--preset", "wind", "--width", "80", "--height", "60"];
        for s in sets.iter().chain(extra) {
            args.extend(["--set", s]);
        }
        args.extend(["--out", out.to_str().unwrap()]);
        args
    }
    let alone = dir.path().join("alone.png");
    let mut a = run(&sets, &["light.fit=bound"], &alone);
    a.extend(["--frame", "3"]);
    let o = hairlab(&a);
    assert!(o.status.success(), "{}", stderr(&o));
    let range = dir.path().join("range");
    let mut a = run(&sets, &["light.fit=bound"], &range);
    a.extend(["--frames", "2..5"]);
    let o = hairlab(&a);
    assert!(o.status.success(), "{}", stderr(&o));
    let per_frame = dir.path().join("per_frame.png");
    let mut a = run(&sets, &["light.fit=per-frame"], &per_frame);
    a.extend(["--frame", "3"]);
    let o = hairlab(&a);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |p: &Path| image::open(p).unwrap().to_rgba8();
    assert_eq!(read(&alone), read(&range.join("frame_0003.png")));
    assert_ne!(
        read(&alone),
        read(&per_frame),
        "the bound fit changes the light frame"
    );
}
