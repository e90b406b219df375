// Light-depth pass: strands drawn from the light; blending keeps the nearest (target 0, Min) and furthest
// (target 1, Max) normalised light depth per texel. Every shadow method builds on these two maps.
#include "common/frame.wgsl"

struct VertexIn {
    @location(0) position: vec3<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: f32,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.world_to_light_clip * vec4<f32>(v.position, 1.0);
    out.depth = light_depth(v.position);
    return out;
}

struct Targets {
    @location(0) near: vec4<f32>,
    @location(1) far: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut) -> Targets {
    let d = clamp(in.depth, 0.0, 1.0);
    return Targets(vec4<f32>(d, 0.0, 0.0, 1.0), vec4<f32>(d, 0.0, 0.0, 1.0));
}
