// Exact eye transparency, pass 3: each pixel's list gathered (at most OIT_MAX nodes, substituted when the
// pipeline is built from the frame's deepest pixel), merge-sorted on (depth bits, segment) — ties kept in a total
// order — and composited front to back: H = Σ T_j a_j c_j, T = Π (1 - a_j); output (H, 1 - T), blended
// premultiplied over the opaque image (C = H + T·B).
#include "common/frame.wgsl"
#include "common/fullscreen.wgsl"
#include "common/eye_node.wgsl"

const OIT_MAX: u32 = 64u;

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

// One bottom-up merge pass of runs of `width` from `src` into `dst`.
fn merge_pass(src: ptr<function, array<Key, OIT_MAX>>, dst: ptr<function, array<Key, OIT_MAX>>, n: u32, width: u32) {
    var start = 0u;
    loop {
        if start >= n {
            break;
        }
        let mid = min(start + width, n);
        let end = min(start + 2u * width, n);
        var i = start;
        var j = mid;
        var k = start;
        loop {
            if k >= end {
                break;
            }
            if i < mid && (j >= end || !before((*src)[j], (*src)[i])) {
                (*dst)[k] = (*src)[i];
                i += 1u;
            } else {
                (*dst)[k] = (*src)[j];
                j += 1u;
            }
            k += 1u;
        }
        start = end;
    }
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(i);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = u32(pos.y) * u32(frame.viewport_size.x) + u32(pos.x);
    var a: array<Key, OIT_MAX>;
    var b: array<Key, OIT_MAX>;
    var n = 0u;
    var i = heads[p];
    loop {
        if i == 0u || n >= OIT_MAX {
            break;
        }
        let node = nodes[i - 1u];
        a[n] = Key(bitcast<u32>(node.depth), node.segment, i - 1u);
        n += 1u;
        i = node.next;
    }
    if n == 0u {
        discard;
    }
    var width = 1u;
    var in_a = true;
    loop {
        if width >= n {
            break;
        }
        if in_a {
            merge_pass(&a, &b, n, width);
        } else {
            merge_pass(&b, &a, n, width);
        }
        in_a = !in_a;
        width *= 2u;
    }
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
