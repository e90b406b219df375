// Sorts each texel's A-buffer list in place (render::passes::list_sort), one invocation per texel: the bottom-up
// merge sort of a linked list (S. Tatham's list merge sort): passes of width 1, 2, 4, … each merge neighbouring
// sorted runs by relinking `next`, until a pass makes one run; O(n log n) steps, no memory besides the state.
// The order is visibility::avsm::insertion_cmp's: (depth, segment, alpha) or (segment, depth, alpha); the merge
// is stable, so fragments equal in all three (identical) keep their list order. The state between dispatches is
// `list_sort_state`: a dispatch takes at most `sort.steps` loop iterations per texel (a CPU adapter stops a
// shader's loops after 65,535 in all) and the next resumes it; the lists are the same however it is split.
#include "common/list_write.wgsl"

struct ListSortUniforms {
    // Texels per side of the map.
    resolution: u32,
    // 0: (depth, segment, alpha), 1: (segment, depth, alpha).
    order: u32,
    // Loop iterations per texel and dispatch.
    steps: u32,
    pad: u32,
}

// A texel's sort between dispatches (zero: not started). Nodes are index + 1 (0: none). 40 bytes
// (render::passes::list_sort::STATE_BYTES).
struct ListSortState {
    // 0: not started, 1: sorting, 2: sorted.
    stage: u32,
    // 0: a merge starts at p, 1: q advances over p's run, 2: the runs at p and q merge.
    phase: u32,
    // Run length of this pass.
    width: u32,
    // Merges in this pass.
    merges: u32,
    // First and last node of the list this pass has built.
    first: u32,
    tail: u32,
    // The two runs being merged and what is left of each.
    p: u32,
    q: u32,
    p_left: u32,
    q_left: u32,
}

@group(0) @binding(0) var<uniform> sort: ListSortUniforms;
@group(0) @binding(1) var<storage, read_write> list_sort_state: array<ListSortState>;

// Whether a comes before b in the sort order.
fn sorts_before(a: ListNode, b: ListNode) -> bool {
    if sort.order == 0u {
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
    return a.alpha < b.alpha;
}

@compute @workgroup_size(8, 8)
fn cs_sort(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = sort.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let t = id.y * res + id.x;
    var s = list_sort_state[t];
    if s.stage == 2u {
        return;
    }
    if s.stage == 0u {
        s = ListSortState(1u, 0u, 1u, 0u, 0u, 0u, atomicLoad(&heads[t]), 0u, 0u, 0u);
    }
    for (var step = 0u; step < sort.steps && s.stage == 1u; step += 1u) {
        if s.phase == 0u {
            if s.p == 0u {
                // The pass is over: end its list; one merge (or none: an empty list) leaves it sorted.
                if s.tail != 0u {
                    link_node(s.tail - 1u, 0u);
                }
                if s.merges <= 1u {
                    atomicStore(&heads[t], s.first);
                    s.stage = 2u;
                } else {
                    s = ListSortState(1u, 0u, 2u * s.width, 0u, 0u, 0u, s.first, 0u, 0u, 0u);
                }
            } else {
                s.merges += 1u;
                s.q = s.p;
                s.p_left = 0u;
                s.phase = 1u;
            }
        } else if s.phase == 1u {
            s.p_left += 1u;
            s.q = load_node(s.q - 1u).next;
            if s.q == 0u || s.p_left == s.width {
                s.q_left = s.width;
                s.phase = 2u;
            }
        } else {
            let q_has = s.q_left > 0u && s.q != 0u;
            if s.p_left == 0u && !q_has {
                s.p = s.q;
                s.phase = 0u;
            } else {
                var e = 0u;
                if s.p_left > 0u {
                    let a = load_node(s.p - 1u);
                    if !q_has || !sorts_before(load_node(s.q - 1u), a) {
                        e = s.p;
                        s.p = a.next;
                        s.p_left -= 1u;
                    }
                }
                if e == 0u {
                    e = s.q;
                    s.q = load_node(s.q - 1u).next;
                    s.q_left -= 1u;
                }
                if s.tail != 0u {
                    link_node(s.tail - 1u, e);
                } else {
                    s.first = e;
                }
                s.tail = e;
            }
        }
    }
    list_sort_state[t] = s;
}
