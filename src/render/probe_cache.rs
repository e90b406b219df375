//! The fibres model's light probe (`shading::mesh_bounce`, `pathtrace::probe`) kept per pose, and baked on
//! another thread where the window asks for it. A probe depends on the pose (a digest of the strand points and
//! the posed triangles), the light, the hair's colour and width and the probe's kind ([`ProbeKey`]); up to
//! [`PROBE_CACHE`] are kept, the last used last, so a motion whose timeline loops bakes each frame once. A
//! measurement bakes what it asks for before it draws ([`ProbeCache::bake_now`]); the window, which must not
//! stop for the path tracer's bake (1–2 s of CPU a pose in a release build, ~10 s in the dev profile), asks with
//! [`ProbeCache::get_or_bake_later`] and draws meanwhile with the probe it had, as engines update their probes
//! asynchronously, saying so in its status line.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use glam::Vec3;

use crate::pathtrace::triangle::Triangle;
use crate::render::uniforms::FrameUniforms;
use crate::shading::mesh_bounce::{self, Grid};
use crate::shading::probe_light::ProbeLight;

/// The probes a scene keeps: a motion's frames up to this many (the presets' longest, `wind`, has 120) are baked
/// once however often the timeline loops; 36 KiB each.
pub const PROBE_CACHE: usize = 128;

/// What a probe's answer depends on: the pose's digest, the light's uniform fields, the hair's colour, its
/// strands' width, and the probe (`render.probe`).
pub type ProbeKey = (u64, [u32; 15], mesh_bounce::Probe);

/// The key of the probe of `kind` for the pose `pose` under the frame uniforms `u`.
pub fn key(pose: u64, u: &FrameUniforms, kind: mesh_bounce::Probe) -> ProbeKey {
    (
        pose,
        [
            u.to_light[0].to_bits(),
            u.to_light[1].to_bits(),
            u.to_light[2].to_bits(),
            u.light_position[0].to_bits(),
            u.light_position[1].to_bits(),
            u.light_position[2].to_bits(),
            u.light_color[0].to_bits(),
            u.light_color[1].to_bits(),
            u.light_color[2].to_bits(),
            u.spot_cos_half_angle.to_bits(),
            u.light_is_spot,
            u.hair_color[0].to_bits(),
            u.hair_color[1].to_bits(),
            u.hair_color[2].to_bits(),
            u.strand_width.to_bits(),
        ],
        kind,
    )
}

/// One probe to bake, with everything it reads owned, so that it can be baked on another thread.
pub struct Bake {
    pub key: ProbeKey,
    pub uniforms: FrameUniforms,
    /// The strand points and each point's thickness (the strand's width there is `thickness × strand_width`).
    pub points: Vec<Vec3>,
    pub thickness: Vec<f32>,
    /// Each strand's `(first point, point count)`.
    pub ranges: Vec<(usize, usize)>,
    /// The meshes' triangles as posed.
    pub triangles: Vec<Triangle>,
}

impl Bake {
    /// The probe (`pathtrace::probe::bake`) of the key's kind through the fibres of these widths and the meshes.
    pub fn run(&self) -> Grid<ProbeLight> {
        let u = &self.uniforms;
        crate::pathtrace::probe::bake(
            self.key.2,
            &u.raster_light(),
            Vec3::from(u.hair_color),
            &self.points,
            &self.ranges,
            |k| self.thickness[k] * u.strand_width,
            self.triangles.clone(),
        )
    }
}

/// What [`ProbeCache::get_or_bake_later`] answers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Answer {
    /// The probe asked for, kept.
    Kept(Grid<ProbeLight>),
    /// It bakes on another thread; the probe of its kind used last (whatever its pose and light; `None` where
    /// there is none) to draw with meanwhile.
    Baking(Option<Grid<ProbeLight>>),
}

/// The probes kept, what is being baked, and how many bakes there were.
#[derive(Default)]
pub struct ProbeCache {
    state: Arc<Mutex<State>>,
    bakes: Arc<AtomicUsize>,
}

