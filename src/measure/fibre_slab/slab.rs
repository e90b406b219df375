//! A slab of parallel round fibres and light traced through it (`measure fibres`' multiple scattering).
//!
//! Geometry, in units of the fibre's width (radius ½): fibres along x, their centres `(y, z)` placed at random
//! in a cell `[0, W) × [−D, 0]` by random sequential addition (no two closer than a width: fibres do not
//! interpenetrate), at area fraction `packing` (the share of a cross-section the fibres cover, `ρ π / 4` with `ρ`
//! fibres per width²). The cell repeats along y (period `W`) and the fibres are infinite along x: the hierarchy
//! holds the cell and its copies at `y ± W`, fibres `2 L` long, and a ray that has gone `W − 1` across or
//! `L − 2` along without meeting a fibre restarts from where it got to, moved back into the cell (both moves are
//! symmetries of the slab), so the slab is infinite sideways. A straight line through the slab at right angles
//! to the fibres crosses `n = N / W` fibres on average (`N` in the cell): the depth `D = n / ρ`.
//!
//! Transport: particles from a directional light above the near face (`z > 0`), entering at a uniform `y`,
//! scatter by hairlab's Chiang BSDF (`pathtrace::bsdf`) at every fibre they meet in the path tracer's frame and
//! with its conventions (a direction into a fibre passes through it, hits' offsets `Hit::offset`, pbrt's
//! Russian roulette after 3 events), until they leave by the far face (forward) or the near face (back). The
//! BSDF is sampled with the light's side as its fixed direction (`wo` = towards where the particle came from),
//! the role the path tracer gives the eye's side: the two agree as far as the model is reciprocal (the
//! `reciprocity_at_zero_tilt` test of `bsdf.rs`; `measure fibres` prints the gap in `a_f`).

use anyhow::{Result, bail};
use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::pathtrace::bsdf::{FibreBsdf, FibreParams};
use crate::pathtrace::bvh::Bvh;
use crate::pathtrace::fibre::{Hit, Ray, Segment};
use crate::rng::SplitMix64;

/// Fibre radius: the unit of length is the fibre's width.
const RADIUS: f32 = 0.5;
/// Half the fibres' length along x.
const HALF_LENGTH: f32 = 256.0;
/// Scattering events a particle may have (Russian roulette ends nearly all far sooner).
const MAX_EVENTS: u32 = 100_000;
/// The path tracer's bounce limit (`pathtrace::integrator::MAX_DEPTH`): light that needs more events is tallied apart.
pub const TRUTH_DEPTH: u32 = crate::pathtrace::integrator::MAX_DEPTH;

/// What a slab is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabSpec {
    /// Mean fibres a straight line crosses through the slab at right angles to the fibres.
    pub fibres_crossed: f32,
    /// Area fraction the fibres cover in a cross-section (0 < packing ≤ 0.4).
    pub packing: f32,
    /// The period `W` across, in fibre widths.
    pub period: f32,
    pub seed: u64,
}

/// A generated slab and its hierarchy.
pub struct Slab {
    bvh: Bvh,
    /// Fibres in one period.
    pub fibres: usize,
    pub period: f32,
    /// Centre band's depth `D`.
    pub depth: f32,
}

/// The light leaving a slab per unit of light entering it, split by the scattering events it had.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    pub particles: u64,
    /// Leaving by the far face: unscattered, after one event, after 2 ..= [`TRUTH_DEPTH`], after more.
    pub forward: [DVec3; 4],
    /// Leaving by the near face, split alike.
    pub back: [DVec3; 4],
    /// Σ of each particle's squared forward and back weight (for the standard errors).
    pub forward_sq: DVec3,
    pub back_sq: DVec3,
    /// Particles stopped at [`MAX_EVENTS`] (their light is lost).
    pub truncated: u64,
}

fn bucket(events: u32) -> usize {
    match events {
        0 => 0,
        1 => 1,
        e if e <= TRUTH_DEPTH => 2,
        _ => 3,
    }
}

