// The light pass shared by the opacity-layer family (OSM, DOM, BOM; methods::opacity_layers,
// visibility::opacity_layers): one vertex stage (the shared light vertex plus the pass index) and the two ways
// a fragment's optical depth b reaches its entry k of N:
// - layer_targets: the colour-target build, 32 entries per geometry pass (8 RGBA32F targets, additive
//   blending); pass p writes entries 32p..32p+31, and b goes to entry k and every later one;
// - layer_count: the atomic build, one geometry pass per band of entries; b is quantised to u32 fixed point
//   and added to the (texel, k) counter with a storage atomic, saturating (layer_resolve.wgsl sums them up).
//   The band's entries are cut into runs (methods::opacity_layers::CounterLayout): within a run a texel's
//   counters lie side by side, texel after texel, so that the resolve of a run reads one block in order; a
//   page (a storage binding) holds runs_per_page whole runs, and a band up to four pages.
// The method's group 1: its uniform (0), the near (1) and far (2) maps, and for the atomic build the counters'
// pages (3, 5, 6, 7) and their uniforms (4).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/cumulative_targets.wgsl"
#include "common/visibility.wgsl"
#include "common/layer_build_uniforms.wgsl"

@group(1) @binding(3) var<storage, read_write> layer_counters: array<atomic<u32>>;
@group(1) @binding(4) var<uniform> layer_build: LayerBuildUniforms;
@group(1) @binding(5) var<storage, read_write> layer_counters_1: array<atomic<u32>>;
@group(1) @binding(6) var<storage, read_write> layer_counters_2: array<atomic<u32>>;
@group(1) @binding(7) var<storage, read_write> layer_counters_3: array<atomic<u32>>;

// Whether the band's counters span more than one run, and more than one page: the count pipelines are made
// with each (methods::opacity_layers), so that a band of one run finds its counter without a division and one
// of one page selects no page.
override layer_runs: bool = true;
override layer_paged: bool = true;

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
    let band_end = min(first + layer_build.band, n);
    if !layer_runs {
        let i = texel_index(f.clip) * (band_end - first) + k - first;
        let old = atomicAdd(&layer_counters[i], q);
        if old + q > LAYER_SATURATION {
            atomicMin(&layer_counters[i], LAYER_SATURATION);
        }
        return;
    }
    // Run r of the band, of `len` entries, in page r / runs_per_page.
    let run = layer_build.run;
    let r = (k - first) / run;
    let run_first = first + r * run;
    let len = min(run, band_end - run_first);
    let texels = layer_build.resolution * layer_build.resolution;
    let i = (r % layer_build.runs_per_page) * texels * run + texel_index(f.clip) * len + k - run_first;
    if !layer_paged {
        let old = atomicAdd(&layer_counters[i], q);
        if old + q > LAYER_SATURATION {
            atomicMin(&layer_counters[i], LAYER_SATURATION);
        }
        return;
    }
    var old: u32;
    switch r / layer_build.runs_per_page {
        case 0u: {
            old = atomicAdd(&layer_counters[i], q);
        }
        case 1u: {
            old = atomicAdd(&layer_counters_1[i], q);
        }
        case 2u: {
            old = atomicAdd(&layer_counters_2[i], q);
        }
        default: {
            old = atomicAdd(&layer_counters_3[i], q);
        }
    }
    if old + q > LAYER_SATURATION {
        switch r / layer_build.runs_per_page {
            case 0u: {
                atomicMin(&layer_counters[i], LAYER_SATURATION);
            }
            case 1u: {
                atomicMin(&layer_counters_1[i], LAYER_SATURATION);
            }
            case 2u: {
                atomicMin(&layer_counters_2[i], LAYER_SATURATION);
            }
            default: {
                atomicMin(&layer_counters_3[i], LAYER_SATURATION);
            }
        }
    }
}
