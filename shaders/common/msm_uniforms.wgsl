// Moment shadow map parameters, declared once for the light pass (msm.wgsl) and the lookup (methods/msm.wgsl).
// Mirrors `methods::msm::MsmUniforms` (a test compares the layouts).
struct MsmUniforms {
    // Power moments beyond b_0: 4 or 6.
    moments: u32,
    // Moment bias beta toward MBOIT's bias vector.
    bias: f32,
    // Weight of the support point at the queried depth (0 lower bound, 1 upper bound).
    overestimation: f32,
    pad0: u32,
}
