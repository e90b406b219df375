// Density Clustering parameters, declared once for the light passes (dc.wgsl, through the lookup) and the lookup
// (methods/dc.wgsl). Mirrors `methods::dc::DcUniforms` (a test compares the layouts).
struct DcUniforms {
    // K, in 1..=16.
    clusters: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}
