// Parameters of the eye transparency technique occupancy-order, declared once for its passes
// (transparency/occupancy_order*.wgsl). Mirrors `render::transparency::occupancy_order::OccupancyOrderUniforms`
// (a test compares the layouts).
struct OccupancyOrderUniforms {
    // 0: slab map, 1: occupancy only (the pixel's total count in slab 0).
    variant: u32,
    // 1: rescale the hair colour so its total weight is 1 - (1 - alpha)^n (S&A's correction).
    correction: u32,
    // Added to every order estimate before clamping at 0 (0 or -0.5).
    order_bias: f32,
    // The global hair alpha (frame.hair_alpha; the resolve has no frame group).
    hair_alpha: f32,
}