impl Tally {
    fn add(&mut self, o: &Tally) {
        self.particles += o.particles;
        for k in 0..4 {
            self.forward[k] += o.forward[k];
            self.back[k] += o.back[k];
        }
        self.forward_sq += o.forward_sq;
        self.back_sq += o.back_sq;
        self.truncated += o.truncated;
    }

    /// Light `w` leaving by the far face (`forward`) or the near one after the events of bucket `k`.
    fn leave(&mut self, forward: bool, k: usize, w: DVec3) {
        if forward {
            self.forward[k] += w;
        } else {
            self.back[k] += w;
        }
    }

    /// One particle's or path's whole weight, for the standard errors.
    fn square(&mut self, forward: bool, w: DVec3) {
        if forward {
            self.forward_sq += w * w;
        } else {
            self.back_sq += w * w;
        }
    }

    fn mean(&self, v: DVec3) -> DVec3 {
        v / self.particles.max(1) as f64
    }

    /// Forward transmittance, all events.
    pub fn forward(&self) -> DVec3 {
        self.mean(self.forward.iter().sum())
    }

    /// Back-scattered share, all events.
    pub fn back(&self) -> DVec3 {
        self.mean(self.back.iter().sum())
    }

    /// Forward or back share of bucket `k` (0: unscattered, 1: one event, 2: up to [`TRUTH_DEPTH`], 3: more).
    pub fn forward_part(&self, k: usize) -> DVec3 {
        self.mean(self.forward[k])
    }
    pub fn back_part(&self, k: usize) -> DVec3 {
        self.mean(self.back[k])
    }

    /// Standard error of [`Self::forward`] and [`Self::back`].
    pub fn forward_error(&self) -> DVec3 {
        self.error(self.forward(), self.forward_sq)
    }
    pub fn back_error(&self) -> DVec3 {
        self.error(self.back(), self.back_sq)
    }
    fn error(&self, mean: DVec3, sq: DVec3) -> DVec3 {
        let n = self.particles.max(2) as f64;
        ((sq / n - mean * mean).max(DVec3::ZERO) / (n - 1.0)).powf(0.5)
    }
}

impl SlabSpec {
    /// An error naming the value when the spec makes no slab: packing beyond (0, 0.4] (random addition jams
    /// near 0.55), `n ≤ 0` or a period under 4 widths.
    pub fn check(&self) -> Result<()> {
        let (n, packing, w) = (self.fibres_crossed, self.packing, self.period);
        if packing.is_nan() || packing <= 0.0 || packing > 0.4 {
            bail!("packing {packing}: the fibres' area fraction must lie in (0, 0.4]");
        }
        if n.is_nan() || n <= 0.0 || !n.is_finite() || w.is_nan() || w < 4.0 || !w.is_finite() {
            bail!("a slab needs n > 0 fibres crossed and a period of at least 4 widths (n {n}, period {w})");
        }
        Ok(())
    }
}

impl Slab {
    /// The slab of `spec`: fibre centres by random sequential addition (an error when [`SlabSpec::check`]
    /// fails or the slab would hold more than a million fibres).
    pub fn new(spec: &SlabSpec) -> Result<Slab> {
        let SlabSpec {
            fibres_crossed: n,
            packing,
            period: w,
            seed,
        } = *spec;
        spec.check()?;
        let rho = packing * 4.0 / std::f32::consts::PI;
        let count = (n * w).round().max(1.0) as usize;
        if count > 1_000_000 {
            bail!("{count} fibres in a slab of n = {n}, period {w}: at most a million");
        }
        let depth = count as f32 / (rho * w);
        let centres = place(count, w, depth, seed)?;
        let mut segments = Vec::with_capacity(3 * count);
        for shift in [-w, 0.0, w] {
            for &(y, z) in &centres {
                let (a, b) = (
                    Vec3::new(-HALF_LENGTH, y + shift, z),
                    Vec3::new(HALF_LENGTH, y + shift, z),
                );
                segments.push(Segment::new(a, b, RADIUS, RADIUS));
            }
        }
        Ok(Slab {
            bvh: Bvh::new(segments),
            fibres: count,
            period: w,
            depth,
        })
    }

