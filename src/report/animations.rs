//! The motion as it looks: a fresh study renders the frames it measured with every motion configuration and
//! with the exact reference shadows, each a looping animated GIF at the motion's frame rate
//! (`crate::animation::animated_gif`, what `hairlab render --frames A..B --out F.gif` writes), scaled to
//! [`WIDTH`] pixels wide, into the motion folder's `animations/` (`reference.gif`, and `k.gif` per row of
//! `motion_summary.csv`). The section shows each beside the reference's.

use super::data::{ANIMATIONS, Motion};
use super::page::figure;
use crate::gpu::Gpu;
use crate::measure::MethodConfig;
use crate::progress::{Progress, share};
use crate::settings::Settings;
use anyhow::Result;
use std::path::Path;

/// The animations' width in pixels.
pub const WIDTH: u32 = 240;

fn animation(gpu: &Gpu, settings: &Settings, method: &MethodConfig, frames: u32) -> Result<Vec<u8>> {
    let mut s = settings.clone();
    s.method.name = method.name.clone();
    s.method.params = method.params.clone();
    let mut images = Vec::new();
    let ks: Vec<u32> = (0..frames).collect();
    crate::animation::render_frames_on(
        gpu,
        &mut s,
        &ks,
        &mut |_| {},
        &mut crate::progress::Quiet,
        &mut |_, image| {
            let h = (image.height() * WIDTH / image.width().max(1)).max(1);
            images.push(image::imageops::thumbnail(&image, WIDTH.min(image.width()), h));
            Ok(())
        },
    )?;
    crate::animation::animated_gif(&images, settings.motion.fps)
}

/// Renders frames `0..frames` of the reference and of each of `configs` (the summary's rows, in order) into
/// `motion_dir/animations`; stops after the animation in progress when `progress` asks. Whether every animation
/// was written.
pub fn write(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MethodConfig],
    frames: u32,
    motion_dir: &Path,
    progress: &mut dyn Progress,
) -> Result<bool> {
    let dir = motion_dir.join(ANIMATIONS);
    std::fs::create_dir_all(&dir)?;
    let reference = MethodConfig::new(crate::methods::registry::reference().name(), Default::default());
    let jobs = std::iter::once((reference.name.clone(), &reference))
        .chain(configs.iter().enumerate().map(|(k, c)| (k.to_string(), c)));
    for (k, (name, c)) in jobs.enumerate() {
        if !progress.step(&format!("animating {}", c.label()), share(k, configs.len() + 1)) {
            return Ok(false);
        }
        crate::io::write_atomic(
            &dir.join(format!("{name}.gif")),
            &animation(gpu, settings, c, frames)?,
        )?;
    }
    Ok(true)
}

/// The names of the animations present in `m`'s folder: the reference's and each row's, when the reference's
/// is there.
pub fn files(m: &Motion) -> Vec<String> {
    let dir = m.dir.join(ANIMATIONS);
    if !dir.join("reference.gif").is_file() {
        return Vec::new();
    }
    std::iter::once("reference.gif".to_string())
        .chain((0..m.summary.rows.len()).map(|k| format!("{k}.gif")))
        .filter(|n| dir.join(n).is_file())
        .collect()
}

/// The animations, each configuration beside the reference, or nothing when none was rendered.
pub fn figures(m: &Motion, dir: &str) -> String {
    let present = files(m);
    if present.len() < 2 {
        return String::new();
    }
    let mut out = String::from("<h3>The motion, looping</h3>\n");
    for k in 0..m.summary.rows.len() {
        let name = format!("{k}.gif");
        if !present.contains(&name) {
            continue;
        }
        let label = m.summary.text(k, "config").unwrap_or("?");
        out += "<div class=\"grid\">\n";
        out += &figure(
            &format!("{dir}/{name}"),
            &format!("Looping animation of the motion's frames with {label} shadows"),
            label,
        );
        out += &figure(
            &format!("{dir}/reference.gif"),
            "Looping animation of the motion's frames with the exact reference shadows",
            crate::methods::registry::reference().name(),
        );
        out += "</div>\n";
    }
    format!("<div class=\"animations\">{out}</div>\n")
}
