//! The fibre of Chiang, Bitterli, Tappan & Burley 2016 ("A Practical and Controllable Hair and Fur Model for
//! Production Path Tracing") as a real-time shading model (`render.shading = chiang`): the path tracer's BSDF
//! (`pathtrace::bsdf`) averaged over the offset `h` across the fibre, which is what a strand thinner than its
//! pixel sends to the eye. The CPU model (the specification) of `shaders/common/chiang.wgsl`.
//!
//! The BSDF's building blocks live here and the path tracer uses them, so the real-time model and the truth
//! share one definition: d'Eon, Francois, Hill, Letteri & Aubry 2011's longitudinal term `M_p` ([`mp`]), the
//! attenuations `A_p` with exact dielectric Fresnel ([`ap`]), the azimuthal centres `Φ(p, h)` ([`phi_p`]), the
//! trimmed logistic `D` ([`Trimmed`]) and the cuticle tilt ([`tilted`]).
//!
//! The shading, `S = Σ_p M_p(θ_i, θ_o) N̄_p(φ, θ_o)`, per unit radiance arriving from `ω_i` (the BSDF times
//! the ribbon's cosine, pbrt's `f · |cos|`, as [`super::marschner`] returns it):
//! - `M_p` does not depend on `h`, so the average over `h` falls on the azimuthal part alone:
//!   `N̄_p = ½ ∫ A_p(h) D(φ − Φ(p, h)) dh` for R, TT and TRT, `N̄_3 = ½ ∫ A_3(h) dh / 2π` for the residual.
//! - [`table`]: `N̄_p` on a grid of `|φ| = π i / 64`, `cos θ_o = k / 16` and
//!   `√σ_a = j · ROOT_SIGMA_MAX / 16` (per channel, `fibre_transport`'s absorption axis), by the midpoint rule
//!   in `h` at [`H_SAMPLES`] points, built once per process (the path tracer's own functions: nothing to
//!   drift) and uploaded to the eye pass as a 3D texture (173 KiB: R once for every absorption, the residual
//!   once for every azimuth); looked up trilinearly per channel ([`lookup`]). Three more layers hold the
//!   fibre's response to light spread over the sphere ([`response_moments`]), which the traced probe's light
//!   takes (`probe_light`).
//!   `N̄_p` is even in `φ` (`A_p` is even in `h`, `Φ` odd) and depends on `θ_o` through `cos θ_o` (Fresnel at
//!   `cos θ_o cos γ_o`, `sin γ_t = h cos θ_o / √(η² − sin² θ_o)`): a grid in `cos θ_o` follows it to grazing,
//!   where one in `sin θ_o` was 21 % off the integral.
//! - `M_p` is evaluated, not tabulated: the CPU in f64 ([`mp`], the path tracer's), the GPU in f32.
//! - The fibre is the path tracer's ([`FIBRE`]): `β_m` = [`BETA_M`] (the real-time Marschner lobe's width),
//!   azimuthal roughness `β_n` = `marschner::BETA_N`, tilt `marschner::ALPHA_R`, index `marschner::ETA`, and
//!   `σ_a` from the colour as `marschner::absorption` takes it.
//!
//! Accuracy of the table against the `h` integral taken at each direction (`tests::table_matches_the_integral`,
//! 400 random directions and colours): mean 0.56 %, within 3 % + 1e-3 everywhere (the largest relative error,
//! 5.8 %, on a TRT tail below 2e-3). The eye pass costs 1.13–1.31× Marschner's (docs/truth.md).

use super::{fibre_transport, marschner};
use glam::Vec3;
use std::f32::consts::PI;
use std::sync::OnceLock;

/// The longitudinal roughness `β_m` whose R lobe is as wide as the real-time Marschner model's: Chiang et al.'s
/// variance `v = (0.726 β_m + 0.812 β_m² + 3.7 β_m²⁰)²` equal to the square of Karis's standard deviation
/// `2 sin β_R` in `sin θ_o` ([`marschner::WIDTH`]`[0]`, 15° for Marschner et al.'s β_R = 7.5°, a width in the
/// half angle θ_h). `β_m = β_R` read Marschner's half-angle width as Chiang's roughness: the traced fibre's
/// lobes were 2.4× narrower than the raster's (6.2° against 15°). TT and TRT follow in both models (`v/4`, `4v`
/// against `β_R/2`, `2β_R`). A test solves for it.
pub const BETA_M: f32 = 0.274_995_65;

