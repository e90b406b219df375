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
//! bindings; past them one error naming `render.raster`), and a fill pass
//! writing each segment's fragments at its offset: the stream is in segment order whatever the scheduling, with
//! no atomics. A segment's fragments are rasterised by its own invocation: hair segments span a few texels, so
//! the work is even without binning segments to tiles (the engines bin to resolve depth and coverage per tile
//! with atomics; here the light passes resolve through the fragment contract). It lines strands only.

use super::{CasterStage, LightCaster};
use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError, readback};
use crate::render::caster::raster_model::RasterFragment;
use crate::render::geometry::RIBBON_GROUP;
use crate::render::maps::storage_entry;
use crate::render::scene_gpu::SceneGpu;

pub const COMPUTE: CasterStage = CasterStage {
    wgsl: "casters/compute.wgsl",
    topology: wgpu::PrimitiveTopology::PointList,
    vertex_buffer: None,
    binds_points: true,
};

/// Segments of one workgroup of the count and fill passes.
const WORKGROUP: u32 = 256;
/// Most workgroups along one dimension of a dispatch.
const MAX_GROUPS: u32 = 65_535;
const FRAGMENT_BYTES: u64 = std::mem::size_of::<RasterFragment>() as u64;

/// The rasteriser's pipelines and buffers, and the stream of the last [`ComputeRaster::prepare`].
pub struct ComputeRaster {
    count: wgpu::ComputePipeline,
    scan: wgpu::ComputePipeline,
    fill: wgpu::ComputePipeline,
    raster_layout: wgpu::BindGroupLayout,
    points_layout: wgpu::BindGroupLayout,
    /// The renderer's ribbon layout, which the stream is bound with at [`RIBBON_GROUP`] for the draw.
    draw_layout: wgpu::BindGroupLayout,
    /// Per segment its count, then its offset; the total last.
    counts: wgpu::Buffer,
    /// The stream's two pages: the first holds `min(total, page)` fragments (`page` the most one binding
    /// holds), the second the rest (one placeholder fragment while none).
    stream: [wgpu::Buffer; 2],
    /// The stream bound for the caster's draw.
    draw_group: wgpu::BindGroup,
    /// Fragments in the stream.
    pub total: u32,
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
        let points_layout = layout("hairlab.raster.points_layout", true, 2);
        let module = |path: &str| {
            let src = crate::shaders::compose(path, None).unwrap_or_else(|e| panic!("{e}"));
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(path),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            })
        };
        let raster = module("raster/raster.wgsl");
        let scan = module("raster/scan.wgsl");
        let pipeline = |label: &str, module: &wgpu::ShaderModule, entry: &str, points: bool| {
            let mut layouts = vec![Some(frame_layout), Some(&raster_layout)];
            if points {
                layouts.resize(RIBBON_GROUP as usize, None);
                layouts.push(Some(&points_layout));
            }
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &layouts,
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let counts = buffer(gpu, "hairlab.raster.counts", 4);
        let stream = [0, 1].map(|_| buffer(gpu, "hairlab.raster.stream", FRAGMENT_BYTES));
        ComputeRaster {
            count: pipeline("hairlab.raster.count", &raster, "count", true),
            scan: pipeline("hairlab.raster.scan", &scan, "scan", false),
            fill: pipeline("hairlab.raster.fill", &raster, "fill", true),
            draw_group: draw_group(gpu, ribbon_layout, &stream),
            raster_layout,
            points_layout,
            draw_layout: ribbon_layout.clone(),
            counts,
            stream,
            total: 0,
        }
    }

    /// Rasterises `scene`'s strands under the frame uniforms bound in `frame` (written before the call): count,
    /// prefix sum, readback of the total, stream sized, fill; submitted before it returns.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        frame: &wgpu::BindGroup,
        scene: &SceneGpu,
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        let device = &gpu.device;
        let segments = scene.segment_count() as u64;
        self.total = 0;
        if segments == 0 {
            return Ok(());
        }
        let limit = device.limits().max_storage_buffer_binding_size;
        let counts_bytes = (segments + 1) * 4;
        if counts_bytes > limit || scene.hair_vertices.size() > limit {
            return Err(too_large("segment counts and strand points", counts_bytes, limit));
        }
        if self.counts.size() != counts_bytes {
            self.counts = buffer(gpu, "hairlab.raster.counts", counts_bytes);
        }
        let points = crate::render::pipelines::buffer_group(
            device,
            "hairlab.raster.points",
            &self.points_layout,
            &[&scene.hair_vertices, &scene.hair_indices],
        );
        let passes = crate::render::pipelines::buffer_group(
            device,
            "hairlab.raster.passes",
            &self.raster_layout,
            &[&self.counts, &self.stream[0], &self.stream[1]],
        );
        let workgroups = (segments as u32).div_ceil(WORKGROUP);
        let size = (workgroups.min(MAX_GROUPS), workgroups.div_ceil(MAX_GROUPS));
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.raster.count"),
        });
        let groups = [frame, &passes, &points];
        dispatch(
            &mut enc,
            &self.count,
            "compute raster: count",
            &groups,
            size,
            timer,
        );
        dispatch(
            &mut enc,
            &self.scan,
            "compute raster: prefix sum",
            &groups[..2],
            (1, 1),
            timer,
        );
        let total = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.raster.total"),
            size: 4,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_buffer_to_buffer(&self.counts, segments * 4, &total, 0, 4);
        gpu.queue.submit([enc.finish()]);
        let total: Vec<u32> = bytemuck::pod_collect_to_vec(&readback::read_buffer(gpu, &total)?);
        self.total = total[0];
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
        let passes = crate::render::pipelines::buffer_group(
            device,
            "hairlab.raster.passes",
            &self.raster_layout,
            &[&self.counts, &self.stream[0], &self.stream[1]],
        );
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.raster.fill"),
        });
        let groups = [frame, &passes, &points];
        dispatch(&mut enc, &self.fill, "compute raster: fill", &groups, size, timer);
        gpu.queue.submit([enc.finish()]);
        Ok(())
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

fn buffer(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
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
