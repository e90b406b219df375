// Weighted blended order-independent transparency (McGuire & Bavoil 2013), the hair pass's store function: every
// fragment adds its weighted premultiplied colour and weight to the accumulation target (One/One) and multiplies
// the revealage target by 1 - alpha (Zero/OneMinusSrc); transparency/wboit_resolve.wgsl divides them out.

struct HairOutput {
    @location(0) accum: vec4<f32>,
    @location(1) revealage: vec4<f32>,
}

fn store_hair(color: vec3<f32>, alpha: f32, depth: f32) -> HairOutput {
    // Depth weight in the spirit of McGuire & Bavoil: nearer fragments dominate. `depth` is in units of the
    // camera-to-target distance, so the weight does not depend on the scene's scale.
    let w = alpha * clamp(pow(max(2.0 - depth, 0.0), 8.0), 1e-2, 3e3);
    var out: HairOutput;
    out.accum = vec4<f32>(color * alpha, alpha) * w;
    out.revealage = vec4<f32>(alpha, 0.0, 0.0, 0.0);
    return out;
}