/// Lobes R, TT, TRT and the residual (Chiang et al.'s `p_max = 3`).
pub const LOBES: usize = 4;
const P_MAX: usize = LOBES - 1;

/// The fibre's roughness, tilt and index: what the path tracer's fibres and this model share.
#[derive(Clone, Copy, Debug)]
pub struct Fibre {
    pub beta_m: f32,
    pub beta_n: f32,
    /// Cuticle scale tilt, radians.
    pub alpha: f32,
    pub eta: f32,
}

/// The path tracer's fibre (`pathtrace::bsdf::fibre_params`).
pub const FIBRE: Fibre = Fibre {
    beta_m: BETA_M,
    beta_n: marschner::BETA_N,
    alpha: marschner::ALPHA_R,
    eta: marschner::ETA,
};

impl Fibre {
    /// Longitudinal variance per lobe: `v`, `v/4`, `4v`, `4v` (Chiang et al. 2016, §4.1).
    pub fn variances(&self) -> [f32; LOBES] {
        let bm = self.beta_m;
        let v0 = (0.726 * bm + 0.812 * bm * bm + 3.7 * bm.powi(20)).powi(2);
        [v0, 0.25 * v0, 4.0 * v0, 4.0 * v0]
    }

    /// The azimuthal logistic's scale `s` (Chiang et al. 2016, §4.2).
    pub fn logistic_scale(&self) -> f32 {
        let bn = self.beta_n;
        (PI / 8.0).sqrt() * (0.265 * bn + 1.194 * bn * bn + 5.372 * bn.powi(22))
    }

    /// `(sin 2^k α, cos 2^k α)` for k = 0, 1, 2.
    pub fn tilts(&self) -> ([f32; 3], [f32; 3]) {
        let mut sin = [self.alpha.sin(), 0.0, 0.0];
        let mut cos = [safe_sqrt(1.0 - sin[0] * sin[0]), 0.0, 0.0];
        for i in 1..3 {
            sin[i] = 2.0 * cos[i - 1] * sin[i - 1];
            cos[i] = cos[i - 1].powi(2) - sin[i - 1].powi(2);
        }
        (sin, cos)
    }
}

pub(crate) fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// Modified Bessel function I0 (f64), by Abramowitz & Stegun's polynomial 9.8.1 (relative error below 1.6e-7;
/// pbrt's fixed 10-term series loses ~2% of the energy near x = 12).
fn i0(x: f64) -> f64 {
    if x >= 3.75 {
        return x.exp() * i0_scaled(x) / x.sqrt();
    }
    let t = (x / 3.75) * (x / 3.75);
    1.0 + t
        * (3.5156229 + t * (3.0899424 + t * (1.2067492 + t * (0.2659732 + t * (0.0360768 + t * 0.0045813)))))
}

/// √x e^-x I0(x) for x ≥ 3.75 by Abramowitz & Stegun's polynomial 9.8.2 (relative error below 5e-7).
fn i0_scaled(x: f64) -> f64 {
    let u = 3.75 / x;
    0.39894228
        + u * (0.01328592
            + u * (0.00225319
                + u * (-0.00157565
                    + u * (0.00916281
                        + u * (-0.02057706 + u * (0.02635537 + u * (-0.01647633 + u * 0.00392377)))))))
}

/// d'Eon et al. 2011's longitudinal scattering, for small variance in the stable form `e^(a − b − 1/v) ·
/// (√a e^-a I0(a)) / (v √a)` (pbrt's `exp(log I0(a) − b − 1/v + ln(1/v))`, its exponentials and
/// logarithms gathered into one exponent).
pub fn mp(cos_i: f32, cos_o: f32, sin_i: f32, sin_o: f32, v: f32) -> f32 {
    let v = v as f64;
    let a = cos_i as f64 * cos_o as f64 / v;
    let b = sin_i as f64 * sin_o as f64 / v;
    let m = if v <= 0.1 {
        if a >= 3.75 {
            (a - b - 1.0 / v).exp() * i0_scaled(a) / (v * a.sqrt())
        } else {
            (-b - 1.0 / v).exp() * i0(a) / v
        }
    } else {
        (-b).exp() * i0(a) / ((1.0 / v).sinh() * 2.0 * v)
    };
    m as f32
}

/// Exact Fresnel reflectance from outside (index 1) into index `eta` at incidence cosine `cos_i`.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(-1.0, 1.0);
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let sin_t = safe_sqrt(1.0 - cos_i * cos_i) / eta;
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = safe_sqrt(1.0 - sin_t * sin_t);
    let par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (par * par + perp * perp)
}

