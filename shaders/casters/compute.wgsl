// The `compute` light caster: the fragment stream of the compute rasteriser (shaders/raster/raster.wgsl), one
// point per fragment (a non-indexed PointList draw) at its texel's centre, pulled from group 3. The light passes
// receive exactly the stream's fragments, depth, alpha and segment id through the light-fragment contract.
#include "common/raster_stream.wgsl"

// The stream's two pages (render::caster::compute): fragment i is in the first below its length.
@group(3) @binding(0) var<storage, read> raster_stream_0: array<RasterFragment>;
@group(3) @binding(1) var<storage, read> raster_stream_1: array<RasterFragment>;

fn stream_read(i: u32) -> RasterFragment {
    let first = arrayLength(&raster_stream_0);
    if i < first {
        return raster_stream_0[i];
    }
    return raster_stream_1[i - first];
}

struct LightVertexIn {
    @builtin(vertex_index) index: u32,
}

fn light_vertex(v: LightVertexIn) -> LightFragment {
    let f = stream_read(v.index);
    let res = frame.light_map_resolution;
    let texel = vec2<f32>(f32(f.texel % res), f32(f.texel / res)) + 0.5;
    let ndc = vec2<f32>(texel.x / f32(res) * 2.0 - 1.0, 1.0 - texel.y / f32(res) * 2.0);
    var out: LightFragment;
    out.clip = vec4<f32>(ndc, 0.5, 1.0);
    out.depth = f.depth;
    out.alpha = f.alpha;
    out.segment = f.segment;
    return out;
}
