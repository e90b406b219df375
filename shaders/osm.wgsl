// Opacity Shadow Maps (Kim & Neumann 2001, as described by Yuksel & Keyser 2008 §2 and Voicu §3): N uniform
// slices over the strands' whole light range [0,1]; a fragment's optical depth goes to its slice and every
// later one, so each stored value is the optical depth accumulated up to the slice's far plane
// (visibility::osm). fs_main: the colour-target build (32 slices per geometry pass); fs_count: the atomic
// build (one geometry pass per band of slices) (common/layer_pass.wgsl).
#include "common/layer_pass.wgsl"
#include "common/osm_uniforms.wgsl"

@group(1) @binding(0) var<uniform> osm: OsmUniforms;

fn osm_slice(f: LayerFragment) -> u32 {
    return slice_index(fragment_depth(f.depth) * f32(osm.slices), osm.slices);
}

@fragment
fn fs_main(f: LayerFragment) -> CumulativeTargets {
    return layer_targets(f, osm_slice(f), osm.slices);
}

@fragment
fn fs_count(f: LayerFragment) {
    layer_count(f, osm_slice(f), osm.slices);
}
