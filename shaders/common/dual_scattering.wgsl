// Dual scattering (Zinke, Yuksel, Weber & Keyser 2008) on the Marschner lobes: the direct light V and the
// light forward-scattered through the `count` strands in front. A line-for-line port of
// `src/shading/dual_scattering.rs` (the specification: forms, sources and conventions are documented there).
#include "common/marschner.wgsl"
// count_from_visibility: the hair count the eye pass feeds it.
#include "common/visibility.wgsl"
// The fibres model's a_f, a_b and densities.
#include "common/fibre_transport.wgsl"

const DUAL_SCATTERING_DENSITY_FORWARD: f32 = 0.7;
const DUAL_SCATTERING_DENSITY_BACK: f32 = 0.7;
// `dual_scattering::TABLE` (a test compares them): per sin θ_i = −1 + k/8, the white fibre's lobe energies and
// mean paths: E_R f, b; E_TT f, b; L_TT f, b; E_TRT f, b; L_TRT f, b.
const DUAL_SCATTERING_TABLE = array<array<f32, 10>, 17>(
    array<f32, 10>(0.084838, 0.084838, 0.00280011, 0.00280011, 10.0813, 10.0813, 5.98999e-09, 5.98999e-09, 11.4623, 11.4623),
    array<f32, 10>(0.0499196, 0.0458943, 0.463676, 0.00270394, 4.36904, 4.12523, 2.99609e-10, 0.0375566, 6.80173, 6.80173),
    array<f32, 10>(0.0442477, 0.0369833, 0.747775, 0.0046228, 3.27218, 3.00025, 3.30891e-10, 0.0414779, 5.6036, 5.6036),
    array<f32, 10>(0.0395832, 0.0342884, 0.852147, 0.00530135, 2.67607, 2.3776, 3.52331e-10, 0.0441654, 4.88716, 4.88716),
    array<f32, 10>(0.0363151, 0.0334399, 0.871424, 0.00519285, 2.33355, 2.01319, 3.66568e-10, 0.0459501, 4.39509, 4.39509),
    array<f32, 10>(0.0341979, 0.033154, 0.874341, 0.0048193, 2.13454, 1.79967, 3.75353e-10, 0.0470513, 4.03984, 4.03984),
    array<f32, 10>(0.0329362, 0.0330479, 0.875048, 0.00439196, 2.01597, 1.67301, 3.8053e-10, 0.0477002, 3.7833, 3.7833),
    array<f32, 10>(0.0323224, 0.0330085, 0.875264, 0.00403402, 1.9487, 1.60189, 3.84062e-10, 0.048143, 3.60789, 3.60789),
    array<f32, 10>(0.0322436, 0.0329929, 0.875319, 0.00384407, 1.91991, 1.57175, 3.87885e-10, 0.0486223, 3.50658, 3.50658),
    array<f32, 10>(0.0326512, 0.0329564, 0.875312, 0.00387835, 1.92481, 1.57685, 3.93764e-10, 0.0493591, 3.47886, 3.47886),
    array<f32, 10>(0.0335109, 0.0328009, 0.875226, 0.00412651, 1.96414, 1.61805, 4.03165e-10, 0.0505375, 3.5291, 3.5291),
    array<f32, 10>(0.0347207, 0.0323509, 0.874923, 0.00451678, 2.04443, 1.70305, 4.17147e-10, 0.0522902, 3.66657, 3.66657),
    array<f32, 10>(0.0359972, 0.0314513, 0.873983, 0.00494382, 2.18149, 1.8495, 4.36235e-10, 0.0546829, 3.90754, 3.90754),
    array<f32, 10>(0.0367824, 0.0302524, 0.870757, 0.00528346, 2.41115, 2.09559, 4.60258e-10, 0.0576943, 4.28228, 4.28228),
    array<f32, 10>(0.0362767, 0.0295368, 0.855074, 0.00534655, 2.82239, 2.53167, 4.88099e-10, 0.0611842, 4.85644, 4.85644),
    array<f32, 10>(0.033634, 0.0311697, 0.768655, 0.00466381, 3.66067, 3.39872, 5.16945e-10, 0.0648001, 5.81796, 5.81796),
    array<f32, 10>(0.0446915, 0.0446915, 0.0121765, 0.0121765, 7.5439, 7.5439, 1.39367e-08, 1.39367e-08, 9.21426, 9.21426)
);

// Per channel: the Gaussian of standard deviation `width` at `x`.
fn dual_scattering_gaussian3(width: vec3<f32>, x: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        marschner_gaussian(width.x, x.x),
        marschner_gaussian(width.y, x.y),
        marschner_gaussian(width.z, x.z),
    );
}

// Energy-weighted mean of per-lobe values `v` over lobe energies `e0`, `e1`, `e2`.
fn dual_scattering_mean(e0: vec3<f32>, e1: vec3<f32>, e2: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let total = e0 + e1 + e2;
    return (e0 * v.x + e1 * v.y + e2 * v.z) / max(total, vec3<f32>(1e-12));
}

// The parts `dual_scattering` and `dual_scattering_forward` combine (`dual_scattering::Terms`).
struct DualScatteringTerms {
    single: vec3<f32>,
    direct: f32,
    global: vec3<f32>,
    scatter: vec3<f32>,
    back_direct: vec3<f32>,
    back_scatter: vec3<f32>,
    density_back: f32,
}

