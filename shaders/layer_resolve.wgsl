// The resolve of the opacity-layer family's atomic build (methods::opacity_layers, visibility::opacity_layers):
// per band, one compute dispatch per run of its entries (at most 64), one invocation per light-map texel, a
// workgroup taking 64 texels of a row (so that its stores to each layer are neighbours). An occupied texel
// sums its counters (in the run's block of the page bound at binding 1, a texel's side by side, as
// common/layer_pass.wgsl counts them) front to back, saturating,
// from the running sum the previous run left in `layer_carry`, zeroes the counters it read (so they are clear
// for the next band and frame without a clear of their own), and stores the run's layers in the map's storage:
// f32, f16 (rounded to 11 significant bits in integers first, so that the texture's conversion is exact) or u8
// (steps of 1/32 as a unorm). A texel without fragments (the light-depth pass's clear values, far < near)
// reads as optical depth 0. `layer_zeros` keeps per texel how many leading layers of the map are all zero, and
// a layer that is zero again is not stored: an empty texel costs nothing once cleared, and an occupied one
// skips the layers in front of its first fragment (a third of OSM's slices, typically). `layer_tails` keeps per
// texel the first layer from which the map holds one sum in every layer and component (the layers behind the
// texel's last fragment hold its total), and that sum: a layer holding it there again is not stored either, so
// a texel lit as in the frame before skips its layers behind its last fragment too. One entry point per storage
// format (a storage texture's format is part of its type).
#include "common/layer_build_uniforms.wgsl"

@group(0) @binding(0) var<uniform> resolve: LayerBuildUniforms;
@group(0) @binding(1) var<storage, read_write> resolve_counters: array<u32>;
@group(0) @binding(2) var<storage, read_write> layer_carry: array<u32>;
@group(0) @binding(3) var resolve_near: texture_2d<f32>;
@group(0) @binding(4) var resolve_far: texture_2d<f32>;
// Per texel: the map's layers 0..Z are all zero (0, nothing known, when the buffers are made).
@group(0) @binding(5) var<storage, read_write> layer_zeros: array<u32>;
// Three per texel: [3t] 1 + the first layer from which every layer of the map holds [3t + 1] in every component
// (0: nothing known, when the buffers are made or the map is), and [3t + 2] this frame's first layer behind the
// last change of the sums, for the runs after the one that wrote it.
@group(0) @binding(7) var<storage, read_write> layer_tails: array<u32>;

// What this dispatch resolves (a dynamic offset per part): a run, the entries first..end (whole layers), whose
// counters start at `offset` in the page. Mirrors methods::opacity_layers::ResolvePart.
struct ResolvePart {
    first: u32,
    end: u32,
    offset: u32,
    pad: u32,
}
@group(0) @binding(6) var<uniform> resolve_part: ResolvePart;

@group(1) @binding(0) var map_f32: texture_storage_2d_array<rgba32float, write>;
@group(1) @binding(0) var map_f16: texture_storage_2d_array<rgba16float, write>;
@group(1) @binding(0) var map_u8: texture_storage_2d_array<rgba8unorm, write>;

// c rounded to 11 significant bits, to nearest with ties to even, unchanged below 2^11
// (visibility::opacity_layers::round_significand), per component.
fn round_significand(c: vec4<u32>) -> vec4<u32> {
    let shift = max(firstLeadingBit(c), vec4<u32>(10u)) - 10u;
    let low = c & ((vec4<u32>(1u) << shift) - 1u);
    let half = vec4<u32>(1u) << max(shift, vec4<u32>(1u)) - 1u;
    let m = c >> shift;
    let up = (low > half) | ((low == half) & ((m & vec4<u32>(1u)) == vec4<u32>(1u)));
    return select(c, (m + select(vec4<u32>(0u), vec4<u32>(1u), up)) << shift, c >= vec4<u32>(2048u));
}

// What the map holds for the fixed-point sums c (visibility::opacity_layers::LayerStorage::raw), per storage.
fn stored_f32(c: vec4<u32>) -> vec4<f32> {
    return vec4<f32>(c) / LAYER_FIXED_POINT_SCALE;
}

fn stored_f16(c: vec4<u32>) -> vec4<f32> {
    return vec4<f32>(round_significand(c)) / LAYER_FIXED_POINT_SCALE;
}

fn stored_u8(c: vec4<u32>) -> vec4<f32> {
    return vec4<f32>(min((c + 1024u) >> vec4<u32>(11u), vec4<u32>(255u))) / 255.0;
}

// What one invocation resolves: texel t's layers first_layer..end_layer (entries first..end of the part;
// entries past the last, in the map's last layer, repeat the last sum); entry e's counter is at counters + e
// in the page.
struct ResolveTexel {
    t: u32,
    counters: u32,
    end: u32,
    first_layer: u32,
    end_layer: u32,
    occupied: bool,
    // The map's leading all-zero layers before this dispatch.
    zeros: u32,
    // Whether every earlier entry of this frame summed to zero.
    leading: bool,
    // The map's flat tail before this frame: 1 + its first layer (0: none known) and the sum its layers hold.
    tail: u32,
    total: u32,
    // Whether this dispatch resolves the part holding the last entry.
    last: bool,
}

