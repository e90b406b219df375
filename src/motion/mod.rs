//! Hair in motion (issue 18): where frame `k`'s strand points come from, chosen by the `[motion]` preset
//! section. `none` keeps the scene still; `simulate` runs the CPU strand simulation ([`sim`], the
//! specification of any GPU simulation); `sequence` plays a recording ([`sequence`]): a folder of `.hair` files
//! of identical topology, or a USD stage with time-sampled points. Every source is deterministic: frame `k` is the same bits whatever was played before.
//! The simulation collides with the generator's head ellipsoid or with the scene's meshes as a signed distance
//! grid ([`sdf`], `motion.colliders`), and the meshes that ride on the root frame are drawn at its pose
//! ([`Motion::show`]).
//!
//! A lower layer: it reads scenes and files, never the settings module (which holds a [`MotionSettings`]).

pub mod follow;
pub mod gpu;
pub mod params;
pub mod pose;
pub mod sdf;
pub mod sequence;
pub mod sim;
mod strand_step;

use crate::render::Renderer;
use crate::scene::{Aabb, Scene};
use anyhow::{Result, bail};
use glam::{Affine3A, Vec3};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::sync::Arc;

pub use sdf::SdfGrid;
pub use sequence::Sequence;
pub use sim::{Collider, Ellipsoid, FrameStats, RootFrame, SimParams, Simulation};

/// Where the frames come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MotionSource {
    /// A still scene: every frame is the preset's strands.
    #[default]
    None,
    /// The CPU strand simulation ([`sim`]).
    Simulate,
    /// A recording (`motion.path`): a folder of `.hair` files sorted by name, or a USD stage with time-sampled
    /// points.
    Sequence,
}

/// The root frame's keyframed rigid motion.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum HeadMotion {
    #[default]
    Still,
    /// Yaw by `head_angle_deg`, eased from 0.1 to 0.6 of `head_period`, then held: the head turns and stops.
    Turn,
    /// Pitch 0 → +a → −a → 0 over each `head_period`.
    Nod,
    /// Yaw 0 → +a → −a → 0 over each `head_period`.
    Shake,
    /// The head still; the roots of the last `sweep_strands` strands slide along +Z by
    /// `sweep_amplitude · sin(2π t / head_period)` (the stray strand of `stray-sweep`).
    Sweep,
}

/// What the simulation collides with (`motion.colliders`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Colliders {
    /// The generator's head ellipsoid when the scene is that head, else the scene's meshes (none without).
    #[default]
    Auto,
    /// The generator's head ellipsoid (an error on any other scene).
    Head,
    /// The scene's meshes that ride on the root frame, as a signed distance grid ([`sdf`]).
    Meshes,
    /// Nothing: the hair passes through the head.
    None,
}

/// `[motion]`: the source and, for `simulate`, the simulation's parameters (see [`sim`] for what each does).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MotionSettings {
    pub source: MotionSource,
    /// Frames per second: the simulation's frame step is `1 / fps`, and a sequence plays at this rate.
    pub fps: f32,
    /// Frames in the motion (a sequence has as many as its files).
    pub frames: u32,
    /// `sequence`: the folder of `.hair` files, or the time-sampled USD file.
    pub path: Option<PathBuf>,
    /// Substeps per frame.
    pub substeps: u32,
    /// Verlet damping `d`: the velocity is scaled by `exp(−d · h · 60)` per substep of `h` seconds (TressFX).
    pub damping: f32,
    /// Gravity along −Y, m/s².
    pub gravity: f32,
    /// Global shape stiffness in [0, 1]: the pull towards the rest pose carried by the root frame.
    pub global_stiffness: f32,
    /// Share of each strand from the root that the global shape pull reaches, in [0, 1].
    pub global_range: f32,
    /// Local shape stiffness `k` in [0, 1]; each end moves `0.5 · min(k, 0.95)` of the gap (TressFX).
    pub local_stiffness: f32,
    /// Müller et al.'s velocity correction factor `s_damping` in [0, 1].
    pub ftl_damping: f32,
    /// Wind strength (an acceleration across the strand, m/s²); 0 = no wind.
    pub wind: f32,
    /// Mean wind direction (need not be unit; not zero).
    pub wind_dir: [f32; 3],
    /// Gust amplitude in [0, 1]: the wind varies by ±gust of its strength.
    pub gust: f32,
    /// The root frame's motion.
    pub head: HeadMotion,
    /// Angle of the turn, nod or shake, degrees.
    pub head_angle_deg: f32,
    /// Period of the head motion or sweep, seconds.
    pub head_period: f32,
    /// `sweep`: how many strands (the last ones) sweep.
    pub sweep_strands: u32,
    /// `sweep`: the sweep's amplitude along +Z, world units.
    pub sweep_amplitude: f32,
    /// What the hair collides with.
    pub colliders: Colliders,
    /// Mesh colliders: cells of the signed distance grid on the meshes' longest axis.
    pub collider_resolution: u32,
    /// Mesh colliders: a point closer to the surface than this (world units) is pushed out to it.
    pub collider_margin: f32,
    /// Share of the strands simulated, in (0, 1]: every `round(1 / guides)`-th strand is a guide, the others
    /// follow their nearest guides (`follow.rs`); 1 simulates every strand.
    pub guides: f32,
}

