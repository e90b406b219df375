//! The compute rasteriser as a light caster (`render.raster = compute`): a compute pre-pass turns the strand
//! segments into a fragment stream (light texel, normalised light depth, alpha, segment id) under the coverage
//! rule of [`super::raster_model`] (its CPU model), and the caster draws the stream as one point per fragment at
//! its texel's centre (`shaders/casters/compute.wgsl`), so every light pass, the exact reference and depth
//! peeling receive exactly the rasteriser's fragments through the unchanged light-fragment contract. The
//! engines' route for sub-pixel strands (Unreal Engine 5's `HairStrandsVisibilityRasterCompute`, Frostbite's
//! strand renderer), where hardware line raster is weak.
//!
//! The pre-pass (`shaders/raster/raster.wgsl`, `shaders/raster/scan.wgsl`): a count pass (one invocation per
//! segment), an exclusive prefix sum of the counts (one workgroup), a readback of the total that sizes the
//! stream (no fixed cap: two pages of one storage binding each, 16.7 M fragments on lavapipe's 128 MiB
//! bindings; past them one error naming `render.raster`), and a fill pass writing each segment's fragments at its
//! offset: the stream is in segment order whatever the scheduling, with no atomics.
//!
//! Binned to tiles (`render.raster_tile` = T > 0, `shaders/raster/tiles.wgsl`), as Unreal's compute rasteriser
//! bins segments to 32×32-pixel tiles: the count pass also counts each segment once in every T×T-texel tile its
//! fragments fall in, a second prefix sum turns the tiles' counts into list offsets (read back with the total,
//! which sizes the lists), a bin pass lists the segments per tile, and one workgroup per tile walks its list and
//! writes each fragment inside the tile at the fragment's place in the segment-ordered stream. The stream is the
//! per-segment passes' bit for bit; what binning costs and buys is measured by `bench scaling`
//! (`docs/design.md`). It lines strands only.

use super::stage::{CasterStage, LightCaster};
use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError, readback};
use crate::render::caster::raster_model::RasterFragment;
use crate::render::geometry::RIBBON_GROUP;
use crate::render::maps::storage_entry;

pub const COMPUTE: CasterStage = CasterStage {
    wgsl: "casters/compute.wgsl",
    topology: wgpu::PrimitiveTopology::PointList,
    vertex_buffer: None,
    binds_points: true,
};

/// Segments of one workgroup of the count, fill and bin passes.
const WORKGROUP: u32 = 256;
/// Tile sides `render.raster_tile` takes besides 0 (one invocation per segment).
pub const RASTER_TILES: std::ops::RangeInclusive<u32> = 4..=256;
/// Most workgroups along one dimension of a dispatch.
const MAX_GROUPS: u32 = 65_535;
const FRAGMENT_BYTES: u64 = std::mem::size_of::<RasterFragment>() as u64;

/// The strands [`ComputeRaster::prepare`] rasterises: the scene's strand points (`HairVertex`), the index pair
/// of each segment, and the number of segments.
#[derive(Clone, Copy)]
pub struct StrandPoints<'a> {
    pub vertices: &'a wgpu::Buffer,
    pub indices: &'a wgpu::Buffer,
    pub segments: u64,
}

/// The rasteriser's pipelines and buffers, and the stream of the last [`ComputeRaster::prepare`].
pub struct ComputeRaster {
    count: wgpu::ComputePipeline,
    scan: wgpu::ComputePipeline,
    fill: wgpu::ComputePipeline,
    raster_layout: wgpu::BindGroupLayout,
    /// The tile passes' group 1: the raster layout's three bindings, the tiles' counts, cursors and lists.
    tile_layout: wgpu::BindGroupLayout,
    points_layout: wgpu::BindGroupLayout,
    frame_layout: wgpu::BindGroupLayout,
    /// The renderer's ribbon layout, which the stream is bound with at [`RIBBON_GROUP`] for the draw.
    draw_layout: wgpu::BindGroupLayout,
    /// Per segment its count, then its offset; the total last.
    counts: wgpu::Buffer,
    /// The stream's two pages: the first holds `min(total, page)` fragments (`page` the most one binding
    /// holds), the second the rest (one placeholder fragment while none).
    stream: [wgpu::Buffer; 2],
    /// The stream bound for the caster's draw.
    draw_group: wgpu::BindGroup,
    /// The tile passes of the last binned [`ComputeRaster::prepare`], built for its tile side.
    tiles: Option<Tiles>,
    /// Fragments in the stream.
    pub total: u32,
}

