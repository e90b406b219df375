// Shadow method "none": hair casts no shadow.
fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    return 1.0;
}
