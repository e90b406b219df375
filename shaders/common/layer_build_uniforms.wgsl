// The atomic build of the opacity-layer family (OSM, DOM, BOM), declared once for its count pass
// (common/layer_pass.wgsl) and its resolve pass (layer_resolve.wgsl). Mirrors
// `methods::opacity_layers::LayerBuildUniforms` (a test compares the layouts).
struct LayerBuildUniforms {
    // Light-map resolution: texel (x, y) counts at y * resolution + x.
    resolution: u32,
    // Entries N per texel.
    entries: u32,
    // Entries per band: band b counts entries b * band .. b * band + band - 1 (one geometry pass).
    band: u32,
    // 0: f32, 1: f16, 2: u8 (visibility::opacity_layers::LayerStorage).
    storage: u32,
    // Entries per run of counters, and whole runs per page (methods::opacity_layers::CounterLayout).
    run: u32,
    runs_per_page: u32,
    pad0: u32,
    pad1: u32,
}

// Fixed point of the counters: 2^16 units per unit of optical depth; sums saturate at 2^24 (optical depth 256).
const LAYER_FIXED_POINT_SCALE: f32 = 65536.0;
const LAYER_SATURATION: u32 = 16777216u;
