// One fragment of the compute rasteriser's stream (raster/raster.wgsl or raster/tiles.wgsl writes it,
// casters/compute.wgsl draws it). Mirrors `render::caster::raster_model::RasterFragment` (a test checks the
// layout).
struct RasterFragment {
    // Row-major light texel.
    texel: u32,
    // Normalised light depth.
    depth: f32,
    alpha: f32,
    // The segment's first point.
    segment: u32,
}
