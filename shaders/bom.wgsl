// Bounding Opacity Maps (Voicu's thesis §5, §5.2), the opacity pass: K layers (1..=32) split each texel's
// range [near, far] (the shared near and far maps, the thesis's start and end depth maps) by the hybrid
// linear/logarithmic split with ratio r. One geometry pass fills all of them: ceil(K/4) RGBA32F targets (array
// layers, 8 render targets of 4 channels at most, thesis §3.4) with additive blending; a fragment adds its
// optical depth to its layer and every later one (visibility::bom, build).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/cumulative_targets.wgsl"
#include "common/visibility.wgsl"
#include "common/bom_uniforms.wgsl"

@group(1) @binding(0) var<uniform> bom: BomUniforms;
@group(1) @binding(1) var bom_near: texture_2d<f32>;
@group(1) @binding(2) var bom_far: texture_2d<f32>;

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

@fragment
fn fs_main(f: LightFragment) -> CumulativeTargets {
    let texel = vec2<i32>(f.clip.xy);
    let near = textureLoad(bom_near, texel, 0).r;
    let far = textureLoad(bom_far, texel, 0).r;
    let z = fragment_depth(f.depth);
    let t = clamp(relative_depth(z, near, far), 0.0, 1.0);
    let r = bom.split_ratio;
    let s = clamp((1.0 - r) * t + r * (log2(1.0 + 254.0 * t) / log2(255.0)), 0.0, 1.0);
    let n = bom.layers;
    let k = slice_index(s * f32(n), n);
    let b = optical_depth(f.alpha);
    return cumulative(k, 0u, b);
}
