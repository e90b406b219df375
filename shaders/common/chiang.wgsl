// Chiang et al. 2016's fibre averaged across its width (`render.shading = chiang`): d'Eon et al. 2011's M_p
// evaluated in f32, the h-averaged azimuthal terms read from the table the CPU builds (`shading::chiang::table`,
// bound beside the scene's maps). A port of `src/shading/chiang.rs` (the specification: sources, grid and
// measurements are documented there).
#include "common/marschner.wgsl"
#include "common/fibre_transport.wgsl"

// `chiang::table`, a 3D texture of PHI x COS x LAYERS floats (x the azimuth, y the inclination; layers R, TT per
// absorption node, TRT per absorption node, the residual with the absorption along x, the response to spread
// light K_0, K_1, K_2 with sin theta_o along x and the absorption along y, the header).
@group(0) @binding(5) var chiang_table: texture_3d<f32>;

// `chiang::PHI_NODES`, `COS_NODES`, `SIGMA_NODES`, `RESPONSE_LAYER`, `HEADER_LAYER` (a test compares them).
const CHIANG_PHI_NODES: u32 = 65u;
const CHIANG_COS_NODES: u32 = 17u;
const CHIANG_SIGMA_NODES: u32 = 17u;
const CHIANG_RESPONSE_LAYER: u32 = 36u;
const CHIANG_HEADER_LAYER: u32 = 39u;

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

// Where a direction falls in the azimuth and inclination axes: the cells and weights `chiang::lookup` takes.
struct ChiangCell {
    i: u32,
    fi: f32,
    k: u32,
    fk: f32,
}

fn chiang_cell(phi: f32, cos_o: f32) -> ChiangCell {
    let ci = fibre_cell(phi * (f32(CHIANG_PHI_NODES - 1u) / 3.14159265), CHIANG_PHI_NODES - 1u);
    let ck = fibre_cell(cos_o * f32(CHIANG_COS_NODES - 1u), CHIANG_COS_NODES - 1u);
    return ChiangCell(u32(ci.x), ci.y, u32(ck.x), ck.y);
}

// Azimuth then inclination on one layer, as `chiang::lookup` interpolates.
fn chiang_bilinear(c: ChiangCell, layer: u32) -> f32 {
    let a0 = chiang_texel(c.i, c.k, layer);
    let b0 = chiang_texel(c.i + 1u, c.k, layer);
    let a1 = chiang_texel(c.i, c.k + 1u, layer);
    let b1 = chiang_texel(c.i + 1u, c.k + 1u, layer);
    let lo = a0 + (b0 - a0) * c.fi;
    let hi = a1 + (b1 - a1) * c.fi;
    return lo + (hi - lo) * c.fk;
}

// `chiang::lookup` of lobe p for the three channels' sqrt(sigma_a). The axis a lobe ignores (`chiang::index`)
// holds equal values, which interpolate to themselves exactly: R is read once for every channel, the residual
// (its absorption along x) without the azimuth.
fn chiang_lobe(p: u32, c: ChiangCell, root_sigma: vec3<f32>) -> vec3<f32> {
    if p == 0u {
        return vec3<f32>(chiang_bilinear(c, 0u));
    }
    let scale = f32(CHIANG_SIGMA_NODES - 1u) / FIBRE_ROOT_SIGMA_MAX;
    var out: vec3<f32>;
    for (var ch = 0u; ch < 3u; ch++) {
        let cj = fibre_cell(root_sigma[ch] * scale, CHIANG_SIGMA_NODES - 1u);
        let j = u32(cj.x);
        var plane: vec2<f32>;
        if p == 3u {
            let layer = 1u + 2u * CHIANG_SIGMA_NODES;
            for (var dj = 0u; dj < 2u; dj++) {
                let a = chiang_texel(j + dj, c.k, layer);
                let b = chiang_texel(j + dj, c.k + 1u, layer);
                plane[dj] = a + (b - a) * c.fk;
            }
        } else {
            let layer = 1u + (p - 1u) * CHIANG_SIGMA_NODES + j;
            plane = vec2<f32>(chiang_bilinear(c, layer), chiang_bilinear(c, layer + 1u));
        }
        out[ch] = plane[0] + (plane[1] - plane[0]) * cj.y;
    }
    return out;
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
    let cell = chiang_cell(phi, cos_o);
    var sum = vec3<f32>(0.0);
    for (var p = 0u; p < 4u; p++) {
        let o = chiang_tilted(p, sin_o, cos_o);
        sum += chiang_mp(cos_i, o.y, sin_i, o.x, chiang_header(p)) * chiang_lobe(p, cell, root_sigma);
    }
    return sum;
}

// `chiang::chiang`: the fibre coloured `colour`.
fn chiang(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    return chiang_absorbing(tangent, to_light, to_eye, marschner_absorption(colour));
}

// `chiang::response_lookup`: K_0, K_1, K_2 at sin theta_o `sin_o` for the channels' sqrt(sigma_a), bilinear.
fn chiang_response(sin_o: f32, root_sigma: vec3<f32>) -> array<vec3<f32>, 3> {
    let ci = fibre_cell((clamp(sin_o, -1.0, 1.0) + 1.0) * 0.5 * f32(CHIANG_PHI_NODES - 1u), CHIANG_PHI_NODES - 1u);
    let i = u32(ci.x);
    let scale = f32(CHIANG_SIGMA_NODES - 1u) / FIBRE_ROOT_SIGMA_MAX;
    var out: array<vec3<f32>, 3>;
    for (var l = 0u; l < 3u; l++) {
        let layer = CHIANG_RESPONSE_LAYER + l;
        for (var ch = 0u; ch < 3u; ch++) {
            let cj = fibre_cell(root_sigma[ch] * scale, CHIANG_SIGMA_NODES - 1u);
            let j = u32(cj.x);
            var plane: vec2<f32>;
            for (var dj = 0u; dj < 2u; dj++) {
                let a = chiang_texel(i, j + dj, layer);
                let b = chiang_texel(i + 1u, j + dj, layer);
                plane[dj] = a + (b - a) * ci.y;
            }
            out[l][ch] = plane[0] + (plane[1] - plane[0]) * cj.y;
        }
    }
    return out;
}
