//! The fibre BSDF of Chiang, Bitterli, Tappan & Burley 2016, "A Practical and Controllable Hair and Fur Model
//! for Production Path Tracing": lobes R, TT, TRT and a residual (p_max = 3), d'Eon et al. 2011's longitudinal
//! term M_p, a trimmed logistic azimuthal term N_p, cuticle tilt, exact dielectric Fresnel and importance
//! sampling. Local frame as in pbrt: x along the fibre tangent, y and z across it.

use crate::shading::marschner;
use glam::Vec3;
use std::f32::consts::PI;

/// The fibres' material for a linear hair colour: Chiang et al. 2016's colour inversion at the real-time
/// Marschner model's lobe widths ([`BETA_M`]), azimuthal roughness, cuticle tilt and index of refraction.
pub fn fibre_params(hair_color: [f32; 3]) -> FibreParams {
    fibre_absorbing(marschner::absorption(Vec3::from(hair_color)))
}

/// [`fibre_params`] for an absorption `σ_a` (per unit radius) rather than a colour.
pub fn fibre_absorbing(sigma_a: Vec3) -> FibreParams {
    FibreParams::with_absorption(sigma_a, BETA_M, marschner::BETA_N, marschner::ALPHA_R)
}

/// The longitudinal roughness `β_m` whose R lobe is as wide as the real-time Marschner model's: Chiang et al.'s
/// variance `v = (0.726 β_m + 0.812 β_m² + 3.7 β_m²⁰)²` equal to the square of Karis's standard deviation
/// `2 sin β_R` in `sin θ_o` ([`marschner::WIDTH`]`[0]`, 15° for Marschner et al.'s β_R = 7.5°, a width in the
/// half angle θ_h). `β_m = β_R` read Marschner's half-angle width as Chiang's roughness: the traced fibre's
/// lobes were 2.4× narrower than the raster's (6.2° against 15°). TT and TRT follow in both models (`v/4`, `4v`
/// against `β_R/2`, `2β_R`). A test solves for it.
pub const BETA_M: f32 = 0.274_995_65;

const P_MAX: usize = 3;

/// pbrt's eumelanin and pheomelanin absorption per unit concentration.
const EUMELANIN_SIGMA_A: Vec3 = Vec3::new(0.419, 0.697, 1.37);
const PHEOMELANIN_SIGMA_A: Vec3 = Vec3::new(0.187, 0.4, 1.05);

/// The fibre's material: absorption per unit radius, longitudinal and azimuthal roughness, cuticle tilt, index.
#[derive(Clone, Copy, Debug)]
pub struct FibreParams {
    pub sigma_a: Vec3,
    pub beta_m: f32,
    pub beta_n: f32,
    /// Cuticle scale tilt, radians.
    pub alpha: f32,
    pub eta: f32,
}

impl FibreParams {
    /// From a linear colour through Chiang et al. 2016's inversion (shared with [`marschner::absorption_for`]).
    pub fn from_colour(colour: Vec3, beta_m: f32, beta_n: f32, alpha: f32) -> Self {
        Self::with_absorption(marschner::absorption_for(colour, beta_n), beta_m, beta_n, alpha)
    }

    /// From eumelanin and pheomelanin concentrations (pbrt's absorption constants).
    pub fn from_melanin(eumelanin: f32, pheomelanin: f32, beta_m: f32, beta_n: f32, alpha: f32) -> Self {
        let sigma_a = eumelanin * EUMELANIN_SIGMA_A + pheomelanin * PHEOMELANIN_SIGMA_A;
        Self::with_absorption(sigma_a, beta_m, beta_n, alpha)
    }

    /// The fibre absorbing `sigma_a` (per unit of diameter), with the real-time model's index of refraction.
    pub fn with_absorption(sigma_a: Vec3, beta_m: f32, beta_n: f32, alpha: f32) -> Self {
        Self {
            sigma_a,
            beta_m,
            beta_n,
            alpha,
            eta: marschner::ETA,
        }
    }
}

