// The vertex stage every eye-space hair pass shares (the shaded hair pass and the techniques' own geometry
// passes), so that all of them see bitwise the same fragments: same clip position, same interpolated world
// position (hence depth) and the same segment id. Lines: `eye_vertex` / `eye_point` per LineList vertex.
// Camera-facing ribbons (Andersen et al. 2016's "camera-facing geometry", spec B.6): `eye_ribbon_point` per
// `vertex_index` of a non-indexed TriangleList draw of 6 vertices per segment, the points pulled from group 3.
#include "common/frame.wgsl"
#include "common/ribbon_points.wgsl"

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

// Ribbon vertex `vertex_index`: its strand point offset by ± half the width along normalize(cross(tangent,
// to_eye)), so the ribbon faces the eye. Width = thickness × strand_width (world); one narrower than a pixel
// at its depth is widened to one pixel and its alpha multiplied by the covered fraction (no conservative
// rasterisation), so thin strands neither vanish nor fatten. Alpha = point alpha × hair_alpha × that fraction,
// whatever the alpha mode (a ribbon's coverage is its geometry). Segment id: its first point's index, as on
// the LineList path. Adjacent segments compute their shared point's corners bitwise alike: no gaps, no
// overlaps.
fn eye_ribbon_point(vertex_index: u32) -> EyePoint {
    let q = ribbon_quad_corner(vertex_index % 6u);
    let p = ribbon_points[ribbon_point_index(vertex_index)];
    let to_eye = frame.eye_position - p.position;
    let pixel = frame.eye_footprint * (frame.world_to_clip * vec4<f32>(p.position, 1.0)).w;
    let width = p.thickness * frame.strand_width;
    let covered = width / max(pixel, 1e-30);
    var side = cross(p.tangent, to_eye);
    let len = length(side);
    if len <= 1e-6 * length(to_eye) {
        // Seen end-on (a point on screen): any direction across the view.
        let up = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(to_eye.y) > 0.9 * length(to_eye));
        side = normalize(cross(up, to_eye));
    } else {
        side = side / len;
    }
    let sign = f32(q & 1u) * 2.0 - 1.0;
    var out: EyePoint;
    out.world = p.position + side * (0.5 * max(width, pixel) * sign);
    out.clip = frame.world_to_clip * vec4<f32>(out.world, 1.0);
    out.alpha = clamp(p.alpha * frame.hair_alpha, 0.0, 1.0) * min(covered, 1.0);
    out.segment = ribbon_segments[2u * (vertex_index / 6u)];
    return out;
}
