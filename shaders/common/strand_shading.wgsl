// The strand shading model selected by `frame.shading_model` (`render.shading`; the values are
// `shading::ShadingModel::uniform`, a test compares them).
#include "common/frame.wgsl"
#include "common/kajiya_kay.wgsl"
#include "common/marschner.wgsl"
#include "common/dual_scattering.wgsl"
#include "common/fibre_transport.wgsl"
#include "common/chiang.wgsl"

const SHADING_KAJIYA_KAY: u32 = 0u;
const SHADING_MARSCHNER: u32 = 1u;
const SHADING_DUAL_SCATTERING: u32 = 2u;
const SHADING_CHIANG: u32 = 3u;

// Whether the fibres model's probe holds the light the fibres scatter, forward and back (`render.probe =
// traced`, the path tracer's gather; the flag rides in bounce_min.w): `shading::strand_lit`'s `probe`.
fn probe_holds_scattering() -> bool {
    return frame.hair_model == HAIR_MODEL_FIBRES && frame.bounce_min.w > 0.5;
}

// The single-scattering lobes of the shading model per unit radiance arriving from `to_light` (dual scattering's
// are Marschner's): what `shading::strand_direct` shades the direct light with under the traced probe.
fn traced_lobes(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    if frame.shading_model == SHADING_CHIANG {
        return chiang(tangent, to_light, to_eye, colour);
    }
    if frame.shading_model != SHADING_KAJIYA_KAY {
        return marschner(tangent, to_light, to_eye, colour);
    }
    return kajiya_kay(tangent, to_light, to_eye, colour);
}

// Radiance towards `to_eye` per unit radiance arriving from `to_light`, before shadowing (dual scattering: with
// nothing in front, V = 1 and no strand).
fn strand_shading(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    if frame.shading_model == SHADING_MARSCHNER {
        return marschner(tangent, to_light, to_eye, colour);
    }
    if frame.shading_model == SHADING_DUAL_SCATTERING {
        return dual_scattering(HAIR_MODEL_ABSORBER, tangent, to_light, to_eye, colour, 1.0, 0.0);
    }
    if frame.shading_model == SHADING_CHIANG {
        return chiang(tangent, to_light, to_eye, colour);
    }
    return kajiya_kay(tangent, to_light, to_eye, colour);
}

// The same with the hair's shadow (`shading::strand_lit`): `visibility` is the method's V and `count` its hair
// count, the strands in front towards the light (dual scattering reads both; the other models are multiplied by
// what arrives: V for absorbers; under fibres Marschner and Chiang shade V and add the global forward scattering,
// Kajiya-Kay
// takes max(V, T_f); lit there by the irradiance pi x the light). Under the traced probe (probe_holds_scattering)
// the probe holds the fibres' scattered light but for the cone about the light, so every model shades the direct
// V (dual scattering by Marschner's lobes) and adds the global forward-scattered term from the count.
fn strand_lit(
    tangent: vec3<f32>,
    to_light: vec3<f32>,
    to_eye: vec3<f32>,
    colour: vec3<f32>,
    visibility: f32,
    count: f32,
) -> vec3<f32> {
    if probe_holds_scattering() {
        let v = clamp(visibility, 0.0, 1.0);
        let forward = dual_scattering_forward(
            dual_scattering_terms(HAIR_MODEL_FIBRES, tangent, to_light, to_eye, colour, v, count),
        );
        return traced_lobes(tangent, to_light, to_eye, colour) * v * FIBRE_IRRADIANCE + forward * FIBRE_IRRADIANCE;
    }
    if frame.shading_model == SHADING_DUAL_SCATTERING {
        let f = dual_scattering(frame.hair_model, tangent, to_light, to_eye, colour, visibility, count);
        if frame.hair_model == HAIR_MODEL_FIBRES {
            return f * FIBRE_IRRADIANCE;
        }
        return f;
    }
    let s = strand_shading(tangent, to_light, to_eye, colour);
    if frame.hair_model == HAIR_MODEL_FIBRES
        && (frame.shading_model == SHADING_MARSCHNER || frame.shading_model == SHADING_CHIANG) {
        let v = clamp(visibility, 0.0, 1.0);
        let t = dual_scattering_terms(HAIR_MODEL_FIBRES, tangent, to_light, to_eye, colour, v, count);
        let scattered = dual_scattering_forward(t);
        return (s * v + scattered) * FIBRE_IRRADIANCE;
    }
    if frame.hair_model == HAIR_MODEL_FIBRES {
        let sin_i = clamp(dot(tangent, to_light), -1.0, 1.0);
        return s * fibre_arriving(visibility, sin_i, marschner_absorption(colour), count) * FIBRE_IRRADIANCE;
    }
    return s * visibility;
}

// The hair count the eye pass reads from the method's V (`shading::HairModel::count`): -ln V / b(hair_alpha)
// for absorbers, -ln V for fibres.
fn hair_count(v: f32) -> f32 {
    if frame.hair_model == HAIR_MODEL_FIBRES {
        return fibre_count(v);
    }
    return count_from_visibility(v, frame.hair_alpha);
}
