// Classic depth peeling (Everitt 2001), the hair pass's entry of one layer: the nearest fragment strictly
// behind the previous layer's depth wins the technique's own depth test (`Less`, written), which orders by
// frag_depth = depth / S, S a power of two above the frame's far eye depth (the division is exact, so the test
// orders exactly as the stored depth does). The meshes are tested by hand (their depth is not in the technique's
// target). Outputs the layer's (c, a) and its depth; transparency/depth_peel_under.wgsl blends the layer.
#include "common/mesh_depth.wgsl"

// Depth of the opaque meshes (the clip z the shared hair state tests `Less`).
@group(2) @binding(0) var peel_mesh_depth: texture_depth_2d;
// Depth of the previous layer per pixel (0 before the first layer, f32::MAX where it peeled nothing).
@group(2) @binding(1) var peel_previous: texture_2d<f32>;
// x: 1 / S.
@group(2) @binding(2) var<uniform> peel_scale: vec4<f32>;

struct PeelOutput {
    @builtin(frag_depth) frag_depth: f32,
    @location(0) color: vec4<f32>,
    @location(1) depth: vec4<f32>,
}

@fragment
fn fs_peel(in: VertexOut) -> PeelOutput {
    if hidden_by_mesh(peel_mesh_depth, in.clip) {
        discard;
    }
    let p = vec2<i32>(in.clip.xy);
    let depth = eye_depth(in.world);
    if depth <= textureLoad(peel_previous, p, 0).r {
        discard;
    }
    let f = shade_hair(in);
    var out: PeelOutput;
    out.frag_depth = depth * peel_scale.x;
    out.color = vec4<f32>(f.color, f.alpha);
    out.depth = vec4<f32>(depth, 0.0, 0.0, 0.0);
    return out;
}
