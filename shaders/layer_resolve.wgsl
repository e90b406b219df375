// The resolve pass of the opacity-layer family's atomic build (methods::opacity_layers,
// visibility::opacity_layers): a full-screen pass over the light map per (at most) 32 entries of one band (up
// to 8 colour targets, no blending). Each texel sums its counters front to back, saturating, from the running sum the previous pass
// left in `layer_carry`, zeroes the counters it read (so they are clear for the next band and frame without a
// clear of their own), and writes every entry in the map's storage: f32, f16 (rounded to 11 significant bits in
// integers first, so that the target's conversion is exact) or u8 (steps of 1/32 as a unorm).
#include "common/fullscreen.wgsl"
#include "common/cumulative_targets.wgsl"
#include "common/layer_build_uniforms.wgsl"

@group(0) @binding(0) var<uniform> resolve: LayerBuildUniforms;
@group(0) @binding(1) var<storage, read_write> resolve_counters: array<u32>;
@group(0) @binding(2) var<storage, read_write> layer_carry: array<u32>;

struct ResolveFragment {
    @builtin(position) clip: vec4<f32>,
    // First entry of the pass (a multiple of 4): the instance index.
    @location(0) @interpolate(flat) first: u32,
}

@vertex
fn vs_resolve(@builtin(vertex_index) i: u32, @builtin(instance_index) first: u32) -> ResolveFragment {
    return ResolveFragment(fullscreen_position(i), first);
}

// c rounded to 11 significant bits, to nearest with ties to even (visibility::opacity_layers::round_significand).
fn round_significand(c: u32) -> u32 {
    if c < 2048u {
        return c;
    }
    let shift = firstLeadingBit(c) - 10u;
    let low = c & ((1u << shift) - 1u);
    let half = 1u << (shift - 1u);
    var m = c >> shift;
    if low > half || (low == half && (m & 1u) == 1u) {
        m += 1u;
    }
    return m << shift;
}

// The value the map holds for the fixed-point sum c (visibility::opacity_layers::LayerStorage::raw).
fn stored_value(c: u32) -> f32 {
    switch resolve.storage {
        case 1u: {
            return f32(round_significand(c)) / LAYER_FIXED_POINT_SCALE;
        }
        case 2u: {
            return f32(min((c + 1024u) >> 11u, 255u)) / 255.0;
        }
        default: {
            return f32(c) / LAYER_FIXED_POINT_SCALE;
        }
    }
}

@fragment
fn fs_resolve(f: ResolveFragment) -> CumulativeTargets {
    let p = vec2<u32>(f.clip.xy);
    let texels = resolve.resolution * resolve.resolution;
    let t = p.y * resolve.resolution + p.x;
    let band_first = (f.first / resolve.band) * resolve.band;
    let band_end = min(band_first + resolve.band, resolve.entries);
    var c = select(layer_carry[t], 0u, f.first == 0u);
    var v: array<f32, 32>;
    for (var j = 0u; j < 32u; j++) {
        let e = f.first + j;
        if e < band_end {
            let i = (e - band_first) * texels + t;
            c = min(c + resolve_counters[i], LAYER_SATURATION);
            resolve_counters[i] = 0u;
        }
        v[j] = stored_value(c);
    }
    layer_carry[t] = c;
    return CumulativeTargets(
        vec4<f32>(v[0], v[1], v[2], v[3]),
        vec4<f32>(v[4], v[5], v[6], v[7]),
        vec4<f32>(v[8], v[9], v[10], v[11]),
        vec4<f32>(v[12], v[13], v[14], v[15]),
        vec4<f32>(v[16], v[17], v[18], v[19]),
        vec4<f32>(v[20], v[21], v[22], v[23]),
        vec4<f32>(v[24], v[25], v[26], v[27]),
        vec4<f32>(v[28], v[29], v[30], v[31]),
    );
}
