//! Dual scattering's constants measured from hairlab's own fibre (`hairlab measure fibres`; docs/truth.md,
//! "Dual scattering's constants, measured").
//!
//! - `ā_f(θ)`, `ā_b(θ)` (Zinke et al. 2008 Eq. 6–7): the energy Chiang et al.'s BSDF (`pathtrace::bsdf`) scatters
//!   into the forward and the backward half of the sphere for light at inclination `θ` to the fibre, averaged
//!   over the offset `h` (which stands for the light's azimuth about the fibre). The BSDF's fixed direction is the
//!   light's (`wo = (sin θ, 0, cos θ)` in its frame), the integrand `f(wo, wi) |wi.z|` as the path tracer weighs a
//!   sampled direction, forward where `wi.z < 0` (past the fibre, away from the light: Zinke's `cos φ < 0`).
//!   Deterministic: the product midpoint rule in `γ = asin h`, `θ_i` and `φ_i` with `N × N × 2N` points (the
//!   hemispheres' boundary on the cells' edges); [`attenuation`] at `N` and `2N` gives the convergence.
//! - The albedo `ā_f + ā_b` checked by an independent estimator ([`sampled_albedo`]: the mean of
//!   `f |cos| / pdf` over `FibreBsdf::sample`).
//! - A slab of parallel fibres (`slab.rs`) at several depths `n` (mean fibres crossed): the light leaving the far
//!   face `T(n)` and the near face `R(n)`, and the fits of hairlab's dual scattering (`shading::dual_scattering`):
//!   `T(n) ≈ d_f ā_f^n` (its global forward transmittance, the total light at depth `n`) and, over the deep
//!   half of the slabs, the light back-scattered after more than one event `R_multi ≈ d_b A_b(ā_f, ā_b)`.

mod fit;
pub mod slab;

pub use fit::{ExponentialFit, ScaleFit, back_energy, fit_exponential, fit_scale};

use anyhow::{Result, bail};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;

use crate::pathtrace::bsdf::{FibreBsdf, FibreParams};
use crate::progress::{Part, Progress, share};
use crate::rng::SplitMix64;
use slab::{Slab, SlabSpec, Tally};

/// The energy a fibre scatters into each half of the sphere, per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hemispheres {
    pub forward: DVec3,
    pub backward: DVec3,
}

/// Whose direction the BSDF holds fixed in [`attenuation`]: the light's (the sampler's albedo, the slab's
/// particles) or the eye's (the path tracer's camera paths, `f(wo = eye, wi = light)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fixed {
    Light,
    Eye,
}

/// `ā_f`, `ā_b` at `sin_theta` by the midpoint rule with `n` (even) points in `γ` and `θ_i` and `2n` in `φ`.
pub fn attenuation(fibre: &FibreParams, sin_theta: f32, n: usize, fixed: Fixed) -> Hemispheres {
    let n = n.max(2).next_multiple_of(2);
    let s = sin_theta.clamp(-1.0, 1.0);
    let light = Vec3::new(s, 0.0, (1.0 - s * s).max(0.0).sqrt());
    let step = PI / n as f64;
    let mid = |k: usize| -PI / 2.0 + (k as f64 + 0.5) * step;
    let rows: Vec<[DVec3; 2]> = (0..n)
        .into_par_iter()
        .map(|g| {
            let gamma = mid(g);
            let bsdf = FibreBsdf::new(fibre, gamma.sin() as f32);
            // Mean over h ∈ [−1, 1]: ½ cos γ dγ.
            let wh = 0.5 * gamma.cos() * step;
            let mut sums = [DVec3::ZERO; 2];
            for t in 0..n {
                let theta = mid(t);
                // dω = cos θ dθ dφ.
                let wt = theta.cos() * step * step * wh;
                for p in 0..2 * n {
                    let phi = (p as f64 + 0.5) * step;
                    let w = DVec3::new(theta.sin(), theta.cos() * phi.cos(), theta.cos() * phi.sin());
                    let other = w.as_vec3();
                    let (e, forward) = match fixed {
                        Fixed::Light => (bsdf.eval(light, other) * other.z.abs(), other.z < 0.0),
                        Fixed::Eye => (bsdf.eval(other, light) * light.z.abs(), other.z < 0.0),
                    };
                    sums[usize::from(!forward)] += e.as_dvec3() * wt;
                }
            }
            sums
        })
        .collect();
    let (mut forward, mut backward) = (DVec3::ZERO, DVec3::ZERO);
    for r in &rows {
        forward += r[0];
        backward += r[1];
    }
    Hemispheres { forward, backward }
}

