// Occupancy-ordered blending (Sintorn & Assarsson 2009 §3.4), the two map passes over the strands, with the
// shared eye vertex stage and tested against the meshes' depth as the hair pass is (fs_slabs by hand, before its
// atomics):
// - fs_range: the pixel's eye depth range, nearest (target 0, Min blend) and furthest (target 1, Max blend);
// - fs_slabs: exactly the light-space shaders/occupancy.wgsl on eye pixels: the fragment's relative depth d in
//   its pixel's range sets the bit of slice floor(d * 128) (atomicOr) and counts it in its slab (atomicAdd;
//   slab = slice >> 5, or slab 0 for the occupancy-only variant).
#include "common/eye_vertex.wgsl"
#include "common/visibility.wgsl"
#include "common/occupancy_order_uniforms.wgsl"
#include "common/mesh_depth.wgsl"

@group(1) @binding(0) var range_near: texture_2d<f32>;
@group(1) @binding(1) var range_far: texture_2d<f32>;
// Four u32 per pixel: slice s is bit s & 31 of word s >> 5.
@group(1) @binding(2) var<storage, read_write> eye_bits: array<atomic<u32>>;
// Four u32 per pixel: fragments per slab (occupancy only: the total in word 0).
@group(1) @binding(3) var<storage, read_write> eye_slabs: array<atomic<u32>>;
@group(1) @binding(4) var<uniform> params: OccupancyOrderUniforms;
@group(1) @binding(5) var mesh_depth: texture_depth_2d;

@vertex
fn vs_main(v: EyeVertexIn) -> EyePoint {
    return eye_vertex(v);
}

struct RangeTargets {
    @location(0) near: vec4<f32>,
    @location(1) far: vec4<f32>,
}

@fragment
fn fs_range(p: EyePoint) -> RangeTargets {
    let d = eye_depth(p.world);
    return RangeTargets(vec4<f32>(d, 0.0, 0.0, 1.0), vec4<f32>(d, 0.0, 0.0, 1.0));
}

@fragment
fn fs_slabs(p: EyePoint) {
    if hidden_by_mesh(mesh_depth, p.clip) {
        discard;
    }
    let px = vec2<i32>(p.clip.xy);
    let near = textureLoad(range_near, px, 0).r;
    let far = textureLoad(range_far, px, 0).r;
    let s = slice_index(relative_depth(eye_depth(p.world), near, far) * 128.0, 128u);
    let t = pixel_index(p.clip) * 4u;
    atomicOr(&eye_bits[t + (s >> 5u)], 1u << (s & 31u));
    atomicAdd(&eye_slabs[t + select(s >> 5u, 0u, params.variant == 1u)], 1u);
}
