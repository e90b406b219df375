//! `hairlab soak`: a long run that must not grow. It renders frames of a preset while the light turns
//! ([`DEGREES_PER_FRAME`]) and the shadow method changes every `switch_every` frames, cycling through every
//! registered method. At the end of each full cycle (the same method held, so the same maps) it samples the
//! process's resident memory and the renderer's GPU memory, and compares the last sample with the first. A method
//! the renderer refuses on this scene (an error such as AVSM's list bound on a CPU adapter) is skipped and named.
//! A preset with a `[motion]` plays it meanwhile, frame `k` of the soak drawing frame `k` of the simulation (a
//! recording loops), through `Renderer::update_points`; a simulation's invariants are tracked over the whole run
//! ([`MotionSoak`]).

use crate::gpu::{AdapterPreference, Gpu};
use crate::methods::registry;
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use anyhow::{Result, bail};

/// Light rotation per frame, in degrees of azimuth.
pub const DEGREES_PER_FRAME: f32 = 0.5;
/// Largest growth from the first cycle's end to the last one's that a soak accepts.
pub const MAX_GROWTH: f64 = 0.05;

/// Memory at the end of one full cycle of methods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Frames rendered so far.
    pub frame: u64,
    /// Resident set size in bytes (`VmRSS`), where the system reports it.
    pub resident_bytes: Option<u64>,
    /// The renderer's GPU memory (`MemoryReport::total`).
    pub gpu_bytes: u64,
}

/// A simulation's invariants over a soak: the worst of each over every frame ([`crate::motion::FrameStats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotionSoak {
    /// Kinetic energy per point, its largest value and the frame that had it.
    pub max_energy_per_point: f64,
    pub max_energy_frame: u64,
    /// The same over the last cycle of methods only: against the whole run's, whether the energy stays bounded.
    pub last_cycle_max_energy_per_point: f64,
    pub max_length_error: f32,
    pub max_depth: f32,
    pub max_root_error: f32,
    /// Whether every point of every frame was finite.
    pub finite: bool,
}

/// What a soak measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Soak {
    pub frames: u64,
    pub cycles: Vec<Sample>,
    /// Methods refused on this scene, with the reason (once each).
    pub refused: Vec<(String, String)>,
    /// The simulation's invariants, when the preset simulates.
    pub motion: Option<MotionSoak>,
}

impl Soak {
    /// Growth from the first cycle's end to the last's: (resident, GPU), as fractions of the first.
    pub fn growth(&self) -> (Option<f64>, f64) {
        let (Some(first), Some(last)) = (self.cycles.first(), self.cycles.last()) else {
            return (None, 0.0);
        };
        let rel = |a: u64, b: u64| (b as f64 - a as f64) / (a.max(1) as f64);
        let resident = first
            .resident_bytes
            .zip(last.resident_bytes)
            .map(|(a, b)| rel(a, b));
        (resident, rel(first.gpu_bytes, last.gpu_bytes))
    }
}

/// This process's resident set size, from `/proc/self/status` (`None` where there is none).
pub fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Renders `frames` frames of `settings`' scene, switching method every `switch_every` frames; `progress` is
/// told each cycle's sample. Needs at least two full cycles (to compare the last with the first).
pub fn soak(
    settings: &Settings,
    frames: u64,
    switch_every: u64,
    mut progress: impl FnMut(&Sample),
) -> Result<Soak> {
    let methods = registry::all();
    let cycle = switch_every * methods.len() as u64;
    if switch_every == 0 || frames < 2 * cycle {
        bail!(
            "--frames {frames} holds fewer than two cycles of {} methods × --switch-every {switch_every} = {} \
             frames",
            methods.len(),
            2 * cycle
        );
    }
    let mut s = settings.clone();
    let (scene, mut motion) = s.open_motion()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution)?;
    let technique = s.transparency.technique()?;
    let defaults = crate::methods::ParamValues::new();
    let mut out = Soak {
        frames,
        cycles: Vec::new(),
        refused: Vec::new(),
        motion: matches!(motion, crate::motion::Motion::Simulate(_)).then_some(MotionSoak {
            finite: true,
            ..MotionSoak::default()
        }),
    };
    let motion_frames = u64::from(motion.frame_count(&s.motion));
    for frame in 0..frames {
        if !motion.is_still() {
            let k = match motion {
                crate::motion::Motion::Simulate(_) => frame,
                _ => frame % motion_frames,
            };
            let k =
                u32::try_from(k).map_err(|_| anyhow::anyhow!("--frames {frames}: more than 2³² frames"))?;
            motion.show(&mut r, k)?;
            if let (crate::motion::Motion::Simulate(sim), Some(m)) = (&motion, &mut out.motion) {
                let st = sim.stats();
                let energy = st.kinetic_energy / scene.strands.point_count().max(1) as f64;
                if energy > m.max_energy_per_point {
                    (m.max_energy_per_point, m.max_energy_frame) = (energy, frame);
                }
                if frame >= frames - cycle {
                    m.last_cycle_max_energy_per_point = m.last_cycle_max_energy_per_point.max(energy);
                }
                m.max_length_error = m.max_length_error.max(st.max_length_error);
                m.max_depth = m.max_depth.max(st.max_depth);
                m.max_root_error = m.max_root_error.max(st.max_root_error);
                m.finite &= st.finite;
            }
        }
        let method = methods[((frame / switch_every) % methods.len() as u64) as usize];
        let mut light = s.light;
        light.azimuth_deg = (light.azimuth_deg + frame as f32 * DEGREES_PER_FRAME).rem_euclid(360.0);
        let params = if method.name() == s.method.name {
            &s.method.params
        } else {
            &defaults
        };
        let input = FrameInput {
            camera: &s.camera,
            light: &light,
            render: &s.render,
            method,
            method_params: params,
            technique,
            technique_params: &s.transparency.params,
            width: s.render.width,
            height: s.render.height,
        };
        if let Err(e) = r.render(&input)
            && !out.refused.iter().any(|(n, _)| n == method.name())
        {
            out.refused.push((method.name().to_string(), format!("{e:#}")));
        }
        // One frame in flight at most: a soak measures what the renderer holds, not a queue.
        let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
        r.wait_timings();
        if (frame + 1) % cycle == 0 {
            let sample = Sample {
                frame: frame + 1,
                resident_bytes: resident_bytes(),
                gpu_bytes: r.memory().total(),
            };
            progress(&sample);
            out.cycles.push(sample);
        }
    }
    Ok(out)
}
