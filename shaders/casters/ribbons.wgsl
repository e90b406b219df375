// The `ribbons` light caster: each strand segment as a light-facing ribbon of two triangles (6 vertices of a
// non-indexed TriangleList draw, the points pulled from group 3, common/ribbon_points.wgsl) with a minimum
// width and a coverage alpha: the light-space twin of the eye's camera-facing ribbons (`eye_ribbon_point`), the
// anti-aliasing Unreal's groom renderer applies in its shadow views (a minimum strand radius that grows with
// distance, opacity scaled by the covered fraction). Width = thickness × strand_width, widened to
// `light_min_width` light texels at its depth when thinner; alpha = point alpha × hair_alpha × min(width /
// drawn width, 1) whatever the alpha mode. Segment id: the segment's first point, as on the `lines` caster.
#include "common/ribbon_points.wgsl"

struct LightVertexIn {
    @builtin(vertex_index) index: u32,
}

fn light_vertex(v: LightVertexIn) -> LightFragment {
    let q = ribbon_quad_corner(v.index % 6u);
    let p = ribbon_points[ribbon_point_index(v.index)];
    let to_light = light_dir(p.position);
    let texel = frame.light_footprint * (frame.world_to_light_clip * vec4<f32>(p.position, 1.0)).w;
    let width = p.thickness * frame.strand_width;
    var side = cross(p.tangent, to_light);
    let len = length(side);
    if len <= 1e-6 {
        // Along the light (a point in the map): any direction across it.
        let up = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(to_light.y) > 0.9);
        side = normalize(cross(up, to_light));
    } else {
        side = side / len;
    }
    let sign = f32(q & 1u) * 2.0 - 1.0;
    let drawn = max(width, frame.light_min_width * texel);
    let world = p.position + side * (0.5 * drawn * sign);
    var out: LightFragment;
    out.clip = frame.world_to_light_clip * vec4<f32>(world, 1.0);
    out.depth = light_depth(world);
    out.alpha = clamp(p.alpha * frame.hair_alpha, 0.0, 1.0) * min(width / max(drawn, 1e-30), 1.0);
    out.segment = ribbon_segments[2u * (v.index / 6u)];
    return out;
}
