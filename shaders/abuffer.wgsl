// Reference A-buffer: every light-space hair fragment of every texel, in per-texel linked lists built in one
// geometry pass (after a counting pass sized the node buffer). Sorted on the CPU, the lists are the exact
// reference the methods are measured against; a test shows they equal the depth peel layer for layer.
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/list_pages_rw.wgsl"

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

@fragment
fn fs_count(f: LightFragment) {
    atomicAdd(&counters[0], 1u);
    atomicMax(&counters[3], atomicAdd(&heads[texel_index(f.clip)], 1u) + 1u);
}

@fragment
fn fs_fill(f: LightFragment) {
    let i = atomicAdd(&counters[1], 1u);
    if i >= atomicLoad(&counters[4]) {
        atomicAdd(&counters[2], 1u);
        return;
    }
    let t = texel_index(f.clip);
    let next = atomicExchange(&heads[t], i + 1u);
    store_node(i, ListNode(fragment_depth(f.depth), f.alpha, f.segment, next));
}
