// Exact eye transparency, pass 1: the lists' count (`common/list_count.wgsl`) over the strands as lines.
#include "common/list_count.wgsl"

@vertex
fn vs_main(v: EyeVertexIn) -> EyePoint {
    return eye_vertex(v);
}
