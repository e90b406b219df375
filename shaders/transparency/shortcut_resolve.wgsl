// Resolve of TressFX ShortCut (transparency::ShortcutParams): the K slots (ascending depth; empty ones hold
// alpha 0) blended front to back, C += T a c, T *= 1 - a, then the tail as one layer behind them with its
// alpha-weighted average colour and coverage 1 - P (P its revealage): C += T (1 - P) S / A. With average_front the
// slots are averaged instead: C = (Σ a c / Σ a)(1 - T P). Output (C, 1 - T P), blended premultiplied over the opaque
// image. Every pixel's key words and slots are reset here for the next frame.
#include "common/fullscreen.wgsl"
#include "common/shortcut.wgsl"

@group(0) @binding(0) var<uniform> shortcut: ShortcutUniforms;
@group(0) @binding(1) var<storage, read_write> keys: array<u32>;
@group(0) @binding(2) var<storage, read_write> slots: array<vec4<f32>>;
@group(0) @binding(3) var tail_tex: texture_2d<f32>;
@group(0) @binding(4) var revealage_tex: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let base = (u32(pos.y) * shortcut.width + u32(pos.x)) * shortcut.k;
    var c = vec3<f32>(0.0);
    var t = 1.0;
    var front_sum = vec3<f32>(0.0);
    var front_alpha = 0.0;
    for (var i = 0u; i < shortcut.k; i += 1u) {
        let s = slots[base + i];
        c += t * s.a * s.rgb;
        t *= 1.0 - s.a;
        front_sum += s.a * s.rgb;
        front_alpha += s.a;
        keys[base + i] = SHORTCUT_EMPTY;
        slots[base + i] = vec4<f32>(0.0);
    }
    let tail = textureLoad(tail_tex, p, 0);
    let revealage = textureLoad(revealage_tex, p, 0).r;
    let t_all = t * revealage;
    if shortcut.average_front != 0u {
        c = vec3<f32>(0.0);
        if front_alpha > 0.0 {
            c = front_sum / front_alpha * (1.0 - t_all);
        }
    } else if tail.a > 0.0 {
        let cover = t * (1.0 - revealage);
        c += cover * tail.rgb / tail.a;
    }
    return vec4<f32>(c, 1.0 - t_all);
}