/// The tile passes' pipelines (built for one tile side) and buffers.
struct Tiles {
    side: u32,
    count: wgpu::ComputePipeline,
    bin: wgpu::ComputePipeline,
    raster: wgpu::ComputePipeline,
    /// Per tile its segment count, then its list's offset; the total last.
    bins: wgpu::Buffer,
    /// Per tile the segments listed so far.
    cursor: wgpu::Buffer,
    /// The tiles' lists of segments, tile after tile.
    lists: wgpu::Buffer,
    /// (segment, tile) pairs listed: the lists' total length.
    pairs: u32,
}

impl ComputeRaster {
    pub fn new(
        gpu: &Gpu,
        frame_layout: &wgpu::BindGroupLayout,
        ribbon_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let device = &gpu.device;
        let compute = wgpu::ShaderStages::COMPUTE;
        let layout = |label, read_only, count| {
            let entries: Vec<_> = (0..count).map(|b| storage_entry(b, compute, read_only)).collect();
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            })
        };
        // Counts and the stream's two pages; the strand points and segments.
        let raster_layout = layout("hairlab.raster.layout", false, 3);
        let tile_layout = layout("hairlab.raster.tile_layout", false, 6);
        let points_layout = layout("hairlab.raster.points_layout", true, 2);
        let raster = module(device, "raster/raster.wgsl");
        let scan = module(device, "raster/scan.wgsl");
        let with_points = layouts(frame_layout, &raster_layout, Some(&points_layout));
        let pipeline = |label, module, entry, layouts: &[Option<&wgpu::BindGroupLayout>]| {
            compute_pipeline(device, label, module, entry, layouts, &[])
        };
        let counts = buffer(gpu, "hairlab.raster.counts", 4);
        let stream = [0, 1].map(|_| buffer(gpu, "hairlab.raster.stream", FRAGMENT_BYTES));
        ComputeRaster {
            count: pipeline("hairlab.raster.count", &raster, "count", &with_points),
            scan: pipeline("hairlab.raster.scan", &scan, "scan", &with_points[..2]),
            fill: pipeline("hairlab.raster.fill", &raster, "fill", &with_points),
            draw_group: draw_group(gpu, ribbon_layout, &stream),
            frame_layout: frame_layout.clone(),
            raster_layout,
            tile_layout,
            points_layout,
            draw_layout: ribbon_layout.clone(),
            counts,
            stream,
            tiles: None,
            total: 0,
        }
    }

    /// Rasterises the `strands` under the frame uniforms bound in `frame` (written before the call) onto a
    /// `side`-texel map, per segment (`tile` 0) or binned to `tile`-texel tiles: count, prefix sums, readback of
    /// the totals, stream (and tile lists) sized, fill (or bin and tile raster); submitted before it returns.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        frame: &wgpu::BindGroup,
        strands: StrandPoints<'_>,
        (side, tile): (u32, u32),
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        let device = &gpu.device;
        let segments = strands.segments;
        self.total = 0;
        if segments == 0 {
            return Ok(());
        }
        let limit = device.limits().max_storage_buffer_binding_size;
        let counts_bytes = (segments + 1) * 4;
        if counts_bytes > limit || strands.vertices.size() > limit {
            return Err(too_large("segment counts and strand points", counts_bytes, limit));
        }
        if self.counts.size() != counts_bytes {
            self.counts = buffer(gpu, "hairlab.raster.counts", counts_bytes);
        }
        if tile == 0 {
            self.tiles = None;
        } else {
            self.ensure_tiles(gpu, side, tile, limit)?;
        }
        let points = crate::render::pipelines::buffer_group(
            device,
            "hairlab.raster.points",
            &self.points_layout,
            &[strands.vertices, strands.indices],
        );
        let workgroups = (segments as u32).div_ceil(WORKGROUP);
        let size = grid(workgroups);
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.raster.count"),
        });
        let passes = self.passes_group(gpu);
        let totals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.raster.totals"),
            size: 8,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        match &self.tiles {
            None => {
                let groups = [frame, &passes, &points];
                dispatch(
                    &mut enc,
                    &self.count,
                    "compute raster: count",
                    &groups,
                    size,
                    timer,
                );
            }
            Some(t) => {
                let tile_group = self.tile_group(gpu, t);
                enc.clear_buffer(&t.bins, 0, None);
                let groups = [frame, &tile_group, &points];
                let label = "compute raster: count and tile counts";
                dispatch(&mut enc, &t.count, label, &groups, size, timer);
                let bins = crate::render::pipelines::buffer_group(
                    device,
                    "hairlab.raster.tile_scan",
                    &self.raster_layout,
                    &[&t.bins, &self.stream[0], &self.stream[1]],
                );
                let groups = [frame, &bins];
                dispatch(
                    &mut enc,
                    &self.scan,
                    "compute raster: tile prefix sum",
                    &groups,
                    (1, 1),
                    timer,
                );
                enc.copy_buffer_to_buffer(&t.bins, t.bins.size() - 4, &totals, 4, 4);
            }
        }
        let groups = [frame, &passes];
        dispatch(
            &mut enc,
            &self.scan,
            "compute raster: prefix sum",
            &groups,
            (1, 1),
            timer,
        );
        enc.copy_buffer_to_buffer(&self.counts, segments * 4, &totals, 0, 4);
        gpu.queue.submit([enc.finish()]);
        let totals: Vec<u32> = bytemuck::pod_collect_to_vec(&readback::read_buffer(gpu, &totals)?);
        self.total = totals[0];
        let total = self.total as u64;
        let page = limit / FRAGMENT_BYTES;
        if total > 2 * page {
            return Err(too_large(
                &format!("fragment stream ({} fragments, in two bindings)", self.total),
                total * FRAGMENT_BYTES,
                2 * page * FRAGMENT_BYTES,
            ));
        }
        // The first page's length is where the shaders split the stream, so it is exact once a second is used.
        let sizes = [total.clamp(1, page), total.saturating_sub(page).max(1)];
        let fits = |b: &wgpu::Buffer, n: u64| b.size() >= n * FRAGMENT_BYTES;
        let first_exact = total <= page || self.stream[0].size() == page * FRAGMENT_BYTES;
        if !(fits(&self.stream[0], sizes[0]) && fits(&self.stream[1], sizes[1]) && first_exact) {
            self.stream = sizes.map(|n| buffer(gpu, "hairlab.raster.stream", n * FRAGMENT_BYTES));
            self.draw_group = draw_group(gpu, &self.draw_layout, &self.stream);
        }
        let passes = self.passes_group(gpu);
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.raster.fill"),
        });
        if let Some(t) = &mut self.tiles {
            // Pairs never outnumber fragments, so the lists fit one binding when the stream fits two.
            t.pairs = totals[1];
            let bytes = (t.pairs as u64).max(1) * 4;
            if t.lists.size() < bytes {
                t.lists = buffer(gpu, "hairlab.raster.tile_lists", bytes);
            }
        }
        match &self.tiles {
            None => {
                let groups = [frame, &passes, &points];
                dispatch(&mut enc, &self.fill, "compute raster: fill", &groups, size, timer);
            }
            Some(t) => {
                let tile_group = self.tile_group(gpu, t);
                enc.clear_buffer(&t.cursor, 0, None);
                let groups = [frame, &tile_group, &points];
                dispatch(&mut enc, &t.bin, "compute raster: bin", &groups, size, timer);
                let tiles = (t.bins.size() / 4 - 1) as u32;
                let label = "compute raster: tiles";
                dispatch(&mut enc, &t.raster, label, &groups, grid(tiles), timer);
            }
        }
        gpu.queue.submit([enc.finish()]);
        Ok(())
    }

    /// Makes the tile passes ready for `tile`-texel tiles on a `side`-texel map: pipelines built for the side,
    /// per-tile counts and cursors sized to the tiles.
    fn ensure_tiles(&mut self, gpu: &Gpu, side: u32, tile: u32, limit: u64) -> Result<(), GpuError> {
        if !RASTER_TILES.contains(&tile) {
            return Err(GpuError::Setting(format!(
                "render.raster_tile must be 0 or in {}..={} texels (got {tile})",
                RASTER_TILES.start(),
                RASTER_TILES.end()
            )));
        }
        let tiles = (side.div_ceil(tile) as u64).pow(2);
        let bins_bytes = (tiles + 1) * 4;
        if bins_bytes > limit {
            return Err(too_large("tile counts", bins_bytes, limit));
        }
        if self
            .tiles
            .as_ref()
            .is_some_and(|t| t.side == tile && t.bins.size() == bins_bytes)
        {
            return Ok(());
        }
        let (count, bin, raster, lists) = match self.tiles.take().filter(|t| t.side == tile) {
            Some(t) => (t.count, t.bin, t.raster, t.lists),
            None => {
                let device = &gpu.device;
                let module = module(device, "raster/tiles.wgsl");
                let layouts = layouts(&self.frame_layout, &self.tile_layout, Some(&self.points_layout));
                let pipeline = |label, entry, list: bool| {
                    let constants = [("TILE", tile as f64), ("LIST", f64::from(u8::from(list)))];
                    compute_pipeline(device, label, &module, entry, &layouts, &constants)
                };
                (
                    pipeline("hairlab.raster.count_tiles", "bin_segments", false),
                    pipeline("hairlab.raster.bin", "bin_segments", true),
                    pipeline("hairlab.raster.tiles", "raster_tile", false),
                    buffer(gpu, "hairlab.raster.tile_lists", 4),
                )
            }
        };
        self.tiles = Some(Tiles {
            side: tile,
            count,
            bin,
            raster,
            bins: buffer(gpu, "hairlab.raster.tile_bins", bins_bytes),
            cursor: buffer(gpu, "hairlab.raster.tile_cursor", tiles * 4),
            lists,
            pairs: 0,
        });
        Ok(())
    }

    /// The counts and the stream's pages as the count, scan and fill passes bind them.
    fn passes_group(&self, gpu: &Gpu) -> wgpu::BindGroup {
        crate::render::pipelines::buffer_group(
            &gpu.device,
            "hairlab.raster.passes",
            &self.raster_layout,
            &[&self.counts, &self.stream[0], &self.stream[1]],
        )
    }

    /// The tile passes' group 1.
    fn tile_group(&self, gpu: &Gpu, t: &Tiles) -> wgpu::BindGroup {
        crate::render::pipelines::buffer_group(
            &gpu.device,
            "hairlab.raster.tile_passes",
            &self.tile_layout,
            &[
                &self.counts,
                &self.stream[0],
                &self.stream[1],
                &t.bins,
                &t.cursor,
                &t.lists,
            ],
        )
    }

    /// Bytes of the rasteriser's buffers: the segment counts, the stream's pages and the tiles' counts, cursors
    /// and lists.
    pub fn memory_bytes(&self) -> u64 {
        let tiles = self
            .tiles
            .as_ref()
            .map_or(0, |t| t.bins.size() + t.cursor.size() + t.lists.size());
        self.counts.size() + self.stream.iter().map(wgpu::Buffer::size).sum::<u64>() + tiles
    }

    /// The (segment, tile) pairs the last binned [`ComputeRaster::prepare`] listed; `None` when it ran per
    /// segment.
    pub fn tile_pairs(&self) -> Option<u32> {
        self.tiles.as_ref().map(|t| t.pairs)
    }

    /// The tiles' lists of the last binned [`ComputeRaster::prepare`], read back: per tile (row-major), its
    /// segments in the order the bin pass listed them.
    pub fn read_tile_lists(&self, gpu: &Gpu) -> Result<Vec<Vec<u32>>, GpuError> {
        let Some(t) = &self.tiles else {
            return Ok(Vec::new());
        };
        let offsets: Vec<u32> = bytemuck::pod_collect_to_vec(&readback::copy_out(gpu, &t.bins)?);
        let lists: Vec<u32> = bytemuck::pod_collect_to_vec(&readback::copy_out(gpu, &t.lists)?);
        Ok(offsets
            .windows(2)
            .map(|w| lists[w[0] as usize..w[1] as usize].to_vec())
            .collect())
    }

    /// The stream of the last [`ComputeRaster::prepare`], read back.
    pub fn read_stream(&self, gpu: &Gpu) -> Result<Vec<RasterFragment>, GpuError> {
        let mut stream: Vec<RasterFragment> = Vec::new();
        for page in &self.stream {
            stream.extend(bytemuck::pod_collect_to_vec::<u8, RasterFragment>(
                &readback::copy_out(gpu, page)?,
            ));
        }
        stream.truncate(self.total as usize);
        Ok(stream)
    }
}

