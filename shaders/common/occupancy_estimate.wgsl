// The order estimate of Occupancy Maps (Sintorn & Assarsson 2009, §3.2) over one texel's maps, shared by the
// light-space lookup (methods/occupancy.wgsl) and the eye-space technique (transparency/occupancy_order.wgsl):
// visibility::occupancy::order, expression for expression.
#include "common/visibility.wgsl"

// Estimated number of the texel's fragments in front of depth z: depth range [near, far], the 128-slice bitmap
// `occ` (slice s is bit s & 31 of word s >> 5) and the slab counts `slabs`; `variant` 0: slab map, 1: occupancy
// only (the total count in slabs[0]). The count in z's slab is interpolated inside z's slice.
fn occupancy_estimate(near: f32, far: f32, occ: vec4<u32>, slabs: vec4<u32>, z: f32, variant: u32) -> f32 {
    let d = relative_depth(z, near, far);
    if !(d > 0.0) {
        return 0.0;
    }
    let x = d * 128.0;
    let s = slice_index(x, 128u);
    let frac = clamp(x - f32(s), 0.0, 1.0);
    let w = s >> 5u;
    let bit = s & 31u;
    let own = (occ[w] >> bit) & 1u;
    let before_in_word = countOneBits(occ[w] & ((1u << bit) - 1u));
    var base = 0u;
    var count = slabs[0];
    var bits = countOneBits(occ[w]);
    var before = before_in_word;
    if variant == 1u {
        let ones = countOneBits(occ);
        bits = ones.x + ones.y + ones.z + ones.w;
        let earlier = select(vec4<u32>(0u), ones, vec4<u32>(0u, 1u, 2u, 3u) < vec4<u32>(w));
        before = earlier.x + earlier.y + earlier.z + earlier.w + before_in_word;
    } else {
        let earlier = select(vec4<u32>(0u), slabs, vec4<u32>(0u, 1u, 2u, 3u) < vec4<u32>(w));
        base = earlier.x + earlier.y + earlier.z + earlier.w;
        count = slabs[w];
    }
    var in_slab = 0.0;
    if bits > 0u {
        let f = f32(count);
        in_slab = min(f * (f32(before) + f32(own) * frac) / f32(bits), f);
    }
    return f32(base) + in_slab;
}
