// Shadow method "opaque shadow map": hair treated as opaque; a point is fully shadowed when it lies behind the
// nearest hair fragment of its light texel. method_params.x: depth bias in normalised light depth.
fn hair_visibility(world: vec3<f32>) -> f32 {
    let texel = light_texel(world);
    if texel.x < 0 {
        return 1.0;
    }
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let far = textureLoad(hair_depth_far, texel, 0).r;
    // An empty texel keeps its clear values (near 1, far 0) and casts no shadow.
    let behind = light_depth(world) > near + frame.method_params.x;
    return select(1.0, 0.0, behind && near <= far);
}
