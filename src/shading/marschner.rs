//! A Marschner-style strand BSDF: the three lobes of Marschner, Jensen, Cammarano, Worley & Hanrahan 2003
//! ("Light Scattering from Human Hair Fibers") — R (reflection at the cuticle), TT (transmission through the
//! fibre) and TRT (one internal reflection) — each a longitudinal Gaussian `M_p` times an azimuthal term `N_p`
//! and an attenuation `A_p`, in the practical forms of Karis 2016 ("Physically Based Hair Shading in Unreal",
//! SIGGRAPH 2016 course), with the lobe normalisation of d'Eon, Francois, Hill, Letteri & Aubry 2011 ("An
//! Energy-Conserving Hair Reflectance Model") and the absorption of Chiang, Bitterli, Tappan & Burley 2016 ("A
//! Practical and Controllable Hair and Fur Model for Production Path Tracing"). The CPU model (the
//! specification) of `shaders/common/marschner.wgsl`, which mirrors it line for line in f32.
//!
//! Angles: `sin θ = τ·ω` for the unit tangent `τ` (root to tip) and a unit direction `ω`, so θ is measured from
//! the normal plane, positive towards the tip; `φ` is the azimuth between the light and the eye around `τ`;
//! `θ_d = (θ_o − θ_i)/2`. The value returned, `S = Σ_p M_p N_p A_p`, is the radiance sent towards the eye per
//! unit radiance of a light arriving from `ω_i` (the BSDF times the fibre's cosine, pbrt's `f · |cos θ_i|`), so
//! that `∫ S dω_o ≤ 1` over the sphere (a white furnace, with `dω = d(sin θ) dφ`).
//!
//! Constants and forms, by source:
//! - η = 1.55, cuticle tilt α_R = −5° and width β_R = 7.5° (Marschner et al. 2003, Table 1: η 1.55,
//!   α_R −10° … −5°, β_R 5° … 10°); α_TT = −α_R/2, α_TRT = −3α_R/2, β_TT = β_R/2, β_TRT = 2β_R (same table).
//! - `M_p = g(2 sin β_p; sin θ_i + sin θ_o − 2 sin α_p)`, a unit Gaussian in `sin θ_o` (Karis 2016 slide
//!   "Longitudinal scattering": the argument `sin θ_i + sin θ_o` for `2 sin θ_h`; d'Eon et al. 2011 on
//!   normalising `M_p` over the sphere).
//! - `N_R = ¼ cos(φ/2)`, `A_R = F(√(½(1 + ω_i·ω_o)))` (Karis 2016, "R" slide: the Fresnel factor at half
//!   the angle between ω_i and ω_o); `F` is Schlick's approximation with `F0 = ((1−η)/(1+η))²` (Karis 2016).
//! - Modified index `η' = 1.19 / cos θ_d + 0.36 cos θ_d` (Karis 2016's fit of Marschner 2003's Bravais index
//!   for η = 1.55).
//! - TT: `h = cos(φ/2) (1 + (0.6 − 0.8 cos φ)/η')`, `N_TT = exp(−3.65 cos φ − 3.98)`,
//!   `A_TT = (1 − F(cos θ_d √(1 − h²)))² T_TT` (Karis 2016, "TT" slide).
//! - TRT: `h = √3/2`, `N_TRT = exp(17 cos φ − 16.78)`, `A_TRT = (1 − f)² f T_TRT`, `f = F(cos θ_d / 2)` (Karis
//!   2016, "TRT" slide).
//! - Absorption `T = exp(−σ_a · 2 cos γ_t / cos θ_d)` per passage through the fibre (unit radius),
//!   `sin γ_t = h / η'` (Marschner 2003's absorption along the refracted path, as d'Eon 2011 and pbrt-v3
//!   evaluate it, with Karis's `cos θ_t ≈ cos θ_d`); TRT passes twice.
//! - `σ_a` from the hair colour `c`: `σ_a = (ln c / (5.969 − 0.215 β_n + 2.532 β_n² − 10.73 β_n³ +
//!   5.574 β_n⁴ + 0.245 β_n⁵))²` at azimuthal roughness β_n = 0.3 (Chiang et al. 2016's fit of σ_a to a
//!   target colour). That fit is made for a fibre's multiple scattering; with single scattering only, a hair
//!   coloured `c` looks lighter than `c` in TT and TRT.
//! - Left out of Karis's forms, as not reciprocal or not normalised: the R lobe's view-dependent shift and its
//!   `cos(φ/2)`-scaled width, and the multiple-scattering diffuse term.
//!
//! Energy (white furnace, σ_a = 0): `∫ S dω_o` is at most 1.0015 over θ_i ∈ [−85°, 85°] (measured by
//! `tests::white_furnace_stays_bounded`; Karis's fitted `N_TT`, `N_TRT` are not exactly normalised).
//! Reciprocity: every factor depends on `ω_i`, `ω_o` through `sin θ_i + sin θ_o`, `|θ_o − θ_i|`, `cos φ` and
//! `ω_i·ω_o` only, so `S(ω_i, ω_o) = S(ω_o, ω_i)` exactly (`tests::reciprocal`).

