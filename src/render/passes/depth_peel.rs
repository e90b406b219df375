//! Light-space depth peeling on (depth, segment id): the exact reference peeled layer by layer until a layer
//! peels nothing. Slow (three geometry passes and a readback per layer) and used to verify the A-buffer, which
//! must give the same per-texel lists; see `shaders/depth_peel.wgsl` for how depth ties are kept.

use super::abuffer::RefFragment;
use crate::gpu::readback::copy_out;
use crate::gpu::{Gpu, GpuError};
use crate::render::caster::{LightCaster, LightStage, draw_casters};
use crate::render::pipelines::{self, ComputePass};

pub struct DepthPeel {
    depth_pipeline: wgpu::RenderPipeline,
    segment_pipeline: wgpu::RenderPipeline,
    alpha_pipeline: wgpu::RenderPipeline,
    advance_pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// Per-texel lists peeled front to back, and the number of layers it took.
pub struct Peeled {
    pub lists: Vec<Vec<RefFragment>>,
    pub layers: u32,
}

impl DepthPeel {
    pub fn new(gpu: &Gpu, frame_layout: &wgpu::BindGroupLayout, light: &LightStage) -> DepthPeel {
        let device = &gpu.device;
        let layout = crate::render::eye::bindings::layout_for(
            device,
            "hairlab.depth_peel.layout",
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[crate::render::eye::bindings::Binding::StorageRw; 6],
        );
        let module = light.module(device, "hairlab.depth_peel.shader", "depth_peel.wgsl");
        let targets = [super::NullTarget::target_state()];
        let pipeline = |e: &str| {
            light.pipeline(
                device,
                "hairlab.depth_peel.pipeline",
                &[frame_layout, &layout],
                &module,
                e,
                &targets,
            )
        };
        let advance_pipeline = pipelines::compute(
            device,
            &ComputePass {
                label: "hairlab.depth_peel.advance",
                module: &module,
                entry: "cs_advance",
                layouts: &[frame_layout, &layout],
            },
        );
        DepthPeel {
            depth_pipeline: pipeline("fs_depth"),
            segment_pipeline: pipeline("fs_segment"),
            alpha_pipeline: pipeline("fs_alpha"),
            advance_pipeline,
            layout,
        }
    }

    /// Peels until a layer is empty or `max_layers` layers are done (then it fails: the lists would be cut).
    pub fn peel(
        &self,
        gpu: &Gpu,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        resolution: u32,
        max_layers: u32,
    ) -> Result<Peeled, GpuError> {
        let device = &gpu.device;
        let texels = resolution as u64 * resolution as u64;
        let buffer = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let previous = buffer("hairlab.depth_peel.previous", texels * 8);
        let cand_depth = buffer("hairlab.depth_peel.candidate_depth", texels * 4);
        let cand_segment = buffer("hairlab.depth_peel.candidate_segment", texels * 4);
        let cand_alpha = buffer("hairlab.depth_peel.candidate_alpha", texels * 4);
        let layer = buffer("hairlab.depth_peel.layer", texels * 16);
        let peeled = buffer("hairlab.depth_peel.peeled", 16);
        let buffers = [
            &previous,
            &cand_depth,
            &cand_segment,
            &cand_alpha,
            &layer,
            &peeled,
        ];
        let bind_group =
            pipelines::buffer_group(device, "hairlab.depth_peel.bind_group", &self.layout, &buffers);
        let target = super::NullTarget::new(device, resolution);
        let none = vec![u32::MAX; texels as usize];
        gpu.queue
            .write_buffer(&cand_depth, 0, bytemuck::cast_slice(&none));
        gpu.queue
            .write_buffer(&cand_segment, 0, bytemuck::cast_slice(&none));
        let mut lists = vec![Vec::new(); texels as usize];
        for layers in 0..=max_layers {
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hairlab.depth_peel.layer"),
            });
            enc.clear_buffer(&peeled, 0, None);
            for pipeline in [&self.depth_pipeline, &self.segment_pipeline, &self.alpha_pipeline] {
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("hairlab.depth_peel.pass"),
                    color_attachments: &[target.attachment()],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                draw_casters(&mut pass, pipeline, frame, Some(&bind_group), casters, 0..1);
            }
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("hairlab.depth_peel.advance"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&self.advance_pipeline);
                pass.set_bind_group(0, frame, &[]);
                pass.set_bind_group(1, &bind_group, &[]);
                pass.dispatch_workgroups((texels as u32).div_ceil(64), 1, 1);
            }
            gpu.queue.submit([enc.finish()]);
            let count: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &peeled)?);
            if count[0] == 0 {
                return Ok(Peeled { lists, layers });
            }
            if layers == max_layers {
                break;
            }
            let texel_layer: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &layer)?);
            for (t, l) in texel_layer.iter().enumerate() {
                if l[3] == 1 {
                    lists[t].push(RefFragment {
                        depth: f32::from_bits(l[0]),
                        alpha: f32::from_bits(l[2]),
                        segment: l[1],
                    });
                }
            }
        }
        Err(GpuError::Readback(format!(
            "depth peel did not finish within {max_layers} layers"
        )))
    }
}
