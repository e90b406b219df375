// Opaque shadow-map pass: opaque meshes rendered depth-only from the light, in the scene-fitted shadow frame.
#include "common/frame.wgsl"

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return frame.world_to_shadow_clip * vec4<f32>(position, 1.0);
}
