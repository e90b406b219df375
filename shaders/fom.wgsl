// Fourier Opacity Mapping (Jansen & Bavoil 2010): each fragment is a Dirac of strength b = -ln(1 - alpha) at
// its light depth d in [0,1] (the strands' whole fitted range) and adds its Fourier coefficients
// a0 = 2b, ak = 2b cos(2πkd), bk = 2b sin(2πkd), in the order a0, a1, b1, ..., aK, bK, four per RGBA32F
// target. Each geometry pass fills 32 coefficients (8 targets, additive blending); the instance index selects
// the pass (visibility::fom::build).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/cumulative_targets.wgsl"
#include "common/visibility.wgsl"
#include "common/fom_uniforms.wgsl"

@group(1) @binding(0) var<uniform> fom: FomUniforms;

struct FomFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: f32,
    @location(1) alpha: f32,
    // First coefficient this geometry pass writes.
    @location(2) @interpolate(flat) first: u32,
}

@vertex
fn vs_main(v: LightVertexIn, @builtin(instance_index) pass_index: u32) -> FomFragment {
    let l = light_vertex(v);
    return FomFragment(l.clip, l.depth, l.alpha, pass_index * 32u);
}

// Coefficient i of a Dirac of strength b2 / 2 at depth d; 0 beyond the 2K + 1 coefficients.
fn fom_coefficient(i: u32, d: f32, b2: f32) -> f32 {
    let a = fom_angle((i + 1u) / 2u, d);
    let trig = select(sin(a), cos(a), (i & 1u) == 1u);
    return select(0.0, b2 * select(trig, 1.0, i == 0u), i < 2u * fom.terms + 1u);
}

fn fom4(first: u32, d: f32, b2: f32) -> vec4<f32> {
    return vec4<f32>(
        fom_coefficient(first, d, b2),
        fom_coefficient(first + 1u, d, b2),
        fom_coefficient(first + 2u, d, b2),
        fom_coefficient(first + 3u, d, b2),
    );
}

@fragment
// The 8 targets of CumulativeTargets, filled with this pass's coefficients (not cumulative sums).
fn fs_main(f: FomFragment) -> CumulativeTargets {
    let d = fragment_depth(f.depth);
    let b2 = 2.0 * optical_depth(f.alpha);
    let c = f.first;
    return CumulativeTargets(
        fom4(c, d, b2),
        fom4(c + 4u, d, b2),
        fom4(c + 8u, d, b2),
        fom4(c + 12u, d, b2),
        fom4(c + 16u, d, b2),
        fom4(c + 20u, d, b2),
        fom4(c + 24u, d, b2),
        fom4(c + 28u, d, b2),
    );
}
