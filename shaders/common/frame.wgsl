// Per-frame uniforms shared by every pass. Mirrors `render::uniforms::FrameUniforms` (a test checks the layout).
#include "common/hair_model.wgsl"
// transmittance() for light_opacity().
#include "common/visibility.wgsl"
struct FrameUniforms {
    world_to_clip: mat4x4<f32>,
    // Hair light frame: fitted tightly to the strand bounds.
    world_to_light_view: mat4x4<f32>,
    world_to_light_clip: mat4x4<f32>,
    // Opaque shadow-map frame: fitted to the whole scene (meshes and hair).
    world_to_shadow_clip: mat4x4<f32>,
    eye_position: vec3<f32>,
    // Camera distance to its orbit target.
    camera_distance: f32,
    // Unit vector towards a directional light; a spot's axis.
    to_light: vec3<f32>,
    // 0: directional light, 1: spot.
    light_is_spot: u32,
    // Spot position.
    light_position: vec3<f32>,
    // Cosine of the spot's half cone angle.
    spot_cos_half_angle: f32,
    // Light colour times intensity.
    light_color: vec3<f32>,
    // Least width of a light-space ribbon, in light texels (casters/ribbons.wgsl).
    light_min_width: f32,
    // Hair colour for strands without per-point colour.
    hair_color: vec3<f32>,
    // Global hair alpha.
    hair_alpha: f32,
    // Light-view distances of the hair frame's near and far planes.
    light_near: f32,
    light_far: f32,
    // Texels per side of the hair light maps.
    light_map_resolution: u32,
    // Lookup flags (1: 3x3 PCF, 2: half-texel jitter; see common/method_lookup.wgsl).
    lookup_flags: u32,
    // Parameters of the selected shadow method (meaning defined by the method's lookup WGSL).
    method_params: vec4<f32>,
    // Eye image width and height in pixels.
    viewport_size: vec2<f32>,
    // Texels per side of the opaque shadow map, and its depth bias.
    shadow_map_resolution: u32,
    shadow_bias: f32,
    // 0: constant alpha, 1: coverage alpha (see strand_alpha()).
    alpha_mode: u32,
    // World width of a strand of thickness 1.
    strand_width: f32,
    // World size of one eye pixel, and of one hair light-map texel, per unit of clip w (the view depth of a
    // perspective, 1 for the orthographic directional light frame).
    eye_footprint: f32,
    light_footprint: f32,
    // The strand shading model (`render.shading`; see common/strand_shading.wgsl).
    shading_model: u32,
    // Guard hairs' base darkening (common/guard_darkening.wgsl): the undercoat's extinction per world unit
    // times `fur.base_darkening` (0 without guard hairs), and its height.
    guard_sigma: f32,
    guard_shell_height: f32,
    // Lights of the guard hairs' environment (common/env_lights.wgsl): 0 or 1 for the scene's light alone; per
    // light the unit direction towards it and its radiance (xyz).
    env_count: u32,
    // Light-map supersampling s (`render.light_supersample`; 0 reads as 1): the hair maps are s times the base
    // resolution a side, and hair_visibility (common/method_lookup.wgsl) averages the s x s sub-texels of the
    // point's base texel.
    light_supersample: u32,
    // The ambient terms every hair and mesh fragment adds, times its colour (`render.ambient` x 0.08 and 0.12;
    // the path tracer has none).
    hair_ambient: f32,
    mesh_ambient: f32,
    // `render.hair_model` (HAIR_MODEL_*, `shading::HairModel::uniform`).
    hair_model: u32,
    env_to_light: array<vec4<f32>, 64>,
    env_radiance: array<vec4<f32>, 64>,
    // Under the fibres model, the probe of the light the meshes bounce and the fibres scatter onto the hair
    // (common/mesh_bounce.wgsl): its lattice's corners and its 8 x 8 x 8 nodes' light and the hair's cover,
    // five vectors a node (`probe_light::packed`: rest and s_xx, first and s_yy, s_zz s_xy s_xz s_yz, the cover
    // of +x -x +y -y, of +z -z); zeros otherwise.
    // bounce_min.w is 1 where the probe holds the fibres' scattered light (render.probe = traced;
    // strand_shading.wgsl's probe_holds_scattering).
    bounce_min: vec4<f32>,
    bounce_max: vec4<f32>,
    bounce_grid: array<vec4<f32>, 2560>,
}

@group(0) @binding(0) var<uniform> frame: FrameUniforms;

// Normalised light depth in [0,1] between the hair frame's near and far planes, linear in distance along the
// light axis. Every light-space map stores this quantity.
fn light_depth(world: vec3<f32>) -> f32 {
    let view = frame.world_to_light_view * vec4<f32>(world, 1.0);
    return (-view.z - frame.light_near) / (frame.light_far - frame.light_near);
}

// A fragment's opacity from its point's alpha and thickness and the world size of its pixel or texel there.
// Constant: the point alpha times the global hair alpha. Coverage: the strand's share of the pixel or texel,
// hair_alpha (the material opacity) times width over footprint, clamped, times the point alpha.
fn strand_alpha(point_alpha: f32, thickness: f32, footprint: f32) -> f32 {
    if frame.alpha_mode == 0u {
        return clamp(point_alpha * frame.hair_alpha, 0.0, 1.0);
    }
    let width = thickness * frame.strand_width;
    let coverage = clamp(frame.hair_alpha * width / max(footprint, 1e-30), 0.0, 1.0);
    return coverage * clamp(point_alpha, 0.0, 1.0);
}

// The one alpha of a strand over a light texel where a method takes one global alpha (occupancy): the material
// opacity, or under the fibres model 1 - exp(-1), the Boolean model's one fibre crossed
// (`RenderSettings::light_opacity`).
fn light_opacity() -> f32 {
    if frame.hair_model == HAIR_MODEL_FIBRES {
        return 1.0 - transmittance(1.0);
    }
    return frame.hair_alpha;
}

// Unit vector from `world` towards the light.
fn light_dir(world: vec3<f32>) -> vec3<f32> {
    if frame.light_is_spot != 0u {
        return normalize(frame.light_position - world);
    }
    return frame.to_light;
}

// Light colour arriving at `world` (spot cone falloff, no shadowing).
fn light_radiance(world: vec3<f32>) -> vec3<f32> {
    if frame.light_is_spot != 0u {
        let axis = frame.to_light;
        let cos_angle = dot(normalize(frame.light_position - world), axis);
        let edge = frame.spot_cos_half_angle;
        return frame.light_color * smoothstep(edge, mix(edge, 1.0, 0.15), cos_angle);
    }
    return frame.light_color;
}
