// No transparency, the hair pass's entry: the technique's own depth target (a copy of the meshes' depth) is
// tested `Less` and written, so the nearest fragment's opaque colour (c, 1) is what stays;
// transparency/opaque_resolve.wgsl copies it onto the image.

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let f = shade_hair(in);
    return vec4<f32>(f.color, 1.0);
}
