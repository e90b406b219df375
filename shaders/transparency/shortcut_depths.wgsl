// TressFX ShortCut, pass 1: every hair fragment the meshes do not hide (tested by hand before the atomics) inserts
// its depth key into its pixel's K key words with an atomicMin chain: each step keeps the smaller of the word and
// the key and carries the larger on, so the words end up holding the K smallest keys ascending (equal keys each
// keep a word). The words start empty (the resolve of the previous frame reset them).
#include "common/eye_vertex.wgsl"
#include "common/mesh_depth.wgsl"
#include "common/shortcut.wgsl"

@group(1) @binding(0) var<uniform> shortcut: ShortcutUniforms;
@group(1) @binding(1) var<storage, read_write> keys: array<atomic<u32>>;
@group(1) @binding(2) var mesh_depth: texture_depth_2d;

@vertex
fn vs_main(v: EyeVertexIn) -> EyePoint {
    return eye_vertex(v);
}

@fragment
fn fs_main(in: EyePoint) {
    if hidden_by_mesh(mesh_depth, in.clip) {
        discard;
    }
    let base = pixel_index(in.clip) * shortcut.k;
    var key = shortcut_key(eye_depth(in.world));
    for (var i = 0u; i < shortcut.k; i += 1u) {
        let old = atomicMin(&keys[base + i], key);
        if old == SHORTCUT_EMPTY {
            break;
        }
        key = max(old, key);
    }
}
