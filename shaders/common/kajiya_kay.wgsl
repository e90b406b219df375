// Kajiya-Kay hair shading (Kajiya & Kay 1989): diffuse ~ sin(T,L), specular ~ cos(angle between the reflected
// cone and the eye)^p.
fn kajiya_kay(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, base: vec3<f32>) -> vec3<f32> {
    let t_l = clamp(dot(tangent, to_light), -1.0, 1.0);
    let t_e = clamp(dot(tangent, to_eye), -1.0, 1.0);
    let sin_tl = sqrt(1.0 - t_l * t_l);
    let sin_te = sqrt(1.0 - t_e * t_e);
    let diffuse = 0.75 * sin_tl;
    let specular = 0.35 * pow(max(t_l * t_e + sin_tl * sin_te, 0.0), 60.0);
    return base * diffuse + vec3<f32>(specular);
}
