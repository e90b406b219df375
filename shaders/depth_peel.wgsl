// Light-space depth peeling: the exact reference of Sintorn & Assarsson Fig. 5, layer by layer. Fragments are
// ordered by the key (depth bits, segment id + 1): depth ties between different segments are peeled one after
// the other instead of one of them being lost to a strict depth test. Each layer takes three geometry passes
// (nearest depth after the previous key, then the smallest segment at that depth, then that fragment's alpha)
// and one compute pass that advances the per-texel key.
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"

const NONE: u32 = 0xffffffffu;

// Key of the last peeled fragment per texel: (depth bits, segment + 1); (0, 0) before the first layer.
@group(1) @binding(0) var<storage, read_write> previous: array<vec2<u32>>;
@group(1) @binding(1) var<storage, read_write> candidate_depth: array<atomic<u32>>;
@group(1) @binding(2) var<storage, read_write> candidate_segment: array<atomic<u32>>;
@group(1) @binding(3) var<storage, read_write> candidate_alpha: array<f32>;
// This layer per texel: (depth bits, segment, alpha bits, 1 if a fragment was peeled).
@group(1) @binding(4) var<storage, read_write> layer: array<vec4<u32>>;
// [0]: texels that peeled a fragment in this layer.
@group(1) @binding(5) var<storage, read_write> peeled: array<atomic<u32>, 4>;

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

fn after_previous(t: u32, depth_bits: u32, segment1: u32) -> bool {
    let p = previous[t];
    return depth_bits > p.x || (depth_bits == p.x && segment1 > p.y);
}

@fragment
fn fs_depth(f: LightFragment) {
    let t = texel_index(f.clip);
    let d = bitcast<u32>(fragment_depth(f.depth));
    if after_previous(t, d, f.segment + 1u) {
        atomicMin(&candidate_depth[t], d);
    }
}

@fragment
fn fs_segment(f: LightFragment) {
    let t = texel_index(f.clip);
    let d = bitcast<u32>(fragment_depth(f.depth));
    if d == atomicLoad(&candidate_depth[t]) && after_previous(t, d, f.segment + 1u) {
        atomicMin(&candidate_segment[t], f.segment + 1u);
    }
}

@fragment
fn fs_alpha(f: LightFragment) {
    let t = texel_index(f.clip);
    let d = bitcast<u32>(fragment_depth(f.depth));
    if d == atomicLoad(&candidate_depth[t]) && f.segment + 1u == atomicLoad(&candidate_segment[t]) {
        candidate_alpha[t] = f.alpha;
    }
}

@compute @workgroup_size(64)
fn cs_advance(@builtin(global_invocation_id) id: vec3<u32>) {
    let t = id.x;
    if t >= arrayLength(&previous) {
        return;
    }
    let d = atomicLoad(&candidate_depth[t]);
    if d == NONE {
        layer[t] = vec4<u32>(0u);
    } else {
        let s = atomicLoad(&candidate_segment[t]);
        previous[t] = vec2<u32>(d, s);
        layer[t] = vec4<u32>(d, s - 1u, bitcast<u32>(candidate_alpha[t]), 1u);
        atomicAdd(&peeled[0], 1u);
    }
    atomicStore(&candidate_depth[t], NONE);
    atomicStore(&candidate_segment[t], NONE);
}
