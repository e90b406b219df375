// A walk along a texel's A-buffer list, a batch of fragments at a time, after list_sort.wgsl has linked it in
// the CPU models' sorted order: shared by the compressors that build their maps from the reference's lists (AVSM,
// compressed deep shadow maps). A walk resumes behind the last fragment it took, so a list of n fragments costs n
// node reads however the walk is split over dispatches (render::passes::abuffer::WalkSplit).
#include "common/list_pages.wgsl"
#include "common/list_key.wgsl"

// Largest batch (render::passes::abuffer::WALK_BATCH_MAX).
const LIST_BATCH_MAX: u32 = 32u;

// The batch taken by list_next_batch, in order.
var<private> list_batch: array<ListKey, LIST_BATCH_MAX>;

// Fills list_batch[0..count) with the `size` (1..=LIST_BATCH_MAX) fragments of texel t's sorted list behind
// `last` (`last.index` 0: from the start); returns count, below `size` only where the list ends.
fn list_next_batch(t: u32, last: ListKey, size: u32) -> u32 {
    var i = ab_heads[t];
    if last.index != 0u {
        i = ab_node(last.index - 1u).next;
    }
    var count = 0u;
    while i != 0u && count < size {
        let node = ab_node(i - 1u);
        list_batch[count] = ListKey(node.depth, node.alpha, node.segment, i);
        count += 1u;
        i = node.next;
    }
    return count;
}
