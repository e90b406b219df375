// Moment shadow maps for translucent occluders (Peters & Klein 2015; MBOIT, Münstermann et al. 2018): one
// additive geometry pass into two RGBA32F layers, layer 0 = (b_0, b_1, b_2, b_3), layer 1 = (b_4, b_5, b_6, 0)
// with b_j = sum of b x^j, x = 2z - 1 (visibility::msm::build, expression for expression; b_5 = b_6 = 0 with 4
// moments).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/visibility.wgsl"
#include "common/msm_uniforms.wgsl"

@group(1) @binding(0) var<uniform> msm: MsmUniforms;

struct MsmTargets {
    @location(0) low: vec4<f32>,
    @location(1) high: vec4<f32>,
}

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

@fragment
fn fs_main(f: LightFragment) -> MsmTargets {
    let b = optical_depth(f.alpha);
    let x = fragment_depth(f.depth) * 2.0 - 1.0;
    let x2 = x * x;
    let x4 = x2 * x2;
    let six = select(0.0, 1.0, msm.moments == 6u);
    return MsmTargets(
        vec4<f32>(b, x * b, x2 * b, (x2 * x) * b),
        vec4<f32>(x4 * b, ((x4 * x) * b) * six, ((x4 * x2) * b) * six, 0.0),
    );
}
