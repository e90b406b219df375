// Visibility of a world-space point through the selected method (its `visibility_at` is pasted before this).
// The CPU model is `visibility::lookup` (src/visibility/lookup.rs).
// frame.lookup_flags: 1 = 3x3 PCF (average of the 3x3 texels around the point's texel, at the same
// depth), 2 = half-texel jitter (Sintorn & Assarsson 2009 §3.3: the light-map coordinate moved by up to half a
// texel, differently for every point, before the lookup; blending many strands turns the aliasing into noise).
// frame.light_supersample = s > 1 (Yuksel & Keyser 2008 §5, multisampling the shadow computation): the maps are
// s times the base resolution a side; texels, jitter and the PCF neighbourhood are those of the base grid, and
// each base texel's visibility is the mean of the method's over its s x s sub-texels.
#include "common/frame.wgsl"

// A hash of a point's bits in [0,1)², stable from frame to frame.
fn jitter_hash(world: vec3<f32>) -> vec2<f32> {
    var h = bitcast<vec3<u32>>(world) * vec3<u32>(0x9e3779b1u, 0x85ebca77u, 0xc2b2ae3du);
    let a = (h.x ^ (h.y >> 15u) ^ (h.z << 7u)) * 0x27d4eb2du;
    let b = (h.y ^ (h.z >> 13u) ^ (h.x << 11u)) * 0x165667b1u;
    return vec2<f32>(f32(a >> 8u), f32(b >> 8u)) / 16777216.0;
}

// The method's visibility at `z` averaged over the s x s sub-texels of base texel `base`.
fn supersampled_at(base: vec2<i32>, z: f32, s: u32) -> f32 {
    if s == 1u {
        return visibility_at(base, z);
    }
    let n = i32(s);
    var sum = 0.0;
    for (var j = 0; j < n; j++) {
        for (var i = 0; i < n; i++) {
            sum += visibility_at(base * n + vec2<i32>(i, j), z);
        }
    }
    return sum / f32(s * s);
}

fn hair_visibility(world: vec3<f32>) -> f32 {
    let flags = frame.lookup_flags;
    let s = max(frame.light_supersample, 1u);
    let base = frame.light_map_resolution / s;
    let res = f32(base);
    let clip = frame.world_to_light_clip * vec4<f32>(world, 1.0);
    let ndc = clip.xy / clip.w;
    var uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return 1.0;
    }
    if (flags & 2u) != 0u {
        uv += (jitter_hash(world) - 0.5) / res;
    }
    let last = i32(base) - 1;
    let texel = clamp(vec2<i32>(floor(uv * res)), vec2<i32>(0), vec2<i32>(last));
    let z = light_depth(world);
    if (flags & 1u) == 0u {
        return supersampled_at(texel, z, s);
    }
    var sum = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            sum += supersampled_at(clamp(texel + vec2<i32>(dx, dy), vec2<i32>(0), vec2<i32>(last)), z, s);
        }
    }
    return sum / 9.0;
}