use glam::Vec3;

/// Relative index of refraction of the fibre (Marschner et al. 2003, Table 1).
pub const ETA: f32 = 1.55;
/// Longitudinal shift of the R lobe, `α_R` (radians; Marschner et al. 2003, Table 1: −10° … −5°).
pub const ALPHA_R: f32 = -5.0 * std::f32::consts::PI / 180.0;
/// Longitudinal width of the R lobe, `β_R` (radians; Marschner et al. 2003, Table 1: 5° … 10°).
pub const BETA_R: f32 = 7.5 * std::f32::consts::PI / 180.0;
/// Azimuthal roughness at which Chiang et al. 2016's colour → σ_a mapping is taken.
pub const BETA_N: f32 = 0.3;
/// Lobe shifts `α_p` and widths `β_p` of R, TT, TRT (Marschner et al. 2003, Table 1).
pub const ALPHA: [f32; 3] = [ALPHA_R, -ALPHA_R / 2.0, -3.0 * ALPHA_R / 2.0];
pub const BETA: [f32; 3] = [BETA_R, BETA_R / 2.0, 2.0 * BETA_R];
/// Standard deviation `2 sin β_p` and centre `2 sin α_p` of each lobe's Gaussian in `sin θ_i + sin θ_o`, as
/// literals so that the GPU need not evaluate `sin` (Vulkan allows it an absolute error of 2⁻¹¹); a test checks
/// them against [`ALPHA`] and [`BETA`], another against `shaders/common/marschner.wgsl`.
pub const WIDTH: [f32; 3] = [0.261_052_4, 0.130_806_27, 0.517_638_1];
pub const CENTRE: [f32; 3] = [-0.174_311_49, 0.087_238_77, 0.261_052_4];
/// The darkest and lightest colour channel the absorption takes (`ln 0` is infinite; above 1 would be gain).
const MIN_COLOUR: f32 = 1e-3;

/// The three lobes' contributions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lobes {
    pub r: f32,
    pub tt: Vec3,
    pub trt: Vec3,
}

impl Lobes {
    pub fn sum(&self) -> Vec3 {
        Vec3::splat(self.r) + self.tt + self.trt
    }
}

/// Unit Gaussian of standard deviation `width` at `x`.
pub fn gaussian(width: f32, x: f32) -> f32 {
    (-0.5 * x * x / (width * width)).exp() / ((2.0 * std::f32::consts::PI).sqrt() * width)
}

/// Schlick's Fresnel reflectance at incidence cosine `cos_theta` for η = [`ETA`].
pub fn fresnel(cos_theta: f32) -> f32 {
    let r0 = (1.0 - ETA) / (1.0 + ETA);
    let f0 = r0 * r0;
    let m = (1.0 - cos_theta).clamp(0.0, 1.0);
    f0 + (1.0 - f0) * m * m * m * m * m
}

/// Absorption coefficient per unit fibre radius from a linear hair colour (Chiang et al. 2016's fit) at [`BETA_N`].
pub fn absorption(colour: Vec3) -> Vec3 {
    absorption_for(colour, BETA_N)
}