/// Attenuations A_p for incidence `cos_theta_o`, offset `h` and one-pass transmittance `t`.
pub fn ap(cos_theta_o: f32, eta: f32, h: f32, t: Vec3) -> [Vec3; LOBES] {
    let cos_gamma_o = safe_sqrt(1.0 - h * h);
    let f = fresnel_dielectric(cos_theta_o * cos_gamma_o, eta);
    let mut a = [Vec3::ZERO; LOBES];
    a[0] = Vec3::splat(f);
    a[1] = (1.0 - f) * (1.0 - f) * t;
    for p in 2..P_MAX {
        a[p] = a[p - 1] * t * f;
    }
    a[P_MAX] = a[P_MAX - 1] * f * t / (Vec3::ONE - t * f);
    a
}

/// The refraction at offset `h` for an outgoing elevation (`sin_o`, `cos_o`): `γ_t` and the path length of one
/// passage through the fibre (unit radius), `2 cos γ_t / cos θ_t`; the passage's transmittance is
/// `exp(−σ_a × length)`.
pub fn refracted(eta: f32, h: f32, sin_o: f32, cos_o: f32) -> (f32, f32) {
    let sin_t = sin_o / eta;
    let cos_t = safe_sqrt(1.0 - sin_t * sin_t);
    let etap = safe_sqrt(eta * eta - sin_o * sin_o) / cos_o;
    let sin_gamma_t = (h / etap).clamp(-1.0, 1.0);
    let cos_gamma_t = safe_sqrt(1.0 - sin_gamma_t * sin_gamma_t);
    (sin_gamma_t.asin(), 2.0 * cos_gamma_t / cos_t)
}

/// The lobe's azimuthal centre: Φ(p, γ_o, γ_t).
pub fn phi_p(p: usize, gamma_o: f32, gamma_t: f32) -> f32 {
    let p = p as f32;
    2.0 * p * gamma_t - 2.0 * gamma_o + p * PI
}

fn logistic(x: f32, s: f32) -> f32 {
    let x = x.abs();
    let e = (-x / s).exp();
    e / (s * (1.0 + e) * (1.0 + e))
}

fn logistic_cdf(x: f32, s: f32) -> f32 {
    1.0 / (1.0 + (-x / s).exp())
}

/// The logistic of scale `s` trimmed to [-π, π]: its CDF at -π and its mass there, worked out once per scale.
#[derive(Clone, Copy, Debug)]
pub struct Trimmed {
    s: f32,
    below: f32,
    mass: f32,
}

impl Trimmed {
    pub fn new(s: f32) -> Trimmed {
        let below = logistic_cdf(-PI, s);
        Trimmed {
            s,
            below,
            mass: logistic_cdf(PI, s) - below,
        }
    }

    /// The logistic renormalised on [-π, π].
    pub fn density(&self, x: f32) -> f32 {
        logistic(x, self.s) / self.mass
    }

    /// Inverts the trimmed CDF at `u` ∈ [0, 1).
    pub fn sample(&self, u: f32) -> f32 {
        let x = -self.s * (1.0 / (u * self.mass + self.below) - 1.0).ln();
        x.clamp(-PI, PI)
    }
}

/// Wraps an angle into [-π, π].
pub fn wrap(mut x: f32) -> f32 {
    while x > PI {
        x -= 2.0 * PI;
    }
    while x < -PI {
        x += 2.0 * PI;
    }
    x
}

/// sin θ_o and |cos θ_o| rotated by the cuticle tilt for lobe `p` (-2α for R, α for TT, 4α for TRT; the
/// residual untilted), with `tilts` = [`Fibre::tilts`].
pub fn tilted(p: usize, sin_o: f32, cos_o: f32, (sa, ca): ([f32; 3], [f32; 3])) -> (f32, f32) {
    match p {
        0 => (
            sin_o * ca[1] - cos_o * sa[1],
            (cos_o * ca[1] + sin_o * sa[1]).abs(),
        ),
        1 => (
            sin_o * ca[0] + cos_o * sa[0],
            (cos_o * ca[0] - sin_o * sa[0]).abs(),
        ),
        2 => (
            sin_o * ca[2] + cos_o * sa[2],
            (cos_o * ca[2] - sin_o * sa[2]).abs(),
        ),
        _ => (sin_o, cos_o),
    }
}

