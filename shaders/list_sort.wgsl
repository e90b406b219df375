// Sorts each texel's A-buffer list in place into the CPU models' order (common/list_key.wgsl), relinking its
// nodes: a bottom-up merge sort of the linked list, so that the compressors (AVSM, compressed deep shadow maps)
// walk an n-fragment list once, in n node reads, where a walk that found the order itself read n² / 32. One
// invocation per texel. Pass 0 sorts each run of SORT_CHUNK consecutive nodes by insertion in a private array;
// pass k >= 1 merges neighbouring runs of SORT_CHUNK · 2^(k-1) nodes along the list (Tatham's merge sort of a
// linked list: no memory beyond the links). A dispatch runs passes [part.first, part.end), so that a CPU adapter,
// whose llvmpipe stops a shader's loops after 65,535 iterations in all, can take the passes over several
// dispatches (render::passes::list_sort::SortSplit). Every pass reads and relinks each node once (pass 0 also
// sorts 16 at a time, a merge pass steps over the first run of each pair once more); a list that is one run at a
// merge pass's width is sorted already and left after that step.
#include "common/list_pages_rw.wgsl"
#include "common/list_key.wgsl"

// Nodes sorted by insertion in pass 0 (render::passes::list_sort::CHUNK).
const SORT_CHUNK: u32 = 16u;

// One dispatch's passes. Mirrors `render::passes::list_sort::SortPart` (bound at a dynamic offset per dispatch).
struct SortPart {
    // Texels per side of the lists.
    resolution: u32,
    // list_precedes' order: 0 (depth, segment), 1 (segment, depth).
    order: u32,
    // Passes first..end.
    first: u32,
    end: u32,
}
@group(0) @binding(0) var<uniform> part: SortPart;

var<private> chunk: array<ListKey, SORT_CHUNK>;

// Node i's (index + 1) key.
fn key_of(i: u32, node: ListNode) -> ListKey {
    return ListKey(node.depth, node.alpha, node.segment, i);
}

// Makes `to` (index + 1; 0 ends the list) follow `tail` (index + 1) in texel t's list (tail 0: `to` becomes the
// head).
fn link(t: u32, tail: u32, to: u32) {
    if tail == 0u {
        atomicStore(&heads[t], to);
    } else {
        set_next(tail - 1u, to);
    }
}

// Pass 0: each run of SORT_CHUNK consecutive nodes of texel t's list sorted in place.
fn sort_chunks(t: u32, order: u32) {
    var tail = 0u;
    var i = atomicLoad(&heads[t]);
    while i != 0u {
        var count = 0u;
        while i != 0u && count < SORT_CHUNK {
            let node = load_node(i - 1u);
            let key = key_of(i, node);
            var j = count;
            while j > 0u && list_precedes(key, chunk[j - 1u], order) {
                chunk[j] = chunk[j - 1u];
                j -= 1u;
            }
            chunk[j] = key;
            count += 1u;
            i = node.next;
        }
        for (var j = 0u; j < count; j += 1u) {
            link(t, tail, chunk[j].index);
            tail = chunk[j].index;
        }
    }
    if tail != 0u {
        link(t, tail, 0u);
    }
}

// Pass k >= 1: texel t's neighbouring sorted runs of `width` nodes merged into runs of 2 · width.
fn merge_runs(t: u32, width: u32, order: u32) {
    var tail = 0u;
    var p = atomicLoad(&heads[t]);
    var first = true;
    while p != 0u {
        // q: the second run's first node, `width` nodes behind p (or the end).
        var q = p;
        var p_left = 0u;
        while q != 0u && p_left < width {
            q = load_node(q - 1u).next;
            p_left += 1u;
        }
        if first && q == 0u {
            // The whole list is one run: sorted already.
            return;
        }
        first = false;
        var q_left = width;
        var p_node = load_node(p - 1u);
        var q_node: ListNode;
        if q != 0u {
            q_node = load_node(q - 1u);
        }
        while p_left > 0u || (q_left > 0u && q != 0u) {
            let take_p = p_left > 0u
                && (q_left == 0u || q == 0u || !list_precedes(key_of(q, q_node), key_of(p, p_node), order));
            var e = q;
            if take_p {
                e = p;
                p = p_node.next;
                p_left -= 1u;
                if p_left > 0u {
                    p_node = load_node(p - 1u);
                }
            } else {
                q = q_node.next;
                q_left -= 1u;
                if q_left > 0u && q != 0u {
                    q_node = load_node(q - 1u);
                }
            }
            link(t, tail, e);
            tail = e;
        }
        p = q;
    }
    if tail != 0u {
        link(t, tail, 0u);
    }
}

@compute @workgroup_size(8, 8)
fn cs_sort(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = part.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let t = id.y * res + id.x;
    for (var pass_index = part.first; pass_index < part.end; pass_index += 1u) {
        if pass_index == 0u {
            sort_chunks(t, part.order);
        } else {
            merge_runs(t, SORT_CHUNK << (pass_index - 1u), part.order);
        }
    }
}
