// Bounding Opacity Maps parameters, declared once for the light pass (bom.wgsl) and the lookup
// (methods/bom.wgsl). Mirrors `methods::bom::BomUniforms` (a test compares the layouts).
struct BomUniforms {
    layers: u32,
    // Hybrid split ratio r in [0, 1]: 0 linear, 1 logarithmic.
    split_ratio: f32,
    // What the lookup multiplies a stored value by to get optical depth (1, or 255/32 for u8 storage).
    unit: f32,
    pad0: u32,
}
