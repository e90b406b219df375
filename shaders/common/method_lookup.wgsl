// Visibility of a world-space point through the selected method (its `visibility_at` is pasted before this).
fn hair_visibility(world: vec3<f32>) -> f32 {
    let texel = light_texel(world);
    if texel.x < 0 {
        return 1.0;
    }
    return visibility_at(texel, light_depth(world));
}
