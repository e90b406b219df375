// The light A-buffer's lists as the passes that write them bind them (render::passes::abuffer, group 1): the
// fill (abuffer.wgsl) links each fragment in, the sort (list_sort.wgsl) relinks each texel's list in order.
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

// Node i (0-based: a head or `next` minus 1).
fn load_node(i: u32) -> ListNode {
    let size = arrayLength(&page_0);
    let j = i % size;
    var node: ListNode;
    switch i / size {
        case 0u: { node = page_0[j]; }
        case 1u: { node = page_1[j]; }
        case 2u: { node = page_2[j]; }
        case 3u: { node = page_3[j]; }
        case 4u: { node = page_4[j]; }
        case 5u: { node = page_5[j]; }
        case 6u: { node = page_6[j]; }
        default: { node = page_7[j]; }
    }
    return node;
}

// Sets node i's `next` (index + 1 of the node after it; 0 ends the list).
fn link_node(i: u32, next: u32) {
    let size = arrayLength(&page_0);
    let j = i % size;
    switch i / size {
        case 0u: { page_0[j].next = next; }
        case 1u: { page_1[j].next = next; }
        case 2u: { page_2[j].next = next; }
        case 3u: { page_3[j].next = next; }
        case 4u: { page_4[j].next = next; }
        case 5u: { page_5[j].next = next; }
        case 6u: { page_6[j].next = next; }
        default: { page_7[j].next = next; }
    }
}
