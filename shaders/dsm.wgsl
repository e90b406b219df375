// Compressed deep shadow maps (Lokovic & Veach 2000, §4): one invocation per texel walks the reference A-buffer's
// list in (depth, segment) order, the order of the CPU model's sorted lists, and runs the greedy compressor, as
// visibility::dsm::compress with these exact expressions (see its doc). The A-buffer sorted each list into that
// order (list_sort.wgsl); common/list_walk.wgsl walks it, `dsm.batch` fragments at a time (the walks stop after
// the texel's node count, as the reference does).
// cs_count only counts each texel's vertices (header count, total in alloc[0]: the vertex buffer is sized from
// it); cs_compress, on the same fragments, allocates that many and writes them.
// Both resume across dispatches: each takes at most dsm.steps batches per texel and keeps where the texel
// stands in `walks`, so that repeated dispatches bound each invocation's loop iterations (a CPU adapter stops a
// shader's loops after 65,535 in all); the vertices are the same however the walk is split or batched.
#include "common/visibility.wgsl"
#include "common/dsm_uniforms.wgsl"
// The A-buffer's sorted lists (render::passes::abuffer), group 1, and the walk along them.
#include "common/list_walk.wgsl"

// Per texel: (offset of its first vertex, vertex count); the vertices (z, V).
@group(0) @binding(0) var<storage, read_write> out_headers: array<vec2<u32>>;
@group(0) @binding(1) var<storage, read_write> out_vertices: array<vec2<f32>>;
@group(0) @binding(2) var<uniform> dsm: DsmUniforms;
// [0]: vertices counted or allocated, [1]: texels whose vertices did not fit their allocation.
@group(0) @binding(3) var<storage, read_write> alloc: array<atomic<u32>, 2>;

// The compressor's state: the origin vertex, the slope window [lo, hi] and the last accepted depth once a point
// behind the origin was accepted (open); where the texel's vertices go and how many it may write (write: false
// only counts).
struct Greedy {
    zo: f32,
    vo: f32,
    lo: f32,
    hi: f32,
    last: f32,
    open: bool,
    write: bool,
    base: u32,
    limit: u32,
    count: u32,
}

fn push_vertex(g: ptr<function, Greedy>, z: f32, v: f32) {
    (*g).zo = z;
    (*g).vo = v;
    if (*g).write && (*g).count < (*g).limit {
        out_vertices[(*g).base + (*g).count] = vec2<f32>(z, v);
    }
    (*g).count += 1u;
}

// Ends the open segment at its last accepted depth (the next origin).
fn close_segment(g: ptr<function, Greedy>) {
    let slope = min(0.5 * ((*g).lo + (*g).hi), max((*g).lo, 0.0));
    let v = min((*g).vo + slope * ((*g).last - (*g).zo), (*g).vo);
    push_vertex(g, (*g).last, v);
    (*g).open = false;
}

// Offers the constraint point (z, v), z at or behind the origin; a second attempt follows a closed segment.
fn offer(g: ptr<function, Greedy>, z: f32, v: f32) {
    let eps = dsm.epsilon;
    for (var attempt = 0u; attempt < 2u; attempt++) {
        let zo = (*g).zo;
        let vo = (*g).vo;
        if z > zo {
            let dz = z - zo;
            let a = (v - eps - vo) / dz;
            let b = (v + eps - vo) / dz;
            if !(*g).open {
                (*g).lo = a;
                (*g).hi = b;
                (*g).last = z;
                (*g).open = true;
                return;
            }
            let lo2 = max((*g).lo, a);
            let hi2 = min((*g).hi, b);
            if lo2 <= hi2 {
                (*g).lo = lo2;
                (*g).hi = hi2;
                (*g).last = z;
                return;
            }
            close_segment(g);
            continue;
        }
        if abs(v - vo) > eps {
            push_vertex(g, zo, min(v, vo));
        }
        return;
    }
}

// Offers the steps of one distinct depth d (the visibility before and after its fragments).
fn offer_depth(g: ptr<function, Greedy>, first: bool, d: f32, before: f32, after: f32) {
    if first {
        push_vertex(g, d, 1.0);
    } else {
        offer(g, d, before);
    }
    offer(g, d, after);
}

