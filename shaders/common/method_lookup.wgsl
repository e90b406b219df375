// Visibility of a world-space point through the selected method (its `visibility_at` is pasted before this).
// With PCF on (frame.light_range.w > 0) it averages the 3x3 texels around the point's texel at the same depth.
fn hair_visibility(world: vec3<f32>) -> f32 {
    let texel = light_texel(world);
    if texel.x < 0 {
        return 1.0;
    }
    let z = light_depth(world);
    if frame.light_range.w <= 0.0 {
        return visibility_at(texel, z);
    }
    let last = i32(frame.light_range.z) - 1;
    var sum = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            sum += visibility_at(clamp(texel + vec2<i32>(dx, dy), vec2<i32>(0), vec2<i32>(last)), z);
        }
    }
    return sum / 9.0;
}
