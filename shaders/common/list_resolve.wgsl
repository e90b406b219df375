// The per-pixel lists' resolve pass (src/render/eye/lists.rs), shared by every list technique: the lists' heads
// and nodes at group 1, a full-screen triangle, each pixel's list walked once to count it, then the including
// file's `resolve_N(head, n)` of the smallest sort size that holds it (`#sort_dispatch`; the including file writes
// its sort for 64 nodes between `#sort_sizes begin` and `#sort_sizes end`, src/shaders.rs pastes it per size), so
// a pixel pays for the arrays its own depth needs.
#include "common/frame.wgsl"
#include "common/fullscreen.wgsl"
#include "common/eye_node.wgsl"

@group(1) @binding(0) var<storage, read> heads: array<u32>;
@group(1) @binding(1) var<storage, read> nodes: array<EyeNode>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = u32(pos.y) * u32(frame.viewport_size.x) + u32(pos.x);
    let head = heads[p];
    var n = 0u;
    var i = head;
    loop {
        if i == 0u {
            break;
        }
        n += 1u;
        i = nodes[i - 1u].next;
    }
    if n == 0u {
        discard;
    }
#sort_dispatch
}
