// Weighted blended order-independent transparency (McGuire & Bavoil 2013), the hair pass's entry: every
// fragment adds its weighted premultiplied colour and weight to the accumulation target (One/One) and multiplies
// the revealage target by 1 - alpha (Zero/OneMinusSrc); transparency/wboit_resolve.wgsl divides them out.

struct WboitOutput {
    @location(0) accum: vec4<f32>,
    @location(1) revealage: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut) -> WboitOutput {
    let f = shade_hair(in);
    // Depth weight in the spirit of McGuire & Bavoil: nearer fragments dominate. `depth` is in units of the
    // camera-to-target distance, so the weight does not depend on the scene's scale.
    let w = f.alpha * clamp(pow(max(2.0 - f.depth, 0.0), 8.0), 1e-2, 3e3);
    var out: WboitOutput;
    out.accum = vec4<f32>(f.color * f.alpha, f.alpha) * w;
    out.revealage = vec4<f32>(f.alpha, 0.0, 0.0, 0.0);
    return out;
}
