// Uniforms of the compressed deep shadow map (compressor and lookup). Mirrors `methods::dsm::DsmUniforms`.
struct DsmUniforms {
    // Error tolerance in visibility.
    epsilon: f32,
    // Texels per side of the map.
    resolution: u32,
    // Batches each texel takes per dispatch of the compressor (its walk resumes where it stopped).
    steps: u32,
    // Fragments per batch of the walk along the sorted list (common/list_walk.wgsl), 1..=32.
    batch: u32,
}
