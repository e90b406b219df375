// Moment-based OIT (Münstermann et al. 2018), pass 1: every hair fragment the meshes do not hide (fixed-function
// Less, no depth write) adds its absorbance b = -ln(1 - a) and b x^j, x = 2z - 1, to two additive RGBA32F targets,
// low = (b_0, b_1, b_2, b_3), high = (b_4, b_5, b_6, 0) (visibility::msm::build over the normalised depths;
// b_5 = b_6 = 0 with 4 moments), exactly as the moment shadow map's light pass (msm.wgsl).
#include "common/eye_vertex.wgsl"
#include "common/mboit.wgsl"

@group(1) @binding(0) var<uniform> mboit: MboitUniforms;

struct MomentTargets {
    @location(0) low: vec4<f32>,
    @location(1) high: vec4<f32>,
}

@vertex
fn vs_main(v: EyeVertexIn) -> EyePoint {
    return eye_vertex(v);
}

@fragment
fn fs_main(in: EyePoint) -> MomentTargets {
    let b = optical_depth(in.alpha);
    let x = mboit_depth(mboit, abs(eye_depth(in.world))) * 2.0 - 1.0;
    let x2 = x * x;
    let x4 = x2 * x2;
    let six = select(0.0, 1.0, mboit.moments == 6u);
    return MomentTargets(
        vec4<f32>(b, x * b, x2 * b, (x2 * x) * b),
        vec4<f32>(x4 * b, ((x4 * x) * b) * six, ((x4 * x2) * b) * six, 0.0),
    );
}
