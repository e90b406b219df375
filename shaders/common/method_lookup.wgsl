// Visibility of a world-space point through the selected method (its `visibility_at` is pasted before this).
// frame.lookup_flags: 1 = 3x3 PCF (average of the 3x3 texels around the point's texel, at the same
// depth), 2 = half-texel jitter (Sintorn & Assarsson 2009 §3.3: the light-map coordinate moved by up to half a
// texel, differently for every point, before the lookup; blending many strands turns the aliasing into noise).
#include "common/frame.wgsl"

// A hash of a point's bits in [0,1)², stable from frame to frame.
fn jitter_hash(world: vec3<f32>) -> vec2<f32> {
    var h = bitcast<vec3<u32>>(world) * vec3<u32>(0x9e3779b1u, 0x85ebca77u, 0xc2b2ae3du);
    let a = (h.x ^ (h.y >> 15u) ^ (h.z << 7u)) * 0x27d4eb2du;
    let b = (h.y ^ (h.z >> 13u) ^ (h.x << 11u)) * 0x165667b1u;
    return vec2<f32>(f32(a >> 8u), f32(b >> 8u)) / 16777216.0;
}

fn hair_visibility(world: vec3<f32>) -> f32 {
    let flags = frame.lookup_flags;
    let res = f32(frame.light_map_resolution);
    let clip = frame.world_to_light_clip * vec4<f32>(world, 1.0);
    let ndc = clip.xy / clip.w;
    var uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return 1.0;
    }
    if (flags & 2u) != 0u {
        uv += (jitter_hash(world) - 0.5) / res;
    }
    let last = i32(frame.light_map_resolution) - 1;
    let texel = clamp(vec2<i32>(floor(uv * res)), vec2<i32>(0), vec2<i32>(last));
    let z = light_depth(world);
    if (flags & 1u) == 0u {
        return visibility_at(texel, z);
    }
    var sum = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            sum += visibility_at(clamp(texel + vec2<i32>(dx, dy), vec2<i32>(0), vec2<i32>(last)), z);
        }
    }
    return sum / 9.0;
}