    /// Mean fibres a line at right angles to them crosses: `N / W` (a fibre of width 1 in a period `W`).
    pub fn fibres_crossed(&self) -> f32 {
        self.fibres as f32 / self.period
    }

    /// `particles` light particles of unit weight from a directional light at inclination `sin_theta` to the
    /// fibres (travelling `(−sin θ, 0, −cos θ)`), particle `i` on its own stream `(seed, i)`, so a tally depends
    /// only on its seed.
    pub fn trace(&self, fibre: &FibreParams, sin_theta: f32, particles: u64, seed: u64) -> Tally {
        const CHUNK: u64 = 256;
        let chunks: Vec<Tally> = (0..particles.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut t = Tally::default();
                for i in c * CHUNK..((c + 1) * CHUNK).min(particles) {
                    self.particle(fibre, sin_theta, &mut SplitMix64::stream(seed, i), &mut t);
                }
                t
            })
            .collect();
        let mut total = Tally::default();
        for c in &chunks {
            total.add(c);
        }
        total
    }

    /// Where a ray from `origin` along `dir` goes next: its first fibre crossing, or out by a face. Rays restart
    /// from the cell when they have gone as far across or along as the hierarchy holds the slab.
    fn next(&self, mut origin: Vec3, dir: Vec3) -> Step {
        let (top, bottom) = self.faces();
        loop {
            let face = if dir.z < 0.0 {
                (bottom - origin.z) / dir.z
            } else if dir.z > 0.0 {
                (top - origin.z) / dir.z
            } else {
                f32::INFINITY
            };
            let side = (self.period - 2.0 * RADIUS) / dir.y.abs();
            let along = (HALF_LENGTH - 4.0 * RADIUS) / dir.x.abs();
            let reach = face.min(side).min(along).max(0.0);
            let ray = Ray { origin, dir };
            match self.bvh.closest_hit(&ray, reach) {
                Some(hit) => return Step::Hit(hit),
                None if reach == face => return Step::Out { forward: dir.z < 0.0 },
                None => origin = self.wrap(ray.at(reach)),
            }
        }
    }

    /// The near and the far face's planes, just outside every fibre.
    fn faces(&self) -> (f32, f32) {
        (RADIUS + 1e-3, -self.depth - RADIUS - 1e-3)
    }

    /// One particle's walk, tallied into `t`.
    fn particle(&self, fibre: &FibreParams, sin_theta: f32, rng: &mut SplitMix64, t: &mut Tally) {
        let to_light = to_light(sin_theta);
        let mut dir = -to_light;
        let mut origin = Vec3::new(0.0, rng.unit() * self.period, self.faces().0);
        let mut beta = Vec3::ONE;
        let mut events = 0u32;
        t.particles += 1;
        loop {
            let hit = match self.next(origin, dir) {
                Step::Hit(hit) => hit,
                Step::Out { forward } => {
                    t.leave(forward, bucket(events), beta.as_dvec3());
                    t.square(forward, beta.as_dvec3());
                    return;
                }
            };
            let frame = Frame::new(&hit, dir);
            let u = [rng.unit(), rng.unit(), rng.unit(), rng.unit()];
            let Some(s) = FibreBsdf::new(fibre, hit.h).sample(frame.local(-dir), u) else {
                return;
            };
            beta *= s.f * s.wi.z.abs() / s.pdf;
            events += 1;
            if events > 3 && !roulette(&mut beta, rng) {
                return;
            }
            if events >= MAX_EVENTS {
                t.truncated += 1;
                return;
            }
            dir = frame.world(s.wi);
            origin = leave(&hit, dir);
        }
    }

    /// `p` moved back into the cell: across by whole periods, along to x = 0.
    fn wrap(&self, p: Vec3) -> Vec3 {
        Vec3::new(0.0, p.y.rem_euclid(self.period), p.z)
    }
}

