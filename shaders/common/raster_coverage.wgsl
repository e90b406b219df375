// The compute rasteriser's coverage rule (render::caster::raster_model, its CPU model, operation for operation),
// shared by the per-segment passes (raster/raster.wgsl) and the tile passes (raster/tiles.wgsl): a segment's
// setup, then its major-axis centre lines one by one. Needs common/frame.wgsl and common/ribbon_points.wgsl.
#include "common/raster_stream.wgsl"

// A segment set up for the walk: its centre lines `m` in `0..n` from `a` to `b`.
struct RasterSegment {
    // Its first point (the segment id) and how many centre lines its walk visits (0: it covers nothing).
    first: u32,
    n: u32,
    major_y: bool,
    // Texel-space `a` and `b - a` on the (major u, minor v) axes; the walk's lowest and highest centre line.
    au: f32,
    av: f32,
    du: f32,
    dv: f32,
    lo: f32,
    hi: f32,
    // Normalised light depth and alpha at `a` and `b`.
    d0: f32,
    d1: f32,
    a0: f32,
    a1: f32,
}

// Texel-space position (x right, y down) of clip-space `c` on a `res`-texel map.
fn texel_space(c: vec4<f32>, res: f32) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((ndc.x * 0.5 + 0.5) * res, (0.5 - ndc.y * 0.5) * res);
}

fn raster_setup(s: u32) -> RasterSegment {
    var r: RasterSegment;
    r.first = ribbon_segments[2u * s];
    r.n = 0u;
    let p0 = ribbon_points[r.first];
    let p1 = ribbon_points[ribbon_segments[2u * s + 1u]];
    let c0 = frame.world_to_light_clip * vec4<f32>(p0.position, 1.0);
    let c1 = frame.world_to_light_clip * vec4<f32>(p1.position, 1.0);
    if !(c0.w > 0.0 && c1.w > 0.0) {
        return r;
    }
    r.d0 = light_depth(p0.position);
    r.d1 = light_depth(p1.position);
    r.a0 = strand_alpha(p0.alpha, p0.thickness, frame.light_footprint * c0.w);
    r.a1 = strand_alpha(p1.alpha, p1.thickness, frame.light_footprint * c1.w);
    let res = f32(frame.light_map_resolution);
    let a = texel_space(c0, res);
    let b = texel_space(c1, res);
    let d = b - a;
    r.major_y = abs(d.y) > abs(d.x);
    r.au = select(a.x, a.y, r.major_y);
    r.av = select(a.y, a.x, r.major_y);
    let bu = select(b.x, b.y, r.major_y);
    let bv = select(b.y, b.x, r.major_y);
    r.du = bu - r.au;
    r.dv = bv - r.av;
    r.lo = max(0.0, floor(min(r.au, bu) - 0.5));
    r.hi = min(ceil(max(r.au, bu) - 0.5), res - 1.0);
    if r.du == 0.0 || r.lo > r.hi {
        return r;
    }
    r.n = u32(r.hi - r.lo) + 1u;
    return r;
}

// The walk's `m`-th centre line: whether it covers a texel, the texel `(x, y)` and `t` along the segment.
struct RasterStep {
    covers: bool,
    x: u32,
    y: u32,
    t: f32,
}

fn raster_step(r: RasterSegment, m: u32) -> RasterStep {
    var out: RasterStep;
    out.covers = false;
    let iu = select(r.lo + f32(m), r.hi - f32(m), r.du < 0.0);
    out.t = (iu + 0.5 - r.au) / r.du;
    if !(out.t >= 0.0 && out.t < 1.0) {
        return out;
    }
    let jv = floor(r.av + out.t * r.dv);
    if !(jv >= 0.0 && jv < f32(frame.light_map_resolution)) {
        return out;
    }
    out.covers = true;
    out.x = u32(select(iu, jv, r.major_y));
    out.y = u32(select(jv, iu, r.major_y));
    return out;
}

// The fragment of a covering step.
fn raster_fragment(r: RasterSegment, f: RasterStep) -> RasterFragment {
    let texel = f.y * frame.light_map_resolution + f.x;
    return RasterFragment(texel, r.d0 + f.t * (r.d1 - r.d0), r.a0 + f.t * (r.a1 - r.a0), r.first);
}

// The stream in two pages of one storage binding each (group 1, bindings 1 and 2 of every rasteriser pass):
// fragment i is in the first page below its length.
@group(1) @binding(1) var<storage, read_write> raster_stream_0: array<RasterFragment>;
@group(1) @binding(2) var<storage, read_write> raster_stream_1: array<RasterFragment>;

fn stream_write(i: u32, f: RasterFragment) {
    let first = arrayLength(&raster_stream_0);
    if i < first {
        raster_stream_0[i] = f;
    } else {
        raster_stream_1[i - first] = f;
    }
}

// The segment of an invocation of a dispatch of (x, y) workgroups of 256.
fn segment_of(group: vec3<u32>, groups: vec3<u32>, local: u32) -> u32 {
    return (group.y * groups.x + group.x) * 256u + local;
}