impl Default for MotionSettings {
    fn default() -> Self {
        MotionSettings {
            source: MotionSource::None,
            fps: 30.0,
            frames: 120,
            path: None,
            substeps: 4,
            damping: 0.08,
            gravity: 9.82,
            global_stiffness: 0.05,
            global_range: 0.3,
            local_stiffness: 0.9,
            ftl_damping: 0.9,
            wind: 0.0,
            wind_dir: [1.0, 0.0, 0.0],
            gust: 0.5,
            head: HeadMotion::Still,
            head_angle_deg: 45.0,
            head_period: 2.0,
            sweep_strands: 1,
            sweep_amplitude: 0.05,
            colliders: Colliders::Auto,
            collider_resolution: 48,
            collider_margin: 0.002,
            guides: 1.0,
        }
    }
}

/// Largest substep count and frame rate a preset may ask for.
pub const MAX_SUBSTEPS: u32 = 64;
pub const MAX_FPS: f32 = 1000.0;
pub const MAX_FRAMES: u32 = 1_000_000;

impl MotionSettings {
    /// Range checks; each message names the key. Parameters that would make the simulation blow up or stand
    /// still forever (no substeps, stiffness outside [0, 1], negative damping, a non-positive time step) are
    /// refused.
    pub fn validate(&self) -> Result<()> {
        let fps = self.fps;
        if !(fps.is_finite() && fps > 0.0 && fps <= MAX_FPS) {
            bail!(
                "motion.fps must be a finite number in (0, {MAX_FPS}]: the time step 1/fps must be a positive \
                 number of seconds (got {fps:?})"
            );
        }
        if !(1..=MAX_FRAMES).contains(&self.frames) {
            bail!("motion.frames must be in 1..={MAX_FRAMES} (got {})", self.frames);
        }
        if !(1..=MAX_SUBSTEPS).contains(&self.substeps) {
            bail!(
                "motion.substeps must be in 1..={MAX_SUBSTEPS} (got {}): with none the simulation never advances",
                self.substeps
            );
        }
        for (k, v) in [
            ("motion.global_stiffness", self.global_stiffness),
            ("motion.global_range", self.global_range),
            ("motion.local_stiffness", self.local_stiffness),
            ("motion.ftl_damping", self.ftl_damping),
            ("motion.gust", self.gust),
        ] {
            if !(0.0..=1.0).contains(&v) {
                bail!(
                    "{k} must be in [0, 1] (got {v:?}): beyond 1 a constraint overshoots and the hair blows up"
                );
            }
        }
        for (k, v, max) in [
            ("motion.damping", self.damping, 100.0),
            ("motion.wind", self.wind, 1000.0),
            ("motion.head_period", self.head_period, 1e4),
        ] {
            if !(v.is_finite() && v >= 0.0 && v <= max) {
                bail!(
                    "motion.{} must be a finite number in [0, {max}] (got {v:?})",
                    &k[7..]
                );
            }
        }
        if self.head_period == 0.0 {
            bail!("motion.head_period must be positive (got 0)");
        }
        for (k, v, max) in [
            ("motion.gravity", self.gravity, 1000.0),
            ("motion.head_angle_deg", self.head_angle_deg, 180.0),
            ("motion.sweep_amplitude", self.sweep_amplitude, 1e4),
        ] {
            if !(v.is_finite() && v.abs() <= max) {
                bail!("{k} must be a finite number within ±{max} (got {v:?})");
            }
        }
        let w = Vec3::from(self.wind_dir);
        if !w.is_finite() || w.length_squared() == 0.0 {
            bail!(
                "motion.wind_dir must be three finite numbers, not all zero (got {:?})",
                self.wind_dir
            );
        }
        if !(self.guides > 0.0 && self.guides <= 1.0) {
            bail!(
                "motion.guides must be in (0, 1]: the share of the strands simulated (got {:?})",
                self.guides
            );
        }
        if !(sdf::MIN_RESOLUTION..=sdf::MAX_RESOLUTION).contains(&self.collider_resolution) {
            bail!(
                "motion.collider_resolution must be in {}..={} cells on the meshes' longest axis (got {})",
                sdf::MIN_RESOLUTION,
                sdf::MAX_RESOLUTION,
                self.collider_resolution
            );
        }
        let margin = self.collider_margin;
        if !(margin.is_finite() && (0.0..=1.0).contains(&margin)) {
            bail!("motion.collider_margin must be a finite number in [0, 1] world units (got {margin:?})");
        }
        if self.sweep_strands == 0 {
            bail!("motion.sweep_strands must be at least 1");
        }
        if self.source == MotionSource::Sequence && self.path.is_none() {
            bail!(
                "motion.path must name a folder of .hair files or a time-sampled USD file when motion.source = \
                 \"sequence\""
            );
        }
        Ok(())
    }
}

