// TressFX ShortCut, pass 2 (the hair entry, pasted into hair.wgsl): a shaded fragment whose depth key is one of its
// pixel's K nearest takes that key word (atomicExchange to SHORTCUT_TAKEN, so of fragments with equal keys each
// takes its own word, in the order they arrive) and stores its colour and alpha in the word's slot; every other
// fragment adds (a c, a) to the tail's additive RGBA32F target and multiplies the tail's revealage by 1 - a. The
// meshes are tested by hand, before the storage writes (no depth attachment).
#include "common/mesh_depth.wgsl"
#include "common/shortcut.wgsl"

@group(2) @binding(0) var<uniform> shortcut: ShortcutUniforms;
@group(2) @binding(1) var<storage, read_write> keys: array<atomic<u32>>;
@group(2) @binding(2) var<storage, read_write> slots: array<vec4<f32>>;
@group(2) @binding(3) var mesh_depth: texture_depth_2d;

struct ShortcutOutput {
    @location(0) tail: vec4<f32>,
    @location(1) revealage: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut) -> ShortcutOutput {
    if hidden_by_mesh(mesh_depth, in.clip) {
        discard;
    }
    let f = shade_hair(in);
    let key = shortcut_key(f.depth);
    let base = pixel_index(in.clip) * shortcut.k;
    for (var i = 0u; i < shortcut.k; i += 1u) {
        if atomicLoad(&keys[base + i]) == key && atomicExchange(&keys[base + i], SHORTCUT_TAKEN) == key {
            slots[base + i] = vec4<f32>(f.color, f.alpha);
            // Nothing added to the tail: 0 adds nothing, and the revealage times 1 - 0 is unchanged.
            return ShortcutOutput(vec4<f32>(0.0), vec4<f32>(0.0));
        }
    }
    return ShortcutOutput(vec4<f32>(f.color * f.alpha, f.alpha), vec4<f32>(f.alpha, 0.0, 0.0, 0.0));
}
