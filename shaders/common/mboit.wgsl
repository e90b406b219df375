// Moment-based OIT's uniforms and depth, declared once for its moment pass and its hair entry. Mirrors
// `render::transparency::mboit::MboitUniforms` (a test compares the layouts).
#include "common/visibility.wgsl"

struct MboitUniforms {
    // The frame's eye depth range [near, far] (ModelContext::depth_range).
    near: f32,
    far: f32,
    // Power moments beyond b_0: 4 or 6.
    moments: u32,
    // Moment bias beta toward MBOIT's bias vector.
    bias: f32,
    // Weight of the support point at the queried depth (0 lower bound, 1 upper bound).
    overestimation: f32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// A fragment's depth normalised over the frame's range, in [0, 1] (transparency::Mboit::normalised).
fn mboit_depth(u: MboitUniforms, depth: f32) -> f32 {
    return clamp(relative_depth(depth, u.near, u.far), 0.0, 1.0);
}
