// Shadow method "avsm" (adaptive volumetric shadow maps, Salvi et al. 2010): the texel's N nodes, piecewise
// linear between them; V = 1 in front of the first node (and at it: strictly less), the last node's
// transmittance behind the last. Unused slots repeat the last node, which this rule reads as the same curve. The
// CPU model is visibility::avsm (`visibility`), with these exact expressions.
#include "common/frame.wgsl"
#include "common/avsm_uniforms.wgsl"

@group(1) @binding(0) var<storage, read> avsm_nodes: array<vec2<f32>>;
@group(1) @binding(1) var<uniform> avsm: AvsmUniforms;

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let n = avsm.nodes;
    let base = (u32(texel.y) * avsm.resolution + u32(texel.x)) * n;
    // k: the number of nodes in front of z.
    var k = 0u;
    while k < n && avsm_nodes[base + k].x < z {
        k += 1u;
    }
    if k == 0u {
        return 1.0;
    }
    if k == n {
        return avsm_nodes[base + n - 1u].y;
    }
    return avsm_interpolate(avsm_nodes[base + k - 1u], avsm_nodes[base + k], z);
}
