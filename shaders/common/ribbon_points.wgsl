// The strand points and segments as the ribbons pull them from storage (group 3 of every ribbon pipeline),
// shared by the eye ribbons (`eye_ribbon_point` in common/eye_vertex.wgsl) and the light-space ribbons
// (casters/ribbons.wgsl).

// One strand point as the ribbons pull it from storage. Mirrors `render::geometry::HairVertex` (a test checks
// the layout).
struct HairPoint {
    position: vec3<f32>,
    alpha: f32,
    // Unit tangent (central differences along the strand).
    tangent: vec3<f32>,
    thickness: f32,
    // rgb colour; a = 1 when the strand carries its own colour.
    color: vec4<f32>,
    // Height above the strand's root along its first segment (common/guard_darkening.wgsl's input).
    base_height: f32,
    pad: array<f32, 3>,
}

// Group 3 of every ribbon pipeline (`render::geometry::RIBBON_GROUP`): the strand points, and the LineList
// index buffer, one pair (first point, second point) per segment.
@group(3) @binding(0) var<storage, read> ribbon_points: array<HairPoint>;
@group(3) @binding(1) var<storage, read> ribbon_segments: array<u32>;

// Corner `c` in 0..6 of a segment's two triangles, (0, 1, 2) and (2, 1, 3), as a quad corner q: bit 1 says
// the second point of the segment, bit 0 the + side.
fn ribbon_quad_corner(c: u32) -> u32 {
    var quad = array<u32, 6>(0u, 1u, 2u, 2u, 1u, 3u);
    return quad[c];
}

// The index in `ribbon_points` of the point ribbon vertex `vertex_index` lies at: segment vertex_index / 6,
// corner vertex_index % 6.
fn ribbon_point_index(vertex_index: u32) -> u32 {
    let q = ribbon_quad_corner(vertex_index % 6u);
    return ribbon_segments[2u * (vertex_index / 6u) + (q >> 1u)];
}
