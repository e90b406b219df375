// No transparency, the hair pass's entry: the technique's own depth target is tested `Less` and written with
// frag_depth = depth / S (S a power of two above the frame's far eye depth: exact, so the nearest fragment is the
// one with the smallest stored depth, as the model takes it, not the one with the smallest clip z); the
// meshes are tested by hand. The nearest fragment's opaque colour (c, 1) stays;
// transparency/opaque_resolve.wgsl copies it onto the image.
#include "common/mesh_depth.wgsl"

// Depth of the opaque meshes (the clip z the shared hair state tests `Less`).
@group(2) @binding(0) var opaque_mesh_depth: texture_depth_2d;
// x: 1 / S.
@group(2) @binding(1) var<uniform> opaque_scale: vec4<f32>;

struct OpaqueOutput {
    @builtin(frag_depth) frag_depth: f32,
    @location(0) color: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut) -> OpaqueOutput {
    if hidden_by_mesh(opaque_mesh_depth, in.clip) {
        discard;
    }
    let f = shade_hair(in);
    var out: OpaqueOutput;
    out.frag_depth = f.depth * opaque_scale.x;
    out.color = vec4<f32>(f.color, 1.0);
    return out;
}
