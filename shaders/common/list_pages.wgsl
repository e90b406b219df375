// The light A-buffer's lists as their readers bind them (render::passes::abuffer, group 1 of the reference lookup
// and of the compressors): index + 1 of each texel's first node (0 = empty), and the nodes in NODE_PAGES pages of
// one storage binding each, node i being node i % P of page i / P, P the first page's length. Unused pages are
// one-node placeholders, never reached: a list's indices are below the frame's node count.
#include "common/list_node.wgsl"

@group(1) @binding(0) var<storage, read> ab_heads: array<u32>;
@group(1) @binding(1) var<storage, read> ab_page_0: array<ListNode>;
@group(1) @binding(2) var<storage, read> ab_page_1: array<ListNode>;
@group(1) @binding(3) var<storage, read> ab_page_2: array<ListNode>;
@group(1) @binding(4) var<storage, read> ab_page_3: array<ListNode>;
@group(1) @binding(5) var<storage, read> ab_page_4: array<ListNode>;
@group(1) @binding(6) var<storage, read> ab_page_5: array<ListNode>;
@group(1) @binding(7) var<storage, read> ab_page_6: array<ListNode>;
@group(1) @binding(8) var<storage, read> ab_page_7: array<ListNode>;

// Node i (0-based: a head or `next` minus 1).
fn ab_node(i: u32) -> ListNode {
    let size = arrayLength(&ab_page_0);
    let j = i % size;
    var node: ListNode;
    switch i / size {
        case 0u: { node = ab_page_0[j]; }
        case 1u: { node = ab_page_1[j]; }
        case 2u: { node = ab_page_2[j]; }
        case 3u: { node = ab_page_3[j]; }
        case 4u: { node = ab_page_4[j]; }
        case 5u: { node = ab_page_5[j]; }
        case 6u: { node = ab_page_6[j]; }
        default: { node = ab_page_7[j]; }
    }
    return node;
}

// At least the nodes the pages hold (the placeholders add one each): the bound of a walk along one list.
fn ab_capacity() -> u32 {
    return arrayLength(&ab_page_0) + arrayLength(&ab_page_1) + arrayLength(&ab_page_2) + arrayLength(&ab_page_3)
        + arrayLength(&ab_page_4) + arrayLength(&ab_page_5) + arrayLength(&ab_page_6) + arrayLength(&ab_page_7);
}
