// Resolve of no transparency: the nearest hair fragment's colour where one was written (alpha 1), the opaque
// image elsewhere (alpha 0).
#include "common/fullscreen.wgsl"

@group(0) @binding(0) var nearest_tex: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let nearest = textureLoad(nearest_tex, vec2<i32>(pos.xy), 0);
    if nearest.a <= 0.0 {
        discard;
    }
    return vec4<f32>(nearest.rgb, 1.0);
}
