// Adaptive volumetric shadow maps (Salvi, Vidimče, Lauritzen & Lefohn 2010), compression of the A-buffer's
// per-texel fragment lists into N nodes (depth, transmittance), one invocation per texel: visibility::avsm's
// `build`, step for step. The fragments are taken in the CPU model's sorted order (the node index breaking ties
// between identical fragments): the A-buffer sorted each list into it (list_sort.wgsl) and common/list_walk.wgsl
// walks it, `avsm.batch` fragments at a time. Each fragment inserts a step (two nodes), and while more than N
// nodes are held the interior node of least removal area goes (ties: the lowest index). Output: N slots per
// texel, the nodes then copies of the last; (1, 1) in every slot of an empty texel. A dispatch takes at most
// `avsm.steps` batches per texel and keeps where the walk stands in `avsm_walk` (the nodes held are the output
// slots), so that repeated dispatches bound each invocation's loop iterations (a CPU adapter stops a shader's
// loops after 65,535 in all); the nodes are the same however the walk is split or batched.
#include "common/avsm_uniforms.wgsl"
// The A-buffer's sorted lists (render::passes::abuffer), group 1, and the walk along them.
#include "common/list_walk.wgsl"

@group(0) @binding(0) var<storage, read_write> avsm_nodes: array<vec2<f32>>;
@group(0) @binding(1) var<uniform> avsm: AvsmUniforms;

// Where a texel's walk stands between dispatches (zero before the first: nothing inserted): the last fragment
// inserted (its index + 1 in `index`; 0: none yet), the count of nodes held and whether the list is done. 32
// bytes (methods::avsm::WALK_BYTES).
struct AvsmWalk {
    depth: f32,
    alpha: f32,
    segment: u32,
    index: u32,
    held: u32,
    done: u32,
    pad1: u32,
    pad2: u32,
}
@group(0) @binding(2) var<storage, read_write> avsm_walk: array<AvsmWalk>;

// N + 2: the nodes held while one fragment's pair is inserted before compression.
const MAX_HELD: u32 = 18u;

// Inserts fragment f's step into the count nodes held (behind every node at or in front of its depth), then
// removes the interior node of least area until n are left; returns the count held.
fn avsm_insert(held: ptr<function, array<vec2<f32>, MAX_HELD>>, count_in: u32, n: u32, f: ListKey) -> u32 {
    var count = count_in;
    let d = f.depth;
    let factor = avsm_fragment_factor(f.alpha);
    var k = 0u;
    while k < count && (*held)[k].x <= d {
        k += 1u;
    }
    var t_in = 1.0;
    if k == count && k > 0u {
        t_in = (*held)[k - 1u].y;
    } else if k > 0u {
        t_in = avsm_interpolate((*held)[k - 1u], (*held)[k], d);
    }
    for (var j = count; j > k; j -= 1u) {
        (*held)[j + 1u] = vec2<f32>((*held)[j - 1u].x, avsm_flush((*held)[j - 1u].y * factor));
    }
    (*held)[k] = vec2<f32>(d, t_in);
    (*held)[k + 1u] = vec2<f32>(d, avsm_flush(t_in * factor));
    count += 2u;

    while count > n {
        var remove = 1u;
        var least = avsm_removal_area((*held)[0], (*held)[1], (*held)[2]);
        for (var j = 2u; j + 1u < count; j += 1u) {
            let a = avsm_removal_area((*held)[j - 1u], (*held)[j], (*held)[j + 1u]);
            if a < least {
                remove = j;
                least = a;
            }
        }
        for (var j = remove; j + 1u < count; j += 1u) {
            (*held)[j] = (*held)[j + 1u];
        }
        count -= 1u;
    }
    return count;
}

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
    if walk.done != 0u {
        return;
    }
    var held: array<vec2<f32>, MAX_HELD>;
    var count = walk.held;
    for (var j = 0u; j < count; j += 1u) {
        held[j] = avsm_nodes[base + j];
    }
    // The last fragment inserted (index 0: none yet).
    var last = ListKey(walk.depth, walk.alpha, walk.segment, walk.index);
    var done = false;
    for (var batch = 0u; batch < avsm.steps && !done; batch += 1u) {
        let taken = list_next_batch(texel, last, avsm.batch);
        done = taken < avsm.batch;
        for (var q = 0u; q < taken; q += 1u) {
            last = list_batch[q];
            count = avsm_insert(&held, count, n, last);
        }
    }

    avsm_walk[texel] = AvsmWalk(last.depth, last.alpha, last.segment, last.index, count, u32(done), 0u, 0u);
    var pad = vec2<f32>(1.0, 1.0);
    if count > 0u {
        pad = held[count - 1u];
    }
    for (var j = 0u; j < n; j += 1u) {
        avsm_nodes[base + j] = select(pad, held[j], j < count);
    }
}
