// Depth peeling's "under" blend of one layer: outputs (a c, a); the accumulation's blend state
// (colour DstAlpha/One, alpha Zero/OneMinusSrcAlpha) makes it C += T a c, T *= 1 − a, front to back.
#include "common/fullscreen.wgsl"

@group(0) @binding(0) var layer_tex: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let layer = textureLoad(layer_tex, vec2<i32>(pos.xy), 0);
    if layer.a <= 0.0 {
        discard;
    }
    return vec4<f32>(layer.rgb * layer.a, layer.a);
}
