// Shadow method "fom": Fourier Opacity Mapping lookup, the absorption density's Fourier series integrated from
// 0 to z, V = exp(-T) clamped to [0, 1] (visibility::fom::visibility, expression for expression).

#include "common/visibility.wgsl"
#include "common/fom_uniforms.wgsl"

@group(1) @binding(0) var fom_coefficients: texture_2d_array<f32>;
@group(1) @binding(1) var<uniform> fom_lookup: FomUniforms;

fn fom_stored(texel: vec2<i32>, i: u32) -> f32 {
    return textureLoad(fom_coefficients, texel, i32(i / 4u), 0)[i % 4u];
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let n = fom_lookup.terms;
    let zc = clamp(z, 0.0, 1.0);
    var t = (fom_stored(texel, 0u) * 0.5) * zc;
    for (var k = 1u; k <= n; k++) {
        let a = fom_angle(k, zc);
        let w = select(1.0, 1.0 - f32(k) / f32(n + 1u), fom_lookup.window == 1u);
        let ak = fom_stored(texel, 2u * k - 1u);
        let bk = fom_stored(texel, 2u * k);
        t += w * (ak * sin(a) + bk * (1.0 - cos(a))) / (6.2831855 * f32(k));
    }
    return clamp(transmittance(t), 0.0, 1.0);
}
