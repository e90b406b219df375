// Deep Opacity Maps parameters, declared once for the light pass (dom.wgsl) and the lookup (methods/dom.wgsl).
// Mirrors `methods::dom::DomUniforms` (a test compares the layouts).
struct DomUniforms {
    // d_1..d_K relative to z0: layer k (0-based) ends at ends[k / 4][k % 4].
    ends: array<vec4<f32>, 4>,
    layers: u32,
    // 0: ignore fragments beyond the last layer, 1: add them to the last layer, 2: stretch the layers to far.
    beyond: u32,
    // What the lookup multiplies a stored value by to get optical depth (1, or 255/32 for u8 storage).
    unit: f32,
    pad0: u32,
}
