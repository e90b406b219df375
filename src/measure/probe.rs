//! `hairlab measure probe`: the fibres model's light probe (`shading::mesh_bounce`, docs/truth.md, "The fibres
//! model", item 5) against the path tracer's own answer at the probe's points. At each strand point the probe
//! averages over, the path tracer gathers the mean radiance arriving over the sphere (`pathtrace::integrator::
//! arriving`: every event of the truth along each direction, the light itself left out as the probe leaves it
//! out; for the traced probe the directions outside the cone about the light, `pathtrace::probe::light_at`, as
//! it bakes); beside it stands what the eye pass reads there, the probe's lattice's mean
//! (`mesh_bounce::Grid::at`). The gather runs in two halves of the directions, each with its own random
//! stream, so their ratio shows the gather's own noise. What the gather holds that the voxel probe leaves to
//! other terms: the light the fibres between the point and the light scatter forward, which the eye pass shades
//! as `T_f` (dual scattering's global term).

use anyhow::Result;
use glam::Vec3;
use rayon::prelude::*;

use crate::path_scene::{PathScene, raster_shading};
use crate::pathtrace::integrator::{arriving, arriving_mean};
use crate::pathtrace::probe::light_at;
use crate::progress::{Outcome, Progress};
use crate::scene::Scene;
use crate::settings::Settings;
use crate::shading::HairModel;
use crate::shading::mesh_bounce::{Probe, spread};
pub use crate::shading::probe_light::luminance;

/// Height bands [`ProbeCheck::bands`] splits the points into.
pub const BANDS: usize = 6;
/// Points gathered between two progress steps.
const CHUNK: usize = 32;

/// One probe point: where it is, what the probe gives there and the path tracer's two half gathers (linear RGB
/// radiance per unit of the light's colour × intensity, as the scene's light has it).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ProbePoint {
    pub x: f32,
    pub y: f32,
    pub z: f32,
    pub probe_r: f32,
    pub probe_g: f32,
    pub probe_b: f32,
    pub gather_r: f32,
    pub gather_g: f32,
    pub gather_b: f32,
    /// The first half's gather over the second's, in luminance.
    pub halves: f32,
}

impl ProbePoint {
    pub fn probe(&self) -> Vec3 {
        Vec3::new(self.probe_r, self.probe_g, self.probe_b)
    }
    pub fn gather(&self) -> Vec3 {
        Vec3::new(self.gather_r, self.gather_g, self.gather_b)
    }
}

/// The points compared and their directions per point.
#[derive(Clone, Debug)]
pub struct ProbeCheck {
    pub points: Vec<ProbePoint>,
    pub directions: u32,
    /// The two half gathers' luminance summed over the points, first and second half.
    pub halves: (f64, f64),
}

/// A set of points' totals: the probe's and the gather's mean radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Totals {
    pub points: usize,
    pub probe: Vec3,
    pub gather: Vec3,
}

impl Totals {
    fn of<'a>(points: impl Iterator<Item = &'a ProbePoint>) -> Totals {
        let (mut n, mut probe, mut gather) = (0, Vec3::ZERO, Vec3::ZERO);
        for p in points {
            n += 1;
            probe += p.probe();
            gather += p.gather();
        }
        let k = n.max(1) as f32;
        Totals {
            points: n,
            probe: probe / k,
            gather: gather / k,
        }
    }

    /// The probe's mean over the gather's, in linear luminance.
    pub fn ratio(&self) -> f32 {
        luminance(self.probe) / luminance(self.gather).max(f32::MIN_POSITIVE)
    }
}

impl ProbeCheck {
    /// Every point.
    pub fn all(&self) -> Totals {
        Totals::of(self.points.iter())
    }

    /// [`BANDS`] equal bands of the points' height (world y), the highest first.
    pub fn bands(&self) -> Vec<Totals> {
        let (lo, hi) = self
            .points
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), p| {
                (a.min(p.y), b.max(p.y))
            });
        let band = |p: &ProbePoint| {
            let t = (hi - p.y) / (hi - lo).max(f32::MIN_POSITIVE);
            ((t * BANDS as f32) as usize).min(BANDS - 1)
        };
        (0..BANDS)
            .map(|b| Totals::of(self.points.iter().filter(|p| band(p) == b)))
            .collect()
    }
}

/// The probe of `scene` under `settings` (taken under the fibres model, whose probe it is, whatever
/// `render.hair_model` says) against the path tracer's gather of `directions` directions per point (at least 2,
/// split in two halves). Stops between chunks of points when `progress` answers `false`, with the points done.
pub fn check(
    settings: &Settings,
    scene: &Scene,
    directions: u32,
    progress: &mut dyn Progress,
) -> Result<Outcome<ProbeCheck>> {
    anyhow::ensure!(
        directions >= 2,
        "--directions {directions}: the gather takes at least 2 (two halves)"
    );
    let mut s = settings.clone();
    s.render.hair_model = HairModel::Fibres;
    let path = PathScene::new(&s, scene)?;
    let raster = raster_shading(&s, scene, &scene.bounds());
    let grid = raster
        .bounce
        .ok_or_else(|| anyhow::anyhow!("the fibres model made no probe"))?;
    let gather = |p: Vec3, n: u32, stream: u64| match s.render.probe {
        Probe::Voxels => arriving_mean(arriving(&path.bvh, &path.light, &path.settings, p, n, stream)),
        Probe::Traced => {
            let to_light = raster.light.toward(p).0;
            light_at(&path.bvh, &path.light, to_light, &path.settings, p, n, stream).mean()
        }
    };
    let at = match s.render.probe {
        Probe::Voxels => spread(&scene.strands.points),
        Probe::Traced => crate::pathtrace::probe::points_of(&path.bvh, &scene.strands.points),
    };
    anyhow::ensure!(
        !at.is_empty(),
        "the scene has no strands: the probe has no points"
    );
    let half = directions / 2;
    let mut points = Vec::with_capacity(at.len());
    let mut halves = (0.0, 0.0);
    for (c, chunk) in at.chunks(CHUNK).enumerate() {
        let done: Vec<(ProbePoint, f32, f32)> = chunk
            .par_iter()
            .enumerate()
            .map(|(k, &p)| {
                let stream = ((c * CHUNK + k) as u64) << 1;
                let a = gather(p, half, stream);
                let b = gather(p, directions - half, stream | 1);
                let gather = (a * half as f32 + b * (directions - half) as f32) / directions as f32;
                let probe = grid.at(p).mean();
                let (la, lb) = (luminance(a), luminance(b));
                let point = ProbePoint {
                    x: p.x,
                    y: p.y,
                    z: p.z,
                    probe_r: probe.x,
                    probe_g: probe.y,
                    probe_b: probe.z,
                    gather_r: gather.x,
                    gather_g: gather.y,
                    gather_b: gather.z,
                    halves: la / lb.max(f32::MIN_POSITIVE),
                };
                (point, la, lb)
            })
            .collect();
        for (p, a, b) in done {
            points.push(p);
            halves.0 += f64::from(a);
            halves.1 += f64::from(b);
        }
        let label = format!("gathering: {}/{} points", points.len(), at.len());
        if !progress.step(&label, crate::progress::share(points.len(), at.len())) && points.len() < at.len() {
            return Ok(Outcome::Stopped(ProbeCheck {
                points,
                directions,
                halves,
            }));
        }
    }
    Ok(Outcome::Complete(ProbeCheck {
        points,
        directions,
        halves,
    }))
}
