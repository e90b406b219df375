// Shadow method "dom": Deep Opacity Maps lookup (Yuksel & Keyser 2008 §2-3). V = 1 up to the texel's nearest
// strand z0 (hair_depth_near), then linear interpolation of the accumulated optical depth between the layer
// boundaries z0 + d_k (scaled to reach the far depth, hair_depth_far, by the stretch option); beyond the last
// layer the last layer's value (visibility::dom::visibility, expression for expression).

#include "common/scene_bindings.wgsl"
#include "common/visibility.wgsl"
#include "common/dom_uniforms.wgsl"

@group(1) @binding(0) var dom_layers: texture_2d_array<f32>;
@group(1) @binding(1) var<uniform> dom_lookup: DomUniforms;

fn dom_lookup_end(k: u32) -> f32 {
    return dom_lookup.ends[k / 4u][k % 4u];
}

fn dom_layer(texel: vec2<i32>, k: u32) -> f32 {
    return textureLoad(dom_layers, texel, i32(k / 4u), 0)[k % 4u] * dom_lookup.unit;
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let dz = z - near;
    if !(dz > 0.0) {
        return 1.0;
    }
    let n = dom_lookup.layers;
    var scale = 1.0;
    if dom_lookup.beyond == 2u {
        let far = textureLoad(hair_depth_far, texel, 0).r;
        scale = max(1.0, (far - near) / dom_lookup_end(n - 1u));
    }
    var k = n;
    for (var i = 0u; i < n; i++) {
        if dz < scale * dom_lookup_end(i) {
            k = i;
            break;
        }
    }
    if k == n {
        return transmittance(dom_layer(texel, n - 1u));
    }
    let lo = select(0.0, scale * dom_lookup_end(max(k, 1u) - 1u), k > 0u);
    let f = (dz - lo) / (scale * dom_lookup_end(k) - lo);
    let prev = select(0.0, dom_layer(texel, max(k, 1u) - 1u), k > 0u);
    let l = dom_layer(texel, k);
    return transmittance(lerp_up(prev, l, f));
}
