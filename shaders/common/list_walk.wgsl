// A walk along a texel's A-buffer list in a sorted order, a batch of fragments at a time: shared by the
// compressors that build their maps from the reference's lists (AVSM, compressed deep shadow maps). The list is a
// linked list in GPU-atomic order; one pass along it keeps, in a private array sorted by insertion, the `size`
// first fragments behind the last one taken, so a list of n fragments is walked n / size + 1 times (n² / size
// node reads) and taken in the CPU models' sorted order whatever its length. `size` 1 is the select-next walk.
// Loop iterations of one batch: at most n × size (a node taken moves at most size - 1 others); the split over
// dispatches (render::passes::abuffer::WalkSplit) budgets that on a CPU adapter.
#include "common/list_pages.wgsl"

// Largest batch (render::passes::abuffer::WALK_BATCH_MAX).
const LIST_BATCH_MAX: u32 = 32u;

// A fragment of a list and its node index + 1 (identical fragments are taken in node order).
struct ListKey {
    depth: f32,
    alpha: f32,
    segment: u32,
    index: u32,
}

// The batch taken by list_next_batch, in order.
var<private> list_batch: array<ListKey, LIST_BATCH_MAX>;

// Whether a comes before b: (depth, segment, alpha) (order 0) or (segment, depth, alpha) (order 1), then the node
// index.
fn list_precedes(a: ListKey, b: ListKey, order: u32) -> bool {
    if order == 0u {
        if a.depth != b.depth {
            return a.depth < b.depth;
        }
        if a.segment != b.segment {
            return a.segment < b.segment;
        }
    } else {
        if a.segment != b.segment {
            return a.segment < b.segment;
        }
        if a.depth != b.depth {
            return a.depth < b.depth;
        }
    }
    if a.alpha != b.alpha {
        return a.alpha < b.alpha;
    }
    return a.index < b.index;
}

// Fills list_batch[0..count) with the first `size` (1..=LIST_BATCH_MAX) fragments of texel t's list behind
// `last` (`last.index` 0: from the start) in `order`, walking at most `bound` nodes; returns count, below `size`
// only where the list ends.
fn list_next_batch(t: u32, last: ListKey, size: u32, order: u32, bound: u32) -> u32 {
    var count = 0u;
    var i = ab_heads[t];
    var walked = 0u;
    while i != 0u && walked < bound {
        let node = ab_node(i - 1u);
        let key = ListKey(node.depth, node.alpha, node.segment, i);
        let behind = last.index == 0u || list_precedes(last, key, order);
        if behind && (count < size || list_precedes(key, list_batch[size - 1u], order)) {
            // Insert it in order; a full batch drops its last.
            var j = min(count, size - 1u);
            while j > 0u && list_precedes(key, list_batch[j - 1u], order) {
                list_batch[j] = list_batch[j - 1u];
                j -= 1u;
            }
            list_batch[j] = key;
            count = min(count + 1u, size);
        }
        i = node.next;
        walked += 1u;
    }
    return count;
}
