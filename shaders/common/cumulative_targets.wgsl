// Colour targets of a light pass that accumulates a per-texel array with additive blending, four entries per
// RGBA32F target and up to 32 per geometry pass (OSM slices, DOM and BOM layers). A fragment adds its optical
// depth to its own entry k and every later one, so each stored entry is the optical depth accumulated up to its
// far end. A pipeline binds as many targets as the array needs; outputs without a target are discarded.

struct CumulativeTargets {
    @location(0) t0: vec4<f32>,
    @location(1) t1: vec4<f32>,
    @location(2) t2: vec4<f32>,
    @location(3) t3: vec4<f32>,
    @location(4) t4: vec4<f32>,
    @location(5) t5: vec4<f32>,
    @location(6) t6: vec4<f32>,
    @location(7) t7: vec4<f32>,
}

// b for the four entries first..first+3 that lie at or behind entry k, 0 for those in front.
fn cumulative4(k: u32, first: u32, b: f32) -> vec4<f32> {
    let e = vec4<u32>(first, first + 1u, first + 2u, first + 3u);
    return select(vec4<f32>(0.0), vec4<f32>(b), e >= vec4<u32>(k));
}

// The 32 entries first..first+31 of one geometry pass.
fn cumulative(k: u32, first: u32, b: f32) -> CumulativeTargets {
    return CumulativeTargets(
        cumulative4(k, first, b),
        cumulative4(k, first + 4u, b),
        cumulative4(k, first + 8u, b),
        cumulative4(k, first + 12u, b),
        cumulative4(k, first + 16u, b),
        cumulative4(k, first + 20u, b),
        cumulative4(k, first + 24u, b),
        cumulative4(k, first + 28u, b),
    );
}
