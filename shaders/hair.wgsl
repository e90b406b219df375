// Eye pass for hair: strands as lines (vs_main) or camera-facing ribbons (vs_ribbon), the strand shading model
// of `render.shading` (common/strand_shading.wgsl), darkened towards the base when they are fur's guard hairs
// (common/guard_darkening.wgsl; 1 without fur) and lit by their environment's lights when fur asks for more
// than one (common/env_lights.wgsl; the shadow method's visibility towards the scene's light scales them),
// shadowed by the selected method's visibility and by opaque meshes; the eye transparency technique's entry
// points (pasted at #include_technique) store what `shade_hair` returns.
#include "common/eye_vertex.wgsl"
#include "common/scene_bindings.wgsl"
#include "common/strand_shading.wgsl"
#include "common/guard_darkening.wgsl"
#include "common/env_lights.wgsl"
#include "common/mesh_bounce.wgsl"
#include "common/visibility.wgsl"
#include_method
#include "common/method_lookup.wgsl"
#include_technique

struct VertexIn {
    @builtin(vertex_index) index: u32,
    @location(0) position: vec3<f32>,
    @location(1) alpha: f32,
    @location(2) tangent: vec3<f32>,
    @location(3) thickness: f32,
    // rgb colour; a = 1 when the strand carries its own colour, 0 to use the global hair colour.
    @location(4) color: vec4<f32>,
    @location(5) base_height: f32,
}

// EyePoint's fields (WGSL has no nested stage structs) and the shading inputs.
struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) alpha: f32,
    @location(2) @interpolate(flat) segment: u32,
    @location(3) tangent: vec3<f32>,
    @location(4) color: vec3<f32>,
    @location(5) base_height: f32,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let p = eye_point(v.index, v.position, v.alpha, v.thickness);
    var out: VertexOut;
    out.clip = p.clip;
    out.world = p.world;
    out.alpha = p.alpha;
    out.segment = p.segment;
    out.tangent = v.tangent;
    out.color = mix(frame.hair_color, v.color.rgb, v.color.a);
    out.base_height = v.base_height;
    return out;
}

// Camera-facing ribbons (a `HairGeometry::Ribbons` entry): non-indexed TriangleList, 6 vertices per segment,
// the same VertexOut (and segment ids) as vs_main.
@vertex
fn vs_ribbon(@builtin(vertex_index) index: u32) -> VertexOut {
    let p = eye_ribbon_point(index);
    let point = ribbon_points[ribbon_point_index(index)];
    var out: VertexOut;
    out.clip = p.clip;
    out.world = p.world;
    out.alpha = p.alpha;
    out.segment = p.segment;
    out.tangent = point.tangent;
    out.color = mix(frame.hair_color, point.color.rgb, point.color.a);
    out.base_height = point.base_height;
    return out;
}

// One shaded hair fragment, as every technique's entry point receives it (see render/transparency/mod.rs).
struct ShadedHair {
    color: vec3<f32>,
    alpha: f32,
    depth: f32,
    segment: u32,
    pixel: vec2<u32>,
}

fn shade_hair(in: VertexOut) -> ShadedHair {
    let world = in.world;
    let t = normalize(in.tangent);
    let to_eye = normalize(frame.eye_position - world);
    let l = light_dir(world);
    // The method's V and the hair count it stands for (`hair_count`; with 3x3 PCF, of the filtered V). Under
    // the fibres model read towards the light past the fragment's own strand, which does not shadow it.
    var read = world;
    if frame.hair_model == HAIR_MODEL_FIBRES {
        let texel = frame.light_footprint * (frame.world_to_light_clip * vec4<f32>(world, 1.0)).w;
        read = world + l * fibre_own_strand_offset(texel, t, l);
    }
    let v = hair_visibility(read);
    let count = hair_count(v);
    let mesh = mesh_visibility(world, 1);
    var lit = strand_lit(t, l, to_eye, in.color, v, count) * light_radiance(world) * mesh;
    if frame.env_count > 1u {
        // Guard hairs under the environment's lights, shadowed by the method's V towards the scene light.
        lit = env_shading(t, to_eye, in.color) * v * mesh;
    }
    let dark = guard_darkening(in.base_height, frame.guard_shell_height, frame.guard_sigma);
    var out: ShadedHair;
    out.color = (lit + hair_ambient_light(in.color, world, t, to_eye)) * dark;
    out.alpha = in.alpha;
    out.depth = eye_depth(world);
    out.segment = in.segment;
    out.pixel = vec2<u32>(in.clip.xy);
    return out;
}
