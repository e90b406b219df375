// Shadow method "opaque shadow map": hair treated as opaque; a point is fully shadowed when it lies behind the
// nearest hair fragment of its light texel. method_params.x: depth bias in normalised light depth.
#include "common/scene_bindings.wgsl"
fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let far = textureLoad(hair_depth_far, texel, 0).r;
    // An empty texel keeps its clear values (near 1, far 0) and casts no shadow.
    return select(1.0, 0.0, z > near + frame.method_params.x && near <= far);
}
