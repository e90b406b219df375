// The strand shading model selected by `frame.shading_model` (`render.shading`; the values are
// `shading::ShadingModel::uniform`, a test compares them).
#include "common/frame.wgsl"
#include "common/kajiya_kay.wgsl"
#include "common/marschner.wgsl"
#include "common/dual_scattering.wgsl"

const SHADING_KAJIYA_KAY: u32 = 0u;
const SHADING_MARSCHNER: u32 = 1u;
const SHADING_DUAL_SCATTERING: u32 = 2u;

// Radiance towards `to_eye` per unit radiance arriving from `to_light`, before shadowing (dual scattering: with
// nothing in front, V = 1 and no strand).
fn strand_shading(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    if frame.shading_model == SHADING_MARSCHNER {
        return marschner(tangent, to_light, to_eye, colour);
    }
    if frame.shading_model == SHADING_DUAL_SCATTERING {
        return dual_scattering(tangent, to_light, to_eye, colour, 1.0, 0.0);
    }
    return kajiya_kay(tangent, to_light, to_eye, colour);
}

// The same with the hair's shadow: `visibility` is the method's V and `count` its hair count, the strands in
// front towards the light (dual scattering reads both; the other models are multiplied by V).
fn strand_lit(
    tangent: vec3<f32>,
    to_light: vec3<f32>,
    to_eye: vec3<f32>,
    colour: vec3<f32>,
    visibility: f32,
    count: f32,
) -> vec3<f32> {
    if frame.shading_model == SHADING_DUAL_SCATTERING {
        return dual_scattering(tangent, to_light, to_eye, colour, visibility, count);
    }
    return strand_shading(tangent, to_light, to_eye, colour) * visibility;
}
