// Resolve of occupancy-ordered blending (Sintorn & Assarsson 2009 §3.4): n = the pixel's four slab counts,
// T = (1 - a)^n = exp(-n b), coverage L = 1 - T; with the correction the accumulated colour is rescaled so its
// total weight is L (rgb * L / acc.a). Output (rgb, L), blended premultiplied over the opaque image: rgb + T B.
#include "common/fullscreen.wgsl"
#include "common/visibility.wgsl"
#include "common/occupancy_order_uniforms.wgsl"

@group(0) @binding(0) var accum_tex: texture_2d<f32>;
@group(0) @binding(1) var<storage, read> slab_counts: array<vec4<u32>>;
@group(0) @binding(2) var<uniform> params: OccupancyOrderUniforms;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<u32>(pos.xy);
    let slabs = slab_counts[p.y * textureDimensions(accum_tex).x + p.x];
    let n = slabs.x + slabs.y + slabs.z + slabs.w;
    if n == 0u {
        discard;
    }
    let acc = textureLoad(accum_tex, vec2<i32>(p), 0);
    let t = transmittance(f32(n) * optical_depth(params.hair_alpha));
    let coverage = 1.0 - t;
    var rgb = acc.rgb;
    if params.correction == 1u && acc.a > 1e-12 {
        rgb = rgb * coverage / acc.a;
    }
    return vec4<f32>(rgb, coverage);
}
