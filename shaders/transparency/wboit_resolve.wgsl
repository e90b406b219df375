// Resolve of weighted blended OIT (McGuire & Bavoil 2013): the average colour of the accumulation target over
// the opaque image, with coverage 1 - revealage (blended SrcAlpha over).
#include "common/fullscreen.wgsl"

@group(0) @binding(0) var accum_tex: texture_2d<f32>;
@group(0) @binding(1) var revealage_tex: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let accum = textureLoad(accum_tex, p, 0);
    let revealage = textureLoad(revealage_tex, p, 0).r;
    if accum.a <= 1e-6 {
        discard;
    }
    let color = accum.rgb / max(accum.a, 1e-6);
    return vec4<f32>(color, 1.0 - revealage);
}
