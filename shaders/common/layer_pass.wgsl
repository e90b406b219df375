// The light pass shared by the opacity-layer family (OSM, DOM, BOM; methods::opacity_layers,
// visibility::opacity_layers): one vertex stage (the shared light vertex plus the pass index) and the two ways
// a fragment's optical depth b reaches its entry k of N:
// - layer_targets: the colour-target build, 32 entries per geometry pass (8 RGBA32F targets, additive
//   blending); pass p writes entries 32p..32p+31, and b goes to entry k and every later one;
// - layer_count: the atomic build, one geometry pass per band of entries; b is quantised to u32 fixed point
//   and added to the (texel, k) counter with a storage atomic, saturating (layer_resolve.wgsl sums them up).
//   A texel's counters lie side by side (texel * band + k - first), so that the resolve reads them in order.
// The method's group 1: its uniform (0), the near (1) and far (2) maps, and for the atomic build the counters
// (3) and their uniforms (4).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/cumulative_targets.wgsl"
#include "common/visibility.wgsl"
#include "common/layer_build_uniforms.wgsl"

@group(1) @binding(3) var<storage, read_write> layer_counters: array<atomic<u32>>;
@group(1) @binding(4) var<uniform> layer_build: LayerBuildUniforms;

struct LayerFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: f32,
    @location(1) alpha: f32,
    // The geometry pass (the instance index): a group of 32 entries, or a band of the atomic build.
    @location(2) @interpolate(flat) pass_index: u32,
}

@vertex
fn vs_main(v: LightVertexIn, @builtin(instance_index) pass_index: u32) -> LayerFragment {
    let l = light_vertex(v);
    return LayerFragment(l.clip, l.depth, l.alpha, pass_index);
}

// The colour-target build: b to entry k and every later one of this pass's 32; k >= n drops the fragment.
fn layer_targets(f: LayerFragment, k: u32, n: u32) -> CumulativeTargets {
    if k >= n {
        discard;
    }
    return cumulative(k, f.pass_index * 32u, optical_depth(f.alpha));
}

// b in fixed point (visibility::opacity_layers::quantise).
fn quantised_optical_depth(alpha: f32) -> u32 {
    return u32(optical_depth(alpha) * LAYER_FIXED_POINT_SCALE + 0.5);
}

// The atomic build: the quantised b to the (texel, k) counter when k lies in this pass's band; every add that
// ends above the cap is followed by its own min, so a counter ends at min(sum, cap).
fn layer_count(f: LayerFragment, k: u32, n: u32) {
    let first = f.pass_index * layer_build.band;
    if k >= n || k < first || k - first >= layer_build.band {
        return;
    }
    let q = quantised_optical_depth(f.alpha);
    let i = texel_index(f.clip) * layer_build.band + k - first;
    let old = atomicAdd(&layer_counters[i], q);
    if old + q > LAYER_SATURATION {
        atomicMin(&layer_counters[i], LAYER_SATURATION);
    }
}