/// The albedo at `sin_theta` by sampling: the mean of `f |cos| / pdf` over `samples` draws of
/// `FibreBsdf::sample` (uniform `h`), split by hemisphere, with the standard error of the whole.
pub fn sampled_albedo(fibre: &FibreParams, sin_theta: f32, samples: u64, seed: u64) -> (Hemispheres, DVec3) {
    let s = sin_theta.clamp(-1.0, 1.0);
    let wo = Vec3::new(s, 0.0, (1.0 - s * s).max(0.0).sqrt());
    const CHUNK: u64 = 4096;
    let parts: Vec<[DVec3; 3]> = (0..samples.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut acc = [DVec3::ZERO; 3];
            for i in c * CHUNK..((c + 1) * CHUNK).min(samples) {
                let mut rng = SplitMix64::stream(seed, i);
                let bsdf = FibreBsdf::new(fibre, rng.range(-1.0, 1.0));
                let u = [rng.unit(), rng.unit(), rng.unit(), rng.unit()];
                if let Some(x) = bsdf.sample(wo, u) {
                    let w = (x.f * x.wi.z.abs() / x.pdf).as_dvec3();
                    acc[usize::from(x.wi.z >= 0.0)] += w;
                    acc[2] += w * w;
                }
            }
            acc
        })
        .collect();
    let mut acc = [DVec3::ZERO; 3];
    for p in &parts {
        for k in 0..3 {
            acc[k] += p[k];
        }
    }
    let k = samples.max(2) as f64;
    let (forward, backward) = (acc[0] / k, acc[1] / k);
    let mean = forward + backward;
    let err = ((acc[2] / k - mean * mean).max(DVec3::ZERO) / (k - 1.0)).powf(0.5);
    (Hemispheres { forward, backward }, err)
}

/// What `measure fibres` measures and how finely.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// `N` of the quadrature (the table is taken at `N` and at `2N`).
    pub quadrature: usize,
    /// Draws of the sampled albedo per inclination.
    pub albedo_samples: u64,
    /// Inclinations of the light to the fibres for the slabs, degrees.
    pub angles_deg: Vec<f32>,
    /// Slab depths in mean fibres crossed.
    pub depths: Vec<f32>,
    pub packing: f32,
    /// The slab's period across, fibre widths.
    pub period: f32,
    /// Light particles per slab.
    pub particles: u64,
    pub seed: u64,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            quadrature: 64,
            albedo_samples: 200_000,
            angles_deg: vec![0.0, 30.0],
            depths: vec![1.0, 2.0, 4.0, 8.0, 16.0, 32.0],
            packing: 0.25,
            period: 64.0,
            particles: 100_000,
            seed: 1,
        }
    }
}

/// One inclination of the attenuation table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TableRow {
    pub sin_theta: f32,
    /// `ā_f`, `ā_b` at `N` and at `2N` (the figures quoted are the `2N` ones).
    pub forward_n: [f64; 3],
    pub backward_n: [f64; 3],
    pub forward: [f64; 3],
    pub backward: [f64; 3],
    /// `ā_f`, `ā_b` with the eye's direction fixed (the path tracer's convention; `2N`): the model's departure
    /// from reciprocity. None at `sin θ = ±1`, where the light runs along the fibre and `|wi.z|` is 0.
    pub forward_eye: Option<[f64; 3]>,
    pub backward_eye: Option<[f64; 3]>,
    /// The sampled albedo and its standard error.
    pub sampled: [f64; 3],
    pub sampled_error: [f64; 3],
}

/// A slab's light.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Transport {
    /// Light particles.
    pub samples: u64,
    /// `T(n)` and its standard error; the unscattered part of it; the part after more than
    /// `pathtrace::integrator::MAX_DEPTH` events.
    pub forward: [f64; 3],
    pub forward_error: [f64; 3],
    pub forward_direct: [f64; 3],
    pub forward_beyond_truth_depth: [f64; 3],
    /// `R(n)`, its standard error and its part after more than one event.
    pub back: [f64; 3],
    pub back_error: [f64; 3],
    pub back_multiple: [f64; 3],
    /// Walks stopped at the event limit.
    pub truncated: u64,
}

