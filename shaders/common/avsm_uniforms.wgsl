// Adaptive volumetric shadow maps (Salvi et al. 2010): the parameters, declared once for the compression pass
// (avsm.wgsl) and the lookup (methods/avsm.wgsl), and the curve's f32 expressions both use, those of
// visibility::avsm (interpolate, removal_area, fragment_factor, flush). Mirrors `methods::avsm::AvsmUniforms` (a test
// compares the layouts). A node is vec2(depth, transmittance).
struct AvsmUniforms {
    // Texels per side of the map.
    resolution: u32,
    // Nodes per texel N, in 4..=16.
    nodes: u32,
    // Batches each texel takes per dispatch of the compression pass (the walk resumes where it stopped).
    steps: u32,
    // Fragments per batch of the walk along the sorted list (common/list_walk.wgsl), 1..=32.
    batch: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    pad3: u32,
}

// x, or 0 below 1e-30: transmittances and areas, alike on devices that flush subnormals and those that keep them.
fn avsm_flush(x: f32) -> f32 {
    return select(x, 0.0, x < 1e-30);
}

// The curve between nodes a and b (a.x < b.x) at z, clamped between their transmittances.
fn avsm_interpolate(a: vec2<f32>, b: vec2<f32>, z: f32) -> f32 {
    let s = (z - a.x) / (b.x - a.x);
    return avsm_flush(min(max(a.y + (b.y - a.y) * s, b.y), a.y));
}

// Twice the area the curve changes by when node m between l and r is removed.
fn avsm_removal_area(l: vec2<f32>, m: vec2<f32>, r: vec2<f32>) -> f32 {
    return avsm_flush(abs((r.x - l.x) * (r.y - m.y) - (r.x - m.x) * (r.y - l.y)));
}

// The transmittance factor 1 - alpha of a fragment, alpha clamped below 1 as in optical_depth.
fn avsm_fragment_factor(alpha: f32) -> f32 {
    return 1.0 - clamp(alpha, 0.0, 1.0 - 1e-6);
}
