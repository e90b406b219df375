// The order of a texel's A-buffer fragments (render::passes::abuffer): the CPU models' sorted order, which the
// lists are sorted into (list_sort.wgsl) and the compressors walk them in (common/list_walk.wgsl).

// Nodes list_sort.wgsl's pass 0 sorts at a time (render::passes::list_sort::CHUNK). A list of at most this many
// is left in fill order there; the walk (common/list_walk.wgsl) sorts it as it takes it.
const SORT_CHUNK: u32 = 16u;
// Keys a private array holds: a walk's largest batch (render::passes::abuffer::WALK_BATCH_MAX), or a chunk.
const LIST_KEYS_MAX: u32 = 32u;

// A fragment of a list and its node index + 1 (identical fragments are taken in node order).
struct ListKey {
    depth: f32,
    alpha: f32,
    segment: u32,
    index: u32,
}

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

// Sorts keys[0..count) into `order` by insertion.
fn sort_keys(keys: ptr<private, array<ListKey, LIST_KEYS_MAX>>, count: u32, order: u32) {
    for (var k = 1u; k < count; k += 1u) {
        let key = (*keys)[k];
        var j = k;
        while j > 0u && list_precedes(key, (*keys)[j - 1u], order) {
            (*keys)[j] = (*keys)[j - 1u];
            j -= 1u;
        }
        (*keys)[j] = key;
    }
}