/// The BSDF at one hit, `h` in [-1, 1] the offset across the fibre.
#[derive(Clone, Debug)]
pub struct FibreBsdf {
    h: f32,
    gamma_o: f32,
    eta: f32,
    sigma_a: Vec3,
    /// Longitudinal variance per lobe.
    v: [f32; P_MAX + 1],
    /// The azimuthal logistic.
    n: Trimmed,
    /// sin and cos of 2^k α for k = 0, 1, 2.
    sin_2k_alpha: [f32; 3],
    cos_2k_alpha: [f32; 3],
}

/// A sampled direction with its BSDF value and solid-angle density.
#[derive(Clone, Copy, Debug)]
pub struct FibreSample {
    pub wi: Vec3,
    pub f: Vec3,
    pub pdf: f32,
}

fn safe_sqrt(x: f32) -> f32 {
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
fn mp(cos_i: f32, cos_o: f32, sin_i: f32, sin_o: f32, v: f32) -> f32 {
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
fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
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
fn ap(cos_theta_o: f32, eta: f32, h: f32, t: Vec3) -> [Vec3; P_MAX + 1] {
    let cos_gamma_o = safe_sqrt(1.0 - h * h);
    let f = fresnel_dielectric(cos_theta_o * cos_gamma_o, eta);
    let mut a = [Vec3::ZERO; P_MAX + 1];
    a[0] = Vec3::splat(f);
    a[1] = (1.0 - f) * (1.0 - f) * t;
    for p in 2..P_MAX {
        a[p] = a[p - 1] * t * f;
    }
    a[P_MAX] = a[P_MAX - 1] * f * t / (Vec3::ONE - t * f);
    a
}

/// The lobe's azimuthal centre: Φ(p, γ_o, γ_t).
fn phi_p(p: usize, gamma_o: f32, gamma_t: f32) -> f32 {
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
struct Trimmed {
    s: f32,
    below: f32,
    mass: f32,
}

impl Trimmed {
    fn new(s: f32) -> Trimmed {
        let below = logistic_cdf(-PI, s);
        Trimmed {
            s,
            below,
            mass: logistic_cdf(PI, s) - below,
        }
    }

    /// The logistic renormalised on [-π, π].
    fn density(&self, x: f32) -> f32 {
        logistic(x, self.s) / self.mass
    }

    fn sample(&self, u: f32) -> f32 {
        let x = -self.s * (1.0 / (u * self.mass + self.below) - 1.0).ln();
        x.clamp(-PI, PI)
    }
}

/// Wraps an angle into [-π, π].
fn wrap(mut x: f32) -> f32 {
    while x > PI {
        x -= 2.0 * PI;
    }
    while x < -PI {
        x += 2.0 * PI;
    }
    x
}

fn np(phi: f32, p: usize, n: &Trimmed, gamma_o: f32, gamma_t: f32) -> f32 {
    n.density(wrap(phi - phi_p(p, gamma_o, gamma_t)))
}

/// sin θ, cos θ and φ of a local direction.
fn angles(w: Vec3) -> (f32, f32, f32) {
    let sin_t = w.x.clamp(-1.0, 1.0);
    (sin_t, safe_sqrt(1.0 - sin_t * sin_t), w.z.atan2(w.y))
}

impl FibreBsdf {
    pub fn new(params: &FibreParams, h: f32) -> Self {
        let h = h.clamp(-1.0, 1.0);
        let bm = params.beta_m;
        let v0 = (0.726 * bm + 0.812 * bm * bm + 3.7 * bm.powi(20)).powi(2);
        let bn = params.beta_n;
        let s = (PI / 8.0).sqrt() * (0.265 * bn + 1.194 * bn * bn + 5.372 * bn.powi(22));
        let mut sin_2k_alpha = [params.alpha.sin(), 0.0, 0.0];
        let mut cos_2k_alpha = [safe_sqrt(1.0 - sin_2k_alpha[0] * sin_2k_alpha[0]), 0.0, 0.0];
        for i in 1..3 {
            sin_2k_alpha[i] = 2.0 * cos_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
            cos_2k_alpha[i] = cos_2k_alpha[i - 1].powi(2) - sin_2k_alpha[i - 1].powi(2);
        }
        Self {
            h,
            gamma_o: h.asin(),
            eta: params.eta,
            sigma_a: params.sigma_a,
            v: [v0, 0.25 * v0, 4.0 * v0, 4.0 * v0],
            n: Trimmed::new(s),
            sin_2k_alpha,
            cos_2k_alpha,
        }
    }

    /// γ_t and the one-pass transmittance for an outgoing elevation.
    fn refracted(&self, sin_o: f32, cos_o: f32) -> (f32, Vec3) {
        let sin_t = sin_o / self.eta;
        let cos_t = safe_sqrt(1.0 - sin_t * sin_t);
        let etap = safe_sqrt(self.eta * self.eta - sin_o * sin_o) / cos_o;
        let sin_gamma_t = (self.h / etap).clamp(-1.0, 1.0);
        let cos_gamma_t = safe_sqrt(1.0 - sin_gamma_t * sin_gamma_t);
        let t = (-self.sigma_a * (2.0 * cos_gamma_t / cos_t)).exp();
        (sin_gamma_t.asin(), t)
    }

    /// sin θ_o and |cos θ_o| rotated by the cuticle tilt for lobe `p` (-2α for R, α for TT, 4α for TRT).
    fn tilted(&self, p: usize, sin_o: f32, cos_o: f32) -> (f32, f32) {
        let (sa, ca) = (self.sin_2k_alpha, self.cos_2k_alpha);
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

    /// What the lobes need of `wo`, worked out once for any number of evaluations and samples.
    pub fn outgoing(&self, wo: Vec3) -> Outgoing {
        let (sin_o, cos_o, phi_o) = angles(wo);
        let (gamma_t, t) = self.refracted(sin_o, cos_o);
        let a = ap(cos_o, self.eta, self.h, t);
        // Lobe-selection probabilities: the A_p averaged over channels, normalised.
        let mean = a.map(|a| (a.x + a.y + a.z) / 3.0);
        let sum: f32 = mean.iter().sum();
        Outgoing {
            sin_o,
            cos_o,
            phi_o,
            gamma_t,
            a,
            apdf: mean.map(|x| if sum > 0.0 { x / sum } else { 0.25 }),
        }
    }

    /// f(wo, wi), without the cosine (pbrt's convention: f |wi.z| integrates to the scattered energy).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.eval_pdf(&self.outgoing(wo), wi).0
    }

    /// [`Self::eval`] for the `wo` of `o`.
    pub fn eval_at(&self, o: &Outgoing, wi: Vec3) -> Vec3 {
        self.eval_pdf(o, wi).0
    }

    /// Samples wi from 4 uniform numbers: lobe, two for M_p, one for N_p.
    pub fn sample(&self, wo: Vec3, u: [f32; 4]) -> Option<FibreSample> {
        self.sample_at(&self.outgoing(wo), u)
    }

    /// [`Self::sample`] for the `wo` of `o`.
    pub fn sample_at(&self, o: &Outgoing, u: [f32; 4]) -> Option<FibreSample> {
        let mut p = 0;
        let mut u0 = u[0];
        while p < P_MAX && u0 >= o.apdf[p] {
            u0 -= o.apdf[p];
            p += 1;
        }
        let (so, co) = self.tilted(p, o.sin_o, o.cos_o);
        let u1 = u[1].max(1e-5);
        let v = self.v[p];
        let cos_theta = 1.0 + v * (u1 + (1.0 - u1) * (-2.0 / v).exp()).ln();
        let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
        let cos_phi = (2.0 * PI * u[2]).cos();
        let sin_i = (-cos_theta * so + sin_theta * cos_phi * co).clamp(-1.0, 1.0);
        let cos_i = safe_sqrt(1.0 - sin_i * sin_i);
        let dphi = if p < P_MAX {
            phi_p(p, self.gamma_o, o.gamma_t) + self.n.sample(u[3])
        } else {
            2.0 * PI * u[3]
        };
        let phi_i = o.phi_o + dphi;
        let wi = Vec3::new(sin_i, cos_i * phi_i.cos(), cos_i * phi_i.sin());
        let (f, pdf) = self.eval_pdf(o, wi);
        (pdf > 0.0 && pdf.is_finite()).then_some(FibreSample { wi, f, pdf })
    }

    /// [`Self::eval`] and [`Self::pdf`] at once: the lobes' M_p and N_p are shared.
    fn eval_pdf(&self, o: &Outgoing, wi: Vec3) -> (Vec3, f32) {
        let (sin_i, cos_i, phi_i) = angles(wi);
        let phi = phi_i - o.phi_o;
        let (mut f, mut pdf) = (Vec3::ZERO, 0.0);
        for p in 0..P_MAX {
            let (so, co) = self.tilted(p, o.sin_o, o.cos_o);
            let (m, n) = (
                mp(cos_i, co, sin_i, so, self.v[p]),
                np(phi, p, &self.n, self.gamma_o, o.gamma_t),
            );
            f += m * o.a[p] * n;
            pdf += m * o.apdf[p] * n;
        }
        let m = mp(cos_i, o.cos_o, sin_i, o.sin_o, self.v[P_MAX]);
        f += m * o.a[P_MAX] / (2.0 * PI);
        let cos_wi = wi.z.abs();
        let f = if cos_wi > 0.0 { f / cos_wi } else { f };
        (f, pdf + m * o.apdf[P_MAX] / (2.0 * PI))
    }

    /// Solid-angle density of [`Self::sample`].
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_pdf(&self.outgoing(wo), wi).1
    }
}

/// [`FibreBsdf::outgoing`]: the angles of `wo` (sin θ_o, cos θ_o, φ_o), γ_t, the attenuations A_p and the lobe
/// probabilities.
#[derive(Clone, Copy, Debug)]
pub struct Outgoing {
    sin_o: f32,
    cos_o: f32,
    phi_o: f32,
    gamma_t: f32,
    a: [Vec3; P_MAX + 1],
    apdf: [f32; P_MAX + 1],
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    fn sphere(rng: &mut SplitMix64) -> Vec3 {
        let z = rng.range(-1.0, 1.0);
        let phi = rng.angle();
        let r = safe_sqrt(1.0 - z * z);
        Vec3::new(z, r * phi.cos(), r * phi.sin())
    }

    fn white(beta_m: f32, beta_n: f32, alpha: f32) -> FibreParams {
        FibreParams {
            sigma_a: Vec3::ZERO,
            beta_m,
            beta_n,
            alpha,
            eta: marschner::ETA,
        }
    }

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

    /// `sample` returns eval and pdf at its direction (relative 1e-4), and f |cos| / pdf = 1 per sample when
    /// nothing is absorbed (importance-sampled furnace: bound 2e-3, measured 3.6e-7); it gives a direction for at
    /// least 99.9 % of the draws (it gives none only where the pdf underflows; measured 18000 of 18000), so a
    /// sampler that fails does not pass by skipping every check.
    #[test]
    fn sample_matches_eval_and_sampled_furnace() {
        let mut rng = SplitMix64::new(7);
        let mut worst: f32 = 0.0;
        let mut sampled = 0;
        for &bm in &[0.1, 0.3, 0.7] {
            for &bn in &[0.1, 0.3, 0.7] {
                for _ in 0..2000 {
                    let b = FibreBsdf::new(&white(bm, bn, 0.035), rng.range(-1.0, 1.0));
                    let wo = sphere(&mut rng);
                    let u = [rng.unit(), rng.unit(), rng.unit(), rng.unit()];
                    let Some(s) = b.sample(wo, u) else { continue };
                    sampled += 1;
                    let f = b.eval(wo, s.wi);
                    assert!((s.f - f).abs().max_element() <= 1e-4 * f.max_element().max(1e-6));
                    assert!((s.pdf - b.pdf(wo, s.wi)).abs() <= 1e-4 * s.pdf);
                    let w = s.f * s.wi.z.abs() / s.pdf;
                    worst = worst.max((w - Vec3::ONE).abs().max_element());
                }
            }
        }
        println!("sampled furnace: max |f cos / pdf - 1| = {worst}, {sampled} of 18000 draws sampled");
        assert!(worst < 2e-3, "{worst}");
        assert!(
            sampled >= 17_982,
            "only {sampled} of 18000 draws sampled a direction"
        );
    }

    /// ∫ f |cos| dω = 1 at σ_a = 0 by uniform-sphere sampling (400k samples per case; bound 2%, measured
    /// 0.985–1.007 over the nine (β_m, β_n) cases, all noise: the sampled furnace pins the integral to 1).
    #[test]
    fn white_furnace_uniform() {
        let mut rng = SplitMix64::new(11);
        for &bm in &[0.2, 0.5, 0.8] {
            for &bn in &[0.2, 0.5, 0.8] {
                let wo = sphere(&mut rng);
                let n = 400_000;
                let mut sum = Vec3::ZERO;
                for _ in 0..n {
                    let b = FibreBsdf::new(&white(bm, bn, 0.0), rng.range(-1.0, 1.0));
                    let wi = sphere(&mut rng);
                    sum += b.eval(wo, wi) * wi.z.abs();
                }
                let e = sum.x * 4.0 * PI / n as f32;
                println!("furnace beta_m {bm} beta_n {bn}: {e}");
                assert!((e - 1.0).abs() < 0.02, "beta_m {bm} beta_n {bn}: {e}");
            }
        }
    }

    /// Histogram of sampled directions over (sin θ, φ) bins against the pdf integrated over each bin
    /// (midpoint rule, 8×8 points a bin), 1M samples: |count - mass| within 5 standard deviations on bins holding
    /// ≥ 0.2% of the mass, and within 4% relative on bins holding ≥ 1% (measured: 2.4σ and 0.7%, 3.5σ and 1.9%).
    #[test]
    fn sampled_histogram_matches_pdf() {
        let (nt, np_) = (16, 32);
        let mut rng = SplitMix64::new(3);
        for &(bm, bn, h) in &[(0.3f32, 0.3f32, 0.4f32), (0.5, 0.6, -0.7)] {
            let b = FibreBsdf::new(
                &FibreParams::from_colour(Vec3::new(0.5, 0.3, 0.2), bm, bn, 0.035),
                h,
            );
            let wo = Vec3::new(0.3, 0.9f32.sqrt() * 0.6, 0.9f32.sqrt() * 0.8);
            let n = 1_000_000;
            let mut hist = vec![0u32; nt * np_];
            for _ in 0..n {
                let u = [rng.unit(), rng.unit(), rng.unit(), rng.unit()];
                if let Some(s) = b.sample(wo, u) {
                    let (st, _, phi) = angles(s.wi);
                    let i = (((st + 1.0) * 0.5 * nt as f32) as usize).min(nt - 1);
                    let j = (((phi + PI) / (2.0 * PI) * np_ as f32) as usize).min(np_ - 1);
                    hist[i * np_ + j] += 1;
                }
            }
            let (dt, dp) = (2.0 / nt as f32, 2.0 * PI / np_ as f32);
            let (mut worst, mut worst_z) = (0.0f32, 0.0f32);
            let mut total = 0.0;
            for i in 0..nt {
                for j in 0..np_ {
                    let mut mass = 0.0;
                    for a in 0..8 {
                        for c in 0..8 {
                            let st = -1.0 + (i as f32 + (a as f32 + 0.5) / 8.0) * dt;
                            let phi = -PI + (j as f32 + (c as f32 + 0.5) / 8.0) * dp;
                            let ct = safe_sqrt(1.0 - st * st);
                            mass += b.pdf(wo, Vec3::new(st, ct * phi.cos(), ct * phi.sin()));
                        }
                    }
                    mass *= dt * dp / 64.0;
                    total += mass;
                    let got = hist[i * np_ + j] as f32 / n as f32;
                    if mass >= 2e-3 {
                        worst_z = worst_z.max((got - mass).abs() / (mass / n as f32).sqrt());
                    }
                    if mass >= 1e-2 {
                        worst = worst.max((got - mass).abs() / mass);
                    }
                }
            }
            println!(
                "histogram beta_m {bm} beta_n {bn}: max rel bin error {worst}, max z {worst_z}, pdf total {total}"
            );
            assert!((total - 1.0).abs() < 0.01, "{total}");
            assert!(worst < 0.04 && worst_z < 5.0, "{worst} {worst_z}");
        }
    }

    /// With α = 0 the model is reciprocal when the roles swap with h → -h on the specular cone (θ_i = -θ_o,
    /// where η' agrees): f(wo, wi)|wi.z| = f(wi, wo)|wo.z| to relative 1e-4 (measured
    /// 1.1e-5). Off the cone, and with α ≠ 0
    /// (tilts of -2α, α, 4α), the model is only approximately reciprocal, as pbrt notes.
    #[test]
    fn reciprocity_at_zero_tilt() {
        let mut rng = SplitMix64::new(5);
        let mut worst: f32 = 0.0;
        for _ in 0..2000 {
            let p = FibreParams::from_melanin(
                rng.range(0.0, 2.0),
                rng.range(0.0, 1.0),
                rng.range(0.1, 0.8),
                rng.range(0.1, 0.8),
                0.0,
            );
            let h = rng.range(-1.0, 1.0);
            let wo = sphere(&mut rng);
            let phi = rng.angle();
            let c = safe_sqrt(1.0 - wo.x * wo.x);
            let wi = Vec3::new(-wo.x, c * phi.cos(), c * phi.sin());
            let a = FibreBsdf::new(&p, h).eval(wo, wi) * wi.z.abs();
            let b = FibreBsdf::new(&p, -h).eval(wi, wo) * wo.z.abs();
            worst = worst.max((a - b).abs().max_element() / a.max_element().max(1e-6));
        }
        println!("reciprocity (alpha = 0, specular cone): max relative error {worst}");
        assert!(worst < 1e-4, "{worst}");
    }

    /// The colour inversion round-trips through the paper's forward relation c = exp(-√σ_a d(β_n)): one d for
    /// all channels, d(0) = 5.969; darker colours absorb more; no melanin absorbs nothing.
    #[test]
    fn absorption_round_trip() {
        let c = Vec3::new(0.6, 0.35, 0.15);
        for &bn in &[0.0f32, 0.1, 0.3, 0.8] {
            let s = FibreParams::from_colour(c, 0.3, bn, 0.0).sigma_a;
            let d = -c.map(f32::ln) / s.map(f32::sqrt);
            assert!((d.max_element() - d.min_element()) < 1e-4 * d.x, "{d}");
            if bn == 0.0 {
                assert!((d.x - 5.969).abs() < 1e-4, "{d}");
            }
            let back = (-s.map(f32::sqrt) * d.x).exp();
            assert!((back - c).abs().max_element() < 1e-5, "{back}");
            let darker = FibreParams::from_colour(c * 0.5, 0.3, bn, 0.0).sigma_a;
            assert!(darker.cmpgt(s).all());
        }
        assert_eq!(
            FibreParams::from_melanin(0.0, 0.0, 0.3, 0.3, 0.0).sigma_a,
            Vec3::ZERO
        );
        assert!(
            FibreParams::from_melanin(1.0, 0.0, 0.3, 0.3, 0.0)
                .sigma_a
                .min_element()
                > 0.0
        );
    }
}