/// Chiang et al. 2016's colour inversion for azimuthal roughness `b` (β_n).
pub fn absorption_for(colour: Vec3, b: f32) -> Vec3 {
    let d = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b * b * b
        + 5.574 * b * b * b * b
        + 0.245 * b * b * b * b * b;
    let l = colour.clamp(Vec3::splat(MIN_COLOUR), Vec3::ONE).ln() / d;
    l * l
}

/// The lobes for a fibre along unit `tangent` lit from `to_light`, seen from `to_eye`, absorbing `sigma_a`.
pub fn lobes(tangent: Vec3, to_light: Vec3, to_eye: Vec3, sigma_a: Vec3) -> Lobes {
    let sin_i = tangent.dot(to_light).clamp(-1.0, 1.0);
    let sin_o = tangent.dot(to_eye).clamp(-1.0, 1.0);
    // cos θ_d = cos((θ_o − θ_i)/2) = √(½(1 + cos θ_o cos θ_i + sin θ_o sin θ_i)), without asin and cos (Vulkan
    // allows those a few thousand ulps).
    let (cos_i, cos_o) = ((1.0 - sin_i * sin_i).sqrt(), (1.0 - sin_o * sin_o).sqrt());
    let cos_d = (0.5 + 0.5 * (cos_o * cos_i + sin_o * sin_i))
        .max(0.0)
        .sqrt()
        .max(1e-4);
    let lp = to_light - sin_i * tangent;
    let vp = to_eye - sin_o * tangent;
    let cos_phi = (lp.dot(vp) / (lp.dot(lp) * vp.dot(vp)).max(1e-12).sqrt()).clamp(-1.0, 1.0);
    let cos_half_phi = (0.5 + 0.5 * cos_phi).sqrt();
    let x = sin_i + sin_o;
    let m = |p: usize| gaussian(WIDTH[p], x - CENTRE[p]);
    let eta_prime = 1.19 / cos_d + 0.36 * cos_d;
    let a = 1.0 / eta_prime;

    let r = m(0) * 0.25 * cos_half_phi * fresnel((0.5 + 0.5 * to_light.dot(to_eye)).clamp(0.0, 1.0).sqrt());

    let h = cos_half_phi * (1.0 + a * (0.6 - 0.8 * cos_phi));
    let f = fresnel(cos_d * (1.0 - h * h).max(0.0).sqrt());
    let cos_gamma_t = (1.0 - h * h * a * a).max(0.0).sqrt();
    let t_tt = (-sigma_a * (2.0 * cos_gamma_t / cos_d)).exp();
    let tt = t_tt * (m(1) * (-3.65 * cos_phi - 3.98).exp() * (1.0 - f) * (1.0 - f));

    let f = fresnel(cos_d * 0.5);
    let cos_gamma_t = (1.0 - 0.75 * a * a).max(0.0).sqrt();
    let t_trt = (-sigma_a * (4.0 * cos_gamma_t / cos_d)).exp();
    let trt = t_trt * (m(2) * (17.0 * cos_phi - 16.78).exp() * (1.0 - f) * (1.0 - f) * f);

    Lobes { r, tt, trt }
}

