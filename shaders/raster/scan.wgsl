// The compute rasteriser's prefix sum (render::caster::compute): one workgroup turns the n segment counts of
// `raster_counts` (n + 1 entries) into their exclusive prefix sums in place and writes the total at index n.
// Each invocation sums a contiguous chunk, the workgroup scans the chunk sums (Hillis & Steele), and each
// invocation writes its chunk's offsets: deterministic whatever the scheduling.

@group(1) @binding(0) var<storage, read_write> raster_counts: array<u32>;

var<workgroup> sums: array<u32, 256>;

@compute @workgroup_size(256)
fn scan(@builtin(local_invocation_index) t: u32) {
    let n = arrayLength(&raster_counts) - 1u;
    let chunk = (n + 255u) / 256u;
    let begin = min(t * chunk, n);
    let end = min(begin + chunk, n);
    var own = 0u;
    for (var i = begin; i < end; i++) {
        own += raster_counts[i];
    }
    sums[t] = own;
    workgroupBarrier();
    for (var d = 1u; d < 256u; d *= 2u) {
        var v = sums[t];
        if t >= d {
            v += sums[t - d];
        }
        workgroupBarrier();
        sums[t] = v;
        workgroupBarrier();
    }
    var run = sums[t] - own;
    for (var i = begin; i < end; i++) {
        let c = raster_counts[i];
        raster_counts[i] = run;
        run += c;
    }
    if t == 255u {
        raster_counts[n] = sums[255];
    }
}
