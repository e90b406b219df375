// Bounding Opacity Maps parameters, declared once for the light pass (bom.wgsl) and the lookup
// (methods/bom.wgsl). Mirrors `methods::bom::BomUniforms` (a test compares the layouts).
struct BomUniforms {
    layers: u32,
    // Hybrid split ratio r in [0, 1]: 0 linear, 1 logarithmic.
    split_ratio: f32,
    pad0: u32,
    pad1: u32,
}
