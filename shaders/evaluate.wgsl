// Evaluation pass: runs the selected method's GPU lookup `visibility_at` at given (texel, light depth) samples,
// or the eye lookup `hair_visibility` at world points, so tests and the inspector compare the GPU path itself
// with the CPU model.
#include "common/frame.wgsl"
#include "common/scene_bindings.wgsl"
#include_method
#include "common/method_lookup.wgsl"

// w = 0: xy a texel of the maps as built, z a normalised light depth (`visibility_at`); w = 1: xyz a world point
// (`hair_visibility`).
@group(2) @binding(0) var<storage, read> samples: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read_write> visibility_out: array<f32>;

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.x + id.y * groups.x * 64u;
    if i >= arrayLength(&visibility_out) {
        return;
    }
    let s = samples[i];
    if s.w == 0.0 {
        visibility_out[i] = visibility_at(vec2<i32>(s.xy), s.z);
    } else {
        visibility_out[i] = hair_visibility(s.xyz);
    }
}
