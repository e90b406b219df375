// Resolve of moment-based OIT (Münstermann et al. 2018): the transmittance-weighted colour sum normalised by its
// weight, covered by the exact total 1 - exp(-b_0): output (S / A (1 - exp(-b_0)), 1 - exp(-b_0)), blended
// premultiplied over the opaque image. No weight (A = 0) leaves the colour 0; no absorbance draws nothing.
#include "common/fullscreen.wgsl"
#include "common/visibility.wgsl"

@group(0) @binding(0) var accum_tex: texture_2d<f32>;
@group(0) @binding(1) var low_tex: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let b0 = textureLoad(low_tex, p, 0).x;
    if !(b0 > 0.0) {
        discard;
    }
    let accum = textureLoad(accum_tex, p, 0);
    let t = transmittance(b0);
    var color = vec3<f32>(0.0);
    if accum.a > 0.0 {
        color = accum.rgb / accum.a * (1.0 - t);
    }
    return vec4<f32>(color, 1.0 - t);
}