/// One slab at one inclination.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SlabRow {
    pub theta_deg: f32,
    /// Mean fibres crossed `N / W`, the fibres in a period, the depth in widths.
    pub fibres_crossed: f32,
    pub fibres: usize,
    pub depth: f32,
    pub transport: Transport,
}

/// The fits at one inclination.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fits {
    /// `ā_f`, `ā_b` at the inclination (quadrature at `2N`) and the `A_b` they give.
    pub forward: [f64; 3],
    pub backward: [f64; 3],
    pub back_energy: [f64; 3],
    /// `d_f` of `T(n) ≈ d_f ā_f^n` over every slab.
    pub d_f: Option<ScaleFit>,
    /// `d a^n` fitted freely per channel.
    pub free: [Option<ExponentialFit>; 3],
    /// `d_b` of `R_multi ≈ d_b A_b` over the deeper half of the slabs.
    pub d_b: Option<ScaleFit>,
}

/// The fits at one inclination.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FitRow {
    pub theta_deg: f32,
    pub fits: Fits,
}

/// Everything `measure fibres` measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FibreConstants {
    pub hair_color: [f32; 3],
    pub sigma_a: [f32; 3],
    pub quadrature: usize,
    pub albedo_samples: u64,
    pub packing: f32,
    pub period: f32,
    pub table: Vec<TableRow>,
    pub slabs: Vec<SlabRow>,
    pub fits: Vec<FitRow>,
    /// Whether every slab was measured (false after a stop).
    pub complete: bool,
}

/// The table's inclinations: `sin θ = −1 + k / 8`, `k = 0..=16`, as `shading::dual_scattering::TABLE`'s.
pub fn table_nodes() -> Vec<f32> {
    (0..=16).map(|k| -1.0 + k as f32 / 8.0).collect()
}

fn arr(v: DVec3) -> [f64; 3] {
    v.to_array()
}

/// Measures the fibre of `hair_color` (through `pathtrace::bsdf::fibre_params`): the table, then each slab at
/// each inclination, then the fits. `progress` is told each inclination and slab; when it answers `false` the
/// slabs measured so far are kept and fitted (`complete` false).
pub fn measure(hair_color: [f32; 3], o: &Options, progress: &mut dyn Progress) -> Result<FibreConstants> {
    if o.quadrature < 2 || o.depths.is_empty() || o.angles_deg.is_empty() || o.particles == 0 {
        bail!("measure fibres needs a quadrature of at least 2, one depth, one angle and one particle");
    }
    if let Some(a) = o.angles_deg.iter().find(|a| a.is_nan() || a.abs() >= 85.0) {
        bail!("angle {a}°: the light's inclination to the fibres must lie within ±85°");
    }
    for &n in &o.depths {
        SlabSpec {
            fibres_crossed: n,
            packing: o.packing,
            period: o.period,
            seed: o.seed,
        }
        .check()?;
    }
    let fibre = crate::pathtrace::bsdf::fibre_params(hair_color);
    let nodes = table_nodes();
    let mut complete = true;
    let mut table = Vec::new();
    {
        let mut part = Part::of(progress, 0.0, 0.3);
        for (k, &s) in nodes.iter().enumerate() {
            if !part.step("fibre attenuation table", share(k, nodes.len())) {
                complete = false;
                break;
            }
            table.push(table_row(&fibre, s, o));
        }
    }
    let mut slabs = Vec::new();
    let total = o.angles_deg.len() * o.depths.len();
    let mut part = Part::of(progress, 0.3, 1.0);
    'angles: for (i, &deg) in o.angles_deg.iter().enumerate() {
        for (j, &n) in o.depths.iter().enumerate() {
            let done = i * o.depths.len() + j;
            if !complete || !part.step(&format!("slab n = {n} at {deg}°"), share(done, total)) {
                complete = false;
                break 'angles;
            }
            let slab = Slab::new(&SlabSpec {
                fibres_crossed: n,
                packing: o.packing,
                period: o.period,
                seed: o.seed ^ ((j as u64) << 20),
            })?;
            let sin = deg.to_radians().sin();
            let seed = o.seed + done as u64;
            let t = slab.trace(&fibre, sin, o.particles, seed);
            slabs.push(SlabRow {
                theta_deg: deg,
                fibres_crossed: slab.fibres_crossed(),
                fibres: slab.fibres,
                depth: slab.depth,
                transport: transport(&t),
            });
        }
    }
    // The fits are how the slabs measured are kept, so they run whatever the answer.
    let _ = part.step("fitting", 1.0);
    let fits = o
        .angles_deg
        .iter()
        .map(|&deg| fit_row(&fibre, deg, o.quadrature * 2, &slabs))
        .collect();
    Ok(FibreConstants {
        hair_color,
        sigma_a: fibre.sigma_a.to_array(),
        quadrature: o.quadrature,
        albedo_samples: o.albedo_samples,
        packing: o.packing,
        period: o.period,
        table,
        slabs,
        fits,
        complete,
    })
}

