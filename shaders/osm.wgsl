// Opacity Shadow Maps (Kim & Neumann 2001, as described by Yuksel & Keyser 2008 §2 and Voicu §3): N uniform
// slices over the strands' whole light range [0,1]. Each geometry pass fills 32 slices: 8 RGBA32F targets
// (array layers) with additive blending; a fragment adds its optical depth to its slice and every later one,
// so each stored value is the optical depth accumulated up to the slice's far plane (visibility::osm).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"

struct OsmUniforms {
    slices: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(1) @binding(0) var<uniform> osm: OsmUniforms;

struct OsmFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: f32,
    @location(1) alpha: f32,
    // First slice this geometry pass writes (the instance index selects the pass).
    @location(2) @interpolate(flat) first_slice: u32,
}

@vertex
fn vs_main(v: LightVertexIn, @builtin(instance_index) pass_index: u32) -> OsmFragment {
    let l = light_vertex(v);
    return OsmFragment(l.clip, l.depth, l.alpha, pass_index * 32u);
}

struct Slices {
    @location(0) s0: vec4<f32>,
    @location(1) s1: vec4<f32>,
    @location(2) s2: vec4<f32>,
    @location(3) s3: vec4<f32>,
    @location(4) s4: vec4<f32>,
    @location(5) s5: vec4<f32>,
    @location(6) s6: vec4<f32>,
    @location(7) s7: vec4<f32>,
}

// b for the four slices first..first+3 that lie at or behind the fragment's slice i, 0 for those in front.
fn contribution(i: u32, first: u32, b: f32) -> vec4<f32> {
    let s = vec4<u32>(first, first + 1u, first + 2u, first + 3u);
    return select(vec4<f32>(0.0), vec4<f32>(b), s >= vec4<u32>(i));
}

@fragment
fn fs_main(f: OsmFragment) -> Slices {
    let n = osm.slices;
    let i = min(u32(max(floor(fragment_depth(f.depth) * f32(n)), 0.0)), n - 1u);
    let b = optical_depth(f.alpha);
    let s = f.first_slice;
    return Slices(
        contribution(i, s, b),
        contribution(i, s + 4u, b),
        contribution(i, s + 8u, b),
        contribution(i, s + 12u, b),
        contribution(i, s + 16u, b),
        contribution(i, s + 20u, b),
        contribution(i, s + 24u, b),
        contribution(i, s + 28u, b),
    );
}
