// Adaptive volumetric shadow maps (Salvi, Vidimče, Lauritzen & Lefohn 2010), compression of the A-buffer's
// per-texel fragment lists into N nodes (depth, transmittance), one invocation per texel: visibility::avsm's
// `build`, step for step. The lists arrive sorted in the insertion order (list_sort.wgsl: (depth, segment, alpha)
// or (segment, depth, alpha), the CPU model's sort), so each texel walks its list once, front to back: O(n)
// reads for n fragments. Each fragment inserts a step (two nodes), and while more than N nodes are held the
// interior node of least removal area goes (ties: the lowest index). Output: N slots per texel, the nodes then
// copies of the last; (1, 1) in every slot of an empty texel. A dispatch inserts at most `avsm.steps` fragments
// per texel and keeps where the walk stands in `avsm_walk` (the nodes held are the output slots), so that
// repeated dispatches bound each invocation's loop iterations (a CPU adapter stops a shader's loops after
// 65,535 in all); the nodes are the same however the walk is split.
#include "common/avsm_uniforms.wgsl"
// The A-buffer's lists (render::passes::abuffer), group 1.
#include "common/list_pages.wgsl"

@group(0) @binding(0) var<storage, read_write> avsm_nodes: array<vec2<f32>>;
@group(0) @binding(1) var<uniform> avsm: AvsmUniforms;

// Where a texel's walk stands between dispatches (zero before the first: not started): whether it started, the
// next fragment to insert (its node index + 1; 0: the list is walked) and the count of nodes held. 32 bytes
// (methods::avsm::WALK_BYTES).
struct AvsmWalk {
    started: u32,
    next: u32,
    held: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    pad3: u32,
    pad4: u32,
}
@group(0) @binding(2) var<storage, read_write> avsm_walk: array<AvsmWalk>;

// N + 2: the nodes held while one fragment's pair is inserted before compression.
const MAX_HELD: u32 = 18u;

@compute @workgroup_size(8, 8)
fn cs_compress(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = avsm.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let texel = id.y * res + id.x;
    let n = avsm.nodes;
    let base = texel * n;
    let walk = avsm_walk[texel];
    var held: array<vec2<f32>, MAX_HELD>;
    var count = walk.held;
    for (var j = 0u; j < count; j += 1u) {
        held[j] = avsm_nodes[base + j];
    }
    var next = select(ab_heads[texel], walk.next, walk.started != 0u);
    for (var inserted = 0u; inserted < avsm.steps && next != 0u; inserted += 1u) {
        let frag = ab_node(next - 1u);
        next = frag.next;

        // Insert the step behind every node at or in front of its depth.
        let d = frag.depth;
        let f = avsm_fragment_factor(frag.alpha);
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

    avsm_walk[texel] = AvsmWalk(1u, next, count, 0u, 0u, 0u, 0u, 0u);
    var pad = vec2<f32>(1.0, 1.0);
    if count > 0u {
        pad = held[count - 1u];
    }
    for (var j = 0u; j < n; j += 1u) {
        avsm_nodes[base + j] = select(pad, held[j], j < count);
    }
}
