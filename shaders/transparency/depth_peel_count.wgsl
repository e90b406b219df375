// Depth peeling's count pass: one geometry pass over the strands with the shared eye vertex stage counts every
// pixel's fragments the meshes do not hide (tested by hand before the atomics) and keeps the largest count, the
// number of layers the peel needs, in slot 0 of `peel_counts` and the total in slot 1; the pixels' counts follow.
#include "common/eye_vertex.wgsl"
#include "common/mesh_depth.wgsl"

@group(1) @binding(0) var<storage, read_write> peel_counts: array<atomic<u32>>;
@group(1) @binding(1) var mesh_depth: texture_depth_2d;

@vertex
fn vs_main(v: EyeVertexIn) -> EyePoint {
    return eye_vertex(v);
}

@fragment
fn fs_main(f: EyePoint) {
    if hidden_by_mesh(mesh_depth, f.clip) {
        discard;
    }
    let n = atomicAdd(&peel_counts[2u + pixel_index(f.clip)], 1u) + 1u;
    atomicMax(&peel_counts[0], n);
    atomicAdd(&peel_counts[1], 1u);
}
