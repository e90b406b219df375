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
@group(0) @binding(3) var resolve_near: texture_2d<f32>;
@group(0) @binding(4) var resolve_far: texture_2d<f32>;

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

// The next entry e: its counter added to the running sum c (and zeroed) when e lies in the band, then its
// stored value.
fn next_entry(e: u32, band_end: u32, band_first: u32, t: u32, c: ptr<function, u32>) -> f32 {
    if e < band_end {
        let i = (e - band_first) * resolve.resolution * resolve.resolution + t;
        *c = min(*c + resolve_counters[i], LAYER_SATURATION);
        resolve_counters[i] = 0u;
    }
    return stored_value(*c);
}

// Four entries from e on, in order.
fn next4(e: u32, band_end: u32, band_first: u32, t: u32, c: ptr<function, u32>) -> vec4<f32> {
    let x = next_entry(e, band_end, band_first, t, c);
    let y = next_entry(e + 1u, band_end, band_first, t, c);
    let z = next_entry(e + 2u, band_end, band_first, t, c);
    let w = next_entry(e + 3u, band_end, band_first, t, c);
    return vec4<f32>(x, y, z, w);
}

@fragment
fn fs_resolve(f: ResolveFragment) -> CumulativeTargets {
    let p = vec2<u32>(f.clip.xy);
    // A texel without fragments (the light-depth pass's clear values, far < near) has no counts: its entries
    // keep the targets' clear value 0, which every storage reads as optical depth 0.
    if textureLoad(resolve_far, p, 0).r < textureLoad(resolve_near, p, 0).r {
        discard;
    }
    let t = p.y * resolve.resolution + p.x;
    let band_first = (f.first / resolve.band) * resolve.band;
    let band_end = min(band_first + resolve.band, resolve.entries);
    var c = select(layer_carry[t], 0u, f.first == 0u);
    let t0 = next4(f.first, band_end, band_first, t, &c);
    let t1 = next4(f.first + 4u, band_end, band_first, t, &c);
    let t2 = next4(f.first + 8u, band_end, band_first, t, &c);
    let t3 = next4(f.first + 12u, band_end, band_first, t, &c);
    let t4 = next4(f.first + 16u, band_end, band_first, t, &c);
    let t5 = next4(f.first + 20u, band_end, band_first, t, &c);
    let t6 = next4(f.first + 24u, band_end, band_first, t, &c);
    let t7 = next4(f.first + 28u, band_end, band_first, t, &c);
    layer_carry[t] = c;
    return CumulativeTargets(t0, t1, t2, t3, t4, t5, t6, t7);
}
