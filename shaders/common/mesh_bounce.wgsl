// The probe of the light the meshes bounce and the fibres scatter onto the hair under the fibres model
// (`render.hair_model = fibres`): trilinear in frame.bounce_grid, its 8 x 8 x 8 radiances (rgb,
// `mesh_bounce::NODES`) on a lattice from frame.bounce_min to bounce_max, the edge held beyond. A port of `shading::mesh_bounce::Grid::at` and `hair_response` (the specification).
#include "common/frame.wgsl"
#include "common/marschner.wgsl"
#include "common/fibre_transport.wgsl"

fn bounce_value(x: u32, y: u32, z: u32) -> vec3<f32> {
    return frame.bounce_grid[(z * 8u + y) * 8u + x].xyz;
}

fn bounce_at(world: vec3<f32>) -> vec3<f32> {
    let span = max(frame.bounce_max.xyz - frame.bounce_min.xyz, vec3<f32>(1e-6));
    let t = clamp((world - frame.bounce_min.xyz) / span, vec3<f32>(0.0), vec3<f32>(1.0)) * 7.0;
    let i = min(u32(floor(t.x)), 6u);
    let j = min(u32(floor(t.y)), 6u);
    let k = min(u32(floor(t.z)), 6u);
    let f = t - vec3<f32>(f32(i), f32(j), f32(k));
    let p0 = mix(
        mix(bounce_value(i, j, k), bounce_value(i + 1u, j, k), f.x),
        mix(bounce_value(i, j + 1u, k), bounce_value(i + 1u, j + 1u, k), f.x),
        f.y,
    );
    let p1 = mix(
        mix(bounce_value(i, j, k + 1u), bounce_value(i + 1u, j, k + 1u), f.x),
        mix(bounce_value(i, j + 1u, k + 1u), bounce_value(i + 1u, j + 1u, k + 1u), f.x),
        f.y,
    );
    return mix(p0, p1, f.z);
}

// The ambient light a hair fragment of `colour` sends to the eye: the absorber model's constant term times the
// colour, or the fibres model's probe of the meshes' bounce at the fragment times the fibre's albedo
// (`shading::mesh_bounce::hair_response`).
fn hair_ambient_light(colour: vec3<f32>, world: vec3<f32>) -> vec3<f32> {
    if frame.hair_model == HAIR_MODEL_FIBRES {
        let a = fibre_attenuation(0.0, marschner_absorption(colour));
        return (a.forward + a.backward) * bounce_at(world);
    }
    return colour * frame.hair_ambient;
}