/// Nodes of [`table`] in `|φ|`, `cos θ_o` and `√σ_a`; `shaders/common/chiang.wgsl` names the same counts (a
/// test compares them).
pub const PHI_NODES: usize = 65;
pub const COS_NODES: usize = 17;
pub const SIGMA_NODES: usize = fibre_transport::ABSORPTION_NODES;
/// `cos θ_o` the first node is computed at: at 0 (the eye along the fibre) Fresnel reflects everything and the
/// residual's `A_3 = A_2 f T / (1 − f T)` is 0/0 for a clear fibre.
pub const MIN_COS: f32 = 1e-3;
/// Offsets `h` of the midpoint rule per node.
pub const H_SAMPLES: usize = 256;
/// Layers of the table, a 3D texture of [`PHI_NODES`] × [`COS_NODES`] × `LAYERS` floats (x the azimuth, y the
/// inclination): R (it does not depend on the absorption, `A_R` is Fresnel alone), TT and TRT one layer per
/// absorption node, the residual (no azimuth, `A_3 / 2π`) one layer with the absorption along x, the three
/// layers of the response to spread light ([`RESPONSE_LAYER`]) and the header.
pub const LAYERS: usize = 2 * SIGMA_NODES + 6;
/// The first of the three layers `K_l`, `l` = 0, 1, 2 ([`response_moments`]): x `sin θ_o = −1 + 2i / 64`, y the
/// absorption node.
pub const RESPONSE_LAYER: usize = 2 * SIGMA_NODES + 2;
const _: () = assert!(SIGMA_NODES <= COS_NODES);
/// The header's layer: at y = 0, the variances `v_p` (x 0–3), `sin 2^k α` (4–6) and `cos 2^k α` (8–10), so that
/// the GPU reads the fibre's constants rather than literals that could drift.
pub const HEADER_LAYER: usize = LAYERS - 1;
/// Floats in [`table`]: 44 200 (173 KiB), uploaded as a texture (a storage binding would have to fit devices
/// whose bindings hold 16 KiB).
pub const TABLE_LEN: usize = PHI_NODES * COS_NODES * LAYERS;
const HEADER: usize = HEADER_LAYER * COS_NODES * PHI_NODES;

/// Index in [`table`] of texel (x, y, layer).
fn texel(x: usize, y: usize, layer: usize) -> usize {
    (layer * COS_NODES + y) * PHI_NODES + x
}

/// Index of node (`|φ|` node `i`, `cos θ_o` node `k`, `√σ_a` node `j`) of lobe `p` in [`table`]; the axis a lobe
/// does not depend on is ignored, so that the trilinear lookup interpolates equal values there.
pub fn index(p: usize, j: usize, k: usize, i: usize) -> usize {
    match p {
        0 => texel(i, k, 0),
        1 => texel(i, k, 1 + j),
        2 => texel(i, k, 1 + SIGMA_NODES + j),
        _ => texel(j, k, 1 + 2 * SIGMA_NODES),
    }
}

/// `|φ|` of node `i`.
pub fn node_phi(i: usize) -> f32 {
    PI * i as f32 / (PHI_NODES - 1) as f32
}

/// `cos θ_o` of node `k`.
pub fn node_cos(k: usize) -> f32 {
    k as f32 / (COS_NODES - 1) as f32
}

/// The averaged azimuthal terms `N̄_p` of `fibre` at outgoing inclination `sin_o` for the absorptions `sigma`
/// (per unit radius, any number), at the azimuths `phis`, by the midpoint rule at `h_samples` offsets:
/// `[p][j][i]` for lobe `p`, absorption `sigma[j]`, azimuth `phis[i]`.
pub fn averaged(
    fibre: &Fibre,
    sin_o: f32,
    sigma: &[f32],
    phis: &[f32],
    h_samples: usize,
) -> Vec<Vec<Vec<f32>>> {
    let cos_o = safe_sqrt(1.0 - sin_o * sin_o);
    let logistic = Trimmed::new(fibre.logistic_scale());
    let mut out = vec![vec![vec![0.0f32; phis.len()]; sigma.len()]; LOBES];
    let w = 1.0 / h_samples as f32;
    let mut d = vec![[0.0f32; P_MAX]; phis.len()];
    for m in 0..h_samples {
        let h = -1.0 + (m as f32 + 0.5) * 2.0 * w;
        let gamma_o = h.asin();
        let (gamma_t, length) = refracted(fibre.eta, h, sin_o, cos_o);
        for (p, centre) in (0..P_MAX).map(|p| (p, phi_p(p, gamma_o, gamma_t))) {
            for (di, &phi) in d.iter_mut().zip(phis) {
                di[p] = logistic.density(wrap(phi - centre));
            }
        }
        for first in (0..sigma.len()).step_by(3) {
            let j = |c: usize| (first + c).min(sigma.len() - 1);
            let t = (-Vec3::new(sigma[j(0)], sigma[j(1)], sigma[j(2)]) * length).exp();
            let a = ap(cos_o, fibre.eta, h, t);
            for c in (0..3).filter(|&c| first + c < sigma.len()) {
                for p in 0..P_MAX {
                    let ap = a[p][c] * w;
                    for (o, di) in out[p][j(c)].iter_mut().zip(&d) {
                        *o += ap * di[p];
                    }
                }
                let residual = a[P_MAX][c] * w / (2.0 * PI);
                out[P_MAX][j(c)].iter_mut().for_each(|o| *o += residual);
            }
        }
    }
    out
}