/// The Marschner shading of a fibre coloured `colour` ([`lobes`] with [`absorption`] of the colour, summed).
pub fn marschner(tangent: Vec3, to_light: Vec3, to_eye: Vec3, colour: Vec3) -> Vec3 {
    lobes(tangent, to_light, to_eye, absorption(colour)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    const TANGENT: Vec3 = Vec3::Z;

    /// The unit direction at longitudinal angle θ (from the normal plane, towards +τ) and azimuth φ around τ.
    fn dir(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(theta.cos() * phi.cos(), theta.cos() * phi.sin(), theta.sin())
    }

    /// White furnace: for σ_a = 0, `∫ S dω_o` over the sphere (midpoint rule in `sin θ_o` × φ_o, 800 × 1440,
    /// `dω = d(sin θ) dφ`) for θ_i every 5° in [−85°, 85°]. Measured maximum 1.0015 at θ_i = 35° (the sum of R
    /// 0.067, TT 0.878, TRT 0.056), minimum 0.28 at θ_i = −85°; Karis's N_TT and N_TRT are fits, not
    /// normalised, hence the 1 % allowance.
    #[test]
    fn white_furnace_stays_bounded() {
        let (ns, nphi) = (800, 1440);
        let dw = (2.0 / ns as f64) * (2.0 * std::f64::consts::PI / nphi as f64);
        let mut worst = (0.0f64, 0);
        for deg in (-85..=85).step_by(5) {
            let wi = dir((deg as f32).to_radians(), 0.0);
            let mut total = 0.0f64;
            for i in 0..ns {
                let sin_o = ((i as f32 + 0.5) / ns as f32) * 2.0 - 1.0;
                for j in 0..nphi {
                    let phi = (j as f32 + 0.5) / nphi as f32 * 2.0 * PI;
                    let wo = dir(sin_o.asin(), phi);
                    total += lobes(TANGENT, wi, wo, Vec3::ZERO).sum().x as f64 * dw;
                }
            }
            assert!(total.is_finite() && total > 0.1, "θ_i = {deg}°: {total}");
            if total > worst.0 {
                worst = (total, deg);
            }
        }
        println!(
            "white furnace: max ∫ S dω_o = {:.4} at θ_i = {}°",
            worst.0, worst.1
        );
        assert!(worst.0 <= 1.01, "white furnace exceeds 1.01: {worst:?}");
    }

    /// Absorption only removes energy: a coloured fibre scatters no more than the white one, per channel, and
    /// R carries no colour. Straight through the fibre (θ_i = θ_o = 0, φ = π: h = 0, a path of one diameter)
    /// TT is attenuated by `exp(−2 σ_a)`; black hair (the darkest colour taken, 10⁻³) has σ_a =
    /// (ln 10⁻³ / 5.888415)² = 1.376186, so `exp(−2.752372) = 0.0637764` of the white fibre's TT is left.
    #[test]
    fn absorption_only_darkens() {
        let brown = absorption(Vec3::new(0.30, 0.18, 0.09));
        assert!(brown.x < brown.y && brown.y < brown.z && brown.x > 0.0, "{brown}");
        assert_eq!(absorption(Vec3::ONE), Vec3::ZERO);
        for k in 0..200 {
            let wi = dir((k as f32 * 0.37).sin() * 1.4, 0.0);
            let wo = dir((k as f32 * 0.71).cos() * 1.4, k as f32 * 0.13);
            let white = lobes(TANGENT, wi, wo, Vec3::ZERO);
            let coloured = lobes(TANGENT, wi, wo, brown);
            assert_eq!(white.r, coloured.r);
            assert!(coloured.tt.cmple(white.tt).all() && coloured.trt.cmple(white.trt).all());
        }
        let (wi, wo) = (dir(0.0, 0.0), dir(0.0, PI));
        let black = lobes(TANGENT, wi, wo, absorption(Vec3::ZERO)).tt.x;
        let white = lobes(TANGENT, wi, wo, Vec3::ZERO).tt.x;
        assert!((black / white - 0.063_776_4).abs() < 1e-5, "{black} / {white}");
    }

    /// `S(ω_i, ω_o) = S(ω_o, ω_i)` on 2000 pairs of directions, coloured and white, to f32 rounding
    /// (relative 1e-5, for the sums taken in the other order; measured 0, bit-exact).
    #[test]
    fn reciprocal() {
        let mut rng = crate::rng::SplitMix64::new(3);
        let mut unit = || {
            let v = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            v.normalize_or(Vec3::X)
        };
        let mut worst = 0.0f32;
        for _ in 0..2000 {
            let (t, a, b) = (unit(), unit(), unit());
            for sigma in [Vec3::ZERO, absorption(Vec3::new(0.30, 0.18, 0.09))] {
                let (ab, ba) = (lobes(t, a, b, sigma).sum(), lobes(t, b, a, sigma).sum());
                let rel = (ab - ba).abs().max_element() / ab.max_element().max(1e-3);
                worst = worst.max(rel);
            }
        }
        println!("reciprocity: max relative |S(i,o) − S(o,i)| = {worst:.2e}");
        assert!(worst <= 1e-5, "{worst}");
    }

    /// The R lobe peaks at `sin θ_o = 2 sin α_R − sin θ_i` (the specular direction tilted towards the root by
    /// 2|α_R|, Marschner et al. 2003) in the plane of incidence, for θ_i within 20° of normal incidence
    /// (further out the Fresnel factor's rise towards grazing pulls the peak outwards). Scanned every 0.01°;
    /// measured within 0.04°.
    #[test]
    fn r_peaks_shifted_towards_the_root() {
        for deg in [-20.0f32, 0.0, 20.0] {
            let wi = dir(deg.to_radians(), 0.0);
            let peak = (-8900..=8900)
                .map(|k| k as f32 * 0.01)
                .max_by(|a, b| {
                    let r = |d: f32| lobes(TANGENT, wi, dir(d.to_radians(), 0.0), Vec3::ZERO).r;
                    r(*a).total_cmp(&r(*b))
                })
                .unwrap();
            let expected = (2.0 * ALPHA_R.sin() - deg.to_radians().sin()).asin().to_degrees();
            assert!(
                (peak - expected).abs() <= 0.1,
                "θ_i = {deg}°: R peaks at {peak}°, expected {expected}°"
            );
            assert!(
                peak < -deg,
                "θ_i = {deg}°: the peak {peak}° is not towards the root of the mirror −θ_i"
            );
        }
    }

    /// TT is strongest with the light behind the fibre (φ = π) and dominates there; in front (φ = 0) it is
    /// negligible and R and TRT carry the highlight.
    #[test]
    fn tt_is_strongest_back_lit() {
        let wi = dir(0.3, 0.0);
        let theta_o = -0.3 + 2.0 * ALPHA[1];
        let tt_at = |phi: f32| lobes(TANGENT, wi, dir(theta_o, phi), Vec3::ZERO);
        let peak = (0..3600)
            .map(|k| k as f32 * 0.1)
            .max_by(|a, b| tt_at(a.to_radians()).tt.x.total_cmp(&tt_at(b.to_radians()).tt.x))
            .unwrap();
        assert!((peak - 180.0).abs() <= 0.1, "TT peaks at φ = {peak}°");
        let (back, front) = (tt_at(PI), tt_at(0.0));
        assert!(back.tt.x > 100.0 * front.tt.x, "{back:?} vs {front:?}");
        assert!(back.tt.x > 10.0 * (back.r + back.trt.x), "{back:?}");
        assert!(front.r + front.trt.x > front.tt.x, "{front:?}");
    }

    /// The Gaussians' literal widths and centres are `2 sin β_p` and `2 sin α_p`, and the WGSL holds the same
    /// literals.
    #[test]
    fn lobe_constants_match_the_angles_and_the_wgsl() {
        for p in 0..3 {
            assert!((WIDTH[p] - 2.0 * BETA[p].sin()).abs() < 1e-7, "width {p}");
            assert!((CENTRE[p] - 2.0 * ALPHA[p].sin()).abs() < 1e-7, "centre {p}");
        }
        let src = crate::shaders::compose("common/marschner.wgsl", None).unwrap();
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        for (name, values) in [("MARSCHNER_WIDTH", WIDTH), ("MARSCHNER_CENTRE", CENTRE)] {
            let (_, c) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("{name} missing"));
            let naga::Expression::Compose { ref components, .. } = module.global_expressions[c.init] else {
                panic!("{name} is not a vec3 literal");
            };
            let wgsl: Vec<f32> = components
                .iter()
                .map(|&h| match module.global_expressions[h] {
                    naga::Expression::Literal(naga::Literal::F32(v)) => v,
                    ref e => panic!("{name}: {e:?}"),
                })
                .collect();
            assert_eq!(wgsl, values, "{name}");
        }
    }

    /// Hand-computed pieces: the Gaussian's peak, Schlick's F0 for η = 1.55 and its grazing limit, and
    /// Chiang's σ_a for c = e^{-1} at β_n = 0.3 (denominator 5.888415).
    #[test]
    fn pieces_by_hand() {
        assert!((gaussian(0.5, 0.0) - 0.797_884_6).abs() < 1e-6);
        assert!((fresnel(1.0) - 0.046_520_6).abs() < 1e-6);
        assert_eq!(fresnel(0.0), 1.0);
        let s = absorption(Vec3::splat((-1.0f32).exp()));
        assert!((s.x - 1.0 / (5.888_415f32 * 5.888_415)).abs() < 1e-6, "{s}");
    }
}