impl LightCaster for ComputeRaster {
    fn stage(&self) -> &'static CasterStage {
        &COMPUTE
    }

    fn is_empty(&self) -> bool {
        self.total == 0
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, instances: std::ops::Range<u32>) {
        pass.set_bind_group(RIBBON_GROUP, &self.draw_group, &[]);
        pass.draw(0..self.total, instances);
    }
}

/// Records a compute pass of `pipeline` over `size` workgroups, `groups` bound at 0, 1 and [`RIBBON_GROUP`].
fn dispatch(
    enc: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    label: &str,
    groups: &[&wgpu::BindGroup],
    size: (u32, u32),
    timer: &mut Option<GpuTimer>,
) {
    let timestamps = timer
        .as_mut()
        .and_then(|t| t.compute_pass(enc, Phase::SharedLight, label));
    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: timestamps,
    });
    pass.set_pipeline(pipeline);
    for (index, group) in [0, 1, RIBBON_GROUP].into_iter().zip(groups) {
        pass.set_bind_group(index, *group, &[]);
    }
    pass.dispatch_workgroups(size.0, size.1, 1);
}

/// A pass's bind group layouts: the frame's at 0, the pass's at 1, the strand points' at [`RIBBON_GROUP`].
fn layouts<'a>(
    frame: &'a wgpu::BindGroupLayout,
    pass: &'a wgpu::BindGroupLayout,
    points: Option<&'a wgpu::BindGroupLayout>,
) -> Vec<Option<&'a wgpu::BindGroupLayout>> {
    let mut layouts = vec![Some(frame), Some(pass)];
    layouts.resize(RIBBON_GROUP as usize, None);
    layouts.push(points);
    layouts
}

