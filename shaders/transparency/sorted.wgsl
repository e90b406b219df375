// Exact eye transparency, pass 2 (the hair entry, pasted into hair.wgsl): every shaded fragment is pushed onto
// its pixel's list. Nodes beyond the buffer (never, when sized from the count pass) are counted in counters[1].
#include "common/eye_node.wgsl"
#include "common/mesh_depth.wgsl"

@group(2) @binding(0) var<storage, read_write> heads: array<atomic<u32>>;
@group(2) @binding(1) var<storage, read_write> nodes: array<EyeNode>;
// [0] nodes used, [1] fragments that did not fit.
@group(2) @binding(2) var<storage, read_write> counters: array<atomic<u32>>;
@group(2) @binding(3) var mesh_depth: texture_depth_2d;

@fragment
fn fs_main(in: VertexOut) {
    if hidden_by_mesh(mesh_depth, in.clip) {
        discard;
    }
    let f = shade_hair(in);
    let i = atomicAdd(&counters[0], 1u);
    if i >= arrayLength(&nodes) {
        atomicAdd(&counters[1], 1u);
        return;
    }
    let p = f.pixel.y * u32(frame.viewport_size.x) + f.pixel.x;
    var node: EyeNode;
    // abs() turns -0.0 into +0.0 so the bit pattern orders like the value.
    node.depth = abs(f.depth);
    node.segment = f.segment;
    node.r = f.color.r;
    node.g = f.color.g;
    node.b = f.color.b;
    node.alpha = f.alpha;
    node.kind = 0u;
    node.next = atomicExchange(&heads[p], i + 1u);
    nodes[i] = node;
}
