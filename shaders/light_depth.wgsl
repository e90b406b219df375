// Light-depth pass: strands drawn from the light; blending keeps the nearest (target 0, Min) and furthest
// (target 1, Max) normalised light depth per texel. Every shadow method builds on these two maps.
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

struct Targets {
    @location(0) near: vec4<f32>,
    @location(1) far: vec4<f32>,
}

@fragment
fn fs_main(f: LightFragment) -> Targets {
    let d = fragment_depth(f.depth);
    return Targets(vec4<f32>(d, 0.0, 0.0, 1.0), vec4<f32>(d, 0.0, 0.0, 1.0));
}