/// `workgroups` laid out as a dispatch grid of at most [`MAX_GROUPS`] along x.
fn grid(workgroups: u32) -> (u32, u32) {
    (workgroups.min(MAX_GROUPS), workgroups.div_ceil(MAX_GROUPS))
}

fn module(device: &wgpu::Device, path: &str) -> wgpu::ShaderModule {
    let src = crate::shaders::compose(path, None).unwrap_or_else(|e| panic!("{e}"));
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(path),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    })
}

/// A compute pipeline of `entry` over `layouts` (a `None` an unused group), its overrides set to `constants`.
fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layouts: &[Option<&wgpu::BindGroupLayout>],
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: layouts,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    })
}

fn buffer(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The stream's pages bound with the renderer's ribbon layout (two read-only storage buffers, which the caster's
/// vertex stage reads as the stream's first and second page).
fn draw_group(gpu: &Gpu, layout: &wgpu::BindGroupLayout, stream: &[wgpu::Buffer; 2]) -> wgpu::BindGroup {
    crate::render::pipelines::buffer_group(
        &gpu.device,
        "hairlab.raster.draw",
        layout,
        &[&stream[0], &stream[1]],
    )
}

/// The error of a rasteriser buffer past the storage binding limit.
fn too_large(what: &str, bytes: u64, limit: u64) -> GpuError {
    GpuError::TooLarge {
        what: format!(
            "render.raster = compute: the {what} (lower the strand count or the map resolution, or use render.raster \
             = hardware)"
        ),
        bytes,
        limit,
    }
}
