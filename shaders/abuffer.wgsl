// Reference A-buffer: every light-space hair fragment of every texel, in per-texel linked lists built in one
// geometry pass (after a counting pass sized the node buffer). Sorted on the CPU, the lists are the exact
// reference the methods are measured against; a test shows they equal the depth peel layer for layer.
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/list_node.wgsl"

// [0]: fragments counted, [1]: nodes allocated, [2]: fragments dropped (node pages full), [3]: the longest texel
// list (counting pass), [4]: nodes the pages hold (written when they are sized, never cleared).
@group(1) @binding(0) var<storage, read_write> counters: array<atomic<u32>, 5>;
// Index + 1 of each texel's first node; 0 = empty texel. The counting pass counts each texel's fragments here.
@group(1) @binding(1) var<storage, read_write> heads: array<atomic<u32>>;
// The node pages (render::passes::abuffer::NODE_PAGES): node i is node i % P of page i / P, P the first page's
// length; common/list_pages.wgsl reads them.
@group(1) @binding(2) var<storage, read_write> page_0: array<ListNode>;
@group(1) @binding(3) var<storage, read_write> page_1: array<ListNode>;
@group(1) @binding(4) var<storage, read_write> page_2: array<ListNode>;
@group(1) @binding(5) var<storage, read_write> page_3: array<ListNode>;
@group(1) @binding(6) var<storage, read_write> page_4: array<ListNode>;
@group(1) @binding(7) var<storage, read_write> page_5: array<ListNode>;
@group(1) @binding(8) var<storage, read_write> page_6: array<ListNode>;
@group(1) @binding(9) var<storage, read_write> page_7: array<ListNode>;

fn store_node(i: u32, node: ListNode) {
    let size = arrayLength(&page_0);
    let j = i % size;
    switch i / size {
        case 0u: { page_0[j] = node; }
        case 1u: { page_1[j] = node; }
        case 2u: { page_2[j] = node; }
        case 3u: { page_3[j] = node; }
        case 4u: { page_4[j] = node; }
        case 5u: { page_5[j] = node; }
        case 6u: { page_6[j] = node; }
        default: { page_7[j] = node; }
    }
}

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
