// The `lines` light caster: strand segments as lines (one LineList index pair per segment), the vertices read
// from the strand vertex buffer (`render::geometry::HairVertex`). Alpha: strand_alpha() of the point over one
// light texel at its depth.

struct LightVertexIn {
    @builtin(vertex_index) index: u32,
    @location(0) position: vec3<f32>,
    @location(1) alpha: f32,
    @location(3) thickness: f32,
}

fn light_vertex(v: LightVertexIn) -> LightFragment {
    var out: LightFragment;
    out.clip = frame.world_to_light_clip * vec4<f32>(v.position, 1.0);
    out.depth = light_depth(v.position);
    out.alpha = strand_alpha(v.alpha, v.thickness, frame.light_footprint * out.clip.w);
    out.segment = v.index;
    return out;
}
