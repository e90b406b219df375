// Shadow method "occupancy": Occupancy Maps lookup (Sintorn & Assarsson 2009, §3.2-3.3), the order estimate
// o(z) from the 128-slice bitmap and the slab counts, interpolated inside z's slice, and V = exp(-o * b) with
// b from the global hair alpha (visibility::occupancy::order and ::visibility, expression for expression).

#include "common/scene_bindings.wgsl"
#include "common/visibility.wgsl"
#include "common/occupancy_uniforms.wgsl"

@group(1) @binding(0) var<storage, read> occupancy_bits: array<vec4<u32>>;
@group(1) @binding(1) var<storage, read> occupancy_slabs: array<vec4<u32>>;
@group(1) @binding(2) var<uniform> occupancy_lookup: OccupancyUniforms;

// Estimated number of the texel's fragments in front of depth z.
fn occupancy_order(texel: vec2<i32>, z: f32) -> f32 {
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let far = textureLoad(hair_depth_far, texel, 0).r;
    let d = relative_depth(z, near, far);
    if !(d > 0.0) {
        return 0.0;
    }
    let x = d * 128.0;
    let s = slice_index(x, 128u);
    let frac = clamp(x - f32(s), 0.0, 1.0);
    let w = s >> 5u;
    let bit = s & 31u;
    let t = u32(texel.y) * frame.light_map_resolution + u32(texel.x);
    let occ = occupancy_bits[t];
    let slabs = occupancy_slabs[t];
    let own = (occ[w] >> bit) & 1u;
    let before_in_word = countOneBits(occ[w] & ((1u << bit) - 1u));
    var base = 0u;
    var count = slabs[0];
    var bits = countOneBits(occ[w]);
    var before = before_in_word;
    if occupancy_lookup.variant == 1u {
        let ones = countOneBits(occ);
        bits = ones.x + ones.y + ones.z + ones.w;
        let earlier = select(vec4<u32>(0u), ones, vec4<u32>(0u, 1u, 2u, 3u) < vec4<u32>(w));
        before = earlier.x + earlier.y + earlier.z + earlier.w + before_in_word;
    } else {
        let earlier = select(vec4<u32>(0u), slabs, vec4<u32>(0u, 1u, 2u, 3u) < vec4<u32>(w));
        base = earlier.x + earlier.y + earlier.z + earlier.w;
        count = slabs[w];
    }
    var in_slab = 0.0;
    if bits > 0u {
        let f = f32(count);
        in_slab = min(f * (f32(before) + f32(own) * frac) / f32(bits), f);
    }
    return f32(base) + in_slab;
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    return transmittance(occupancy_order(texel, z) * optical_depth(frame.hair_alpha));
}
