// Uniforms of the compressed deep shadow map (compressor and lookup). Mirrors `methods::dsm::DsmUniforms`.
struct DsmUniforms {
    // Error tolerance in visibility.
    epsilon: f32,
    // Texels per side of the map.
    resolution: u32,
    // Fragments each texel takes per dispatch of the compressor (its walk resumes where it stopped).
    steps: u32,
    pad1: u32,
}
