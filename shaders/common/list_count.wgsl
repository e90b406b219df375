// The per-pixel lists' count pass (src/render/eye/lists.rs, step 1), shared by every list technique: every eye
// fragment the meshes do not hide adds 1 to its pixel's count (counts[W·H] holds the total), so the node buffer is
// sized to exactly the frame's fragments. The including file writes `vs_main` (lines or ribbons).
#include "common/eye_vertex.wgsl"
#include "common/mesh_depth.wgsl"

@group(1) @binding(0) var<storage, read_write> counts: array<atomic<u32>>;
@group(1) @binding(1) var mesh_depth: texture_depth_2d;

@fragment
fn fs_main(in: EyePoint) {
    if hidden_by_mesh(mesh_depth, in.clip) {
        discard;
    }
    atomicAdd(&counts[pixel_index(in.clip)], 1u);
    atomicAdd(&counts[arrayLength(&counts) - 1u], 1u);
}
