// Eye pass for hair: strands as lines, Kajiya-Kay shading, shadowed by the selected method's visibility and by
// opaque meshes, stored by the selected eye transparency technique (`store_hair`, its targets `HairOutput`).
#include "common/frame.wgsl"
#include "common/scene_bindings.wgsl"
#include "common/kajiya_kay.wgsl"
#include_method
#include "common/method_lookup.wgsl"
#include_technique

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) alpha: f32,
    @location(2) tangent: vec3<f32>,
    @location(3) thickness: f32,
    // rgb colour; a = 1 when the strand carries its own colour, 0 to use the global hair colour.
    @location(4) color: vec4<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) color: vec4<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.world_to_clip * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.tangent = v.tangent;
    let rgb = mix(frame.hair_color, v.color.rgb, v.color.a);
    out.color = vec4<f32>(rgb, clamp(v.alpha * frame.hair_alpha, 0.0, 1.0));
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> HairOutput {
    let t = normalize(in.tangent);
    let to_eye = normalize(frame.eye_position - in.world);
    let l = light_dir(in.world);
    let v = hair_visibility(in.world) * mesh_visibility(in.world, 1);
    let shaded = kajiya_kay(t, l, to_eye, in.color.rgb) * light_radiance(in.world) * v + in.color.rgb * 0.08;
    // Distance from the eye in units of the camera-to-target distance (camera_distance): scale-free.
    let depth = length(frame.eye_position - in.world) / frame.camera_distance;
    return store_hair(shaded, in.color.a, depth);
}
