// Bounding Opacity Maps (Voicu's thesis §5, §5.2), the opacity pass: K layers (1..=32) split each texel's
// range [near, far] (the shared near and far maps, the thesis's start and end depth maps) by the hybrid
// linear/logarithmic split with ratio r; a fragment's optical depth goes to its layer and every later one
// (visibility::bom, build). fs_main: the colour-target build (ceil(K/4) RGBA32F targets in one pass, 8 at
// most, thesis §3.4); fs_count: the atomic build (common/layer_pass.wgsl).
#include "common/layer_pass.wgsl"
#include "common/bom_uniforms.wgsl"

@group(1) @binding(0) var<uniform> bom: BomUniforms;
@group(1) @binding(1) var bom_near: texture_2d<f32>;
@group(1) @binding(2) var bom_far: texture_2d<f32>;

fn bom_layer_of(f: LayerFragment) -> u32 {
    let texel = vec2<i32>(f.clip.xy);
    let near = textureLoad(bom_near, texel, 0).r;
    let far = textureLoad(bom_far, texel, 0).r;
    let z = fragment_depth(f.depth);
    let t = clamp(relative_depth(z, near, far), 0.0, 1.0);
    let r = bom.split_ratio;
    let s = clamp((1.0 - r) * t + r * (log2(1.0 + 254.0 * t) / log2(255.0)), 0.0, 1.0);
    return slice_index(s * f32(bom.layers), bom.layers);
}

@fragment
fn fs_main(f: LayerFragment) -> CumulativeTargets {
    return layer_targets(f, bom_layer_of(f), bom.layers);
}

@fragment
fn fs_count(f: LayerFragment) {
    layer_count(f, bom_layer_of(f), bom.layers);
}
