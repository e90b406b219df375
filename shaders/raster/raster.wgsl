// The compute rasteriser's per-segment count and fill passes (render::caster::compute): one invocation per
// strand segment walks the coverage rule of common/raster_coverage.wgsl. `count` writes each segment's
// fragment count; after the exclusive prefix sum (raster/scan.wgsl) `fill` writes the segment's fragments at its
// offset, so the stream is in segment order whatever the scheduling.
#include "common/frame.wgsl"
#include "common/ribbon_points.wgsl"
#include "common/raster_coverage.wgsl"

// Per segment: its count (count), then its offset in the stream (after the scan); the total last.
@group(1) @binding(0) var<storage, read_write> raster_counts: array<u32>;

// Counts segment `s`'s fragments, and writes them from `base` on when `emit`.
fn raster_segment(s: u32, emit: bool, base: u32) -> u32 {
    let r = raster_setup(s);
    var k = 0u;
    for (var m = 0u; m < r.n; m++) {
        let f = raster_step(r, m);
        if !f.covers {
            continue;
        }
        if emit {
            stream_write(base + k, raster_fragment(r, f));
        }
        k++;
    }
    return k;
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
