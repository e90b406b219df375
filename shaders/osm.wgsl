// Opacity Shadow Maps (Kim & Neumann 2001, as described by Yuksel & Keyser 2008 §2 and Voicu §3): N uniform
// slices over the strands' whole light range [0,1]. Each geometry pass fills 32 slices: 8 RGBA32F targets
// (array layers) with additive blending; a fragment adds its optical depth to its slice and every later one,
// so each stored value is the optical depth accumulated up to the slice's far plane (visibility::osm).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/cumulative_targets.wgsl"
#include "common/visibility.wgsl"
#include "common/osm_uniforms.wgsl"

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

@fragment
fn fs_main(f: OsmFragment) -> CumulativeTargets {
    let n = osm.slices;
    let i = slice_index(fragment_depth(f.depth) * f32(n), n);
    return cumulative(i, f.first_slice, optical_depth(f.alpha));
}