fn table_row(fibre: &FibreParams, s: f32, o: &Options) -> TableRow {
    let n = o.quadrature;
    let coarse = attenuation(fibre, s, n, Fixed::Light);
    let fine = attenuation(fibre, s, 2 * n, Fixed::Light);
    let eye = (s.abs() < 1.0).then(|| attenuation(fibre, s, 2 * n, Fixed::Eye));
    let (sampled, err) = sampled_albedo(fibre, s, o.albedo_samples, o.seed ^ 0xA1BE);
    TableRow {
        sin_theta: s,
        forward_n: arr(coarse.forward),
        backward_n: arr(coarse.backward),
        forward: arr(fine.forward),
        backward: arr(fine.backward),
        forward_eye: eye.map(|e| arr(e.forward)),
        backward_eye: eye.map(|e| arr(e.backward)),
        sampled: arr(sampled.forward + sampled.backward),
        sampled_error: arr(err),
    }
}

fn transport(t: &Tally) -> Transport {
    Transport {
        samples: t.particles,
        forward: arr(t.forward()),
        forward_error: arr(t.forward_error()),
        forward_direct: arr(t.forward_part(0)),
        forward_beyond_truth_depth: arr(t.forward_part(3)),
        back: arr(t.back()),
        back_error: arr(t.back_error()),
        back_multiple: arr(t.back_part(2) + t.back_part(3)),
        truncated: t.truncated,
    }
}

/// The fits at inclination `deg` over `slabs`' rows at that inclination, with `ā_f`, `ā_b` at quadrature `n`.
fn fit_row(fibre: &FibreParams, deg: f32, n: usize, slabs: &[SlabRow]) -> FitRow {
    let rows: Vec<(f32, &Transport)> = slabs
        .iter()
        .filter(|r| r.theta_deg == deg)
        .map(|r| (r.fibres_crossed, &r.transport))
        .collect();
    FitRow {
        theta_deg: deg,
        fits: fits(attenuation(fibre, deg.to_radians().sin(), n, Fixed::Light), &rows),
    }
}

/// `d_f`, the free fit and `d_b` of `slabs` (mean fibres crossed, transport) against the attenuations `a`.
fn fits(a: Hemispheres, slabs: &[(f32, &Transport)]) -> Fits {
    let (af, ab) = (arr(a.forward), arr(a.backward));
    let back: [f64; 3] = std::array::from_fn(|c| back_energy(af[c], ab[c]));
    let forward_points: Vec<([f64; 3], [f64; 3])> = slabs
        .iter()
        .map(|&(n, t)| (t.forward, std::array::from_fn(|c| af[c].powf(f64::from(n)))))
        .collect();
    let deepest = slabs.iter().map(|s| s.0).fold(0.0f32, f32::max);
    let back_points: Vec<([f64; 3], [f64; 3])> = slabs
        .iter()
        .filter(|s| s.0 >= 0.5 * deepest)
        .map(|&(_, t)| (t.back_multiple, back))
        .collect();
    Fits {
        forward: af,
        backward: ab,
        back_energy: back,
        d_f: fit_scale(&forward_points),
        free: std::array::from_fn(|c| {
            let p: Vec<(f64, f64)> = slabs.iter().map(|&(n, t)| (f64::from(n), t.forward[c])).collect();
            fit_exponential(&p)
        }),
        d_b: fit_scale(&back_points),
    }
}

