// Hybrid fur, the guard hairs' count pass (Andersen et al. 2016; spec B.6–B.7): every fragment of the strands'
// camera-facing ribbons that the meshes do not hide adds 1 to its pixel's count (counts[W·H] the total), through
// the same ribbon vertex stage as the fur's shaded ribbon fill, so the lists are sized to exactly its fragments.
#include "common/eye_vertex.wgsl"
#include "common/mesh_depth.wgsl"

@group(1) @binding(0) var<storage, read_write> counts: array<atomic<u32>>;
@group(1) @binding(1) var mesh_depth: texture_depth_2d;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> EyePoint {
    return eye_ribbon_point(i);
}

@fragment
fn fs_main(in: EyePoint) {
    if hidden_by_mesh(mesh_depth, in.clip) {
        discard;
    }
    atomicAdd(&counts[pixel_index(in.clip)], 1u);
    atomicAdd(&counts[arrayLength(&counts) - 1u], 1u);
}
