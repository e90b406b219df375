// The compute rasteriser binned to tiles (render::caster::compute, `render.raster_tile` > 0): the light map is
// cut into TILE × TILE-texel tiles. `bin_segments` (one invocation per segment), as the count pass, writes the
// segment's fragment count as `count` does and counts the segment once in each tile its fragments fall in; after
// the prefix sums of both (raster/scan.wgsl) it runs again as the bin pass and lists each segment in those
// tiles, and `raster_tile` (one workgroup per tile) walks the tile's segments and writes each fragment inside the
// tile at its place in the segment-ordered stream (the segment's offset plus its rank along the segment): the
// same stream as the per-segment passes', bit for bit, whatever the order of a tile's list. A segment's tiles
// come in one run each along its walk (the walk is monotonic on both axes), so a segment is listed once per tile.
#include "common/frame.wgsl"
#include "common/ribbon_points.wgsl"
#include "common/raster_coverage.wgsl"

// Tile side in texels (the pipeline sets it from `render.raster_tile`).
override TILE: u32 = 32u;

// Per segment: its fragment count (count_tiles), then its offset in the stream (after the scan); the total last.
@group(1) @binding(0) var<storage, read_write> raster_counts: array<u32>;
// Per tile: its segment count (count_tiles), then the offset of its list (after the scan); the total last.
@group(1) @binding(3) var<storage, read_write> tile_bins: array<atomic<u32>>;
// Per tile: the segments listed so far by `bin` (zero before it).
@group(1) @binding(4) var<storage, read_write> tile_cursor: array<atomic<u32>>;
// The tiles' segment lists, tile after tile.
@group(1) @binding(5) var<storage, read_write> tile_segments: array<u32>;

fn tiles_across() -> u32 {
    return (frame.light_map_resolution + TILE - 1u) / TILE;
}

fn tile_of(f: RasterStep) -> u32 {
    return (f.y / TILE) * tiles_across() + f.x / TILE;
}

// Whether this pipeline is the bin pass (lists each segment in its tiles) or the count pass (counts each segment
// once in each of its tiles and writes its fragment count).
override LIST: bool = false;

@compute @workgroup_size(256)
fn bin_segments(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let s = segment_of(group, groups, local);
    if s >= arrayLength(&raster_counts) - 1u {
        return;
    }
    let r = raster_setup(s);
    var k = 0u;
    var last = 0xffffffffu;
    for (var m = 0u; m < r.n; m++) {
        let f = raster_step(r, m);
        if !f.covers {
            continue;
        }
        k++;
        let tile = tile_of(f);
        if tile == last {
            continue;
        }
        last = tile;
        if LIST {
            let slot = atomicLoad(&tile_bins[tile]) + atomicAdd(&tile_cursor[tile], 1u);
            tile_segments[slot] = s;
        } else {
            atomicAdd(&tile_bins[tile], 1u);
        }
    }
    if !LIST {
        raster_counts[s] = k;
    }
}

// Invocations of a tile's workgroup.
const TILE_GROUP: u32 = 64u;

@compute @workgroup_size(64)
fn raster_tile(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let tile = group.y * groups.x + group.x;
    if tile >= arrayLength(&tile_bins) - 1u {
        return;
    }
    let end = atomicLoad(&tile_bins[tile + 1u]);
    for (var i = atomicLoad(&tile_bins[tile]) + local; i < end; i += TILE_GROUP) {
        let s = tile_segments[i];
        let r = raster_setup(s);
        let base = raster_counts[s];
        var k = 0u;
        var inside = false;
        for (var m = 0u; m < r.n; m++) {
            let f = raster_step(r, m);
            if !f.covers {
                continue;
            }
            if tile_of(f) == tile {
                inside = true;
                stream_write(base + k, raster_fragment(r, f));
            } else if inside {
                break;
            }
            k++;
        }
    }
}
