// Hybrid fur, the typed resolve (Andersen et al. 2016 §3.3; CPU model src/fur/blend.rs): each pixel's typed
// list (explicit guard-hair, shell or virtual fragments) gathered, merge-sorted on (depth bits, id, kind) and
// composited front to back with "over": H = Σ T_j a_j c_j, T = Π (1 - a_j); output (H, 1 - T), blended
// premultiplied over the opaque meshes. Two inspection views replace the colours: each fragment's by its type's,
// or the whole pixel's by its fragment count. Simplified blending (eq. 4) first lowers each shell fragment's alpha by
// exp(-a d) (`transmittance(a d)`) for every explicit fragment a distance d behind it, up to the next shell fragment. The sort is
// instantiated per size by the shared list resolve (`common/list_resolve.wgsl`), as the exact reference's.
#include "common/list_resolve.wgsl"
#include "common/visibility.wgsl"

// Mirrors `FurResolveUniforms` in src/render/fur/typed.rs.
struct FurResolveUniforms {
    // 0: naive, 1: simplified, 2: virtual.
    blending: u32,
    // Eq. (4)'s a, per world unit.
    attenuation: f32,
    // 0: shaded, 1: fragments coloured by type, 2: fragments per pixel.
    view: u32,
    // The frame's deepest list (the fragments-per-pixel view's full scale).
    deepest: u32,
}

@group(1) @binding(2) var<uniform> fur: FurResolveUniforms;

const EXPLICIT: u32 = 0u;
const SHELL: u32 = 1u;

// The type view's colours (explicit, shell, virtual); mirrored by `TYPE_COLOURS` in src/fur/blend.rs.
fn type_colour(kind: u32) -> vec3<f32> {
    switch kind {
        case 0u: {
            return vec3<f32>(1.0, 0.8, 0.1);
        }
        case 1u: {
            return vec3<f32>(0.1, 0.4, 1.0);
        }
        default: {
            return vec3<f32>(0.1, 0.9, 0.8);
        }
    }
}

// The fragments-per-pixel view's colour ramp (blue, through green, to red at the frame's deepest list).
fn count_colour(n: u32) -> vec3<f32> {
    let x = f32(n) / f32(max(fur.deepest, 1u));
    return clamp(vec3<f32>(2.0 * x - 1.0, 1.0 - abs(2.0 * x - 1.0), 1.0 - 2.0 * x), vec3<f32>(0.0), vec3<f32>(1.0));
}

struct Key {
    depth: u32,
    segment: u32,
    kind: u32,
    node: u32,
}

fn before(a: Key, b: Key) -> bool {
    if a.depth != b.depth {
        return a.depth < b.depth;
    }
    if a.segment != b.segment {
        return a.segment < b.segment;
    }
    return a.kind < b.kind;
}

#sort_sizes begin
#include "common/eye_sort.wgsl"

// Node of the `k`-th key of the sorted list.
fn sorted_node_64(a: ptr<function, array<Key, 64u>>, b: ptr<function, array<Key, 64u>>, in_a: bool, k: u32) -> EyeNode {
    if in_a {
        return nodes[(*a)[k].node];
    }
    return nodes[(*b)[k].node];
}

// The composite of the `n` nodes of the list starting at `head`, sorted.
fn resolve_64(head: u32, n: u32) -> vec4<f32> {
    var a: array<Key, 64u>;
    var b: array<Key, 64u>;
    var i = head;
    for (var k = 0u; k < n; k += 1u) {
        let node = nodes[i - 1u];
        a[k] = Key(bitcast<u32>(node.depth), node.segment, node.kind, i - 1u);
        i = node.next;
    }
    let in_a = sort_64(&a, &b, n);
    if fur.view == 2u {
        return vec4<f32>(count_colour(n), 1.0);
    }
    var h = vec3<f32>(0.0);
    var t = 1.0;
    for (var k = 0u; k < n; k += 1u) {
        let node = sorted_node_64(&a, &b, in_a, k);
        var alpha = node.alpha;
        if fur.blending == 1u && node.kind == SHELL {
            var sub = 0.0;
            for (var j = k + 1u; j < n; j += 1u) {
                let e = sorted_node_64(&a, &b, in_a, j);
                if e.kind == SHELL {
                    break;
                }
                if e.kind == EXPLICIT {
                    sub += transmittance(fur.attenuation * (e.depth - node.depth) * frame.camera_distance);
                }
            }
            alpha = clamp(alpha - sub, 0.0, 1.0);
        }
        var c = vec3<f32>(node.r, node.g, node.b);
        if fur.view == 1u {
            c = type_colour(node.kind);
        }
        h += t * alpha * c;
        t *= 1.0 - alpha;
    }
    return vec4<f32>(h, 1.0 - t);
}
#sort_sizes end
