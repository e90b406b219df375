//! Evaluation pass: the method's WGSL lookup run in a compute shader at arbitrary (texel, depth) samples, or the
//! eye lookup `hair_visibility` at world points ([`Sample`]). The
//! GPU = CPU tests and the texel inspector read visibility through it, so they test the real GPU path.

use crate::gpu::{Gpu, GpuError, readback};
use crate::render::method::{LightMethod, MethodGpu};
use crate::render::pipelines::{Pass, PipelineCache, PipelineKey};
use wgpu::util::DeviceExt;

/// What the evaluation pass looks up.
#[derive(Clone, Copy, Debug)]
pub enum Sample {
    /// `visibility_at` at a texel of the maps as built (x, y) and a normalised light depth.
    Texel([f32; 3]),
    /// `hair_visibility` (the eye passes' lookup, under the frame's filters and supersampling) at a world point.
    World([f32; 3]),
}

impl Sample {
    fn packed(self) -> [f32; 4] {
        match self {
            Sample::Texel([x, y, z]) => [x, y, z, 0.0],
            Sample::World([x, y, z]) => [x, y, z, 1.0],
        }
    }
}

pub struct EvaluatePass {
    scene_layout: wgpu::BindGroupLayout,
    io_layout: wgpu::BindGroupLayout,
    pipelines: PipelineCache<wgpu::ComputePipeline>,
}

impl EvaluatePass {
    pub fn new(device: &wgpu::Device, scene_layout: &wgpu::BindGroupLayout) -> EvaluatePass {
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let io_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.evaluate.io_layout"),
            entries: &[storage(0, true), storage(1, false)],
        });
        EvaluatePass {
            scene_layout: scene_layout.clone(),
            io_layout,
            pipelines: PipelineCache::default(),
        }
    }

    pub fn run(
        &mut self,
        gpu: &Gpu,
        method: &dyn LightMethod,
        method_gpu: &dyn MethodGpu,
        scene: &wgpu::BindGroup,
        samples: &[Sample],
    ) -> Result<Vec<f32>, GpuError> {
        if samples.is_empty() {
            return Ok(Vec::new());
        }
        let device = &gpu.device;
        let (scene_layout, io_layout) = (&self.scene_layout, &self.io_layout);
        let key = PipelineKey {
            pass: Pass::Evaluate,
            method: method.name(),
            technique: None,
        };
        let pipeline = self.pipelines.get_or_build(key, |key| {
            let module = super::shader_module(
                device,
                &key.label("shader"),
                "evaluate.wgsl",
                Some(method.lookup_wgsl()),
            );
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&key.label("layout")),
                bind_group_layouts: &[
                    Some(scene_layout),
                    Some(method_gpu.bind_group_layout()),
                    Some(io_layout),
                ],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&key.label("pipeline")),
                layout: Some(&layout),
                module: &module,
                entry_point: Some("cs_main"),
                compilation_options: Default::default(),
                cache: None,
            })
        });
        // Samples in runs of at most one storage binding each (16 bytes a sample in).
        let run = (device.limits().max_storage_buffer_binding_size / 16).max(1) as usize;
        let mut out = Vec::with_capacity(samples.len());
        for part in samples.chunks(run) {
            out.extend(run_part(gpu, pipeline, io_layout, method_gpu, scene, part)?);
        }
        Ok(out)
    }
}

/// [`EvaluatePass::run`] over samples that fit one storage binding.
fn run_part(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    io_layout: &wgpu::BindGroupLayout,
    method_gpu: &dyn MethodGpu,
    scene: &wgpu::BindGroup,
    samples: &[Sample],
) -> Result<Vec<f32>, GpuError> {
    let device = &gpu.device;
    let packed: Vec<[f32; 4]> = samples.iter().map(|s| s.packed()).collect();
    let bytes = (samples.len() * 4) as u64;
    gpu.check_buffer_size("evaluation samples", bytes * 4)?;
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hairlab.evaluate.samples"),
        contents: bytemuck::cast_slice(&packed),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hairlab.evaluate.visibility"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hairlab.evaluate.readback"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let io = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hairlab.evaluate.io"),
        layout: io_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("hairlab.evaluate.encoder"),
    });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hairlab.evaluate.pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, scene, &[]);
        pass.set_bind_group(1, method_gpu.bind_group(), &[]);
        pass.set_bind_group(2, &io, &[]);
        let groups = (samples.len() as u32).div_ceil(64);
        let max = device.limits().max_compute_workgroups_per_dimension;
        pass.dispatch_workgroups(groups.min(max), groups.div_ceil(max).max(1), 1);
    }
    enc.copy_buffer_to_buffer(&output, 0, &readback_buffer, 0, bytes);
    gpu.queue.submit([enc.finish()]);
    Ok(bytemuck::pod_collect_to_vec(&readback::read_buffer(
        gpu,
        &readback_buffer,
    )?))
}
