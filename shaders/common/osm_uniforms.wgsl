// Opacity Shadow Maps parameters, declared once for the light pass (osm.wgsl) and the lookup (methods/osm.wgsl).
// Mirrors `methods::osm::OsmUniforms` (a test compares the layouts).
struct OsmUniforms {
    slices: u32,
    // What the lookup multiplies a stored value by to get optical depth (1, or 255/32 for u8 storage).
    unit: f32,
    pad0: u32,
    pad1: u32,
}
