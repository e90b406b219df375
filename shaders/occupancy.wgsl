// Occupancy Maps (Sintorn & Assarsson 2009, §3.1), light pass: one geometry pass over the strands. Each fragment
// finds its relative depth d in its texel's [near, far] (the shared light-depth maps), sets the bit of its slice
// floor(d * 128) in the texel's 128-bit occupancy bitmap (atomicOr) and counts itself in its slab's fragment
// count (atomicAdd; slab = slice >> 5, or slab 0 for the occupancy-only variant). visibility::occupancy::build.
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/visibility.wgsl"
#include "common/occupancy_uniforms.wgsl"

@group(1) @binding(0) var occupancy_near: texture_2d<f32>;
@group(1) @binding(1) var occupancy_far: texture_2d<f32>;
// Four u32 per texel: slice s is bit s & 31 of word s >> 5.
@group(1) @binding(2) var<storage, read_write> occupancy_bits: array<atomic<u32>>;
// Four u32 per texel: fragments per slab (occupancy only: the total in word 0).
@group(1) @binding(3) var<storage, read_write> occupancy_slabs: array<atomic<u32>>;
@group(1) @binding(4) var<uniform> occupancy: OccupancyUniforms;

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

@fragment
fn fs_main(f: LightFragment) {
    let p = vec2<i32>(f.clip.xy);
    let near = textureLoad(occupancy_near, p, 0).r;
    let far = textureLoad(occupancy_far, p, 0).r;
    let z = fragment_depth(f.depth);
    let s = slice_index(relative_depth(z, near, far) * 128.0, 128u);
    let t = texel_index(f.clip) * 4u;
    atomicOr(&occupancy_bits[t + (s >> 5u)], 1u << (s & 31u));
    atomicAdd(&occupancy_slabs[t + select(s >> 5u, 0u, occupancy.variant == 1u)], 1u);
}