/// An opened motion source.
pub enum Motion {
    Still(Vec<Vec3>),
    Simulate(Box<Simulation>),
    /// A recording, and the preset's root motion that still carries its meshes (a baked simulation plays back
    /// with the head turning as it did live).
    Sequence(Sequence, Box<MeshMotion>),
}

/// The root frame's keyframed motion (`motion.head`) and the scene's meshes it carries.
pub struct MeshMotion {
    params: SimParams,
    pivot: Vec3,
    meshes: Vec<usize>,
}

impl MeshMotion {
    /// Frame `k`'s transform of the meshes, `None` when the root frame does not turn or carries none.
    fn at(&self, k: u32) -> Option<(&[usize], Affine3A)> {
        let turns = matches!(
            self.params.head,
            HeadMotion::Turn | HeadMotion::Nod | HeadMotion::Shake
        );
        (turns && !self.meshes.is_empty()).then(|| {
            let t = f64::from(k) / f64::from(self.params.fps);
            (&self.meshes[..], self.params.head_pose(t, self.pivot).affine())
        })
    }
}

impl Motion {
    /// Opens the source `m` names on `scene`. A sequence replaces the scene's strands with its first frame's
    /// (meshes kept). `head` is the generator's head ellipsoid when the scene is the generated head (the
    /// root frame pivots at its bottom, the neck); `root_meshes` are the scene's meshes that ride on the root
    /// frame (the head, not the floor): what `motion.colliders = meshes` collides with.
    pub fn open(
        m: &MotionSettings,
        scene: &mut Scene,
        head: Option<Ellipsoid>,
        root_meshes: Vec<usize>,
    ) -> Result<Motion> {
        m.validate()?;
        Ok(match m.source {
            MotionSource::None => Motion::Still(scene.strands.points.clone()),
            MotionSource::Simulate => Motion::Simulate(Box::new(Simulation::new(
                SimParams::from_settings(m),
                &scene.strands.points,
                &scene.strands.counts,
                root_frame(m, scene, head, root_meshes)?,
            ))),
            MotionSource::Sequence => {
                let dir = m.path.as_ref().expect("validated: a sequence has a path");
                let seq = Sequence::open(dir)?;
                *scene = Scene::new(seq.strands().clone(), std::mem::take(&mut scene.meshes));
                let carried = MeshMotion {
                    params: SimParams::from_settings(m),
                    pivot: pivot(scene, head, &root_meshes),
                    meshes: root_meshes,
                };
                Motion::Sequence(seq, Box::new(carried))
            }
        })
    }

    /// Frame `k`'s pose of the meshes that ride on the root frame (their indices and transform); `None`
    /// when nothing moves them.
    pub fn mesh_pose(&self, k: u32) -> Option<(&[usize], Affine3A)> {
        let turns = |h: HeadMotion| matches!(h, HeadMotion::Turn | HeadMotion::Nod | HeadMotion::Shake);
        match self {
            Motion::Simulate(s) if !s.root_meshes().is_empty() && turns(s.params().head) => {
                Some((s.root_meshes(), s.head_pose_at_frame(k).affine()))
            }
            Motion::Sequence(_, carried) => carried.at(k),
            _ => None,
        }
    }

    /// Shows frame `k` in `r`: its strand points ([`Renderer::update_points`]) and the pose of the meshes
    /// that ride on the root frame ([`Renderer::pose_meshes`]).
    pub fn show(&mut self, r: &mut Renderer, k: u32) -> Result<()> {
        r.update_points(self.frame(k)?)?;
        if let Some((meshes, pose)) = self.mesh_pose(k) {
            r.pose_meshes(meshes, pose)?;
        }
        Ok(())
    }

