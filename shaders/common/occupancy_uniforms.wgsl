// Occupancy Maps parameters, declared once for the light pass (occupancy.wgsl) and the lookup
// (methods/occupancy.wgsl). Mirrors `methods::occupancy::OccupancyUniforms` (a test compares the layouts).
struct OccupancyUniforms {
    // 0: slab map, 1: occupancy only.
    variant: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}
