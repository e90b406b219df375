// The compute rasteriser's count and fill passes (render::caster::compute): one invocation per strand segment
// runs the coverage rule of render::caster::raster_model (its CPU model, operation for operation). `count`
// writes each segment's fragment count; after the exclusive prefix sum (raster/scan.wgsl) `fill` writes the
// segment's fragments at its offset, so the stream is in segment order whatever the scheduling.
#include "common/frame.wgsl"
#include "common/ribbon_points.wgsl"
#include "common/raster_stream.wgsl"

// Per segment: its count (count), then its offset in the stream (after the scan); the total last.
@group(1) @binding(0) var<storage, read_write> raster_counts: array<u32>;
// The stream in two pages of one storage binding each: fragment i is in the first page below its length.
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

// Texel-space position (x right, y down) of clip-space `c` on a `res`-texel map.
fn texel_space(c: vec4<f32>, res: f32) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((ndc.x * 0.5 + 0.5) * res, (0.5 - ndc.y * 0.5) * res);
}

// Counts segment `s`'s fragments, and writes them from `base` on when `emit`.
fn raster_segment(s: u32, emit: bool, base: u32) -> u32 {
    let i0 = ribbon_segments[2u * s];
    let p0 = ribbon_points[i0];
    let p1 = ribbon_points[ribbon_segments[2u * s + 1u]];
    let c0 = frame.world_to_light_clip * vec4<f32>(p0.position, 1.0);
    let c1 = frame.world_to_light_clip * vec4<f32>(p1.position, 1.0);
    if !(c0.w > 0.0 && c1.w > 0.0) {
        return 0u;
    }
    let d0 = light_depth(p0.position);
    let d1 = light_depth(p1.position);
    let a0 = strand_alpha(p0.alpha, p0.thickness, frame.light_footprint * c0.w);
    let a1 = strand_alpha(p1.alpha, p1.thickness, frame.light_footprint * c1.w);
    let resolution = frame.light_map_resolution;
    let res = f32(resolution);
    let a = texel_space(c0, res);
    let b = texel_space(c1, res);
    let d = b - a;
    let major_y = abs(d.y) > abs(d.x);
    let au = select(a.x, a.y, major_y);
    let av = select(a.y, a.x, major_y);
    let bu = select(b.x, b.y, major_y);
    let bv = select(b.y, b.x, major_y);
    let du = bu - au;
    let dv = bv - av;
    let lo = max(0.0, floor(min(au, bu) - 0.5));
    let hi = min(ceil(max(au, bu) - 0.5), res - 1.0);
    if du == 0.0 || lo > hi {
        return 0u;
    }
    let n = u32(hi - lo) + 1u;
    var k = 0u;
    for (var m = 0u; m < n; m++) {
        let iu = select(lo + f32(m), hi - f32(m), du < 0.0);
        let t = (iu + 0.5 - au) / du;
        if !(t >= 0.0 && t < 1.0) {
            continue;
        }
        let jv = floor(av + t * dv);
        if !(jv >= 0.0 && jv < res) {
            continue;
        }
        if emit {
            let x = u32(select(iu, jv, major_y));
            let y = u32(select(jv, iu, major_y));
            stream_write(base + k, RasterFragment(y * resolution + x, d0 + t * (d1 - d0), a0 + t * (a1 - a0), i0));
        }
        k++;
    }
    return k;
}

// The segment of an invocation of a dispatch of (x, y) workgroups of 256.
fn segment_of(group: vec3<u32>, groups: vec3<u32>, local: u32) -> u32 {
    return (group.y * groups.x + group.x) * 256u + local;
}

@compute @workgroup_size(256)
fn count(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let s = segment_of(group, groups, local);
    if s < arrayLength(&raster_counts) - 1u {
        raster_counts[s] = raster_segment(s, false, 0u);
    }
}

@compute @workgroup_size(256)
fn fill(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let s = segment_of(group, groups, local);
    if s < arrayLength(&raster_counts) - 1u {
        _ = raster_segment(s, true, raster_counts[s]);
    }
}