/// The path tracer's fibre ([`FIBRE`]) tabulated: `N̄_p` at [`index`], the header at [`HEADER_LAYER`]. Built on first use (all
/// cores; ~0.1 s in a release build).
pub fn table() -> &'static [f32] {
    static TABLE: OnceLock<Vec<f32>> = OnceLock::new();
    TABLE.get_or_init(|| build(&FIBRE, H_SAMPLES))
}

/// [`table`] for `fibre` at `h_samples` offsets.
pub fn build(fibre: &Fibre, h_samples: usize) -> Vec<f32> {
    use rayon::prelude::*;
    let sigma: Vec<f32> = (0..SIGMA_NODES).map(fibre_transport::node_sigma).collect();
    let phis: Vec<f32> = (0..PHI_NODES).map(node_phi).collect();
    let rows: Vec<_> = (0..COS_NODES)
        .into_par_iter()
        .map(|k| {
            let cos_o = node_cos(k).max(MIN_COS);
            averaged(fibre, safe_sqrt(1.0 - cos_o * cos_o), &sigma, &phis, h_samples)
        })
        .collect();
    let mut table = vec![0.0f32; TABLE_LEN];
    let v = fibre.variances();
    let (sin, cos) = fibre.tilts();
    table[HEADER..HEADER + 4].copy_from_slice(&v);
    table[HEADER + 4..HEADER + 7].copy_from_slice(&sin);
    table[HEADER + 8..HEADER + 11].copy_from_slice(&cos);
    for (k, row) in rows.iter().enumerate() {
        for (p, lobe) in row.iter().enumerate() {
            for (j, values) in lobe.iter().enumerate() {
                for (i, &x) in values.iter().enumerate() {
                    table[index(p, j, k, i)] = x;
                }
            }
        }
    }
    let response: Vec<_> = (0..PHI_NODES)
        .into_par_iter()
        .map(|i| response_moments(fibre, node_response_sin(i), &sigma, h_samples))
        .collect();
    for (i, moments) in response.iter().enumerate() {
        for (l, values) in moments.iter().enumerate() {
            for (j, &x) in values.iter().enumerate() {
                table[texel(i, j, RESPONSE_LAYER + l)] = x;
            }
        }
    }
    table
}

/// `sin θ_o` of the response layers' node `i`.
pub fn node_response_sin(i: usize) -> f32 {
    -1.0 + 2.0 * i as f32 / (PHI_NODES - 1) as f32
}

