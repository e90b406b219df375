//! The eye depth complexity of a frame, counted on the GPU: one storage-only pass over the strands as lines
//! (a technique's count shader: `atomicAdd` per pixel, `atomicMax` of the deepest pixel and the total, the
//! meshes tested by hand) into a buffer of the deepest pixel's count, the total, then every pixel's count; the
//! frame so far is submitted and the first two words read back, once per frame. For a technique that sizes its
//! passes by the deepest pixel (depth peeling's layer count).

use super::bindings::{self, Binding};
use super::{passes, pipelines, targets};
use crate::gpu::{Gpu, GpuError};
use crate::render::transparency::{EyeFrame, EyeSetup, HairGeometry};

pub struct DepthComplexity {
    technique: &'static str,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// The deepest pixel's count, the total, then every pixel's count.
    counts: wgpu::Buffer,
    readback: wgpu::Buffer,
    size: (u32, u32),
}

/// The counts' buffer of `technique` for a `size` viewport.
fn counts(gpu: &Gpu, technique: &str, (width, height): (u32, u32)) -> Result<wgpu::Buffer, GpuError> {
    targets::storage(
        gpu,
        technique,
        "counts",
        &format!("{technique}'s per-pixel fragment counts at a {width}×{height} viewport"),
        (width as u64 * height as u64 + 2) * 4,
    )
}

impl DepthComplexity {
    /// The counter of `technique` running the count shader `wgsl` (group 1: the counts, the meshes' depth).
    pub fn new(setup: &EyeSetup, technique: &'static str, wgsl: &str) -> Result<DepthComplexity, GpuError> {
        let device = &setup.gpu.device;
        let label = format!("hairlab.{technique}.count");
        let layout = bindings::layout(
            device,
            &format!("{label}_layout"),
            &[Binding::StorageRw, Binding::MeshDepth],
        );
        let size = (setup.width, setup.height);
        Ok(DepthComplexity {
            technique,
            pipeline: pipelines::storage_pass(
                device,
                &label,
                wgsl,
                [setup.frame_layout, &layout],
                HairGeometry::Lines,
            ),
            layout,
            counts: counts(setup.gpu, technique, size)?,
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("hairlab.{technique}.readback")),
                size: 8,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            size,
        })
    }

    pub fn resize(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<(), GpuError> {
        if self.size != size {
            self.counts = counts(gpu, self.technique, size)?;
            self.size = size;
        }
        Ok(())
    }

    /// Records the count pass (timed as `eye: depth complexity`), submits the frame so far and reads back the
    /// deepest pixel's fragment count and the total.
    pub fn count(&self, frame: &mut EyeFrame<'_>) -> Result<(u32, u32), GpuError> {
        let group = bindings::group(
            &frame.gpu.device,
            &format!("hairlab.{}.count_group", self.technique),
            &self.layout,
            &[
                self.counts.as_entire_binding(),
                wgpu::BindingResource::TextureView(&frame.targets.depth_view),
            ],
        );
        frame.encoder.clear_buffer(&self.counts, 0, None);
        passes::record_line_count(
            frame,
            &format!("hairlab.{}.count_pass", self.technique),
            "eye: depth complexity",
            &self.pipeline,
            &group,
        );
        frame
            .encoder
            .copy_buffer_to_buffer(&self.counts, 0, &self.readback, 0, 8);
        frame.flush();
        let bytes = crate::gpu::readback::read_buffer(frame.gpu, &self.readback)?;
        let [deepest, total]: [u32; 2] = bytemuck::pod_read_unaligned(&bytes[..8]);
        Ok((deepest, total))
    }

    /// Bytes held per pixel: its count.
    pub const BYTES_PER_PIXEL: u64 = 4;
}
