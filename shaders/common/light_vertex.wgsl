// The vertex stage every light-space pass shares, so that all of them (the light-depth pass, the reference and
// every method) see bitwise the same fragments: same position, same interpolated depth and alpha. A pass's
// `vs_main` takes a `LightVertexIn` and calls `light_vertex`; the caster the pipeline is built for defines both.
#include "common/frame.wgsl"

struct LightFragment {
    @builtin(position) clip: vec4<f32>,
    // Normalised light depth (see light_depth()).
    @location(0) depth: f32,
    // Opacity: strand_alpha() of the point over one light texel at its depth.
    @location(1) alpha: f32,
    // Segment id: the index of the segment's first point (the provoking vertex of a LineList segment).
    @location(2) @interpolate(flat) segment: u32,
}

// `LightVertexIn` and `light_vertex(v: LightVertexIn) -> LightFragment`: the vertex input and stage of the
// light caster the pass is built for (`shaders/casters/<caster>.wgsl`, `render::caster`).
#include_caster

// The depth a light-space fragment stores: clamped to [0,1]; abs() turns -0.0 into +0.0 so the bit pattern of
// the depth orders like the value (the depth peel compares bits).
fn fragment_depth(depth: f32) -> f32 {
    return abs(clamp(depth, 0.0, 1.0));
}

// Linear index of a light-map texel.
fn texel_index(clip: vec4<f32>) -> u32 {
    let p = vec2<u32>(clip.xy);
    return p.y * frame.light_map_resolution + p.x;
}