/// The fibre's response to light spread over the sphere, by the Legendre moments of its spread along the
/// fibre: light of integral `E` over the sphere whose directions' `u = sin θ_i` (along the tangent) have the
/// first two moments `m₁`, `m₂` (the density of `u` taken as `½ (1 + 3 m₁ u + 5/2 (3 m₂ − 1) P₂(u))`, its
/// azimuth about the fibre uniform) sends `E (K₀ + m₁ K₁ + (3 m₂ − 1) K₂)` towards an eye at `sin θ_o`.
/// The azimuthal average of `S` is `Σ_p M_p Ā_p / 2π` with `Ā_p = ½ ∫ A_p dh`, so with
/// `μ_pl = ∫ M_p(u, θ_o) P_l(u) du` (`M_p` at the lobe's tilt): `K₀ = Σ_p Ā_p μ_p0 / 4π`,
/// `K₁ = 3 Σ_p Ā_p μ_p1 / 4π`, `K₂ = 5 Σ_p Ā_p μ_p2 / 8π`. `[l][j]` for the absorptions `sigma[j]`; the
/// midpoint rule at `h_samples` points in `h` and in `u`.
pub fn response_moments(fibre: &Fibre, sin_o: f32, sigma: &[f32], h_samples: usize) -> [Vec<f32>; 3] {
    let cos_o = safe_sqrt(1.0 - sin_o * sin_o).max(MIN_COS);
    let v = fibre.variances();
    let tilts = fibre.tilts();
    let du = 2.0 / h_samples as f32;
    let mut mu = [[0.0f32; 3]; LOBES];
    for m in 0..h_samples {
        let u = -1.0 + (m as f32 + 0.5) * du;
        let legendre = [1.0, u, 0.5 * (3.0 * u * u - 1.0)];
        for (p, mu_p) in mu.iter_mut().enumerate() {
            let (so, co) = tilted(p, sin_o, cos_o, tilts);
            let weight = mp(safe_sqrt(1.0 - u * u), co, u, so, v[p]) * du;
            for (x, l) in mu_p.iter_mut().zip(legendre) {
                *x += weight * l;
            }
        }
    }
    let scale = [1.0 / (4.0 * PI), 3.0 / (4.0 * PI), 5.0 / (8.0 * PI)];
    let mut out = [
        vec![0.0f32; sigma.len()],
        vec![0.0f32; sigma.len()],
        vec![0.0f32; sigma.len()],
    ];
    for (j, &s) in sigma.iter().enumerate() {
        let mut mean = [0.0f32; LOBES];
        for m in 0..h_samples {
            let h = -1.0 + (m as f32 + 0.5) * 2.0 / h_samples as f32;
            let (_, length) = refracted(fibre.eta, h, sin_o, cos_o);
            let a = ap(cos_o, fibre.eta, h, Vec3::splat((-s * length).exp()));
            for (x, a) in mean.iter_mut().zip(a) {
                *x += a.x / h_samples as f32;
            }
        }
        for (l, o) in out.iter_mut().enumerate() {
            o[j] = scale[l] * (0..LOBES).map(|p| mean[p] * mu[p][l]).sum::<f32>();
        }
    }
    out
}

/// `K₀`, `K₁`, `K₂` of [`response_moments`] from `table` at `sin θ_o` `sin_o` for the three channels'
/// `√σ_a` `root_sigma`, bilinear.
pub fn response_lookup(table: &[f32], sin_o: f32, root_sigma: Vec3) -> [Vec3; 3] {
    let (i, fi) = fibre_transport::cell(
        (sin_o.clamp(-1.0, 1.0) + 1.0) * 0.5 * (PHI_NODES - 1) as f32,
        PHI_NODES - 1,
    );
    let scale = (SIGMA_NODES - 1) as f32 / fibre_transport::ROOT_SIGMA_MAX;
    std::array::from_fn(|l| {
        let channel = |r: f32| {
            let (j, fj) = fibre_transport::cell(r * scale, SIGMA_NODES - 1);
            let along = |j: usize| {
                let (a, b) = (
                    table[texel(i, j, RESPONSE_LAYER + l)],
                    table[texel(i + 1, j, RESPONSE_LAYER + l)],
                );
                a + (b - a) * fi
            };
            let (a, b) = (along(j), along(j + 1));
            a + (b - a) * fj
        };
        Vec3::new(
            channel(root_sigma.x),
            channel(root_sigma.y),
            channel(root_sigma.z),
        )
    })
}

/// `N̄_p` of `table` at `|φ|` `phi`, `cos θ_o` `cos_o` and `√σ_a` `root_sigma`, trilinear.
pub fn lookup(table: &[f32], p: usize, phi: f32, cos_o: f32, root_sigma: f32) -> f32 {
    let (i, fi) = fibre_transport::cell(phi * ((PHI_NODES - 1) as f32 / PI), PHI_NODES - 1);
    let (k, fk) = fibre_transport::cell(cos_o * (COS_NODES - 1) as f32, COS_NODES - 1);
    let scale = (SIGMA_NODES - 1) as f32 / fibre_transport::ROOT_SIGMA_MAX;
    let (j, fj) = fibre_transport::cell(root_sigma * scale, SIGMA_NODES - 1);
    let along = |j: usize, k: usize| {
        let (a, b) = (table[index(p, j, k, i)], table[index(p, j, k, i + 1)]);
        a + (b - a) * fi
    };
    let plane = |j: usize| {
        let (a, b) = (along(j, k), along(j, k + 1));
        a + (b - a) * fk
    };
    let (a, b) = (plane(j), plane(j + 1));
    a + (b - a) * fj
}

