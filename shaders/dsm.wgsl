// Compressed deep shadow maps (Lokovic & Veach 2000, §4): one invocation per texel walks the reference A-buffer's
// list in (depth, segment) order, the order of the CPU model's sorted lists, and runs the greedy compressor, as
// visibility::dsm::compress with these exact expressions (see its doc). The order without a private array:
// select-next, each step walks the list for the smallest (depth, segment) behind the previous one, O(n^2) per
// texel and no bound on the list length (the walks stop after the texel's node count, as the reference does).
// cs_count only counts each texel's vertices (header count, total in alloc[0]: the vertex buffer is sized from
// it); cs_compress, on the same fragments, allocates that many and writes them.
#include "common/visibility.wgsl"
#include "common/dsm_uniforms.wgsl"
#include "common/list_node.wgsl"

// The A-buffer's lookup group: index + 1 of each texel's first node (0 = empty), the nodes.
@group(0) @binding(0) var<storage, read> ab_heads: array<u32>;
@group(0) @binding(1) var<storage, read> ab_nodes: array<ListNode>;
// Per texel: (offset of its first vertex, vertex count); the vertices (z, V).
@group(1) @binding(0) var<storage, read_write> out_headers: array<vec2<u32>>;
@group(1) @binding(1) var<storage, read_write> out_vertices: array<vec2<f32>>;
@group(1) @binding(2) var<uniform> dsm: DsmUniforms;
// [0]: vertices counted or allocated, [1]: texels whose vertices did not fit their allocation.
@group(1) @binding(3) var<storage, read_write> alloc: array<atomic<u32>, 2>;

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

// Compresses texel t's list of n nodes; returns its vertex count (written from base, at most limit, if write).
fn compress_texel(t: u32, n: u32, write: bool, base: u32, limit: u32) -> u32 {
    var g = Greedy(0.0, 1.0, 0.0, 0.0, 0.0, false, write, base, limit, 0u);
    var prev_depth = 0.0;
    var prev_segment = 0u;
    // The depth whose fragments are being summed, their optical depth, the visibility in front of them.
    var group = 0.0;
    var sum = 0.0;
    var omega = 0.0;
    var before = 1.0;
    for (var k = 0u; k < n; k++) {
        var best_depth = 0.0;
        var best_segment = 0u;
        var best_alpha = 0.0;
        var found = false;
        var j = ab_heads[t];
        var walked = 0u;
        while j != 0u && walked < n {
            let node = ab_nodes[j - 1u];
            let behind = k == 0u || node.depth > prev_depth || (node.depth == prev_depth && node.segment > prev_segment);
            let smaller = !found || node.depth < best_depth || (node.depth == best_depth && node.segment < best_segment);
            if behind && smaller {
                best_depth = node.depth;
                best_segment = node.segment;
                best_alpha = node.alpha;
                found = true;
            }
            j = node.next;
            walked += 1u;
        }
        if !found {
            break;
        }
        if k > 0u && best_depth != group {
            omega += sum;
            let after = transmittance(omega);
            offer_depth(&g, g.count == 0u, group, before, after);
            before = after;
            sum = 0.0;
        }
        group = best_depth;
        sum += optical_depth(best_alpha);
        prev_depth = best_depth;
        prev_segment = best_segment;
    }
    if n > 0u {
        omega += sum;
        offer_depth(&g, g.count == 0u, group, before, transmittance(omega));
    }
    if g.open {
        close_segment(&g);
    }
    return g.count;
}

// Nodes in texel t's list.
fn list_length(t: u32) -> u32 {
    let node_count = arrayLength(&ab_nodes);
    var n = 0u;
    var i = ab_heads[t];
    while i != 0u && n < node_count {
        i = ab_nodes[i - 1u].next;
        n += 1u;
    }
    return n;
}

@compute @workgroup_size(8, 8)
fn cs_count(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = dsm.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let t = id.y * res + id.x;
    let count = compress_texel(t, list_length(t), false, 0u, 0u);
    out_headers[t] = vec2<u32>(0u, count);
    atomicAdd(&alloc[0], count);
}

@compute @workgroup_size(8, 8)
fn cs_compress(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = dsm.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let t = id.y * res + id.x;
    let counted = out_headers[t].y;
    let base = atomicAdd(&alloc[0], counted);
    let limit = select(0u, counted, base + counted <= arrayLength(&out_vertices));
    let count = compress_texel(t, list_length(t), true, base, limit);
    if count != limit {
        atomicAdd(&alloc[1], 1u);
        out_headers[t] = vec2<u32>(0u, 0xffffffffu);
        return;
    }
    out_headers[t] = vec2<u32>(base, count);
}
