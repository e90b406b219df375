// Uniforms of the compressed deep shadow map (compressor and lookup). Mirrors `methods::dsm::DsmUniforms`.
struct DsmUniforms {
    // Error tolerance in visibility.
    epsilon: f32,
    // Texels per side of the map.
    resolution: u32,
    pad0: u32,
    pad1: u32,
}
