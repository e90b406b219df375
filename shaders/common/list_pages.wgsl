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

// Node i (0-based: a head or `next` minus 1): the pages up to list_pages tested in turn.
fn ab_node(i: u32) -> ListNode {
    let at = list_page(i, arrayLength(&ab_page_0));
    let j = at.x;
    if list_pages == 1u || at.y == 0u {
        return ab_page_0[j];
    }
    if list_pages == 2u || at.y == 1u {
        return ab_page_1[j];
    }
    if list_pages == 3u || at.y == 2u {
        return ab_page_2[j];
    }
    if list_pages == 4u || at.y == 3u {
        return ab_page_3[j];
    }
    if list_pages == 5u || at.y == 4u {
        return ab_page_4[j];
    }
    if list_pages == 6u || at.y == 5u {
        return ab_page_5[j];
    }
    if list_pages == 7u || at.y == 6u {
        return ab_page_6[j];
    }
    return ab_page_7[j];
}

// At least the nodes the pages hold (the placeholders add one each): the bound of a walk along one list.
fn ab_capacity() -> u32 {
    return arrayLength(&ab_page_0) + arrayLength(&ab_page_1) + arrayLength(&ab_page_2) + arrayLength(&ab_page_3)
        + arrayLength(&ab_page_4) + arrayLength(&ab_page_5) + arrayLength(&ab_page_6) + arrayLength(&ab_page_7);
}