/// `acos x` by Abramowitz & Stegun's polynomial 4.4.46 (absolute error below 2e-8 rad), the same arithmetic
/// the GPU runs: Vulkan lets `acos` drift by thousands of ulps (lavapipe's moved the azimuth's table lookup by
/// 2e-4 relative).
pub fn acos(x: f32) -> f32 {
    let a = x.abs().min(1.0);
    let r = safe_sqrt(1.0 - a)
        * (std::f32::consts::FRAC_PI_2
            + a * (-0.214_598_8
                + a * (0.088_978_99
                    + a * (-0.050_174_3
                        + a * (0.030_891_88
                            + a * (-0.017_088_126 + a * (0.006_670_09 + a * -0.001_262_491)))))));
    if x < 0.0 { PI - r } else { r }
}

/// The angles the shading needs: `sin θ_i`, `cos θ_i`, `sin θ_o`, `cos θ_o` and `|φ|`.
fn angles(tangent: Vec3, to_light: Vec3, to_eye: Vec3) -> [f32; 5] {
    let sin_i = tangent.dot(to_light).clamp(-1.0, 1.0);
    let sin_o = tangent.dot(to_eye).clamp(-1.0, 1.0);
    let lp = to_light - sin_i * tangent;
    let vp = to_eye - sin_o * tangent;
    let cos_phi = (lp.dot(vp) / (lp.dot(lp) * vp.dot(vp)).max(1e-12).sqrt()).clamp(-1.0, 1.0);
    [
        sin_i,
        safe_sqrt(1.0 - sin_i * sin_i),
        sin_o,
        safe_sqrt(1.0 - sin_o * sin_o),
        acos(cos_phi),
    ]
}

/// Each lobe's share of [`chiang_with`]: `[R, TT, TRT, residual]`.
pub fn lobes_with(
    table: &[f32],
    tangent: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    sigma_a: Vec3,
) -> [Vec3; LOBES] {
    let [sin_i, cos_i, sin_o, cos_o, phi] = angles(tangent, to_light, to_eye);
    let h = &table[HEADER..];
    let tilts = ([h[4], h[5], h[6]], [h[8], h[9], h[10]]);
    let root_sigma = sigma_a.max(Vec3::ZERO).map(f32::sqrt);
    let mut out = [Vec3::ZERO; LOBES];
    for (p, o) in out.iter_mut().enumerate() {
        let (so, co) = tilted(p, sin_o, cos_o, tilts);
        let m = mp(cos_i, co, sin_i, so, h[p]);
        let n = Vec3::new(
            lookup(table, p, phi, cos_o, root_sigma.x),
            lookup(table, p, phi, cos_o, root_sigma.y),
            lookup(table, p, phi, cos_o, root_sigma.z),
        );
        *o = m * n;
    }
    out
}

/// The shading of a fibre absorbing `sigma_a` through `table` (the sum of [`lobes_with`]).
pub fn chiang_with(table: &[f32], tangent: Vec3, to_light: Vec3, to_eye: Vec3, sigma_a: Vec3) -> Vec3 {
    lobes_with(table, tangent, to_light, to_eye, sigma_a)
        .into_iter()
        .sum()
}

