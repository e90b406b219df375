// Fourier Opacity Mapping parameters and the phase both its passes share, declared once for the light pass
// (fom.wgsl) and the lookup (methods/fom.wgsl). FomUniforms mirrors `methods::fom::FomUniforms` (a test compares
// the layouts); fom_angle is `visibility::fom::angle`.
struct FomUniforms {
    // Fourier terms K, 1..=16 (2K + 1 coefficients a0, a1, b1, ..., aK, bK).
    terms: u32,
    // 0: plain truncation, 1: Fejér weights 1 - k / (K + 1).
    window: u32,
    pad0: u32,
    pad1: u32,
}

// The angle 2πkd reduced to [-π, π]: 2π (x - floor(x + 0.5)) with x = k d (6.2831855 is f32 2π).
fn fom_angle(k: u32, d: f32) -> f32 {
    let x = f32(k) * d;
    return 6.2831855 * (x - floor(x + 0.5));
}