/// One figure of [`FibreConstants`] as a row of `fibre_constants.csv`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConstantRow {
    /// What the row holds: `a_f`, `a_b` (quadrature at 2N), `a_f_n`, `a_b_n` (at N), `a_f_eye`, `a_b_eye`,
    /// `albedo_sampled`, `slab_forward`, `slab_forward_direct`, `slab_forward_beyond_truth_depth`, `slab_back`,
    /// `slab_back_multiple`, `A_b`, `d_f`, `d_b`, `free_d`, `free_a`.
    pub quantity: String,
    pub sin_theta: f32,
    /// Mean fibres crossed (slab rows), else empty.
    pub fibres_crossed: Option<f32>,
    pub r: f64,
    pub g: f64,
    pub b: f64,
    /// The row's uncertainty: a standard error (sampled rows), a fit's residual (`d_f`, `d_b`, `free_*`: the
    /// RMS misfit as a share of the RMS light measured), else empty.
    pub error: Option<f64>,
    /// Samples, particles or fitted points behind the row.
    pub samples: Option<u64>,
}

impl FibreConstants {
    /// Every figure as a row of `fibre_constants.csv`.
    pub fn rows(&self) -> Vec<ConstantRow> {
        let row =
            |q: &str, s: f32, n: Option<f32>, v: [f64; 3], e: Option<f64>, k: Option<u64>| ConstantRow {
                quantity: q.to_string(),
                sin_theta: s,
                fibres_crossed: n,
                r: v[0],
                g: v[1],
                b: v[2],
                error: e,
                samples: k,
            };
        let mut out = Vec::new();
        for t in &self.table {
            let s = t.sin_theta;
            let err = t.sampled_error.iter().copied().fold(0.0, f64::max);
            out.extend([
                row("a_f", s, None, t.forward, None, None),
                row("a_b", s, None, t.backward, None, None),
                row("a_f_n", s, None, t.forward_n, None, None),
                row("a_b_n", s, None, t.backward_n, None, None),
                row(
                    "albedo_sampled",
                    s,
                    None,
                    t.sampled,
                    Some(err),
                    Some(self.albedo_samples),
                ),
            ]);
            if let (Some(f), Some(b)) = (t.forward_eye, t.backward_eye) {
                out.push(row("a_f_eye", s, None, f, None, None));
                out.push(row("a_b_eye", s, None, b, None, None));
            }
        }
        for r in &self.slabs {
            let (s, n) = (r.theta_deg.to_radians().sin(), Some(r.fibres_crossed));
            let max = |v: [f64; 3]| Some(v.iter().copied().fold(0.0, f64::max));
            let (t, k) = (&r.transport, Some(r.transport.samples));
            out.extend([
                row("slab_forward", s, n, t.forward, max(t.forward_error), k),
                row("slab_forward_direct", s, n, t.forward_direct, None, k),
                row(
                    "slab_forward_beyond_truth_depth",
                    s,
                    n,
                    t.forward_beyond_truth_depth,
                    None,
                    k,
                ),
                row("slab_back", s, n, t.back, max(t.back_error), k),
                row("slab_back_multiple", s, n, t.back_multiple, None, k),
            ]);
        }
        for f in &self.fits {
            let s = f.theta_deg.to_radians().sin();
            let x = &f.fits;
            out.push(row("A_b", s, None, x.back_energy, None, None));
            for (q, fit) in [("d_f", x.d_f), ("d_b", x.d_b)] {
                if let Some(v) = fit {
                    out.push(row(
                        q,
                        s,
                        None,
                        [v.scale; 3],
                        Some(v.residual),
                        Some(v.points as u64),
                    ));
                }
            }
            if let [Some(r), Some(g), Some(b)] = x.free {
                let res = Some(r.residual.max(g.residual).max(b.residual));
                out.push(row("free_d", s, None, [r.d, g.d, b.d], res, None));
                out.push(row("free_a", s, None, [r.a, g.a, b.a], res, None));
            }
        }
        out
    }
}
