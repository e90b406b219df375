// Exact eye transparency, pass 3: each pixel's list gathered into private arrays, merge-sorted on (depth bits,
// segment) — ties kept in a total order — and composited front to back: H = Σ T_j a_j c_j, T = Π (1 - a_j); output
// (H, 1 - T), blended premultiplied over the opaque image (C = H + T·B). The sort between `template begin` and
// `template end` is written for 64 nodes; the pipeline instantiates it for each size up to the frame's deepest
// pixel (src/render/transparency/sorted.rs replaces `_64` and `64u`) and the `dispatch` line picks the smallest
// that holds the pixel's list, so a pixel pays for the arrays its own depth needs.
#include "common/frame.wgsl"
#include "common/fullscreen.wgsl"
#include "common/eye_node.wgsl"

@group(1) @binding(0) var<storage, read> heads: array<u32>;
@group(1) @binding(1) var<storage, read> nodes: array<EyeNode>;

struct Key {
    depth: u32,
    segment: u32,
    node: u32,
}

fn before(a: Key, b: Key) -> bool {
    return a.depth < b.depth || (a.depth == b.depth && a.segment < b.segment);
}

// template begin
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
// template end

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(i);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = u32(pos.y) * u32(frame.viewport_size.x) + u32(pos.x);
    let head = heads[p];
    var n = 0u;
    var i = head;
    loop {
        if i == 0u {
            break;
        }
        n += 1u;
        i = nodes[i - 1u].next;
    }
    if n == 0u {
        discard;
    }
    return resolve_64(head, min(n, 64u)); // dispatch
}
