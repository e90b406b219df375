// The vertex stage every eye-space hair pass shares (the shaded hair pass and the techniques' own geometry
// passes), so that all of them see bitwise the same fragments: same clip position, same interpolated world
// position (hence depth) and the same segment id.
#include "common/frame.wgsl"

struct EyePoint {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    // Opacity: strand_alpha() of the point over one pixel at its view depth.
    @location(1) alpha: f32,
    // Segment id: the index of the segment's first point (the provoking vertex of a LineList segment).
    @location(2) @interpolate(flat) segment: u32,
}

// The vertex inputs of the techniques' own geometry passes (the hair pass reads more).
struct EyeVertexIn {
    @builtin(vertex_index) index: u32,
    @location(0) position: vec3<f32>,
    @location(1) alpha: f32,
    @location(3) thickness: f32,
}

fn eye_vertex(v: EyeVertexIn) -> EyePoint {
    return eye_point(v.index, v.position, v.alpha, v.thickness);
}

fn eye_point(index: u32, position: vec3<f32>, alpha: f32, thickness: f32) -> EyePoint {
    var out: EyePoint;
    out.clip = frame.world_to_clip * vec4<f32>(position, 1.0);
    out.world = position;
    out.alpha = strand_alpha(alpha, thickness, frame.eye_footprint * out.clip.w);
    out.segment = index;
    return out;
}

// Distance from the eye in units of the camera-to-target distance (scale-free, 1 at the orbit target): the
// depth every eye technique orders and weights fragments by.
fn eye_depth(world: vec3<f32>) -> f32 {
    return length(frame.eye_position - world) / frame.camera_distance;
}

// Linear index of the pixel under a fragment.
fn pixel_index(clip: vec4<f32>) -> u32 {
    let p = vec2<u32>(clip.xy);
    return p.y * u32(frame.viewport_size.x) + p.x;
}
