// Resolve of depth peeling: the accumulation holds (C, T) after every layer; outputs (C, 1 − T), blended
// premultiplied over the opaque image: C + T B.
#include "common/fullscreen.wgsl"

@group(0) @binding(0) var accum_tex: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let accum = textureLoad(accum_tex, vec2<i32>(pos.xy), 0);
    if accum.a >= 1.0 && all(accum.rgb == vec3<f32>(0.0)) {
        discard;
    }
    return vec4<f32>(accum.rgb, 1.0 - accum.a);
}
