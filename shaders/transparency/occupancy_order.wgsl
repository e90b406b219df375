// Occupancy-ordered blending (Sintorn & Assarsson 2009 §3.4), the hair pass's entries: each fragment's order
// estimate o from its pixel's eye maps (common/occupancy_estimate.wgsl, the light-space lookup's function) gives
// it the weight w = (1 - a)^o a = exp(-o b) a of the global hair alpha a (b = -ln(1 - a)); it adds (w c, w) to
// the accumulation target (One/One), 32-bit (fs_main) or 16-bit (fs_half) float.
#include "common/visibility.wgsl"
#include "common/occupancy_estimate.wgsl"
#include "common/occupancy_order_uniforms.wgsl"

@group(2) @binding(0) var order_near: texture_2d<f32>;
@group(2) @binding(1) var order_far: texture_2d<f32>;
@group(2) @binding(2) var<storage, read> order_bits: array<vec4<u32>>;
@group(2) @binding(3) var<storage, read> order_slabs: array<vec4<u32>>;
@group(2) @binding(4) var<uniform> order_params: OccupancyOrderUniforms;

fn occupancy_order_weighted(in: VertexOut) -> vec4<f32> {
    let f = shade_hair(in);
    let p = vec2<i32>(f.pixel);
    let i = f.pixel.y * u32(frame.viewport_size.x) + f.pixel.x;
    let near = textureLoad(order_near, p, 0).r;
    let far = textureLoad(order_far, p, 0).r;
    let estimate = occupancy_estimate(near, far, order_bits[i], order_slabs[i], f.depth, order_params.variant);
    let o = max(estimate + order_params.order_bias, 0.0);
    let a = frame.hair_alpha;
    let w = transmittance(o * optical_depth(a)) * a;
    return vec4<f32>(w * f.color, w);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return occupancy_order_weighted(in);
}

@fragment
fn fs_half(in: VertexOut) -> @location(0) vec4<f32> {
    return occupancy_order_weighted(in);
}