#[derive(Default)]
struct State {
    /// The digest of the current pose with the generation it was taken at: taken when a probe is asked for,
    /// not when the geometry moves (the absorber model asks for none).
    pose: Option<(u64, u64)>,
    probes: Vec<(ProbeKey, Grid<ProbeLight>)>,
    /// The key a thread is baking now.
    baking: Option<ProbeKey>,
    /// The bake asked for while another ran: the latest only (the pose the window shows now).
    next: Option<Bake>,
}

impl State {
    /// The probe of `key` if kept, moved to the end (the last used).
    fn take(&mut self, key: &ProbeKey) -> Option<Grid<ProbeLight>> {
        let i = self.probes.iter().position(|(k, _)| k == key)?;
        let hit = self.probes.remove(i);
        let grid = hit.1;
        self.probes.push(hit);
        Some(grid)
    }

    fn keep(&mut self, key: ProbeKey, grid: Grid<ProbeLight>) {
        if self.probes.len() >= PROBE_CACHE {
            self.probes.remove(0);
        }
        self.probes.push((key, grid));
    }
}

impl ProbeCache {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The digest of the pose at `generation`, taken by `digest` once a generation.
    pub fn pose(&self, generation: u64, digest: impl FnOnce() -> u64) -> u64 {
        let mut state = self.lock();
        match state.pose {
            Some((g, d)) if g == generation => d,
            _ => {
                let d = digest();
                state.pose = Some((generation, d));
                d
            }
        }
    }

    /// The probe of `key` if it is kept.
    pub fn get(&self, key: &ProbeKey) -> Option<Grid<ProbeLight>> {
        self.lock().take(key)
    }

    /// Bakes `bake` on this thread and keeps it.
    pub fn bake_now(&self, bake: Bake) -> Grid<ProbeLight> {
        self.bakes.fetch_add(1, Ordering::Relaxed);
        let grid = bake.run();
        self.lock().keep(bake.key, grid);
        grid
    }

    /// The probe of `key` if kept; else [`Answer::Baking`], `bake()` baking on another thread unless it is being
    /// baked. Asked while
    /// another bake runs, it waits for that one, replacing any other waiting (the window wants the pose it shows
    /// now, not the ones it passed).
    pub fn get_or_bake_later(&self, key: &ProbeKey, bake: impl FnOnce() -> Bake) -> Answer {
        let mut state = self.lock();
        if let Some(grid) = state.take(key) {
            return Answer::Kept(grid);
        }
        let stand_in = state
            .probes
            .iter()
            .rev()
            .find(|(k, _)| k.2 == key.2)
            .map(|(_, g)| *g);
        if state.baking == Some(*key) {
            return Answer::Baking(stand_in);
        }
        if state.baking.is_some() {
            state.next = Some(bake());
            return Answer::Baking(stand_in);
        }
        state.baking = Some(*key);
        let bake = bake();
        drop(state);
        let (shared, bakes) = (self.state.clone(), self.bakes.clone());
        std::thread::spawn(move || {
            let mut bake = bake;
            loop {
                bakes.fetch_add(1, Ordering::Relaxed);
                let grid = bake.run();
                let mut state = shared.lock().unwrap_or_else(|e| e.into_inner());
                state.keep(bake.key, grid);
                let next = state
                    .next
                    .take()
                    .filter(|b| !state.probes.iter().any(|(k, _)| *k == b.key));
                state.baking = next.as_ref().map(|b| b.key);
                match next {
                    Some(b) => bake = b,
                    None => return,
                }
            }
        });
        Answer::Baking(stand_in)
    }

    /// Whether a probe is being baked on another thread.
    pub fn pending(&self) -> bool {
        self.lock().baking.is_some()
    }

    /// How many probes were baked (the answers not found kept).
    pub fn bakes(&self) -> usize {
        self.bakes.load(Ordering::Relaxed)
    }
}
