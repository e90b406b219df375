//! `hairlab simulate`: a preset's motion baked to a folder of `.hair` files (`frame_0000.hair` …), one per
//! frame, each written whole, or to one `.usda` file with time-sampled points, so it plays back with
//! `--set motion.source=sequence --set motion.path=DIR` (or the `.usda` file). With
//! no `--out` it only runs the frames and prints the simulation's invariants (segment lengths, head
//! penetration, roots, energy) and its cost; `--gpu` times the GPU compute pass too.

use crate::motion::Motion;
use crate::scene::hair::{HairFile, write_hair_file};
use crate::settings::Settings;
use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct SimulateArgs {
    /// Preset with a `[motion]` section: built-in name (wind, head-turn, …), `presets/<name>.toml`, or a path.
    #[arg(long)]
    pub preset: String,
    /// Override any preset value, e.g. `--set motion.wind=4` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Frames to compute, from frame 0 (default: the preset's `motion.frames`).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Folder to write `frame_0000.hair` … into (created; it must hold no `.hair` files yet), or a `.usda` file
    /// to write every frame into as time-sampled points (at `motion.fps` time codes per second).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also step the simulation's GPU compute pass over the same frames and print its median GPU time per frame
    /// (timestamp queries; the adapter policy's device).
    #[arg(long)]
    pub gpu: bool,
}

/// The file name of frame `k` in a baked folder of `frames` frames (zero-padded so names sort as frames).
pub fn frame_file_name(k: u32, frames: u32) -> String {
    let digits = (frames.saturating_sub(1).max(1).ilog10() as usize + 1).max(4);
    format!("frame_{k:0digits$}.hair")
}

pub(super) fn simulate(a: &SimulateArgs) -> Result<()> {
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    if settings.motion.source == crate::motion::MotionSource::None {
        bail!(
            "preset '{}' is still (motion.source = \"none\"): choose a motion preset (wind, head-turn, stray-sweep, \
             straight-motion) or --set motion.source=simulate",
            a.preset
        );
    }
    let opening = std::time::Instant::now();
    let (scene, mut motion) = settings.open_motion()?;
    let open_ms = opening.elapsed().as_secs_f64() * 1e3;
    if let Motion::Simulate(sim) = &motion {
        println!(
            "scene and motion opened in {open_ms:.1} ms; collider: {}",
            match sim.collider() {
                None => "no collider".to_string(),
                Some(crate::motion::Collider::Ellipsoid(_)) => "the head ellipsoid".to_string(),
                Some(crate::motion::Collider::Sdf(g)) => format!(
                    "signed distance grid of {}×{}×{} nodes, cell {:.3e}, {:.1} KiB",
                    g.dims[0],
                    g.dims[1],
                    g.dims[2],
                    g.cell,
                    g.bytes() as f64 / 1024.0
                ),
            }
        );
    }
    let frames = a.frames.unwrap_or(motion.frame_count(&settings.motion));
    if frames == 0 {
        bail!("--frames must be at least 1");
    }
    if a.gpu && frames < 2 {
        bail!("--gpu times the steps from frame 0: --frames must be at least 2");
    }
    let usda = a
        .out
        .as_ref()
        .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("usda")));
    if let Some(file) = usda {
        crate::io::check_output(file, "usda")?;
    }
    let folder = a.out.as_ref().filter(|_| usda.is_none());
    if let Some(dir) = folder {
        if dir.exists() {
            let has_hair = std::fs::read_dir(dir)
                .with_context(|| format!("--out {}: cannot read the folder", dir.display()))?
                .flatten()
                .any(|e| {
                    e.path()
                        .extension()
                        .is_some_and(|x| x.eq_ignore_ascii_case("hair"))
                });
            if has_hair {
                bail!(
                    "--out {}: the folder already holds .hair files; a sequence is every .hair file in its \
                     folder, so choose an empty or new folder",
                    dir.display()
                );
            }
        } else {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("--out {}: cannot create", dir.display()))?;
        }
    }
    let mut strands = scene.strands.clone();
    let mut usda_frames = Vec::new();
    let (mut len, mut depth, mut root, mut speed, mut energy) = (0f32, 0f32, 0f32, 0f32, 0f64);
    let mut sim_s = 0.0;
    for k in 0..frames {
        let start = std::time::Instant::now();
        let points = motion.frame(k)?;
        sim_s += start.elapsed().as_secs_f64();
        if let Some(dir) = folder {
            strands.points.copy_from_slice(points);
            let info = format!("hairlab simulate {} frame {k}", a.preset);
            let path = dir.join(frame_file_name(k, frames));
            write_hair_file(&path, &HairFile::from_strands(&strands, &info)?)?;
        } else if usda.is_some() {
            strands.points.copy_from_slice(points);
            usda_frames.push(strands.clone());
        }
        if let Motion::Simulate(sim) = &motion {
            let st = sim.stats();
            if !st.finite {
                bail!("frame {k}: the simulation produced a non-finite point; the parameters are unstable");
            }
            len = len.max(st.max_length_error);
            depth = depth.max(st.max_depth);
            root = root.max(st.max_root_error);
            speed = speed.max(st.max_speed);
            energy = energy.max(st.kinetic_energy);
        }
    }
    println!(
        "{} strands, {} points; {frames} frames in {:.3} s ({:.3} ms per frame, CPU)",
        scene.strands.strand_count(),
        scene.strands.point_count(),
        sim_s,
        1e3 * sim_s / f64::from(frames)
    );
    if !motion.is_still() && matches!(motion, Motion::Simulate(_)) {
        println!(
            "worst relative segment-length error {len:.3e}; worst head penetration {depth:.3e}; worst root \
             error {root:.3e}; top speed {speed:.3} m/s; top kinetic energy {energy:.4e} (unit mass per point)"
        );
    }
    if a.gpu
        && let Motion::Simulate(sim) = motion
    {
        let gpu = crate::gpu::Gpu::headless(crate::gpu::AdapterPreference::from_env_or(
            crate::gpu::AdapterPreference::Hardware,
        ))?;
        let ms = crate::measure::motion::gpu_sim_ms(&gpu, *sim, frames)?;
        println!(
            "GPU compute pass: {} per frame (median of {} frames) on {}",
            ms.map_or("n/a (no timestamp queries)".to_string(), |ms| format!(
                "{ms:.3} ms"
            )),
            frames.saturating_sub(1),
            crate::gpu::describe(&gpu.info)
        );
    }
    if let Some(file) = usda {
        crate::scene::usda_write::write_usda_file(file, &usda_frames, f64::from(settings.motion.fps))?;
    }
    if let Some(out) = &a.out {
        println!("wrote {frames} frames to {}", out.display());
    }
    Ok(())
}
