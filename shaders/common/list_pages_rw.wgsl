// The light A-buffer as its writers bind it (render::passes::abuffer, group 1 of the fill and of the list sort):
// the counters, each texel's head and the node pages, read-write. common/list_pages.wgsl binds the same heads and
// pages read-only for the readers.
#include "common/list_node.wgsl"

// [0]: fragments counted, [1]: nodes allocated, [2]: fragments dropped (node pages full), [3]: the longest texel
// list (counting pass), [4]: nodes the pages hold (written when they are sized, never cleared).
@group(1) @binding(0) var<storage, read_write> counters: array<atomic<u32>, 5>;
// Index + 1 of each texel's first node; 0 = empty texel. The counting pass counts each texel's fragments here.
@group(1) @binding(1) var<storage, read_write> heads: array<atomic<u32>>;
// The node pages (render::passes::abuffer::NODE_PAGES): node i is node i % P of page i / P, P the first page's
// length.
@group(1) @binding(2) var<storage, read_write> page_0: array<ListNode>;
@group(1) @binding(3) var<storage, read_write> page_1: array<ListNode>;
@group(1) @binding(4) var<storage, read_write> page_2: array<ListNode>;
@group(1) @binding(5) var<storage, read_write> page_3: array<ListNode>;
@group(1) @binding(6) var<storage, read_write> page_4: array<ListNode>;
@group(1) @binding(7) var<storage, read_write> page_5: array<ListNode>;
@group(1) @binding(8) var<storage, read_write> page_6: array<ListNode>;
@group(1) @binding(9) var<storage, read_write> page_7: array<ListNode>;

// Node i's store, load and link to the next node (index + 1): the pages up to list_pages tested in turn, the
// last one taken unconditionally.
fn store_node(i: u32, node: ListNode) {
    let at = list_page(i, arrayLength(&page_0));
    let j = at.x;
    if list_pages == 1u || at.y == 0u {
        page_0[j] = node;
        return;
    }
    if list_pages == 2u || at.y == 1u {
        page_1[j] = node;
        return;
    }
    if list_pages == 3u || at.y == 2u {
        page_2[j] = node;
        return;
    }
    if list_pages == 4u || at.y == 3u {
        page_3[j] = node;
        return;
    }
    if list_pages == 5u || at.y == 4u {
        page_4[j] = node;
        return;
    }
    if list_pages == 6u || at.y == 5u {
        page_5[j] = node;
        return;
    }
    if list_pages == 7u || at.y == 6u {
        page_6[j] = node;
        return;
    }
    page_7[j] = node;
}

fn set_next(i: u32, next: u32) {
    let at = list_page(i, arrayLength(&page_0));
    let j = at.x;
    if list_pages == 1u || at.y == 0u {
        page_0[j].next = next;
        return;
    }
    if list_pages == 2u || at.y == 1u {
        page_1[j].next = next;
        return;
    }
    if list_pages == 3u || at.y == 2u {
        page_2[j].next = next;
        return;
    }
    if list_pages == 4u || at.y == 3u {
        page_3[j].next = next;
        return;
    }
    if list_pages == 5u || at.y == 4u {
        page_4[j].next = next;
        return;
    }
    if list_pages == 6u || at.y == 5u {
        page_5[j].next = next;
        return;
    }
    if list_pages == 7u || at.y == 6u {
        page_6[j].next = next;
        return;
    }
    page_7[j].next = next;
}

fn load_node(i: u32) -> ListNode {
    let at = list_page(i, arrayLength(&page_0));
    let j = at.x;
    if list_pages == 1u || at.y == 0u {
        return page_0[j];
    }
    if list_pages == 2u || at.y == 1u {
        return page_1[j];
    }
    if list_pages == 3u || at.y == 2u {
        return page_2[j];
    }
    if list_pages == 4u || at.y == 3u {
        return page_3[j];
    }
    if list_pages == 5u || at.y == 4u {
        return page_4[j];
    }
    if list_pages == 6u || at.y == 5u {
        return page_5[j];
    }
    if list_pages == 7u || at.y == 6u {
        return page_6[j];
    }
    return page_7[j];
}
