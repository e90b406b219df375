//! Eye pass for opaque meshes (clears colour and depth). One pipeline per shadow method, built on first use (it
//! does not depend on the eye transparency technique).

use crate::render::geometry::MeshVertex;
use crate::render::method::{LightMethod, MethodGpu};
use crate::render::pipelines::{Pass, PipelineCache, PipelineKey};
use crate::render::scene_gpu::SceneGpu;
use crate::render::targets::EyeTargets;

pub struct MeshPass {
    scene_layout: wgpu::BindGroupLayout,
    pipelines: PipelineCache<wgpu::RenderPipeline>,
}

impl MeshPass {
    /// Pipelines this pass has built ([`PipelineCache::built`]).
    pub fn pipelines_built(&self) -> u64 {
        self.pipelines.built()
    }

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
    ) -> &wgpu::RenderPipeline {
        let scene_layout = &self.scene_layout;
        let key = PipelineKey {
            pass: Pass::Mesh,
            method: method.name(),
            technique: None,
        };
        self.pipelines.get_or_build(key, |key| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&key.label("layout")),
                bind_group_layouts: &[Some(scene_layout), Some(method_gpu.bind_group_layout())],
                immediate_size: 0,
            });
            let module = super::shader_module(
                device,
                &key.label("shader"),
                "mesh.wgsl",
                Some(method.lookup_wgsl()),
            );
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&key.label("pipeline")),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(MeshVertex::layout())],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: EyeTargets::DEPTH,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(EyeTargets::COLOR.into())],
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
        targets: &EyeTargets,
        background: [f32; 3],
        scene: &wgpu::BindGroup,
        geometry: &SceneGpu,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let pipeline = self.pipeline(device, method, method_gpu);
        let [r, g, b] = background.map(|c| c as f64);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.mesh.pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &targets.color_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if geometry.mesh_index_count == 0 {
            return;
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, scene, &[]);
        pass.set_bind_group(1, method_gpu.bind_group(), &[]);
        pass.set_vertex_buffer(0, geometry.mesh_vertices.slice(..));
        pass.set_index_buffer(geometry.mesh_indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..geometry.mesh_index_count, 0, 0..1);
    }
}
