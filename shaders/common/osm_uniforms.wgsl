// Opacity Shadow Maps parameters, declared once for the light pass (osm.wgsl) and the lookup (methods/osm.wgsl).
// Mirrors `methods::osm::OsmUniforms` (a test compares the layouts).
struct OsmUniforms {
    slices: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}
