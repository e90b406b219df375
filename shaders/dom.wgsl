// Deep Opacity Maps (Yuksel & Keyser 2008 §3), the opacity pass: K layers (1..=16) behind each texel's nearest
// strand depth z0 (the shared near map), layer k from z0 + d_(k-1) to z0 + d_k; a fragment's optical depth
// goes to its layer and every later one, so each stored value is the optical depth accumulated up to the
// layer's far end (visibility::dom, build). fs_main: the colour-target build (ceil(K/4) RGBA32F targets in
// one pass); fs_count: the atomic build (common/layer_pass.wgsl).
#include "common/layer_pass.wgsl"
#include "common/dom_uniforms.wgsl"

@group(1) @binding(0) var<uniform> dom: DomUniforms;
@group(1) @binding(1) var dom_near: texture_2d<f32>;
@group(1) @binding(2) var dom_far: texture_2d<f32>;

fn dom_end(k: u32) -> f32 {
    return dom.ends[k / 4u][k % 4u];
}

// The fragment's layer; K when it lies beyond the last layer and the option ignores it.
fn dom_layer_of(f: LayerFragment) -> u32 {
    let texel = vec2<i32>(f.clip.xy);
    let near = textureLoad(dom_near, texel, 0).r;
    let n = dom.layers;
    // The stretch scales every d_k to reach the texel's far depth; only it reads the far map.
    var scale = 1.0;
    if dom.beyond == 2u {
        let far = textureLoad(dom_far, texel, 0).r;
        scale = max(1.0, (far - near) / dom_end(n - 1u));
    }
    let dz = fragment_depth(f.depth) - near;
    // The first layer whose far end lies beyond the fragment; n when none does.
    var k = n;
    for (var i = 0u; i < n; i++) {
        if dz < scale * dom_end(i) {
            k = i;
            break;
        }
    }
    if k == n && dom.beyond != 0u {
        k = n - 1u;
    }
    return k;
}

@fragment
fn fs_main(f: LayerFragment) -> CumulativeTargets {
    return layer_targets(f, dom_layer_of(f), dom.layers);
}

@fragment
fn fs_count(f: LayerFragment) {
    layer_count(f, dom_layer_of(f), dom.layers);
}
