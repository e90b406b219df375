// Shadow method "adsm" (approximated deep shadow maps, TressFX ComputeShadow): visibility from the nearest strand
// depth and a constant fibre spacing. method_params: x fibre spacing, y shadow alpha, z max fibres. The CPU
// model is visibility::adsm, with these exact expressions.
#include "common/scene_bindings.wgsl"
#include "common/visibility.wgsl"
fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let far = textureLoad(hair_depth_far, texel, 0).r;
    let d = max(z - near, 0.0);
    let n = min(d / frame.method_params.x, frame.method_params.z);
    // TressFX: a point behind the nearest strand has at least one fibre in front of it.
    let fibres = select(n, max(n, 1.0), d > 1e-5);
    // An empty texel keeps its clear values (near 1, far 0) and is lit.
    return select(1.0, transmittance(fibres * optical_depth(frame.method_params.y)), near <= far);
}
