// Compressed deep shadow maps (Lokovic & Veach 2000, §4): one invocation per texel walks the reference A-buffer's
// list in depth order and writes the greedy compressor's vertices, as visibility::dsm::compress with these exact
// expressions (see its doc). Depth order without a private array: select-next, each step walks the list for the
// smallest depth behind the previous one and sums the optical depth of the fragments at it, O(n x distinct depths)
// per texel and no bound on the list length (the walks stop after the texel's node count, as the reference does).
#include "common/visibility.wgsl"
#include "common/dsm_uniforms.wgsl"

struct AbNode {
    depth: f32,
    alpha: f32,
    segment: u32,
    next: u32,
}

// The A-buffer's lookup group: index + 1 of each texel's first node (0 = empty), the nodes.
@group(0) @binding(0) var<storage, read> ab_heads: array<u32>;
@group(0) @binding(1) var<storage, read> ab_nodes: array<AbNode>;
// Per texel: (offset of its first vertex, vertex count); the vertices (z, V).
@group(1) @binding(0) var<storage, read_write> out_headers: array<vec2<u32>>;
@group(1) @binding(1) var<storage, read_write> out_vertices: array<vec2<f32>>;
@group(1) @binding(2) var<uniform> dsm: DsmUniforms;
// [0]: vertices allocated (2 per fragment of each texel), [1]: texels that did not fit.
@group(1) @binding(3) var<storage, read_write> alloc: array<atomic<u32>, 2>;

// The compressor's state: the origin vertex, the slope window [lo, hi] and the last accepted depth once a point
// behind the origin was accepted (open), where the texel's vertices go.
struct Greedy {
    zo: f32,
    vo: f32,
    lo: f32,
    hi: f32,
    last: f32,
    open: bool,
    base: u32,
    count: u32,
}

fn push_vertex(g: ptr<function, Greedy>, z: f32, v: f32) {
    (*g).zo = z;
    (*g).vo = v;
    out_vertices[(*g).base + (*g).count] = vec2<f32>(z, v);
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

@compute @workgroup_size(8, 8)
fn cs_compress(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = dsm.resolution;
    if id.x >= res || id.y >= res {
        return;
    }
    let t = id.y * res + id.x;
    let node_count = arrayLength(&ab_nodes);
    var n = 0u;
    var i = ab_heads[t];
    while i != 0u && n < node_count {
        i = ab_nodes[i - 1u].next;
        n += 1u;
    }
    if n == 0u {
        out_headers[t] = vec2<u32>(0u, 0u);
        return;
    }
    let base = atomicAdd(&alloc[0], 2u * n);
    if base + 2u * n > arrayLength(&out_vertices) {
        atomicAdd(&alloc[1], 1u);
        out_headers[t] = vec2<u32>(0u, 0xffffffffu);
        return;
    }
    var g = Greedy(0.0, 1.0, 0.0, 0.0, 0.0, false, base, 0u);
    var prev = 0.0;
    var started = false;
    var omega = 0.0;
    var before = 1.0;
    loop {
        // The next distinct depth d behind prev, and the optical depth of its fragments (in list order).
        var found = false;
        var d = 0.0;
        var sum = 0.0;
        var j = ab_heads[t];
        var steps = 0u;
        while j != 0u && steps < n {
            let node = ab_nodes[j - 1u];
            if !started || node.depth > prev {
                if !found || node.depth < d {
                    d = node.depth;
                    sum = optical_depth(node.alpha);
                    found = true;
                } else if node.depth == d {
                    sum += optical_depth(node.alpha);
                }
            }
            j = node.next;
            steps += 1u;
        }
        if !found {
            break;
        }
        omega += sum;
        let after = transmittance(omega);
        if started {
            offer(&g, d, before);
        } else {
            push_vertex(&g, d, 1.0);
            started = true;
        }
        offer(&g, d, after);
        before = after;
        prev = d;
    }
    if g.open {
        close_segment(&g);
    }
    out_headers[t] = vec2<u32>(base, g.count);
}
