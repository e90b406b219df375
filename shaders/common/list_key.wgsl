// The order of a texel's A-buffer fragments (render::passes::abuffer): the CPU models' sorted order, which the
// lists are sorted into (list_sort.wgsl) and the compressors walk them in (common/list_walk.wgsl).

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
