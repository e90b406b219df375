// A Marschner-style strand BSDF (Marschner et al. 2003 lobes R, TT, TRT in Karis 2016's practical forms,
// d'Eon et al. 2011 normalisation, Chiang et al. 2016 absorption from colour). A line-for-line port of
// `src/shading/marschner.rs` (the specification: constants, sources and conventions are documented there).

const MARSCHNER_ETA: f32 = 1.55;
const MARSCHNER_PI: f32 = 3.14159265358979;
// Standard deviation 2 sin β_p and centre 2 sin α_p of the Gaussians of R, TT, TRT in sin θ_i + sin θ_o
// (α_R = −5°, α_TT = −α_R/2, α_TRT = −3α_R/2; β_R = 7.5°, β_TT = β_R/2, β_TRT = 2β_R): `marschner::WIDTH`
// and `marschner::CENTRE`, a test compares them.
const MARSCHNER_WIDTH: vec3<f32> = vec3<f32>(0.2610524, 0.13080627, 0.5176381);
const MARSCHNER_CENTRE: vec3<f32> = vec3<f32>(-0.17431149, 0.08723877, 0.2610524);
const MARSCHNER_BETA_N: f32 = 0.3;
const MARSCHNER_MIN_COLOUR: f32 = 1e-3;

struct MarschnerLobes {
    r: f32,
    tt: vec3<f32>,
    trt: vec3<f32>,
}

fn marschner_gaussian(width: f32, x: f32) -> f32 {
    return exp(-0.5 * x * x / (width * width)) / (sqrt(2.0 * MARSCHNER_PI) * width);
}

fn marschner_fresnel(cos_theta: f32) -> f32 {
    let r0 = (1.0 - MARSCHNER_ETA) / (1.0 + MARSCHNER_ETA);
    let f0 = r0 * r0;
    let m = clamp(1.0 - cos_theta, 0.0, 1.0);
    return f0 + (1.0 - f0) * m * m * m * m * m;
}

// σ_a per unit fibre radius from a linear hair colour (Chiang et al. 2016's fit, β_n = 0.3).
fn marschner_absorption(colour: vec3<f32>) -> vec3<f32> {
    let b = MARSCHNER_BETA_N;
    let d = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b * b * b + 5.574 * b * b * b * b
        + 0.245 * b * b * b * b * b;
    let l = log(clamp(colour, vec3<f32>(MARSCHNER_MIN_COLOUR), vec3<f32>(1.0))) / d;
    return l * l;
}

fn marschner_m(p: u32, x: f32) -> f32 {
    return marschner_gaussian(MARSCHNER_WIDTH[p], x - MARSCHNER_CENTRE[p]);
}

fn marschner_lobes(
    tangent: vec3<f32>,
    to_light: vec3<f32>,
    to_eye: vec3<f32>,
    sigma_a: vec3<f32>,
) -> MarschnerLobes {
    let sin_i = clamp(dot(tangent, to_light), -1.0, 1.0);
    let sin_o = clamp(dot(tangent, to_eye), -1.0, 1.0);
    let cos_i = sqrt(1.0 - sin_i * sin_i);
    let cos_o = sqrt(1.0 - sin_o * sin_o);
    let cos_d = max(sqrt(max(0.5 + 0.5 * (cos_o * cos_i + sin_o * sin_i), 0.0)), 1e-4);
    let lp = to_light - sin_i * tangent;
    let vp = to_eye - sin_o * tangent;
    let cos_phi = clamp(dot(lp, vp) / sqrt(max(dot(lp, lp) * dot(vp, vp), 1e-12)), -1.0, 1.0);
    let cos_half_phi = sqrt(0.5 + 0.5 * cos_phi);
    let x = sin_i + sin_o;
    let eta_prime = 1.19 / cos_d + 0.36 * cos_d;
    let a = 1.0 / eta_prime;

    var out: MarschnerLobes;
    out.r = marschner_m(0u, x) * 0.25 * cos_half_phi
        * marschner_fresnel(sqrt(clamp(0.5 + 0.5 * dot(to_light, to_eye), 0.0, 1.0)));

    let h = cos_half_phi * (1.0 + a * (0.6 - 0.8 * cos_phi));
    let f = marschner_fresnel(cos_d * sqrt(max(1.0 - h * h, 0.0)));
    let cos_gamma_t = sqrt(max(1.0 - h * h * a * a, 0.0));
    let t_tt = exp(-sigma_a * (2.0 * cos_gamma_t / cos_d));
    out.tt = t_tt * (marschner_m(1u, x) * exp(-3.65 * cos_phi - 3.98) * (1.0 - f) * (1.0 - f));

    let f2 = marschner_fresnel(cos_d * 0.5);
    let cos_gamma_t2 = sqrt(max(1.0 - 0.75 * a * a, 0.0));
    let t_trt = exp(-sigma_a * (4.0 * cos_gamma_t2 / cos_d));
    out.trt = t_trt * (marschner_m(2u, x) * exp(17.0 * cos_phi - 16.78) * (1.0 - f2) * (1.0 - f2) * f2);
    return out;
}

// Radiance towards `to_eye` per unit radiance from `to_light` of a fibre along `tangent` coloured `colour`.
fn marschner(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    let s = marschner_lobes(tangent, to_light, to_eye, marschner_absorption(colour));
    return vec3<f32>(s.r) + s.tt + s.trt;
}