fn dual_scattering_terms(
    hair_model: u32,
    tangent: vec3<f32>,
    to_light: vec3<f32>,
    to_eye: vec3<f32>,
    colour: vec3<f32>,
    visibility: f32,
    count: f32,
) -> DualScatteringTerms {
    let sigma_a = marschner_absorption(colour);
    let s = marschner_lobes(tangent, to_light, to_eye, sigma_a);
    let single = vec3<f32>(s.r) + s.tt + s.trt;
    let sin_i = clamp(dot(tangent, to_light), -1.0, 1.0);
    let x = vec3<f32>(sin_i + clamp(dot(tangent, to_eye), -1.0, 1.0));

    // The table row at sin_i.
    let tx = (sin_i + 1.0) * 8.0;
    let k = slice_index(tx, 16u);
    let f = clamp(tx - f32(k), 0.0, 1.0);
    var table = DUAL_SCATTERING_TABLE;
    var r: array<f32, 10>;
    for (var j = 0u; j < 10u; j++) {
        r[j] = table[k][j] + (table[k + 1u][j] - table[k][j]) * f;
    }
    // Forward (f) and backward (b) lobe energies R, TT, TRT.
    let rf = vec3<f32>(r[0]);
    let rb = vec3<f32>(r[1]);
    let ttf = r[2] * exp(-sigma_a * r[4]);
    let ttb = r[3] * exp(-sigma_a * r[5]);
    let trtf = r[6] * exp(-sigma_a * r[8]);
    let trtb = r[7] * exp(-sigma_a * r[9]);
    var af = rf + ttf + trtf;
    var ab = rb + ttb + trtb;
    var density_forward = DUAL_SCATTERING_DENSITY_FORWARD;
    var density_back = DUAL_SCATTERING_DENSITY_BACK;
    if hair_model == HAIR_MODEL_FIBRES {
        let a = fibre_attenuation(sin_i, sigma_a);
        af = a.forward;
        ab = a.backward;
        density_forward = FIBRE_DENSITY_FORWARD;
        density_back = FIBRE_DENSITY_BACK;
    }
    let var_w = MARSCHNER_WIDTH * MARSCHNER_WIDTH;
    let shift_f = dual_scattering_mean(rf, ttf, trtf, MARSCHNER_CENTRE);
    let shift_b = dual_scattering_mean(rb, ttb, trtb, MARSCHNER_CENTRE);
    let var_f = dual_scattering_mean(rf, ttf, trtf, var_w);
    let var_b = dual_scattering_mean(rb, ttb, trtb, var_w);

    // Back-scattering.
    let af2 = af * af;
    let ab2 = ab * ab;
    let q = max(vec3<f32>(1.0) - af2, vec3<f32>(1e-4));
    let q3 = q * q * q;
    let a1 = ab * af2 / q;
    let a3 = ab2 * ab * af2 / q3;
    let shift = shift_b * (vec3<f32>(1.0) - 2.0 * ab2 / (q * q)) + shift_f * (2.0 * q * q + 4.0 * af2 * ab2) / q3;
    let ab3 = ab2 * ab;
    let spread_b = (vec3<f32>(1.0) + density_back * af2)
        * (ab * sqrt(2.0 * var_f + var_b) + ab3 * sqrt(2.0 * var_f + 3.0 * var_b))
        / max(ab + ab3 * (2.0 * sqrt(var_f) + 3.0 * sqrt(var_b)), vec3<f32>(1e-12));
    let back_energy = a1 + a3;
    let back_variance = spread_b * spread_b;

    let n = max(count, 0.0);
    let v = clamp(visibility, 0.0, 1.0);
    let inv_2pi = 0.5 / MARSCHNER_PI;
    let spread = n * var_f;
    let transmitted = density_forward * pow(af, vec3<f32>(n));
    var scatter = vec3<f32>(0.0);
    let lobe_energy = array<vec3<f32>, 3>(rf + rb, ttf + ttb, trtf + trtb);
    for (var p = 0u; p < 3u; p++) {
        let w = vec3<f32>(MARSCHNER_WIDTH[p] * MARSCHNER_WIDTH[p]);
        scatter += lobe_energy[p] * dual_scattering_gaussian3(sqrt(w + spread), x - MARSCHNER_CENTRE[p]) * inv_2pi;
    }
    let back_direct = back_energy * dual_scattering_gaussian3(sqrt(back_variance), x - shift) * inv_2pi;
    let back_scatter = back_energy * dual_scattering_gaussian3(sqrt(back_variance + spread), x - shift) * inv_2pi;
    return DualScatteringTerms(
        single,
        v,
        max(transmitted - v, vec3<f32>(0.0)) * density_forward,
        scatter,
        back_direct,
        back_scatter,
        density_back,
    );
}

// Radiance towards `to_eye` per unit light radiance from `to_light`, shadow included: `visibility` is the
// direct fraction, `count` the strands in front towards the light.
fn dual_scattering(
    hair_model: u32,
    tangent: vec3<f32>,
    to_light: vec3<f32>,
    to_eye: vec3<f32>,
    colour: vec3<f32>,
    visibility: f32,
    count: f32,
) -> vec3<f32> {
    let t = dual_scattering_terms(hair_model, tangent, to_light, to_eye, colour, visibility, count);
    return t.direct * (t.single + t.density_back * t.back_direct)
        + t.global * (t.scatter + t.density_back * t.back_scatter);
}

// The global forward scattering alone, max(T_f - V, 0) d_f S_scatter (`dual_scattering::Terms::forward_scattered`).
fn dual_scattering_forward(t: DualScatteringTerms) -> vec3<f32> {
    return t.global * t.scatter;
}
