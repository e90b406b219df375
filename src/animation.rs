//! A motion's frames rendered offscreen with one renderer (the first frame's points uploaded with the scene, the
//! later ones through `Renderer::update_points`), as `hairlab render --frame/--frames` and the window's
//! animation export do, and streamed by [`AnimationOut::write`] as a numbered PNG sequence or one looping
//! animated GIF: each frame encoded and written as it is rendered, into a temporary file or folder beside the
//! target that is renamed into place once every frame is in, so memory holds one frame and a cancelled or
//! failed run leaves nothing at the target.

use crate::gpu::{self, AdapterPreference, Gpu};
use crate::io::encode_png;
use crate::methods::registry;
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use anyhow::{Context, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The file name of frame `k` in a PNG sequence whose frames end before `end`: `frame_0007.png` (at least four
/// digits, more when `end` needs them).
pub fn frame_file_name(k: u32, end: u32) -> String {
    let digits = (end.saturating_sub(1).max(1).ilog10() as usize + 1).max(4);
    format!("frame_{k:0digits$}.png")
}

/// A sink of frames: frame number and image, in order.
pub type FrameSink<'a> = dyn FnMut(u32, image::RgbaImage) -> Result<()> + 'a;

/// `images` as an animated GIF at `fps` frames per second, looping (each frame quantised to 256 colours), in
/// memory; the bytes [`AnimationOut::write`] streams to a `.gif` for the same frames.
pub fn animated_gif(images: &[image::RgbaImage], fps: f32) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    stream_gif(&mut bytes, fps, |sink| {
        images.iter().try_for_each(|i| sink(0, i.clone()))
    })?;
    Ok(bytes)
}

/// The looping animated GIF at `fps` of the frames `produce` hands its sink, each encoded into `w` as it
/// arrives; the trailer is written when `produce` returns.
fn stream_gif<W: Write>(
    w: W,
    fps: f32,
    produce: impl FnOnce(&mut FrameSink<'_>) -> Result<()>,
) -> Result<()> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let mut encoder = GifEncoder::new_with_speed(w, 10);
    encoder.set_repeat(Repeat::Infinite)?;
    let delay = image::Delay::from_numer_denom_ms(1000, fps.max(1e-3).round().max(1.0) as u32);
    produce(&mut |_: u32, image: image::RgbaImage| {
        Ok(encoder.encode_frame(image::Frame::from_parts(image, 0, 0, delay))?)
    })
}

/// Where a run of frames goes: what `hairlab render --frames A..B --out …` and the window's export write.
#[derive(Clone, Debug, PartialEq)]
pub enum AnimationOut {
    /// A numbered PNG sequence ([`frame_file_name`]s) in the folder `dir`; `end` is the range's end (for the
    /// digits).
    Pngs { dir: PathBuf, end: u32 },
    /// One looping animated GIF at `fps` frames per second.
    Gif { file: PathBuf, fps: f32 },
}

/// A folder's parent for files made beside it (`.` for a bare name).
fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// The name of a temporary file or folder beside `target` starts with this: hidden, after the target.
fn temp_prefix(target: &Path) -> String {
    let name = target
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    format!(".{name}.")
}

/// A temporary file or folder's builder (named `prefix….partial`), with the usual permissions of a new file or
/// folder (less the umask) rather than the owner-only ones of a temporary.
fn temp_builder(prefix: &str, mode: u32) -> tempfile::Builder<'_, 'static> {
    let mut b = tempfile::Builder::new();
    b.prefix(prefix).suffix(".partial");
    #[cfg(unix)]
    b.permissions(std::os::unix::fs::PermissionsExt::from_mode(mode));
    #[cfg(not(unix))]
    let _ = mode;
    b
}

impl AnimationOut {
    /// Checks the target before anything renders: a GIF's folder exists and the file is not a folder; a
    /// sequence's folder is not a file.
    pub fn check(&self) -> Result<()> {
        match self {
            AnimationOut::Gif { file, .. } => crate::io::check_output(file, "gif"),
            AnimationOut::Pngs { dir, .. } if dir.exists() && !dir.is_dir() => {
                anyhow::bail!("{}: is a file, not a folder", dir.display())
            }
            AnimationOut::Pngs { .. } => Ok(()),
        }
    }

    /// The target path.
    pub fn path(&self) -> &Path {
        match self {
            AnimationOut::Pngs { dir, .. } => dir,
            AnimationOut::Gif { file, .. } => file,
        }
    }

    /// Writes the frames `produce` hands its sink, each encoded and written as it arrives, into a temporary file
    /// (GIF) or folder (PNG sequence) beside the target, and renames it into place once `produce` returns
    /// `Ok`: the GIF replaces the file, the sequence becomes the folder (or, when the folder exists, its frames
    /// replace the files of the same names in it, one rename each). When `produce` or a write fails (or a sink
    /// error stops it: a cancel), the temporary goes and nothing appears at the target. A sequence's missing
    /// parent folders are created first.
    pub fn write(&self, produce: impl FnOnce(&mut FrameSink<'_>) -> Result<()>) -> Result<()> {
        self.check()?;
        match self {
            AnimationOut::Gif { file, fps } => {
                let cannot = || format!("{}: cannot write", file.display());
                let mut tmp = temp_builder(&temp_prefix(file), 0o666)
                    .tempfile_in(parent_of(file))
                    .with_context(|| format!("cannot create a file in {}", parent_of(file).display()))?;
                let mut w = std::io::BufWriter::new(tmp.as_file_mut());
                stream_gif(&mut w, *fps, produce)?;
                w.flush().with_context(cannot)?;
                drop(w);
                tmp.as_file().sync_all().with_context(cannot)?;
                // On failure the error hands the temporary file back, and dropping it deletes it.
                tmp.persist(file).map_err(|e| e.error).with_context(cannot)?;
            }
            AnimationOut::Pngs { dir, end } => {
                let parent = parent_of(dir);
                std::fs::create_dir_all(parent)
                    .with_context(|| format!("{}: cannot create the folder", parent.display()))?;
                let tmp = temp_builder(&temp_prefix(dir), 0o777)
                    .tempdir_in(parent)
                    .with_context(|| format!("cannot create a folder in {}", parent.display()))?;
                let mut names = Vec::new();
                produce(&mut |k: u32, image: image::RgbaImage| {
                    let name = frame_file_name(k, *end);
                    let png = encode_png(&image)?;
                    crate::io::write_atomic_io(&tmp.path().join(&name), &png)
                        .with_context(|| format!("{}: cannot write", dir.join(&name).display()))?;
                    names.push(name);
                    Ok(())
                })?;
                if dir.is_dir() {
                    for name in &names {
                        std::fs::rename(tmp.path().join(name), dir.join(name))
                            .with_context(|| format!("{}: cannot write", dir.join(name).display()))?;
                    }
                } else {
                    std::fs::rename(tmp.path(), dir)
                        .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
                    // Renamed into place: nothing is left for the temporary folder's clean-up.
                    let _ = tmp.keep();
                }
            }
        }
        Ok(())
    }
}

/// Renders frame `k` of `settings`' motion (a still preset has only its one scene, whatever `k`).
pub fn render_frame_image(settings: &mut Settings, k: u32) -> Result<image::RgbaImage> {
    let mut out = None;
    render_frames(settings, &[k], &mut |_, image| {
        out = Some(image);
        Ok(())
    })?;
    out.context("no frame rendered")
}

/// Renders `settings` headlessly (framing the camera when its distance is 0) and returns the image. Prints the
/// scene, the adapter and per-pass GPU times on stderr.
pub fn render_image(settings: &mut Settings) -> Result<image::RgbaImage> {
    render_frame_image(settings, 0)
}

/// Renders `frames` of `settings`' motion in order with one renderer (the first frame's points uploaded with
/// the scene, the later ones through `Renderer::update_points`), passing each image to `sink`. The camera is
/// framed on the first frame when its distance is 0. Prints the scene, the adapter and the first frame's
/// per-pass GPU times on stderr.
pub fn render_frames(
    settings: &mut Settings,
    frames: &[u32],
    sink: &mut dyn FnMut(u32, image::RgbaImage) -> Result<()>,
) -> Result<()> {
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let log = &mut |line: &str| eprintln!("{line}");
    render_frames_on(&gpu, settings, frames, log, &mut crate::progress::Quiet, sink)
}

/// [`render_frames`] on `gpu`, the scene, adapter, GPU times and fur figures told to `log` line by line, each
/// frame's image handed to `sink` once `progress` is told of it; a stop `progress` asks for fails with
/// [`crate::progress::Stopped`] (so a streamed output is discarded).
pub fn render_frames_on(
    gpu: &Gpu,
    settings: &mut Settings,
    frames: &[u32],
    log: &mut dyn FnMut(&str),
    progress: &mut dyn crate::progress::Progress,
    sink: &mut dyn FnMut(u32, image::RgbaImage) -> Result<()>,
) -> Result<()> {
    let total = frames.len();
    let mut sent = 0;
    let mut sink = |k: u32, image: image::RgbaImage| -> Result<()> {
        sink(k, image)?;
        sent += 1;
        let what = format!("frame {sent} of {total} written");
        if progress.step(&what, crate::progress::share(sent, total)) {
            Ok(())
        } else {
            Err(crate::progress::Stopped.into())
        }
    };
    let Some((&first, rest)) = frames.split_first() else {
        return Ok(());
    };
    let start = std::time::Instant::now();
    let (mut scene, mut motion) = settings.open_motion()?;
    // Framed on the motion's frame 0 (the scene as built), so every frame of a motion gets the same camera.
    if settings.camera.distance <= 0.0 {
        settings.camera.frame(&scene.framing_bounds());
    }
    if !motion.is_still() {
        let count = motion.frame_count(&settings.motion);
        if let Some(&k) = frames.iter().find(|&&k| k >= count) {
            anyhow::bail!(
                "frame {k} is beyond the motion's {count} frames (0..={})",
                count - 1
            );
        }
        scene.set_strand_points(motion.frame(first)?)?;
    }
    // Under `light.fit = bound` (`stable`) every frame's hair maps are fitted to the whole motion's box (its
    // bounding sphere), whichever frames are rendered.
    let fit_bound = match settings.light.fit {
        crate::scene::LightFit::Bound | crate::scene::LightFit::Stable if !motion.is_still() => {
            Some(motion.bound(&settings.motion)?)
        }
        _ => None,
    };
    let scene_ms = start.elapsed().as_secs_f64() * 1e3;
    let fur = crate::fur::settings::FurScene::build(&scene, &settings.fur).map_err(anyhow::Error::msg)?;
    for w in fur.iter().flat_map(|f| &f.warnings) {
        log(&format!("warning: {w}"));
    }
    let mut renderer = Renderer::new(gpu, &scene, settings.render.map_resolution)?;
    renderer.set_fit_bound(fit_bound);
    if let Some((meshes, pose)) = motion.mesh_pose(first) {
        renderer.pose_meshes(meshes, pose)?;
    }
    renderer.set_fur(fur.as_ref().map(|f| (f, &settings.fur)))?;
    let method = registry::find(&settings.method.name).map_err(anyhow::Error::msg)?;
    let input = FrameInput {
        camera: &settings.camera,
        light: &settings.light,
        render: &settings.render,
        method,
        method_params: &settings.method.params,
        technique: settings.transparency.technique()?,
        technique_params: &settings.transparency.params,
        width: settings.render.width,
        height: settings.render.height,
    };
    renderer.render(&input)?;
    let times = renderer.wait_timings();
    sink(first, renderer.read_output()?)?;
    log(&format!(
        "{} strands, {} segments, {} triangles on {}",
        scene.strands.strand_count(),
        scene.strands.segment_count(),
        scene.triangle_count(),
        gpu::describe(&gpu.info)
    ));
    for t in &times {
        log(&format!("  {:>16}: {:.3} ms", t.name, t.ms));
    }
    if let Some(f) = &fur {
        let table = crate::measure::fur::table1(&renderer, f, scene_ms, &times)?;
        let march = match renderer.fur_state() {
            Some(state) => state.shell.read_stats(gpu)?,
            None => Default::default(),
        };
        log(&format!(
            "fur ({}, {} blending): {} triangles, {} sub-elements; march: {} rays, {} steps, {} hops, {} light \
             steps, {} rays lost at the hop cap, {} capped at fur.max_steps, {} light marches lost\n{}",
            settings.fur.mode.word(),
            settings.fur.blending.word(),
            f.shell.mesh.faces.len(),
            f.shell.sub_elements,
            march.rays,
            march.steps,
            march.hops,
            march.light_steps,
            march.lost,
            march.capped,
            march.light_lost,
            table.render(None)
        ));
    }
    for &k in rest {
        motion.show(&mut renderer, k)?;
        renderer.render(&input)?;
        sink(k, renderer.read_output()?)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three small frames that differ.
    fn frames() -> Vec<image::RgbaImage> {
        (0..3u8)
            .map(|k| {
                image::RgbaImage::from_fn(12, 8, |x, y| {
                    image::Rgba([
                        (x * 20 + u32::from(k) * 7) as u8,
                        (y * 30) as u8,
                        255 - k * 60,
                        255,
                    ])
                })
            })
            .collect()
    }

    /// Hands `images` to the sink as frames `first..`, then fails when `fail_after` frames went (a cancel).
    fn feed(
        images: &[image::RgbaImage],
        first: u32,
        fail_after: Option<usize>,
    ) -> impl FnOnce(&mut FrameSink<'_>) -> Result<()> + '_ {
        move |sink| {
            for (i, image) in images.iter().enumerate() {
                if fail_after == Some(i) {
                    anyhow::bail!("stopped");
                }
                sink(first + i as u32, image.clone())?;
            }
            Ok(())
        }
    }

    /// Everything in `dir`, sorted.
    fn listing(dir: &Path) -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    }

    #[test]
    fn a_streamed_gif_is_the_whole_encoding_byte_for_byte() {
        let images = frames();
        // What the export wrote before it streamed: every frame held, then encoded in one go.
        let mut whole = Vec::new();
        {
            use image::codecs::gif::{GifEncoder, Repeat};
            let mut encoder = GifEncoder::new_with_speed(&mut whole, 10);
            encoder.set_repeat(Repeat::Infinite).unwrap();
            let delay = image::Delay::from_numer_denom_ms(1000, 30);
            encoder
                .encode_frames(
                    images
                        .iter()
                        .map(|i| image::Frame::from_parts(i.clone(), 0, 0, delay)),
                )
                .unwrap();
        }
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.gif");
        let out = AnimationOut::Gif {
            file: file.clone(),
            fps: 30.0,
        };
        out.write(feed(&images, 0, None)).unwrap();
        assert!(std::fs::read(&file).unwrap() == whole);
        assert!(animated_gif(&images, 30.0).unwrap() == whole);
        assert_eq!(listing(dir.path()), ["a.gif"], "no temporary left");
    }

    #[test]
    fn a_streamed_png_sequence_is_each_frame_encoded() {
        let images = frames();
        let dir = tempfile::tempdir().unwrap();
        let frames_dir = dir.path().join("sub").join("frames");
        let out = AnimationOut::Pngs {
            dir: frames_dir.clone(),
            end: 12,
        };
        out.write(feed(&images, 9, None)).unwrap();
        assert_eq!(
            listing(&frames_dir),
            ["frame_0009.png", "frame_0010.png", "frame_0011.png"]
        );
        for (k, image) in (9..).zip(&images) {
            let bytes = std::fs::read(frames_dir.join(frame_file_name(k, 12))).unwrap();
            assert!(bytes == encode_png(image).unwrap(), "frame {k}");
        }
        assert_eq!(listing(&dir.path().join("sub")), ["frames"], "no temporary left");
        // Into a folder that exists: the frames of the same names are replaced, other files stay.
        std::fs::write(frames_dir.join("notes.txt"), "mine").unwrap();
        let again = AnimationOut::Pngs {
            dir: frames_dir.clone(),
            end: 12,
        };
        again.write(feed(&images[..2], 10, None)).unwrap();
        assert_eq!(
            listing(&frames_dir),
            ["frame_0009.png", "frame_0010.png", "frame_0011.png", "notes.txt"]
        );
        let replaced = std::fs::read(frames_dir.join("frame_0010.png")).unwrap();
        assert!(replaced == encode_png(&images[0]).unwrap());
        assert_eq!(listing(&dir.path().join("sub")), ["frames"]);
    }

    #[test]
    fn a_stopped_or_failed_run_leaves_nothing_at_the_target() {
        let images = frames();
        let dir = tempfile::tempdir().unwrap();
        let gif = AnimationOut::Gif {
            file: dir.path().join("a.gif"),
            fps: 24.0,
        };
        let pngs = AnimationOut::Pngs {
            dir: dir.path().join("frames"),
            end: 3,
        };
        for out in [&gif, &pngs] {
            let e = out.write(feed(&images, 0, Some(2))).unwrap_err();
            assert_eq!(e.to_string(), "stopped");
            assert!(listing(dir.path()).is_empty(), "{:?}", listing(dir.path()));
        }
        // A GIF over an earlier one: the earlier stays whole when the new run stops.
        gif.write(feed(&images, 0, None)).unwrap();
        let before = std::fs::read(gif.path()).unwrap();
        gif.write(feed(&images[..1], 0, Some(0))).unwrap_err();
        assert!(std::fs::read(gif.path()).unwrap() == before);
        assert_eq!(listing(dir.path()), ["a.gif"]);
        // A sequence's folder that is a file, and a GIF that is a folder, are refused before anything runs.
        let file = AnimationOut::Pngs {
            dir: dir.path().join("a.gif"),
            end: 3,
        };
        assert!(file.check().unwrap_err().to_string().contains("is a file"));
        let folder = AnimationOut::Gif {
            file: dir.path().join("x.gif"),
            fps: 24.0,
        };
        std::fs::create_dir(folder.path()).unwrap();
        assert!(folder.write(feed(&images, 0, None)).is_err());
        assert_eq!(listing(dir.path()), ["a.gif", "x.gif"]);
    }
}