    /// How many frames the motion has: a sequence its files, otherwise `motion.frames`.
    pub fn frame_count(&self, m: &MotionSettings) -> u32 {
        match self {
            Motion::Sequence(s, _) => s.len() as u32,
            _ => m.frames,
        }
    }

    /// Frame `k`'s strand points (one per point of the scene, same order).
    pub fn frame(&mut self, k: u32) -> Result<&[Vec3]> {
        match self {
            Motion::Still(p) => Ok(p),
            Motion::Simulate(s) => Ok(s.frame(k)),
            Motion::Sequence(s, _) => s.frame(k),
        }
    }

    /// Whether the points change from frame to frame.
    pub fn is_still(&self) -> bool {
        matches!(self, Motion::Still(_))
    }

    /// The box holding the strands of every frame of the motion (`light.fit = bound` fits the hair maps' light
    /// frame to it once, `stable` to its bounding sphere, so normalised light depth does not swim). Plays the
    /// whole motion once; frame `k` is the same bits afterwards.
    pub fn bound(&mut self, m: &MotionSettings) -> Result<crate::scene::Aabb> {
        let bound = self.bound_with(m, &mut crate::progress::Quiet)?;
        Ok(bound.unwrap_or(crate::scene::Aabb::EMPTY))
    }

    /// [`Motion::bound`] telling `progress` before each frame; `None` once it answers `false`.
    pub fn bound_with(
        &mut self,
        m: &MotionSettings,
        progress: &mut dyn crate::progress::Progress,
    ) -> Result<Option<crate::scene::Aabb>> {
        let n = self.frame_count(m);
        let mut bound = crate::scene::Aabb::EMPTY;
        for k in 0..n {
            let label = format!("fitting the light to the whole motion: frame {k}");
            if !progress.step(&label, crate::progress::share(k as usize, n as usize)) {
                return Ok(None);
            }
            bound = bound.union(crate::scene::Aabb::from_points(self.frame(k)?));
        }
        Ok(Some(bound))
    }
}

/// The simulation's root frame on `scene` under `m.colliders` (see [`Motion::open`]): the collider, the pivot
/// (the head's neck, else the bottom centre of the root meshes' bounds) and the meshes that ride on it.
fn root_frame(
    m: &MotionSettings,
    scene: &Scene,
    head: Option<Ellipsoid>,
    meshes: Vec<usize>,
) -> Result<RootFrame> {
    let mesh_grid = || -> Result<Collider> {
        let list: Vec<&crate::scene::Mesh> = meshes.iter().filter_map(|&i| scene.meshes.get(i)).collect();
        if list.is_empty() {
            bail!("motion.colliders = \"meshes\": the scene has no mesh to collide with");
        }
        let grid = SdfGrid::build(&list, m.collider_resolution, m.collider_margin)?;
        Ok(Collider::Sdf(Arc::new(grid)))
    };
    let collider = match (m.colliders, head) {
        (Colliders::None, _) => None,
        (Colliders::Head | Colliders::Auto, Some(e)) => Some(Collider::Ellipsoid(e)),
        (Colliders::Head, None) => bail!(
            "motion.colliders = \"head\" needs the generator's head (scene.generator.kind = \"head\", no \
             scene.file or scene.scalp); use \"meshes\" to collide with a loaded scene's meshes"
        ),
        (Colliders::Auto, None) if meshes.is_empty() => None,
        (Colliders::Auto | Colliders::Meshes, _) => Some(mesh_grid()?),
    };
    Ok(RootFrame {
        pivot: pivot(scene, head, &meshes),
        collider,
        meshes,
    })
}

/// The root frame's pivot: the head ellipsoid's bottom (the neck), else the bottom centre of the bounds of
/// the scene's `meshes`, else the origin.
fn pivot(scene: &Scene, head: Option<Ellipsoid>, meshes: &[usize]) -> Vec3 {
    if let Some(e) = head {
        return e.center - Vec3::new(0.0, e.radii.y, 0.0);
    }
    let b = meshes
        .iter()
        .filter_map(|&i| scene.meshes.get(i))
        .fold(Aabb::EMPTY, |b, mesh| b.union(Aabb::from_points(&mesh.positions)));
    if b.is_empty() {
        Vec3::ZERO
    } else {
        Vec3::new(0.5 * (b.min.x + b.max.x), b.min.y, 0.5 * (b.min.z + b.max.z))
    }
}
