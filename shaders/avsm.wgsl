// Adaptive volumetric shadow maps (Salvi, Vidimče, Lauritzen & Lefohn 2010), compression of the A-buffer's
// per-texel fragment lists into N nodes (depth, transmittance), one invocation per texel: visibility::avsm's
// `build`, step for step. The list is a linked list in GPU-atomic order; each step selects the next fragment in
// the insertion order (the smallest key after the last one inserted, the node index breaking ties between
// identical fragments), so any list length gives the CPU model's sorted order: O(n²) reads for n fragments.
// Each fragment inserts a step (two nodes), and while more than N nodes are held the interior node of least
// removal area goes (ties: the lowest index). Output: N slots per texel, the nodes then copies of the last;
// (1, 1) in every slot of an empty texel. A dispatch inserts at most `avsm.steps` fragments per texel and keeps
// where the walk stands in `avsm_walk` (the nodes held are the output slots), so that repeated dispatches bound
// each invocation's loop iterations (a CPU adapter stops a shader's loops after 65,535 in all); the nodes are
// the same however the walk is split.
#include "common/avsm_uniforms.wgsl"
// The A-buffer's lists (render::passes::abuffer), group 1.
#include "common/list_pages.wgsl"

@group(0) @binding(0) var<storage, read_write> avsm_nodes: array<vec2<f32>>;
@group(0) @binding(1) var<uniform> avsm: AvsmUniforms;

// Where a texel's walk stands between dispatches (zero before the first: nothing inserted): the last fragment
// inserted (its index + 1 in `index`; 0: none yet) and the count of nodes held. 32 bytes
// (methods::avsm::WALK_BYTES).
struct AvsmWalk {
    depth: f32,
    alpha: f32,
    segment: u32,
    index: u32,
    held: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}
@group(0) @binding(2) var<storage, read_write> avsm_walk: array<AvsmWalk>;

// N + 2: the nodes held while one fragment's pair is inserted before compression.
const MAX_HELD: u32 = 18u;

// Whether list node a (at index + 1 ia) comes before b (ib) in the insertion order: (depth, segment, alpha) or
// (segment, depth, alpha), then the index.
fn precedes(a: ListNode, ia: u32, b: ListNode, ib: u32) -> bool {
    if avsm.order == 0u {
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
    return ia < ib;
}

@compute @workgroup_size(8, 8)
fn cs_compress(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = avsm.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let texel = id.y * res + id.x;
    let n = avsm.nodes;
    let list_len = ab_capacity();
    let base = texel * n;
    let walk = avsm_walk[texel];
    var held: array<vec2<f32>, MAX_HELD>;
    var count = walk.held;
    for (var j = 0u; j < count; j += 1u) {
        held[j] = avsm_nodes[base + j];
    }
    // The last fragment inserted (its index + 1; 0: none yet).
    var last = ListNode(walk.depth, walk.alpha, walk.segment, 0u);
    var last_i = walk.index;
    for (var inserted = 0u; inserted < avsm.steps; inserted += 1u) {
        // Select the next fragment.
        var best = ListNode(0.0, 0.0, 0u, 0u);
        var best_i = 0u;
        var i = ab_heads[texel];
        var steps = 0u;
        while i != 0u && steps < list_len {
            let node = ab_node(i - 1u);
            let after_last = last_i == 0u || precedes(last, last_i, node, i);
            let before_best = best_i == 0u || precedes(node, i, best, best_i);
            if after_last && before_best {
                best = node;
                best_i = i;
            }
            i = node.next;
            steps += 1u;
        }
        if best_i == 0u {
            break;
        }
        last = best;
        last_i = best_i;

        // Insert the step behind every node at or in front of its depth.
        let d = best.depth;
        let f = avsm_fragment_factor(best.alpha);
        var k = 0u;
        while k < count && held[k].x <= d {
            k += 1u;
        }
        var t_in = 1.0;
        if k == count && k > 0u {
            t_in = held[k - 1u].y;
        } else if k > 0u {
            t_in = avsm_interpolate(held[k - 1u], held[k], d);
        }
        for (var j = count; j > k; j -= 1u) {
            held[j + 1u] = vec2<f32>(held[j - 1u].x, avsm_flush(held[j - 1u].y * f));
        }
        held[k] = vec2<f32>(d, t_in);
        held[k + 1u] = vec2<f32>(d, avsm_flush(t_in * f));
        count += 2u;

        // Compress: remove the interior node of least area until N are left.
        while count > n {
            var remove = 1u;
            var least = avsm_removal_area(held[0], held[1], held[2]);
            for (var j = 2u; j + 1u < count; j += 1u) {
                let a = avsm_removal_area(held[j - 1u], held[j], held[j + 1u]);
                if a < least {
                    remove = j;
                    least = a;
                }
            }
            for (var j = remove; j + 1u < count; j += 1u) {
                held[j] = held[j + 1u];
            }
            count -= 1u;
        }
    }

    avsm_walk[texel] = AvsmWalk(last.depth, last.alpha, last.segment, last_i, count, 0u, 0u, 0u);
    var pad = vec2<f32>(1.0, 1.0);
    if count > 0u {
        pad = held[count - 1u];
    }
    for (var j = 0u; j < n; j += 1u) {
        avsm_nodes[base + j] = select(pad, held[j], j < count);
    }
}