// Where a texel's compression stands between dispatches (zero before the first: not started): the compressor's
// state, the walk's (fragments taken k of n, the last one's depth and segment, the depth being summed, its
// optical depth, the total in front of it, the visibility in front of it), the stage (0 not started, 1 walking,
// 2 done), the vertices allocated (cs_compress) and the last fragment's alpha and node index + 1. 80 bytes
// (methods::dsm::WALK_BYTES).
struct DsmWalk {
    zo: f32,
    vo: f32,
    lo: f32,
    hi: f32,
    last: f32,
    open: u32,
    count: u32,
    k: u32,
    n: u32,
    prev_depth: f32,
    prev_segment: u32,
    group: f32,
    sum: f32,
    omega: f32,
    before: f32,
    stage: u32,
    base: u32,
    limit: u32,
    prev_alpha: f32,
    prev_index: u32,
}
@group(0) @binding(4) var<storage, read_write> walks: array<DsmWalk>;

// Takes at most dsm.steps more batches of texel t's list (n nodes, known once a batch comes back short) into its
// compression (vertices written from w.base, at most w.limit, if write) and finishes it once the list is walked;
// returns the state.
fn advance(t: u32, write: bool, state: DsmWalk) -> DsmWalk {
    var w = state;
    var g = Greedy(w.zo, w.vo, w.lo, w.hi, w.last, w.open != 0u, write, w.base, w.limit, w.count);
    var last = ListKey(w.prev_depth, w.prev_alpha, w.prev_segment, w.prev_index);
    for (var s = 0u; s < dsm.steps && w.k < w.n; s++) {
        let taken = list_next_batch(t, last, dsm.batch);
        if taken < dsm.batch {
            w.n = w.k + taken;
        }
        for (var q = 0u; q < taken; q++) {
            last = list_batch[q];
            if w.k > 0u && last.depth != w.group {
                w.omega += w.sum;
                let after = transmittance(w.omega);
                offer_depth(&g, g.count == 0u, w.group, w.before, after);
                w.before = after;
                w.sum = 0.0;
            }
            w.group = last.depth;
            w.sum += optical_depth(last.alpha);
            w.k += 1u;
        }
    }
    w.prev_depth = last.depth;
    w.prev_alpha = last.alpha;
    w.prev_segment = last.segment;
    w.prev_index = last.index;
    if w.k >= w.n {
        if w.n > 0u {
            w.omega += w.sum;
            offer_depth(&g, g.count == 0u, w.group, w.before, transmittance(w.omega));
        }
        if g.open {
            close_segment(&g);
        }
        w.stage = 2u;
    }
    w.zo = g.zo;
    w.vo = g.vo;
    w.lo = g.lo;
    w.hi = g.hi;
    w.last = g.last;
    w.open = u32(g.open);
    w.count = g.count;
    return w;
}

// The state of a texel not started: nothing taken, the list's length not known yet, the visibility 1 in front.
fn started() -> DsmWalk {
    var w: DsmWalk;
    w.vo = 1.0;
    w.n = 0xffffffffu;
    w.before = 1.0;
    w.stage = 1u;
    return w;
}

@compute @workgroup_size(8, 8)
fn cs_count(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = dsm.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let t = id.y * res + id.x;
    var w = walks[t];
    if w.stage == 2u {
        return;
    }
    if w.stage == 0u {
        w = started();
    }
    w = advance(t, false, w);
    walks[t] = w;
    if w.stage == 2u {
        out_headers[t] = vec2<u32>(0u, w.count);
        atomicAdd(&alloc[0], w.count);
    }
}

@compute @workgroup_size(8, 8)
fn cs_compress(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = dsm.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let t = id.y * res + id.x;
    var w = walks[t];
    if w.stage == 2u {
        return;
    }
    if w.stage == 0u {
        w = started();
        let counted = out_headers[t].y;
        w.base = atomicAdd(&alloc[0], counted);
        w.limit = select(0u, counted, w.base + counted <= arrayLength(&out_vertices));
    }
    w = advance(t, true, w);
    walks[t] = w;
    if w.stage != 2u {
        return;
    }
    if w.count != w.limit {
        atomicAdd(&alloc[1], 1u);
        out_headers[t] = vec2<u32>(0u, 0xffffffffu);
        return;
    }
    out_headers[t] = vec2<u32>(w.base, w.count);
}
