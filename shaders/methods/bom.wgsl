// Shadow method "bom": Bounding Opacity Maps lookup (Voicu's thesis §5). V = 1 up to the texel's start depth
// (hair_depth_near), then linear interpolation of the accumulated optical depth between the layer boundaries in
// the split coordinate s of the range [near, far] (hair_depth_far) (visibility::bom::visibility, expression for
// expression).

struct BomLookup {
    layers: u32,
    split_ratio: f32,
    pad0: u32,
    pad1: u32,
}

@group(1) @binding(0) var bom_layers: texture_2d_array<f32>;
@group(1) @binding(1) var<uniform> bom_lookup: BomLookup;

fn bom_layer(texel: vec2<i32>, k: u32) -> f32 {
    return textureLoad(bom_layers, texel, i32(k / 4u), 0)[k % 4u];
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let near = textureLoad(hair_depth_near, texel, 0).r;
    let far = textureLoad(hair_depth_far, texel, 0).r;
    let t_unclamped = select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near);
    if !(t_unclamped > 0.0) {
        return 1.0;
    }
    let t = clamp(t_unclamped, 0.0, 1.0);
    let r = bom_lookup.split_ratio;
    let s = clamp((1.0 - r) * t + r * (log2(1.0 + 254.0 * t) / log2(255.0)), 0.0, 1.0);
    let n = bom_lookup.layers;
    let x = s * f32(n);
    let j = min(u32(max(floor(x), 0.0)), n - 1u);
    let f = clamp(x - f32(j), 0.0, 1.0);
    let prev = select(0.0, bom_layer(texel, max(j, 1u) - 1u), j > 0u);
    let l = bom_layer(texel, j);
    return exp(-min(prev + (l - prev) * f, l));
}
