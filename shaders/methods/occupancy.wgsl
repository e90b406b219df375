// Shadow method "occupancy": Occupancy Maps lookup (Sintorn & Assarsson 2009, §3.2-3.3), the order estimate
// o(z) from the 128-slice bitmap and the slab counts, interpolated inside z's slice, and V = exp(-o * b) with
// b from the global hair alpha (visibility::occupancy::order and ::visibility, expression for expression).

#include "common/scene_bindings.wgsl"
#include "common/visibility.wgsl"
#include "common/occupancy_uniforms.wgsl"
#include "common/occupancy_estimate.wgsl"

@group(1) @binding(0) var<storage, read> occupancy_bits: array<vec4<u32>>;
@group(1) @binding(1) var<storage, read> occupancy_slabs: array<vec4<u32>>;
@group(1) @binding(2) var<uniform> occupancy_lookup: OccupancyUniforms;

// Estimated number of the texel's fragments in front of depth z (common/occupancy_estimate.wgsl).
fn occupancy_order(texel: vec2<i32>, z: f32) -> f32 {
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let far = textureLoad(hair_depth_far, texel, 0).r;
    let t = u32(texel.y) * frame.light_map_resolution + u32(texel.x);
    return occupancy_estimate(near, far, occupancy_bits[t], occupancy_slabs[t], z, occupancy_lookup.variant);
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    return transmittance(occupancy_order(texel, z) * optical_depth(light_opacity()));
}
