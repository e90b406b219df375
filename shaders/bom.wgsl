// Bounding Opacity Maps (Voicu's thesis §5, §5.2), the opacity pass: K layers (1..=32) split each texel's
// range [near, far] (the shared near and far maps, the thesis's start and end depth maps) by the hybrid
// linear/logarithmic split with ratio r. One geometry pass fills all of them: ceil(K/4) RGBA32F targets (array
// layers, 8 render targets of 4 channels at most, thesis §3.4) with additive blending; a fragment adds its
// optical depth to its layer and every later one (visibility::bom, build).
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"

struct BomUniforms {
    layers: u32,
    // Hybrid split ratio r in [0, 1]: 0 linear, 1 logarithmic.
    split_ratio: f32,
    pad0: u32,
    pad1: u32,
}

@group(1) @binding(0) var<uniform> bom: BomUniforms;
@group(1) @binding(1) var bom_near: texture_2d<f32>;
@group(1) @binding(2) var bom_far: texture_2d<f32>;

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

struct Layers {
    @location(0) l0: vec4<f32>,
    @location(1) l1: vec4<f32>,
    @location(2) l2: vec4<f32>,
    @location(3) l3: vec4<f32>,
    @location(4) l4: vec4<f32>,
    @location(5) l5: vec4<f32>,
    @location(6) l6: vec4<f32>,
    @location(7) l7: vec4<f32>,
}

// b for the four layers first..first+3 that lie at or behind the fragment's layer k, 0 for those in front.
fn contribution(k: u32, first: u32, b: f32) -> vec4<f32> {
    let l = vec4<u32>(first, first + 1u, first + 2u, first + 3u);
    return select(vec4<f32>(0.0), vec4<f32>(b), l >= vec4<u32>(k));
}

@fragment
fn fs_main(f: LightFragment) -> Layers {
    let texel = vec2<i32>(f.clip.xy);
    let near = textureLoad(bom_near, texel, 0).r;
    let far = textureLoad(bom_far, texel, 0).r;
    let z = fragment_depth(f.depth);
    let t = clamp(select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near), 0.0, 1.0);
    let r = bom.split_ratio;
    let s = clamp((1.0 - r) * t + r * (log2(1.0 + 254.0 * t) / log2(255.0)), 0.0, 1.0);
    let n = bom.layers;
    let k = min(u32(max(floor(s * f32(n)), 0.0)), n - 1u);
    let b = optical_depth(f.alpha);
    return Layers(
        contribution(k, 0u, b),
        contribution(k, 4u, b),
        contribution(k, 8u, b),
        contribution(k, 12u, b),
        contribution(k, 16u, b),
        contribution(k, 20u, b),
        contribution(k, 24u, b),
        contribution(k, 28u, b),
    );
}
