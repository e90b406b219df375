// Exact eye transparency, pass 3: each pixel's list gathered into private arrays, merge-sorted on (depth bits,
// segment) — ties kept in a total order — and composited front to back: H = Σ T_j a_j c_j, T = Π (1 - a_j); output
// (H, 1 - T), blended premultiplied over the opaque image (C = H + T·B). The sort is written for 64 nodes and
// instantiated per sort size by the shared list resolve (`common/list_resolve.wgsl`).
#include "common/list_resolve.wgsl"

struct Key {
    depth: u32,
    segment: u32,
    node: u32,
}

fn before(a: Key, b: Key) -> bool {
    return a.depth < b.depth || (a.depth == b.depth && a.segment < b.segment);
}

#sort_sizes begin
#include "common/eye_sort.wgsl"

// The composite of the `n` nodes of the list starting at `head`, sorted.
fn resolve_64(head: u32, n: u32) -> vec4<f32> {
    var a: array<Key, 64u>;
    var b: array<Key, 64u>;
    var i = head;
    for (var k = 0u; k < n; k += 1u) {
        let node = nodes[i - 1u];
        a[k] = Key(bitcast<u32>(node.depth), node.segment, i - 1u);
        i = node.next;
    }
    let in_a = sort_64(&a, &b, n);
    var h = vec3<f32>(0.0);
    var t = 1.0;
    for (var k = 0u; k < n; k += 1u) {
        var key: Key;
        if in_a {
            key = a[k];
        } else {
            key = b[k];
        }
        let node = nodes[key.node];
        h += t * node.alpha * vec3<f32>(node.r, node.g, node.b);
        t *= 1.0 - node.alpha;
    }
    return vec4<f32>(h, 1.0 - t);
}
#sort_sizes end