/// What a ray meets next in the slab.
enum Step {
    Hit(Hit),
    Out { forward: bool },
}

/// The path tracer's frame at a hit for a ray along `dir`: x the tangent, y = x × dir, z = x × y.
struct Frame([Vec3; 3]);

impl Frame {
    fn new(hit: &Hit, dir: Vec3) -> Frame {
        let x = hit.tangent;
        let y = x
            .cross(dir)
            .try_normalize()
            .unwrap_or_else(|| x.any_orthonormal_vector());
        Frame([x, y, x.cross(y)])
    }
    fn local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.0[0]), w.dot(self.0[1]), w.dot(self.0[2]))
    }
    fn world(&self, l: Vec3) -> Vec3 {
        (l.x * self.0[0] + l.y * self.0[1] + l.z * self.0[2]).normalize()
    }
}

/// Where a ray leaving `hit` along `w` starts: off the surface on `w`'s side (into a fibre is through it).
fn leave(hit: &Hit, w: Vec3) -> Vec3 {
    hit.point + hit.offset() * hit.normal.dot(w).signum() * hit.normal
}

/// The direction towards a light at inclination `sin_theta` to the fibres (x), above the near face.
fn to_light(sin_theta: f32) -> Vec3 {
    let s = sin_theta.clamp(-0.999, 0.999);
    Vec3::new(s, 0.0, (1.0 - s * s).sqrt())
}

/// pbrt's Russian roulette, as the path tracer plays it: survive with the throughput's largest channel (at most
/// 0.95), the survivors weighted up. Whether the walk goes on.
fn roulette(beta: &mut Vec3, rng: &mut SplitMix64) -> bool {
    let survive = beta.max_element().min(0.95);
    if rng.unit() >= survive {
        return false;
    }
    *beta /= survive;
    true
}

/// `count` fibre centres in `[0, w) × [−depth, 0]`, none closer than a width to another (periodic across), by
/// random sequential addition over a grid of one-width cells.
fn place(count: usize, w: f32, depth: f32, seed: u64) -> Result<Vec<(f32, f32)>> {
    let gap = 2.0 * RADIUS * 1.001f32;
    // Cells a little wider than the least distance, so a neighbour that is too near is in a neighbouring cell.
    let size = 1.01 * gap;
    let (nx, nz) = (
        ((w / size) as usize).max(1),
        ((depth / size).ceil() as usize).max(1),
    );
    let cell = |y: f32, z: f32| {
        let i = ((y / w * nx as f32) as usize).min(nx - 1);
        let j = ((-z / size) as usize).min(nz - 1);
        (i, j)
    };
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); nx * nz];
    let mut out: Vec<(f32, f32)> = Vec::with_capacity(count);
    let mut rng = SplitMix64::stream(seed, 0x51AB);
    let mut tries = 0usize;
    while out.len() < count {
        tries += 1;
        if tries > 200 * count + 10_000 {
            bail!(
                "cannot place {count} fibres without overlap in a {w} × {depth} cell (placed {})",
                out.len()
            );
        }
        let (y, z) = (rng.unit() * w, -rng.unit() * depth);
        let (i, j) = cell(y, z);
        let clear = (j.saturating_sub(1)..=(j + 1).min(nz - 1)).all(|jj| {
            [nx - 1, 0, 1].iter().all(|&di| {
                grid[(i + di) % nx + jj * nx].iter().all(|&k| {
                    let (py, pz) = out[k];
                    let dy = (y - py).abs();
                    let dy = dy.min(w - dy);
                    dy * dy + (z - pz) * (z - pz) >= gap * gap
                })
            })
        });
        if clear {
            grid[i + j * nx].push(out.len());
            out.push((y, z));
        }
    }
    Ok(out)
}
