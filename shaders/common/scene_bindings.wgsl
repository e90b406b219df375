// Light-space maps every eye pass can read (group 0, beside the frame uniforms).
#include "common/frame.wgsl"

// Nearest and furthest hair fragment depth per texel (normalised light depth), from the light-depth pass.
@group(0) @binding(1) var hair_depth_near: texture_2d<f32>;
@group(0) @binding(2) var hair_depth_far: texture_2d<f32>;
// Depth of opaque meshes from the light, in the scene-fitted shadow frame.
@group(0) @binding(3) var mesh_shadow_map: texture_depth_2d;
@group(0) @binding(4) var mesh_shadow_sampler: sampler_comparison;

// 3x3 PCF visibility of `world` in the opaque meshes' shadow map (1 = lit); `taps` 1 takes the single
// bilinear comparison tap (hair: thousands of fragments per pixel already average the edge), 3 the 3x3 grid.
fn mesh_visibility(world: vec3<f32>, taps: i32) -> f32 {
    let clip = frame.world_to_shadow_clip * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 {
        return 1.0;
    }
    let texel = 1.0 / f32(frame.shadow_map_resolution);
    let r = taps / 2;
    var sum = 0.0;
    for (var y = -r; y <= r; y++) {
        for (var x = -r; x <= r; x++) {
            let offset = vec2<f32>(f32(x), f32(y)) * texel;
            sum += textureSampleCompareLevel(mesh_shadow_map, mesh_shadow_sampler, uv + offset, ndc.z - frame.shadow_bias);
        }
    }
    return sum / f32((2 * r + 1) * (2 * r + 1));
}
