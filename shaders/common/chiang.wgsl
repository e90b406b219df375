// Chiang et al. 2016's fibre averaged across its width (`render.shading = chiang`): d'Eon et al. 2011's M_p
// evaluated in f32, the h-averaged azimuthal terms read from the table the CPU builds (`shading::chiang::table`,
// bound beside the scene's maps). A port of `src/shading/chiang.rs` (the specification: sources, grid and
// measurements are documented there).
#include "common/marschner.wgsl"
#include "common/fibre_transport.wgsl"

// `chiang::table`, a 3D texture of PHI x COS x LAYERS floats (x the azimuth, y the inclination; layers R, TT per
// absorption node, TRT per absorption node, the residual with the absorption along x, the header).
@group(0) @binding(5) var chiang_table: texture_3d<f32>;

// `chiang::PHI_NODES`, `COS_NODES`, `SIGMA_NODES`, `HEADER_LAYER` (a test compares them).
const CHIANG_PHI_NODES: u32 = 65u;
const CHIANG_COS_NODES: u32 = 17u;
const CHIANG_SIGMA_NODES: u32 = 17u;
const CHIANG_HEADER_LAYER: u32 = 36u;

fn chiang_texel(x: u32, y: u32, layer: u32) -> f32 {
    return textureLoad(chiang_table, vec3<u32>(x, y, layer), 0).x;
}

// The header's value x: the variances v_p (0-3), sin 2^k alpha (4-6), cos 2^k alpha (8-10).
fn chiang_header(x: u32) -> f32 {
    return chiang_texel(x, 0u, CHIANG_HEADER_LAYER);
}

fn chiang_i0(x: f32) -> f32 {
    let t = (x / 3.75) * (x / 3.75);
    return 1.0 + t * (3.5156229 + t * (3.0899424 + t * (1.2067492 + t * (0.2659732 + t * (0.0360768 + t * 0.0045813)))));
}

fn chiang_i0_scaled(x: f32) -> f32 {
    let u = 3.75 / x;
    return 0.39894228 + u * (0.01328592 + u * (0.00225319 + u * (-0.00157565 + u * (0.00916281
        + u * (-0.02057706 + u * (0.02635537 + u * (-0.01647633 + u * 0.00392377)))))));
}

// `chiang::mp` in f32.
fn chiang_mp(cos_i: f32, cos_o: f32, sin_i: f32, sin_o: f32, v: f32) -> f32 {
    let a = cos_i * cos_o / v;
    let b = sin_i * sin_o / v;
    if v <= 0.1 {
        if a >= 3.75 {
            return exp(a - b - 1.0 / v) * chiang_i0_scaled(a) / (v * sqrt(a));
        }
        return exp(-b - 1.0 / v) * chiang_i0(a) / v;
    }
    let e = exp(1.0 / v);
    return exp(-b) * chiang_i0(a) / ((e - 1.0 / e) * v);
}

// `chiang::acos`: Abramowitz & Stegun 4.4.46 (the builtin's drift moved the table lookup).
fn chiang_acos(x: f32) -> f32 {
    let a = min(abs(x), 1.0);
    let r = sqrt(max(1.0 - a, 0.0)) * (1.5707964 + a * (-0.2145988 + a * (0.08897899 + a * (-0.0501743
        + a * (0.03089188 + a * (-0.017088126 + a * (0.00667009 + a * -0.001262491)))))));
    if x < 0.0 {
        return 3.14159265 - r;
    }
    return r;
}

// `chiang::index`: node (i, k, j) of lobe p; R ignores the absorption, the residual the azimuth.
fn chiang_node(p: u32, j: u32, k: u32, i: u32) -> f32 {
    if p == 0u {
        return chiang_texel(i, k, 0u);
    }
    if p == 3u {
        return chiang_texel(j, k, 1u + 2u * CHIANG_SIGMA_NODES);
    }
    return chiang_texel(i, k, 1u + (p - 1u) * CHIANG_SIGMA_NODES + j);
}

