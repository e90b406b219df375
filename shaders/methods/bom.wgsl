// Shadow method "bom": Bounding Opacity Maps lookup (Voicu's thesis §5). V = 1 up to the texel's start depth
// (hair_depth_near), then linear interpolation of the accumulated optical depth between the layer boundaries in
// the split coordinate s of the range [near, far] (hair_depth_far) (visibility::bom::visibility, expression for
// expression).

#include "common/scene_bindings.wgsl"
#include "common/visibility.wgsl"
#include "common/bom_uniforms.wgsl"

@group(1) @binding(0) var bom_layers: texture_2d_array<f32>;
@group(1) @binding(1) var<uniform> bom_lookup: BomUniforms;

fn bom_layer(texel: vec2<i32>, k: u32) -> f32 {
    return textureLoad(bom_layers, texel, i32(k / 4u), 0)[k % 4u] * bom_lookup.unit;
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let far = textureLoad(hair_depth_far, texel, 0).r;
    let t_unclamped = relative_depth(z, near, far);
    if !(t_unclamped > 0.0) {
        return 1.0;
    }
    let t = clamp(t_unclamped, 0.0, 1.0);
    let r = bom_lookup.split_ratio;
    let s = clamp((1.0 - r) * t + r * (log2(1.0 + 254.0 * t) / log2(255.0)), 0.0, 1.0);
    let n = bom_lookup.layers;
    let x = s * f32(n);
    let j = slice_index(x, n);
    let f = clamp(x - f32(j), 0.0, 1.0);
    let prev = select(0.0, bom_layer(texel, max(j, 1u) - 1u), j > 0u);
    let l = bom_layer(texel, j);
    return transmittance(lerp_up(prev, l, f));
}
