//! Eye pass for hair: strands as lines (LineList), depth-tested against the meshes without writing depth, into
//! the eye transparency technique's targets (its store function and blend states). One pipeline per method and
//! technique.

use crate::render::geometry::{GeometryBuffers, HairVertex};
use crate::render::method::{LightMethod, MethodGpu};
use crate::render::pipelines::{Pass, PipelineCache, PipelineKey};
use crate::render::targets::EyeTargets;
use crate::render::transparency::{EyeTransparency, TransparencyGpu};

pub struct HairPass {
    scene_layout: wgpu::BindGroupLayout,
    pipelines: PipelineCache<wgpu::RenderPipeline>,
}

impl HairPass {
    pub fn new(scene_layout: &wgpu::BindGroupLayout) -> Self {
        Self {
            scene_layout: scene_layout.clone(),
            pipelines: PipelineCache::default(),
        }
    }

    fn pipeline(
        &mut self,
        device: &wgpu::Device,
        method: &dyn LightMethod,
        method_gpu: &dyn MethodGpu,
        technique: &dyn EyeTransparency,
    ) -> &wgpu::RenderPipeline {
        let scene_layout = &self.scene_layout;
        let key = PipelineKey {
            pass: Pass::Hair,
            method: method.name(),
            technique: Some(technique.name()),
        };
        self.pipelines.get_or_build(key, |key| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&key.label("layout")),
                bind_group_layouts: &[Some(scene_layout), Some(method_gpu.bind_group_layout())],
                immediate_size: 0,
            });
            let src = crate::shaders::compose_with(
                "hair.wgsl",
                Some(method.lookup_wgsl()),
                Some(technique.info().store_wgsl),
            )
            // As `passes::shader_module`: only a shader failing naga validation panics, which
            // `tests/shaders.rs` rules out for every method × technique.
            .unwrap_or_else(|e| panic!("{e}"));
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&key.label("shader")),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            });
            let targets: Vec<_> = technique.info().hair_targets.iter().cloned().map(Some).collect();
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&key.label("pipeline")),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(HairVertex::layout())],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::LineList,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: EyeTargets::DEPTH,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    pub fn record(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        method: &dyn LightMethod,
        method_gpu: &dyn MethodGpu,
        technique: &dyn EyeTransparency,
        technique_gpu: &dyn TransparencyGpu,
        targets: &EyeTargets,
        scene: &wgpu::BindGroup,
        geometry: &GeometryBuffers,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let pipeline = self.pipeline(device, method, method_gpu, technique);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.hair.pass"),
            color_attachments: &technique_gpu.hair_attachments(),
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if geometry.hair_index_count == 0 {
            return;
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, scene, &[]);
        pass.set_bind_group(1, method_gpu.bind_group(), &[]);
        pass.set_vertex_buffer(0, geometry.hair_vertices.slice(..));
        pass.set_index_buffer(geometry.hair_indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..geometry.hair_index_count, 0, 0..1);
    }
}
