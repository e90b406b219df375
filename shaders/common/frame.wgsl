// Per-frame uniforms shared by every pass. Mirrors `render::uniforms::FrameUniforms` (a test checks the layout).
struct FrameUniforms {
    world_to_clip: mat4x4<f32>,
    // Hair light frame: fitted tightly to the strand bounds.
    world_to_light_view: mat4x4<f32>,
    world_to_light_clip: mat4x4<f32>,
    // Opaque shadow-map frame: fitted to the whole scene (meshes and hair).
    world_to_shadow_clip: mat4x4<f32>,
    // xyz: camera position; w: camera distance to its orbit target.
    eye_position: vec4<f32>,
    // xyz: unit vector towards a directional light; w: 0 directional, 1 spot.
    to_light: vec4<f32>,
    // xyz: spot position; w: cosine of the spot's half cone angle.
    light_position: vec4<f32>,
    // rgb: light colour times intensity.
    light_color: vec4<f32>,
    // rgb: hair colour for strands without per-point colour; a: global hair alpha.
    hair_color: vec4<f32>,
    // x: near, y: far (light-view distances of the hair frame), z: hair map resolution, w: lookup flags
    // (1: 3x3 PCF, 2: half-texel jitter; see common/method_lookup.wgsl).
    light_range: vec4<f32>,
    // Parameters of the selected shadow method (meaning defined by the method's lookup WGSL).
    method_params: vec4<f32>,
    // x: width, y: height, z: opaque shadow-map resolution, w: opaque shadow-map depth bias.
    viewport: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: FrameUniforms;

// Normalised light depth in [0,1] between the hair frame's near and far planes, linear in distance along the
// light axis. Every light-space map stores this quantity.
fn light_depth(world: vec3<f32>) -> f32 {
    let view = frame.world_to_light_view * vec4<f32>(world, 1.0);
    return (-view.z - frame.light_range.x) / (frame.light_range.y - frame.light_range.x);
}

// Unit vector from `world` towards the light.
fn light_dir(world: vec3<f32>) -> vec3<f32> {
    if frame.to_light.w > 0.5 {
        return normalize(frame.light_position.xyz - world);
    }
    return frame.to_light.xyz;
}

// Light colour arriving at `world` (spot cone falloff, no shadowing).
fn light_radiance(world: vec3<f32>) -> vec3<f32> {
    if frame.to_light.w > 0.5 {
        let axis = frame.to_light.xyz;
        let cos_angle = dot(normalize(frame.light_position.xyz - world), axis);
        let edge = frame.light_position.w;
        return frame.light_color.rgb * smoothstep(edge, mix(edge, 1.0, 0.15), cos_angle);
    }
    return frame.light_color.rgb;
}

// Optical depth b = -ln(1 - alpha), alpha clamped below 1 (design.md; visibility::optical_depth).
fn optical_depth(alpha: f32) -> f32 {
    return -log(1.0 - clamp(alpha, 0.0, 1.0 - 1e-6));
}
