// Shadow method "none": hair casts no shadow.
fn hair_visibility(world: vec3<f32>) -> f32 {
    return 1.0;
}
