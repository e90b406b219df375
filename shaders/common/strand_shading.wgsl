// The strand shading model selected by `frame.shading_model` (`render.shading`; the values are
// `shading::ShadingModel::uniform`, a test compares them).
#include "common/frame.wgsl"
#include "common/kajiya_kay.wgsl"
#include "common/marschner.wgsl"

const SHADING_KAJIYA_KAY: u32 = 0u;
const SHADING_MARSCHNER: u32 = 1u;

// Radiance towards `to_eye` per unit radiance arriving from `to_light`, before shadowing.
fn strand_shading(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    if frame.shading_model == SHADING_MARSCHNER {
        return marschner(tangent, to_light, to_eye, colour);
    }
    return kajiya_kay(tangent, to_light, to_eye, colour);
}
