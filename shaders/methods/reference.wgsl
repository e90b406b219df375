// Shadow method "reference": exact visibility from the texel's complete fragment list,
// V(z) = exp(-sum of b over fragments with depth < z) (design.md).
#include "common/frame.wgsl"
#include "common/visibility.wgsl"
#include "common/list_pages.wgsl"

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let t = u32(texel.y) * frame.light_map_resolution + u32(texel.x);
    var i = ab_heads[t];
    var sum = 0.0;
    var steps = 0u;
    let n = ab_capacity();
    while i != 0u && steps < n {
        let node = ab_node(i - 1u);
        if node.depth < z {
            sum += optical_depth(node.alpha);
        }
        i = node.next;
        steps += 1u;
    }
    return transmittance(sum);
}