// The running fixed-point sum of the invocation's texel, the sums of the layer next_layer took last, and the
// first of its layers with a non-zero sum.
var<private> sum: u32;
var<private> layer_value: vec4<u32>;
var<private> first_nonzero: u32;
// This frame's first layer behind the last change of the running sum (in the layers taken so far).
var<private> flat_from: u32;

fn begin_texel(p: vec2<u32>) -> ResolveTexel {
    let n = resolve.resolution;
    let t = p.y * n + p.x;
    let part = resolve_part;
    let last = part.end == resolve.entries;
    let layers = vec2<u32>(part.first / 4u, (part.end + 3u) / 4u);
    let counters = part.offset + t * (part.end - part.first) - part.first;
    var r = ResolveTexel(t, counters, part.end, layers.x, layers.y, false, layers.y, true, 1u, 0u, last);
    first_nonzero = layers.y;
    if p.x >= n {
        return r;
    }
    r.occupied = textureLoad(resolve_far, p, 0).r >= textureLoad(resolve_near, p, 0).r;
    r.zeros = layer_zeros[t];
    r.tail = layer_tails[3u * t];
    r.total = layer_tails[3u * t + 1u];
    flat_from = select(layer_tails[3u * t + 2u], 0u, part.first == 0u);
    sum = 0u;
    if r.occupied {
        sum = select(layer_carry[t], 0u, part.first == 0u);
    }
    r.leading = sum == 0u;
    return r;
}

// Whether the invocation has anything to do: an occupied texel, or an empty one whose map is not known to be
// all zero yet.
fn resolves(r: ResolveTexel) -> bool {
    return r.occupied || r.zeros < r.end_layer || r.tail != 1u || r.total != 0u;
}

// Whether `layer` of sums v need not be stored: zero, where the map is zero already, or the sum the map's flat
// tail holds, in that tail.
fn unchanged(r: ResolveTexel, layer: u32, v: vec4<u32>) -> bool {
    return (layer < r.zeros && v.w == 0u) || (r.tail != 0u && layer + 1u >= r.tail && all(v == vec4<u32>(r.total)));
}

// Entry e's counter (zeroed once read) added to the running sum, saturating; entries past the last add 0.
fn next_sum(r: ResolveTexel, e: u32) -> u32 {
    if e < r.end {
        let i = r.counters + e;
        sum = min(sum + resolve_counters[i], LAYER_SATURATION);
        resolve_counters[i] = 0u;
    }
    return sum;
}

// The running sums of the four entries of `layer`: for an occupied texel its counters added front to back,
// for an empty one zeros.
fn layer_sums(r: ResolveTexel, layer: u32) -> vec4<u32> {
    if !r.occupied {
        return vec4<u32>(0u);
    }
    let e = layer * 4u;
    let x = next_sum(r, e);
    let y = next_sum(r, e + 1u);
    let z = next_sum(r, e + 2u);
    let w = next_sum(r, e + 3u);
    return vec4<u32>(x, y, z, w);
}

// The running sum to the next run, and the map's leading zero layers now: this frame's where a layer of this
// run is the first non-zero one, else the zero layers continue into the earlier frame's (sums are monotone, so
// a layer is zero when its last sum is).
fn end_texel(r: ResolveTexel) {
    if r.occupied {
        layer_carry[r.t] = sum;
    }
    if r.last {
        layer_tails[3u * r.t] = flat_from + 1u;
        layer_tails[3u * r.t + 1u] = sum;
    } else {
        layer_tails[3u * r.t + 2u] = flat_from;
    }
    if r.leading {
        let zeros = select(max(r.end_layer, r.zeros), first_nonzero, first_nonzero < r.end_layer);
        if zeros != r.zeros {
            layer_zeros[r.t] = zeros;
        }
    }
}

// Takes `layer`'s sums into layer_value; whether they must be stored.
fn next_layer(r: ResolveTexel, layer: u32) -> bool {
    let before = sum;
    layer_value = layer_sums(r, layer);
    if layer_value.x != before || layer_value.w != before {
        flat_from = layer + 1u;
    }
    if layer_value.w != 0u {
        first_nonzero = min(first_nonzero, layer);
    }
    return !unchanged(r, layer, layer_value);
}


@compute @workgroup_size(64)
fn cs_resolve_f32(@builtin(global_invocation_id) id: vec3<u32>) {
    let r = begin_texel(id.xy);
    if !resolves(r) {
        return;
    }
    for (var l = r.first_layer; l < r.end_layer; l++) {
        if next_layer(r, l) {
            textureStore(map_f32, id.xy, l, stored_f32(layer_value));
        }
    }
    end_texel(r);
}

@compute @workgroup_size(64)
fn cs_resolve_f16(@builtin(global_invocation_id) id: vec3<u32>) {
    let r = begin_texel(id.xy);
    if !resolves(r) {
        return;
    }
    for (var l = r.first_layer; l < r.end_layer; l++) {
        if next_layer(r, l) {
            textureStore(map_f16, id.xy, l, stored_f16(layer_value));
        }
    }
    end_texel(r);
}

@compute @workgroup_size(64)
fn cs_resolve_u8(@builtin(global_invocation_id) id: vec3<u32>) {
    let r = begin_texel(id.xy);
    if !resolves(r) {
        return;
    }
    for (var l = r.first_layer; l < r.end_layer; l++) {
        if next_layer(r, l) {
            textureStore(map_u8, id.xy, l, stored_u8(layer_value));
        }
    }
    end_texel(r);
}