// `chiang::lookup`: N_p at |phi|, cos theta_o and sqrt(sigma_a), trilinear.
fn chiang_lookup(p: u32, phi: f32, cos_o: f32, root_sigma: f32) -> f32 {
    let ci = fibre_cell(phi * (f32(CHIANG_PHI_NODES - 1u) / 3.14159265), CHIANG_PHI_NODES - 1u);
    let ck = fibre_cell(cos_o * f32(CHIANG_COS_NODES - 1u), CHIANG_COS_NODES - 1u);
    let cj = fibre_cell(root_sigma * (f32(CHIANG_SIGMA_NODES - 1u) / FIBRE_ROOT_SIGMA_MAX), CHIANG_SIGMA_NODES - 1u);
    let i = u32(ci.x);
    let k = u32(ck.x);
    let j = u32(cj.x);
    var plane: array<f32, 2>;
    for (var dj = 0u; dj < 2u; dj++) {
        var along: array<f32, 2>;
        for (var dk = 0u; dk < 2u; dk++) {
            let a = chiang_node(p, j + dj, k + dk, i);
            let b = chiang_node(p, j + dj, k + dk, i + 1u);
            along[dk] = a + (b - a) * ci.y;
        }
        plane[dj] = along[0] + (along[1] - along[0]) * ck.y;
    }
    return plane[0] + (plane[1] - plane[0]) * cj.y;
}

// `chiang::tilted`: sin theta_o and |cos theta_o| turned by the cuticle tilt of lobe p.
fn chiang_tilted(p: u32, sin_o: f32, cos_o: f32) -> vec2<f32> {
    let s = vec3<f32>(chiang_header(4u), chiang_header(5u), chiang_header(6u));
    let c = vec3<f32>(chiang_header(8u), chiang_header(9u), chiang_header(10u));
    if p == 0u {
        return vec2<f32>(sin_o * c[1] - cos_o * s[1], abs(cos_o * c[1] + sin_o * s[1]));
    }
    if p == 1u {
        return vec2<f32>(sin_o * c[0] + cos_o * s[0], abs(cos_o * c[0] - sin_o * s[0]));
    }
    if p == 2u {
        return vec2<f32>(sin_o * c[2] + cos_o * s[2], abs(cos_o * c[2] - sin_o * s[2]));
    }
    return vec2<f32>(sin_o, cos_o);
}

// `chiang::chiang_with` for absorption sigma_a.
fn chiang_absorbing(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, sigma_a: vec3<f32>) -> vec3<f32> {
    let sin_i = clamp(dot(tangent, to_light), -1.0, 1.0);
    let sin_o = clamp(dot(tangent, to_eye), -1.0, 1.0);
    let cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0));
    let cos_o = sqrt(max(1.0 - sin_o * sin_o, 0.0));
    let lp = to_light - sin_i * tangent;
    let vp = to_eye - sin_o * tangent;
    let phi = chiang_acos(clamp(dot(lp, vp) / sqrt(max(dot(lp, lp) * dot(vp, vp), 1e-12)), -1.0, 1.0));
    let root_sigma = sqrt(max(sigma_a, vec3<f32>(0.0)));
    var sum = vec3<f32>(0.0);
    for (var p = 0u; p < 4u; p++) {
        let o = chiang_tilted(p, sin_o, cos_o);
        let m = chiang_mp(cos_i, o.y, sin_i, o.x, chiang_header(p));
        let n = vec3<f32>(
            chiang_lookup(p, phi, cos_o, root_sigma.x),
            chiang_lookup(p, phi, cos_o, root_sigma.y),
            chiang_lookup(p, phi, cos_o, root_sigma.z),
        );
        sum += m * n;
    }
    return sum;
}

// `chiang::chiang`: the fibre coloured `colour`.
fn chiang(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    return chiang_absorbing(tangent, to_light, to_eye, marschner_absorption(colour));
}
