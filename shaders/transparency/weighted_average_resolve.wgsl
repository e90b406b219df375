// Resolve of weighted average blending (Bavoil & Myers 2008): C_avg = Σ a c / Σ a, α_avg = Σ a / n and
// T = (1 − α_avg)^n (as exp(−n b), b the optical depth of α_avg: WGSL's pow is undefined for base 0); outputs
// (C_avg (1 − T), 1 − T), blended premultiplied over the opaque image: C = C_avg (1 − T) + T B.
#include "common/fullscreen.wgsl"
#include "common/visibility.wgsl"

@group(0) @binding(0) var accum_tex: texture_2d<f32>;
@group(0) @binding(1) var count_tex: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let accum = textureLoad(accum_tex, p, 0);
    let n = textureLoad(count_tex, p, 0).r;
    if accum.a <= 0.0 || n <= 0.0 {
        discard;
    }
    let t = transmittance(n * optical_depth(accum.a / n));
    return vec4<f32>(accum.rgb / accum.a * (1.0 - t), 1.0 - t);
}
