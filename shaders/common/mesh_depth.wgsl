// The meshes' depth test done by hand, for eye passes whose fragment shaders write storage: a fixed-function
// test after the shader would not undo their side effects. The same comparison as the hair pass's `Less` test on
// the same fragment depth, so every eye pass keeps the same fragments.
fn hidden_by_mesh(mesh_depth: texture_depth_2d, clip: vec4<f32>) -> bool {
    return clip.z >= textureLoad(mesh_depth, vec2<i32>(clip.xy), 0);
}
