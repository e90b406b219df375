// Hybrid fur, the guard hairs' count pass (Andersen et al. 2016; spec B.6–B.7): the lists' count
// (`common/list_count.wgsl`) over the strands' camera-facing ribbons, through the same ribbon vertex stage as the
// fur's shaded ribbon fill, so the lists are sized to exactly its fragments.
#include "common/list_count.wgsl"

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> EyePoint {
    return eye_ribbon_point(i);
}
