// The probe of the light the meshes bounce and the fibres scatter onto the hair under the fibres model
// (`render.hair_model = fibres`): trilinear in frame.bounce_grid, its 8 x 8 x 8 nodes' light and the hair's
// cover (five vectors a node, `mesh_bounce::NODES`, `probe_light::packed`) on a lattice from frame.bounce_min to
// bounce_max, the edge held beyond. A port of `shading::mesh_bounce::Grid::at`, `probe_light::probe_response`
// and `probe_light::mesh_probe_light` (the specification).
#include "common/frame.wgsl"
#include "common/marschner.wgsl"
#include "common/fibre_transport.wgsl"
#include "common/probe_light.wgsl"
#include "common/strand_shading.wgsl"

fn bounce_vector(x: u32, y: u32, z: u32, k: u32) -> vec4<f32> {
    return frame.bounce_grid[((z * 8u + y) * 8u + x) * 5u + k];
}

// Vector `k` of the nodes, trilinear at `world`.
fn bounce_lerp(world: vec3<f32>, k: u32) -> vec4<f32> {
    let span = max(frame.bounce_max.xyz - frame.bounce_min.xyz, vec3<f32>(1e-6));
    let t = clamp((world - frame.bounce_min.xyz) / span, vec3<f32>(0.0), vec3<f32>(1.0)) * 7.0;
    let i = min(u32(floor(t.x)), 6u);
    let j = min(u32(floor(t.y)), 6u);
    let l = min(u32(floor(t.z)), 6u);
    let f = t - vec3<f32>(f32(i), f32(j), f32(l));
    let p0 = mix(
        mix(bounce_vector(i, j, l, k), bounce_vector(i + 1u, j, l, k), f.x),
        mix(bounce_vector(i, j + 1u, l, k), bounce_vector(i + 1u, j + 1u, l, k), f.x),
        f.y,
    );
    let p1 = mix(
        mix(bounce_vector(i, j, l + 1u, k), bounce_vector(i + 1u, j, l + 1u, k), f.x),
        mix(bounce_vector(i, j + 1u, l + 1u, k), bounce_vector(i + 1u, j + 1u, l + 1u, k), f.x),
        f.y,
    );
    return mix(p0, p1, f.z);
}

// The node's light at `world`, its first `vectors` vectors interpolated (1 holds `rest`, what the voxel probe
// reads; 3 all of it), the others zero.
fn bounce_at(world: vec3<f32>, vectors: u32) -> ProbeLight {
    var v: array<vec4<f32>, 3>;
    for (var n = 0u; n < vectors; n++) {
        v[n] = bounce_lerp(world, n);
    }
    return ProbeLight(v[0].xyz, v[1].xyz, vec3<f32>(v[0].w, v[1].w, v[2].x), v[2].yzw);
}

// The light beyond one event a hair fragment of `colour` along `tangent` sends to the eye: the absorber model's
// constant term times the colour; under the fibres model its response to the probe at the fragment
// (`probe_light::probe_response`): to the traced probe's light by the directions it arrives from, or the
// fibre's albedo times the voxel probe's mean (`shading::mesh_bounce::hair_response`).
fn hair_ambient_light(colour: vec3<f32>, world: vec3<f32>, tangent: vec3<f32>, to_eye: vec3<f32>) -> vec3<f32> {
    if frame.hair_model == HAIR_MODEL_FIBRES {
        if probe_holds_scattering() {
            return probe_response(bounce_at(world, 3u), tangent, to_eye, marschner_absorption(colour));
        }
        let a = fibre_attenuation(0.0, marschner_absorption(colour));
        return (a.forward + a.backward) * (bounce_at(world, 1u).rest / (4.0 * 3.14159265));
    }
    return colour * frame.hair_ambient;
}

// `probe_light::fade`: 1 inside the lattice, 0 one node spacing outside it.
fn probe_fade(world: vec3<f32>) -> f32 {
    let spacing = max((frame.bounce_max.xyz - frame.bounce_min.xyz) / 7.0, vec3<f32>(1e-6));
    let outside = max(max(frame.bounce_min.xyz - world, world - frame.bounce_max.xyz), vec3<f32>(0.0)) / spacing;
    return max(1.0 - length(outside), 0.0);
}

// `hair_cover::hemisphere`: the cover of the hemisphere about the unit `n`, the cube's axes weighted by n_a^2.
fn hair_cover_hemisphere(plus: vec3<f32>, minus: vec3<f32>, n: vec3<f32>) -> f32 {
    let side = select(minus, plus, n >= vec3<f32>(0.0));
    return clamp(dot(n * n, side), 0.0, 1.0);
}

// `probe_light::mesh_probe_light`: what a Lambertian mesh point of `albedo`, its unit normal `n` towards the eye,
// sends to the eye of the light the hair around it scatters (one fibre's albedo times the probe's mean, over
// the part of its hemisphere the hair covers), under the fibres model; zero under the absorber model, which has
// its ambient term instead.
fn mesh_probe_light(world: vec3<f32>, n: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    if frame.hair_model != HAIR_MODEL_FIBRES {
        return vec3<f32>(0.0);
    }
    let a = fibre_attenuation(0.0, marschner_absorption(frame.hair_color));
    let mean = bounce_lerp(world, 0u).xyz / (4.0 * 3.14159265);
    let c0 = bounce_lerp(world, 3u);
    let c1 = bounce_lerp(world, 4u);
    let cover = hair_cover_hemisphere(vec3<f32>(c0.x, c0.z, c1.x), vec3<f32>(c0.y, c0.w, c1.y), n);
    return albedo * (a.forward + a.backward) * mean * cover * probe_fade(world);
}
