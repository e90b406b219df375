// Moment-based OIT (Münstermann et al. 2018), pass 2 (the hair entry, pasted into hair.wgsl): every shaded
// fragment reconstructs the transmittance T(z) of what lies in front of it from its pixel's moments (the moment
// bound, common/msm_bound.wgsl) and adds (a c T, a T) to an additive RGBA32F target; transparency/mboit_resolve.wgsl
// normalises it.
#include "common/msm_bound.wgsl"
#include "common/mboit.wgsl"

@group(2) @binding(0) var<uniform> mboit: MboitUniforms;
@group(2) @binding(1) var mboit_low: texture_2d<f32>;
@group(2) @binding(2) var mboit_high: texture_2d<f32>;

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let f = shade_hair(in);
    let p = vec2<i32>(f.pixel);
    let lo = textureLoad(mboit_low, p, 0);
    let hi = textureLoad(mboit_high, p, 0);
    let z = mboit_depth(mboit, abs(f.depth));
    let w = f.alpha * msm_bound_visibility(lo, hi, z, mboit.moments, mboit.bias, mboit.overestimation);
    return vec4<f32>(f.color * w, w);
}
