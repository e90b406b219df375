// The light a probe node holds and a fibre's response to it: a port of `shading::probe_light` (the
// specification; sources and measurements are documented there). The light from outside the cone about the
// direction to the light, its integral and the first two moments of its directions, answered by the fibre's
// response to light spread along it, K_0 + m_1 K_1 + (3 m_2 - 1) K_2 (`chiang_response`).
#include "common/chiang.wgsl"

struct ProbeLight {
    rest: vec3<f32>,
    first: vec3<f32>,
    // s_xx, s_yy, s_zz and s_xy, s_xz, s_yz.
    diagonal: vec3<f32>,
    off_diagonal: vec3<f32>,
}

// `probe_light::luminance`.
fn probe_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// `ProbeLight::moments_along`: <u> and <u^2> along `t`, isotropic where the node is dark.
fn probe_moments_along(light: ProbeLight, t: vec3<f32>) -> vec2<f32> {
    let y = probe_luminance(light.rest);
    if y <= 0.0 {
        return vec2<f32>(0.0, 1.0 / 3.0);
    }
    let d = light.diagonal;
    let o = light.off_diagonal;
    let quad = d.x * t.x * t.x + d.y * t.y * t.y + d.z * t.z * t.z
        + 2.0 * (o.x * t.x * t.y + o.y * t.x * t.z + o.z * t.y * t.z);
    return vec2<f32>(dot(light.first, t) / y, quad / y);
}

// `ProbeLight::response`.
fn probe_response(light: ProbeLight, t: vec3<f32>, to_eye: vec3<f32>, sigma_a: vec3<f32>) -> vec3<f32> {
    let m = probe_moments_along(light, t);
    let sin_o = clamp(dot(t, to_eye), -1.0, 1.0);
    let k = chiang_response(sin_o, sqrt(max(sigma_a, vec3<f32>(0.0))));
    return light.rest * max(k[0] + k[1] * m.x + k[2] * (3.0 * m.y - 1.0), vec3<f32>(0.0));
}
