// Shadow method "msm": moment shadow map lookup, the moment bound of common/msm_bound.wgsl (visibility::msm,
// expression for expression) on the texel's moments with the method's parameters.
//
// Map: RGBA32F array, layer 0 = (b_0, b_1, b_2, b_3), layer 1 = (b_4, b_5, b_6, 0); x = 2z - 1.

#include "common/msm_bound.wgsl"
#include "common/msm_uniforms.wgsl"

@group(1) @binding(0) var msm_moments: texture_2d_array<f32>;
@group(1) @binding(1) var<uniform> msm_lookup: MsmUniforms;

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let lo = textureLoad(msm_moments, texel, 0, 0);
    let hi = textureLoad(msm_moments, texel, 1, 0);
    return msm_bound_visibility(lo, hi, z, msm_lookup.moments, msm_lookup.bias, msm_lookup.overestimation);
}
