// Eye pass for opaque meshes: Lambert shading, shadowed by other meshes (shadow map) and by hair (the selected
// shadow method's visibility; under the fibres model, the light its fibres scatter forward), and under the
// fibres model lit by the light the hair around it scatters (`mesh_probe_light`).
#include "common/frame.wgsl"
#include "common/scene_bindings.wgsl"
#include "common/marschner.wgsl"
#include "common/fibre_transport.wgsl"
#include "common/mesh_bounce.wgsl"
#include_method
#include "common/method_lookup.wgsl"

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.world_to_clip * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.color = v.color;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    let to_eye = normalize(frame.eye_position - in.world);
    if dot(n, to_eye) < 0.0 {
        n = -n;
    }
    let l = light_dir(in.world);
    // Through the hair: V, or under the fibres model what the hair's fibres scatter forward (light across them).
    let hair_v = hair_visibility(in.world);
    var through = vec3<f32>(hair_v);
    if frame.hair_model == HAIR_MODEL_FIBRES {
        through = fibre_arriving(hair_v, 0.0, marschner_absorption(frame.hair_color), fibre_count(hair_v));
    }
    let v = mesh_visibility(in.world, 3) * through;
    let lit = in.color * light_radiance(in.world) * max(dot(n, l), 0.0) * v;
    return vec4<f32>(lit + in.color * frame.mesh_ambient + mesh_probe_light(in.world, n, in.color), 1.0);
}
