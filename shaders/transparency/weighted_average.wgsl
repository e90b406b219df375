// Weighted average blending (Bavoil & Myers 2008), the hair pass's entry: every fragment adds its premultiplied
// colour and alpha (a c, a) to the accumulation target and 1 to the count target (both One/One);
// transparency/weighted_average_resolve.wgsl forms the average.

struct WeightedAverageOutput {
    @location(0) accum: vec4<f32>,
    @location(1) count: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut) -> WeightedAverageOutput {
    let f = shade_hair(in);
    var out: WeightedAverageOutput;
    out.accum = vec4<f32>(f.color * f.alpha, f.alpha);
    out.count = vec4<f32>(1.0, 0.0, 0.0, 0.0);
    return out;
}
