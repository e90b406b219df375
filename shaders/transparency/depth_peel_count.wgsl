// Depth peeling's count pass: one geometry pass over the strands with the shared eye vertex stage (depth test
// `Less` against the meshes, no write) counts every pixel's fragments and keeps the largest count, the number
// of layers the peel needs (slot 0 of `peel_counts`; the pixels' counts follow).
#include "common/eye_vertex.wgsl"

@group(1) @binding(0) var<storage, read_write> peel_counts: array<atomic<u32>>;

struct CountVertexIn {
    @builtin(vertex_index) index: u32,
    @location(0) position: vec3<f32>,
    @location(1) alpha: f32,
}

@vertex
fn vs_main(v: CountVertexIn) -> EyePoint {
    return eye_point(v.index, v.position, v.alpha);
}

@fragment
fn fs_main(f: EyePoint) {
    let n = atomicAdd(&peel_counts[1u + pixel_index(f.clip)], 1u) + 1u;
    atomicMax(&peel_counts[0], n);
}