/// The Chiang shading of a fibre coloured `colour` ([`chiang_with`] of [`table`] with
/// `marschner::absorption` of the colour).
pub fn chiang(tangent: Vec3, to_light: Vec3, to_eye: Vec3, colour: Vec3) -> Vec3 {
    chiang_with(table(), tangent, to_light, to_eye, marschner::absorption(colour))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// [`BETA_M`] gives the R lobe Karis's width: `√v = 0.726 β_m + 0.812 β_m² + 3.7 β_m²⁰` equals
    /// `2 sin 7.5°` (the real-time model's standard deviation in `sin θ_o`, computed here from Marschner et
    /// al.'s β_R, not read from `marschner::WIDTH`) within 1e-6, in f64.
    #[test]
    fn beta_m_matches_the_real_time_lobe_width() {
        let b = f64::from(BETA_M);
        let root_v = 0.726 * b + 0.812 * b * b + 3.7 * b.powi(20);
        let karis = 2.0 * 7.5f64.to_radians().sin();
        assert!((root_v - karis).abs() <= 1e-6, "{root_v} against {karis}");
    }

    /// [`acos`] against the standard library's, every 1e-4 over [−1, 1]: within 1e-6 rad (measured maximum
    /// printed; the polynomial's own error is 2e-8, the rest f32 rounding).
    #[test]
    fn polynomial_acos_is_acos() {
        let worst = (-10_000..=10_000)
            .map(|k| {
                let x = k as f32 * 1e-4;
                (acos(x) - x.acos()).abs()
            })
            .fold(0.0f32, f32::max);
        println!("acos polynomial: max |Δ| = {worst:.2e} rad");
        assert!(worst <= 1e-6, "{worst}");
    }

    /// Every lobe's nodes have their own texels, once per node the lobe depends on, none in the header's layer.
    #[test]
    fn indices_cover_the_lobes_once() {
        let mut seen = vec![0u32; TABLE_LEN];
        for p in 0..LOBES {
            for j in 0..if p == 0 { 1 } else { SIGMA_NODES } {
                for k in 0..COS_NODES {
                    for i in 0..if p == P_MAX { 1 } else { PHI_NODES } {
                        seen[index(p, j, k, i)] += 1;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&n| n <= 1), "an index shared");
        let nodes = COS_NODES * (PHI_NODES * (1 + 2 * SIGMA_NODES) + SIGMA_NODES);
        assert_eq!(seen.iter().sum::<u32>() as usize, nodes);
        assert!(seen[texel(0, 0, RESPONSE_LAYER)..].iter().all(|&n| n == 0));
    }

    /// The node counts and the header's layer are the ones `chiang.wgsl` reads with.
    #[test]
    fn wgsl_constants_match() {
        let names = [
            "PHI_NODES",
            "COS_NODES",
            "SIGMA_NODES",
            "RESPONSE_LAYER",
            "HEADER_LAYER",
        ]
        .map(|n| format!("CHIANG_{n}"));
        let values = [PHI_NODES, COS_NODES, SIGMA_NODES, RESPONSE_LAYER, HEADER_LAYER].map(|v| v as u32);
        assert_eq!(
            crate::shading::tests::wgsl_u32_constants("common/chiang.wgsl", &names),
            values,
            "{names:?}"
        );
    }

    fn unit(rng: &mut SplitMix64) -> Vec3 {
        Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X)
    }

    /// The table against the `h` integral taken at each of 400 random directions and colours (the same
    /// quadrature, [`averaged`] at the direction's own `|φ|`, `sin θ_o` and `σ_a`, 256 offsets), the shading
    /// summed over lobes: what interpolating the grid costs. Bound: 3 % of the shading plus 1e-3 (its scale is
    /// ~0.1–2). Measured: mean relative error 0.56 %, the largest 5.8 % of a shading below 2e-3 (a TRT tail),
    /// where the bound's 1e-3 holds it.
    #[test]
    fn table_matches_the_integral() {
        let table = table();
        let mut rng = SplitMix64::new(42);
        let (mut worst, mut sum, mut n) = (0.0f32, 0.0f32, 0);
        let tilts = FIBRE.tilts();
        let v = FIBRE.variances();
        for _ in 0..400 {
            let (t, l, e) = (unit(&mut rng), unit(&mut rng), unit(&mut rng));
            let colour = Vec3::new(rng.range(0.01, 1.0), rng.range(0.01, 1.0), rng.range(0.01, 1.0));
            let sigma = marschner::absorption(colour);
            let [sin_i, cos_i, sin_o, cos_o, phi] = angles(t, l, e);
            let exact = averaged(&FIBRE, sin_o.abs(), &sigma.to_array(), &[phi], H_SAMPLES);
            let mut want = Vec3::ZERO;
            for (p, lobe) in exact.iter().enumerate() {
                let (so, co) = tilted(p, sin_o, cos_o, tilts);
                want += mp(cos_i, co, sin_i, so, v[p]) * Vec3::new(lobe[0][0], lobe[1][0], lobe[2][0]);
            }
            let got = chiang_with(table, t, l, e, sigma);
            let d = (got - want).abs().max_element();
            let rel = d / want.max_element().max(1e-3);
            worst = worst.max(rel);
            sum += rel;
            n += 1;
            assert!(
                d <= 0.03 * want.max_element() + 1e-3,
                "{t} {l} {e} {colour}: table {got}, integral {want}"
            );
        }
        println!(
            "Chiang table against the integral: max relative {worst:.4}, mean {:.5} over {n} directions",
            sum / n as f32
        );
    }
}
