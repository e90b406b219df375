// Shadow method "osm": Opacity Shadow Maps lookup, linear interpolation of the accumulated optical depth
// between the two slice planes around z (visibility::osm::visibility, expression for expression).

#include "common/visibility.wgsl"
#include "common/osm_uniforms.wgsl"

@group(1) @binding(0) var osm_planes: texture_2d_array<f32>;
@group(1) @binding(1) var<uniform> osm_lookup: OsmUniforms;

fn osm_plane(texel: vec2<i32>, i: u32) -> f32 {
    return textureLoad(osm_planes, texel, i32(i / 4u), 0)[i % 4u] * osm_lookup.unit;
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let n = osm_lookup.slices;
    let x = z * f32(n);
    let j = slice_index(x, n);
    let f = clamp(x - f32(j), 0.0, 1.0);
    let s = osm_plane(texel, j);
    let prev = select(0.0, osm_plane(texel, max(j, 1u) - 1u), j > 0u);
    return transmittance(lerp_up(prev, s, f));
}
